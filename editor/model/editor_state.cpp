// EditorState as a document: edits and undo, dirty flags, new / open / save (the selection is in
// selection.cpp, the edits one makes in command_factories.cpp).
#include "editor/model/editor_state.h"

#include "editor/model/scene_paths.h"
#include "renderer/scene_io.h"

#include <filesystem>
#include <utility>

namespace fs = std::filesystem;

namespace caustic::editor {

EditorState::EditorState() { newScene(false); }

bool EditorState::apply(std::unique_ptr<Command> command, std::string* why) {
    if (!command) return false;
    if (std::string wrong = command->check(); !wrong.empty()) {
        if (why) *why = "edit refused: " + wrong;
        return false;
    }
    if (command->changesNothing()) return true;   // no undo step, nothing dirty (issue 15)
    history.push(std::move(command), *this, false);
    return true;
}

bool EditorState::applyContinuous(std::unique_ptr<Command> command, std::string* why) {
    if (!command) return false;
    if (std::string wrong = command->check(); !wrong.empty()) {
        if (why) *why = "edit refused: " + wrong;
        return false;
    }
    if (command->changesNothing()) return true;   // no undo step, nothing dirty (issue 15)
    history.push(std::move(command), *this, true);
    return true;
}

std::uint32_t dirtyForRenderer(std::uint32_t dirty, std::uint32_t* deferred) {
    if (dirty == kDirtyAll) {   // a new scene: everything, nothing held back
        *deferred = kDirtyNone;
        return dirty;
    }
    if (dirty & kDirtyUnseen) *deferred |= kDirtyGeometry;
    dirty &= ~std::uint32_t(kDirtyTarget | kDirtyUnseen);
    if (dirty != kDirtyNone) dirty |= std::exchange(*deferred, kDirtyNone);
    return dirty;
}

void EditorState::moveView(const Camera& to, bool freeViewMode, bool continuous) {
    if (freeViewMode || freeView) {
        if (freeView && *freeView == to) return;
        freeView = to;
        markDirty(kDirtyCamera);
        return;
    }
    if (continuous) applyContinuous(makeSetCamera(*this, to));
    else apply(makeSetCamera(*this, to));
}

void EditorState::toggleCameraView() {
    if (freeView) {
        m_leftFreeView = std::exchange(freeView, std::nullopt);
    } else {
        freeView = m_leftFreeView ? *m_leftFreeView : scene.camera;
    }
    markDirty(kDirtyCamera);
}

bool EditorState::cameraToView(std::string* why) {
    if (!freeView) {
        if (why) *why = "no free view to move the camera to (the viewport looks through the camera)";
        return false;
    }
    Camera c = scene.camera;
    c.position = freeView->position;
    c.lookAt = freeView->lookAt;
    c.up = freeView->up;
    if (!apply(makeSetCamera(*this, c), why)) return false;
    m_leftFreeView = std::exchange(freeView, std::nullopt);
    markDirty(kDirtyCamera);
    return true;
}

bool EditorState::undo() {
    bool done = history.undo(*this);
    validateSelection();
    return done;
}

bool EditorState::redo() {
    bool done = history.redo(*this);
    validateSelection();
    return done;
}

std::string EditorState::displayName() const {
    return path.empty() ? std::string("untitled") : fs::path(path).filename().string();
}

void EditorState::newScene(bool starter) {
    scene = Scene{};
    scene.render.width = 512;
    scene.render.height = 384;
    scene.materials.push_back(Material{.name = "default"});
    scene.environment.type = EnvironmentType::Sky;
    selection = {};
    history.clear();
    path.clear();
    freeView.reset();
    m_leftFreeView.reset();
    m_dirty = kDirtyAll;
    ++m_generation;
    if (!starter) return;
    // Something to build on, as a new Blender file has: a ground, a key light and a camera at
    // eye height looking down at the spot where new objects appear (its look-at point: a default
    // object there, a 0.25 sphere, rests on the ground).
    Material ground{.name = "ground"};
    ground.albedo = glm::vec3(0.35f);
    scene.materials.push_back(ground);
    Object floor;
    floor.name = "ground";
    floor.shape = Shape::Quad;
    floor.material = "ground";
    floor.transform.rotate = glm::vec3(-90.0f, 0.0f, 0.0f);   // +z up: facing the sky
    floor.transform.scale = glm::vec3(5.0f);
    scene.objects.push_back(floor);
    Light key;
    key.name = "key light";
    key.type = LightType::Rect;
    key.transform.translate = glm::vec3(-1.5f, 2.5f, 1.5f);
    key.transform.rotate = glm::vec3(46.7f, 135.0f, 0.0f);   // its +z towards the look-at point
    key.transform.scale = glm::vec3(0.5f, 0.5f, 1.0f);
    key.position = key.transform.translate;
    key.color = glm::vec3(12.0f);
    scene.lights.push_back(key);
    scene.camera.position = glm::vec3(0.0f, 1.6f, 4.0f);
    scene.camera.lookAt = glm::vec3(0.0f, 0.25f, 0.0f);
}

bool EditorState::open(const std::string& file, std::string* error) {
    SceneLoadResult loaded = loadScene(file);
    if (!loaded) {
        if (error) *error = loaded.error;
        return false;
    }
    adoptOpened(std::move(*loaded.scene), file);
    return true;
}

void EditorState::adoptOpened(Scene opened, const std::string& file) {
    scene = std::move(opened);
    scene.sourcePath = file;
    path = file;
    selection = {};
    history.clear();
    freeView.reset();
    m_leftFreeView.reset();
    m_dirty = kDirtyAll;
    ++m_generation;
}

bool EditorState::save(std::string* error) {
    if (path.empty()) {
        if (error) *error = "the scene has no file yet: use Save As";
        return false;
    }
    return saveAs(path, error);
}

bool EditorState::saveAs(const std::string& file, std::string* error) {
    // Into another folder, the files the scene names are rebased to stay the same files (and
    // the undo history's with them); in memory too, since they now resolve from the new folder.
    const std::string from = sceneFolderOf(path), to = sceneFolderOf(file);
    Scene saved = scene;
    rebaseScenePaths(saved, from, to);
    saved.sourcePath = file;
    if (!saveScene(saved, file, error)) return false;
    scene = std::move(saved);
    if (from != to) history.rebasePaths(from, to);
    path = file;
    history.markClean();
    return true;
}

void EditorState::adoptRecovered(Scene recovered, const std::string& file) {
    scene = std::move(recovered);
    scene.sourcePath = file;
    path = file;
    selection = {};
    history.clear();
    history.markUnclean();
    freeView.reset();
    m_leftFreeView.reset();
    m_dirty = kDirtyAll;
    ++m_generation;
}

}  // namespace caustic::editor
