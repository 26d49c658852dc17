// What the panels share: the model, the renderer, the display, view options, pending requests.
// One panel per file (viewport_panel.cpp, outliner_panel.cpp, inspector_panel.cpp, status_bar.cpp,
// menu_bar.cpp, file_browser.cpp); editor_app.cpp owns the window and the frame loop.
#pragma once

#include "editor/model/editor_state.h"
#include "editor/model/frame_pacer.h"
#include "editor/model/status.h"
#include "editor/ui/display.h"
#include "editor/ui/mesh_import.h"
#include "renderer/renderer.h"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

struct GLFWwindow;

namespace caustic::editor {

class ScriptRunner;
class ViewportDenoiser;

enum class GizmoOp { Translate, Rotate, Scale };

struct FileBrowserState {
    enum class Mode { Open, SaveAs, RenderTo, ImportMesh, MeshFile };   // MeshFile: the selected mesh object's file
    bool open = false;
    bool justOpened = false;
    Mode mode = Mode::Open;
    std::string directory;
    std::string fileName;
    std::string confirmOverwrite;   // the existing file Save As / Render to file asks to replace
};

struct EditorUi {
    GLFWwindow* window = nullptr;
    EditorState state;
    std::unique_ptr<Renderer> renderer;
    std::unique_ptr<Display> display;
    std::string shaderDir;
    FramePacer pacer;
    RecentFiles recent;
    std::string recentListPath;
    Autosave autosave;
    double lastAutosave = 0.0;
    std::uint64_t autosaveWrites = 0;   // autosaves written this session (scripts wait on it)
    bool scriptAutosave = false;        // a script turned autosave on (`autosave on`)

    // Viewport interaction.
    GizmoOp gizmoOp = GizmoOp::Translate;
    bool gizmoLocal = false;
    bool snap = false;
    float snapTranslate = 0.1f, snapRotate = 15.0f, snapScale = 0.1f;
    bool gizmoWasUsing = false;
    bool navigating = false;          // a camera drag is in progress
    double lastWheel = -1.0;          // wheel zoom steps merge until a pause
    bool interacting = false;         // something is being dragged this frame (preview resolution)
    double lastInteraction = -1.0;
    bool viewportHovered = false;
    bool viewportFocused = false;     // this frame (Del deletes there and in the outliner)
    bool outlinerFocused = false;

    // Rendering.
    int previewDivisor = 1;           // 1 = full resolution
    bool sceneUploaded = false;
    std::optional<int> sampleCap;     // scripts stop at an exact sample count
    std::string renderError;          // the renderer's last failure (scene compile, shader reload)
    double samplesPerSecond = 0.0;    // per second of path-tracer time (the status bar's tooltip)
    SampleRateMeter sampleRate;       // per second of elapsed time since the restart (the status bar)
    std::uint64_t droppedSamples = 0;
    double lastCounterRead = 0.0;
    double frameSeconds = 0.0, uiSeconds = 0.004, renderSeconds = 0.0;
    double overheadSeconds = 0.01;    // a rendering frame's time outside the path tracer (smoothed)
    int samplesThisFrame = 0;         // whole samples finished this frame
    bool renderedThisFrame = false;   // any pixels rendered this frame (a band counts)
    // The scene (EditorState::generation) of which the viewport shows a whole image, if any.
    std::optional<std::uint64_t> displayedWholeImageOf;
    std::uint32_t deferredDirty = 0;  // unseen material edits, handed over with the next real update (dirtyForRenderer)
    std::uint32_t heldDirty = 0;      // scene updates waiting for meshes to import again (renderFrame)
    // Bumped whenever accumulation restarts (every scene upload or update): a denoised image
    // is shown only for the generation it was read from.
    std::uint64_t accumulationGeneration = 0;
    std::unique_ptr<ViewportDenoiser> denoiser;   // viewport_denoise.h (view state, not saved)

    // Lookdev.
    bool compare = false;
    float compareSplit = 0.5f;
    std::optional<std::string> renderToFile;   // written when the target sample count is reached
    std::string lastMessage;          // status bar: the latest info or error
    bool lastMessageIsError = false;
    ShownError shownError;            // where the shown error came from (cleared when its cause is gone)

    // Dialogs.
    FileBrowserState browser;
    std::function<void()> afterUnsavedPrompt;   // runs after Save / Discard in the prompt
    bool unsavedPromptRequested = false;
    bool recoveryPromptRequested = false;
    std::optional<std::pair<Scene, std::string>> recovered;
    bool scriptAnswersRecover = false;   // the script's `recover`: pressed like the button
    std::string errorPopup;           // shown in a modal (bad scene, failed save ...)
    bool errorPopupRequested = false;
    bool quit = false;
    bool resetLayout = false;

    std::unique_ptr<ScriptRunner> script;

    // Mesh imports in the background (mesh_import.h): the edit applies when the mesh is ready.
    MeshImports meshImports;
};

// Panels (each begins with `if (!ImGui::Begin(...)) { ImGui::End(); return; }`).
void drawViewportPanel(EditorUi& ui);
void drawOutlinerPanel(EditorUi& ui);
void drawInspectorPanel(EditorUi& ui);
void drawStatusBar(EditorUi& ui);
void drawMenuBar(EditorUi& ui);
void drawFileBrowser(EditorUi& ui);

// Actions shared by menus, shortcuts and scripts.
void notify(EditorUi& ui, const std::string& message, bool isError = false);
void showError(EditorUi& ui, const std::string& message);   // modal + status bar
bool openFile(EditorUi& ui, const std::string& file);        // keeps the current scene on failure
bool saveFile(EditorUi& ui, const std::string& file);
void saveOrSaveAs(EditorUi& ui);
// Runs `action` now if nothing is unsaved, else after the user saves or discards.
void guardUnsaved(EditorUi& ui, std::function<void()> action);
void openFileBrowser(EditorUi& ui, FileBrowserState::Mode mode);
void frameSelection(EditorUi& ui);
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
