// The editor's model: the scene being edited, the selection, the undo history, the file it
// belongs to, and the dirty flags the renderer has not consumed yet. No ImGui, no GL: everything
// here is unit-tested without a window (tests/editor/).
#pragma once

#include "editor/model/command_factories.h"   // the edits made on it (makeSetObject ...)
#include "editor/model/commands.h"
#include "renderer/scene.h"
#include "renderer/tonemap.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace caustic::editor {

// How the viewport shows the render (not part of the scene file: a view preference).
struct ViewSettings {
    ToneMap toneMap = ToneMap::Aces;
    float exposure = 0.0f;       // EV
    bool fitToWindow = true;     // else 1:1 pixels
    // The viewport renders at this fraction of its panel's pixels (1, 1/2 or 1/4): less detail,
    // faster convergence on a slow machine (render_session.h). 0: automatic, from the measured
    // rate (RenderSession::autoScale); scripted sessions start at 1 (they measure sizes).
    float viewportScale = 0.0f;
};

class EditorState {
public:
    EditorState();

    Scene scene;
    EntityRef selection;
    ViewSettings view;
    CommandStack history;
    std::string path;            // the file the scene belongs to; empty while untitled

    // The viewport's own view (Blender's free view: the Blender key map navigates it, the default
    // map once View > Free view turns it on): navigation and the numpad views move it instead of
    // the scene's camera; it is neither saved nor undone, and a new or opened scene starts without
    // one. Empty: the viewport looks through the scene camera, and the default map's navigation
    // moves the camera (lookdev's way).
    std::optional<Camera> freeView;
    const Camera& viewCamera() const { return freeView ? *freeView : scene.camera; }
    // Navigation to `to`: into the free view (freeView mode; made from the camera if there was
    // none), else the scene camera (an edit; continuous: merged until seal()).
    void moveView(const Camera& to, bool freeViewMode, bool continuous);
    // Numpad 0: the camera view, or back to the free view left for it.
    void toggleCameraView();
    // Ctrl+Alt+Numpad 0: the scene camera takes the free view's place (one undo step; its lens,
    // focus and other settings stay), and the viewport looks through it.
    bool cameraToView(std::string* why = nullptr);

    // Edits. apply() is a discrete edit (one undo step); applyContinuous() is one step of a drag
    // or slider that merges with the previous step until seal() (call it on release). A command
    // whose value the scene file could not hold (Command::check: NaN or infinity, 0 samples, ...)
    // is refused: nothing changes, false is returned and *why (if given) says what was wrong.
    bool apply(std::unique_ptr<Command> command, std::string* why = nullptr);
    bool applyContinuous(std::unique_ptr<Command> command, std::string* why = nullptr);
    void seal() { history.seal(); }
    bool undo();
    bool redo();

    // Dirty flags accumulated by commands (and by opening a scene) until the renderer takes them.
    void markDirty(std::uint32_t flags) { m_dirty |= flags; }
    std::uint32_t takeDirty() { std::uint32_t d = m_dirty; m_dirty = kDirtyNone; return d; }
    std::uint32_t pendingDirty() const { return m_dirty; }

    bool modified() const { return !history.isClean(); }
    // Which scene this is: changes when a scene is made new, opened or recovered (an edit
    // prepared for one scene, e.g. a mesh imported in the background, is dropped in another).
    std::uint64_t generation() const { return m_generation; }
    std::string displayName() const;   // file name or "untitled", for the title bar

    // Files. A failed open leaves everything as it was and returns the loader's message
    // (file and JSON path). Saves are atomic (saveScene).
    // File > New and the editor started without a file: the starter scene (a ground, a key light,
    // a camera at eye height). starter = false: only a camera, a "default" material and the sky
    // (what EditorState() starts with, and what the model's tests build on).
    void newScene(bool starter = true);
    bool open(const std::string& file, std::string* error);
    // The second half of open(): adopts a scene already loaded from `file` (the editor loads it
    // first and imports its meshes in the background; docs/editor.md, "Opening scenes").
    void adoptOpened(Scene opened, const std::string& file);
    bool save(std::string* error);     // to `path`; fails when untitled
    bool saveAs(const std::string& file, std::string* error);
    // Adopts a scene (e.g. a recovered autosave) as modified and unsaved, belonging to `file`.
    void adoptRecovered(Scene recovered, const std::string& file);

    // The selected entity still exists (indices change under deletes); clears it when it does not.
    void validateSelection();

    // Multi-selection of objects (Ctrl/Shift+click in the viewport and the outliner): `selection`
    // is the active one (the inspector's and the gizmo's), and other objects may be selected with
    // it. The others belong to the active selection they were made with: any other assignment of
    // `selection` (a plain click, an undo that selects what it changed back, an insert) ends the
    // multi-selection, so it can never outlive what it was made for.
    enum class SelectMode { Replace, Toggle };
    // Replace: only `ref`. Toggle (objects, while an object is active): adds `ref` and makes it the
    // active one, or, if it was selected, removes it (the next remaining one becomes active).
    void select(EntityRef ref, SelectMode mode = SelectMode::Replace);
    // Every selected object's index, ascending (the active one included); empty when the active
    // selection is no object.
    std::vector<int> selectedObjects() const;
    bool isSelected(EntityRef ref) const;
    // Sets the active selection and the other selected objects (commands that restore a selection).
    void setSelection(EntityRef active, const std::vector<int>& objects);

private:
    std::optional<Camera> m_leftFreeView;   // the free view Numpad 0 left
    std::vector<int> m_otherObjects;   // selected with m_otherFor (the active selection then)
    EntityRef m_otherFor;
    std::uint32_t m_dirty = kDirtyAll;
    std::uint64_t m_generation = 0;
};

// What of the dirty flags the edits left (EditorState::takeDirty) goes to the renderer now, so
// that only edits that change the image restart accumulation: kDirtyTarget never does (the frame
// loop reads the target from the scene each frame: a higher one renders on, a lower one than done
// stops), and kDirtyUnseen (materials no object uses) waits in *deferred until something else goes
// to the renderer, and then goes as kDirtyGeometry (a full recompile: the material table's
// indices may have moved). kDirtyNone when nothing needs the renderer.
std::uint32_t dirtyForRenderer(std::uint32_t dirty, std::uint32_t* deferred);

}  // namespace caustic::editor
