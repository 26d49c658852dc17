// What the panels share: the UI state (EditorUi) over the application (AppState, app_state.h), and
// the actions (actions.cpp). One panel per file (viewport_panel.cpp, outliner_panel.cpp,
// inspector_panel.cpp, status_bar.cpp, menu_bar.cpp, file_browser.cpp); editor_app.cpp owns the
// window and the frame loop.
#pragma once

#include "editor/model/modal_transform.h"
#include "editor/ui/app_state.h"

#include <functional>
#include <memory>
#include <string_view>

enum ImGuiKey : int;   // imgui.h
#include <optional>
#include <string>
#include <vector>

namespace caustic::editor {

enum class GizmoOp { Translate, Rotate, Scale };

struct FileBrowserState {
    enum class Mode { Open, SaveAs, RenderTo, ImportMesh, MeshFile };   // MeshFile: the selected mesh object's file
    bool open = false;
    bool justOpened = false;
    Mode mode = Mode::Open;
    std::string directory;
    std::string fileName;
    std::string confirmOverwrite;   // the existing file Save As / Render to file asks to replace
    std::string error;              // why the last Save As failed, shown in the browser
};

// A save that waits for the user's answer (requestSave): what it would do that they may not want.
struct SavePrompt {
    std::string file;
    std::string missingFolder;     // does not exist: created on "Save"
    std::string refusedBecause;    // batch mode would refuse the scene (the renderer does): why
    bool requested = false;        // open the modal next frame
    bool isOpen() const { return !file.empty(); }
};

// The UI's own state: widgets, hover and focus, the gizmo, dialogs and prompts; the application it
// shows is `app` (app_state.h). Panels take an EditorUi and read and edit the application through it.
struct EditorUi {
    explicit EditorUi(AppState& application) : app(application) {}
    EditorUi(const EditorUi&) = delete;
    EditorUi& operator=(const EditorUi&) = delete;

    AppState& app;

    // Viewport interaction.
    GizmoOp gizmoOp = GizmoOp::Translate;
    bool gizmoLocal = false;
    bool snap = false;
    float snapTranslate = 0.1f, snapRotate = 15.0f, snapScale = 0.1f;
    bool gizmoWasUsing = false;
    bool navigating = false;          // a camera drag is in progress
    double lastWheel = -1.0;          // wheel zoom steps merge until a pause
    // The focus-plane overlay (focus_overlay.h): shown until this time (after a focus edit), and
    // the cells it marked in the last frame (scripts check it).
    double focusOverlayUntil = -1.0;
    int focusOverlayCells = -1;       // -1: not shown
    // The Blender map's modal transform (G / R / S) in progress.
    struct Modal {
        bool active = false;
        ModalStart start;
        ModalAxis axis = ModalAxis::Free;
        EntityRef ref;
        Light light;            // a light's value when it started
        bool applied = false;   // a step went to the history (undone on cancel)
        std::size_t undoAtStart = 0;
    } modal;
    float viewportImage[4] = {0, 0, 1, 1};   // the viewport image's screen x, y, width, height
    float uiScaleApplied = -1.0f;     // the UI scale the style has now (app.uiScaleChoice chooses it)
    bool viewportHovered = false;
    bool ignoreClickRelease = false;  // the left button's next release confirmed a G / R / S move
    bool viewportFocused = false;     // this frame (Del deletes there and in the outliner)
    bool outlinerFocused = false;

    // Lookdev: the split view of the snapshot and the live render.
    bool compare = false;
    float compareSplit = 0.5f;
    std::uint64_t snapshotGeneration = 0;   // the scene (EditorState::generation) the snapshot may belong to

    // Dialogs.
    FileBrowserState browser;
    std::function<void()> afterUnsavedPrompt;   // runs after Save / Discard in the prompt
    SavePrompt savePrompt;
    bool unsavedPromptRequested = false;
    bool recoveryPromptRequested = false;
    std::string errorPopup;           // shown in a modal (bad scene, failed save ...)
    bool errorPopupRequested = false;
    bool resetLayout = false;
    bool showShortcuts = false;       // Help > Keyboard and mouse
};

// Panels (each begins with `if (!ImGui::Begin(...)) { ImGui::End(); return; }`).
void drawViewportPanel(EditorUi& ui);
void drawOutlinerPanel(EditorUi& ui);
void drawInspectorPanel(EditorUi& ui);
void drawStatusBar(EditorUi& ui);
void drawMenuBar(EditorUi& ui);
void drawFileBrowser(EditorUi& ui);

struct Chord;
// A key map chord (editor/model/keymap.h) pressed this frame, with exactly its modifiers.
bool chordPressed(const Chord& chord);
// The ImGui key of a key map name ("Z", "F5", "Delete", "Escape", "Enter", "Numpad7"), or
// ImGuiKey_None: the one list of names, for the key map and for scripts' `key`.
ImGuiKey imguiKey(std::string_view name);

// Actions shared by menus, shortcuts and scripts.
// Saved camera views of the current scene: store the camera under `name`, recall one (one undo
// step), delete one; the views file is written after each change (a failure is shown).
void storeCameraView(EditorUi& ui, const std::string& name);
bool recallCameraView(EditorUi& ui, const std::string& name);
void deleteCameraView(EditorUi& ui, const std::string& name);
void notify(EditorUi& ui, const std::string& message, bool isError = false);
void showError(EditorUi& ui, const std::string& message);   // modal + status bar
// A program build is announced by the viewport's session or a preview (the next frames build it).
bool shadersBuilding(const EditorUi& ui);
bool openFile(EditorUi& ui, const std::string& file);        // keeps the current scene on failure
// Saves to `file` now (its missing folders created); a failure is shown (in *error if given, else
// in a modal) and in the status bar, and changes nothing on disk.
bool saveFile(EditorUi& ui, const std::string& file, std::string* error = nullptr);
// Save, Save As and scripts: saves at once, or asks first (ui.savePrompt) when the folder does not
// exist or the scene is one batch mode would refuse (the viewport shows the last good scene).
enum class SaveResult { Saved, Asked, Failed };
SaveResult requestSave(EditorUi& ui, const std::string& file, std::string* error = nullptr);
// The prompt's answer: save (running afterUnsavedPrompt once saved), or not.
bool answerSavePrompt(EditorUi& ui, bool save);
void saveOrSaveAs(EditorUi& ui);
// Runs `action` now if nothing is unsaved, else after the user saves or discards.
void guardUnsaved(EditorUi& ui, std::function<void()> action);
void openFileBrowser(EditorUi& ui, FileBrowserState::Mode mode);
// Frames the selection (or everything) in the view navigation moves (the free view in the Blender
// key map), or in the scene camera itself with `camera` (the camera inspector's button).
void frameSelection(EditorUi& ui, bool camera = false);
void reloadShaders(EditorUi& ui);
void startRenderToFile(EditorUi& ui, const std::string& file);
bool writeFilmImage(EditorUi& ui, const std::string& file, std::string* error);   // tone mapped as in batch
// What the viewport shows: the denoised image while it is shown, else the film (writeFilmImage).
bool writeViewportImage(EditorUi& ui, const std::string& file, std::string* error);
// "Denoise now" (menu, inspector, F6): denoises the current image and holds accumulation there.
void denoiseNow(EditorUi& ui);
// The autosave interval: $CAUSTIC_EDITOR_AUTOSAVE_SECONDS (> 0), else 30 s.
double autosaveIntervalSeconds();
// Scripts may touch the autosave only when $CAUSTIC_EDITOR_HOME names the config folder.
bool scriptMayUseAutosave();

}  // namespace caustic::editor
