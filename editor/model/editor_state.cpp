// EditorState as a document: edits and undo, dirty flags, new / open / save (the selection is in
// selection.cpp, the edits one makes in command_factories.cpp).
#include "editor/model/editor_state.h"

#include "editor/model/scene_paths.h"
#include "renderer/scene_io.h"

#include <filesystem>
#include <utility>

namespace fs = std::filesystem;

namespace caustic::editor {

EditorState::EditorState() { newScene(); }

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

void EditorState::newScene() {
    scene = Scene{};
    scene.render.width = 512;
    scene.render.height = 384;
    scene.materials.push_back(Material{.name = "default"});
    scene.environment.type = EnvironmentType::Sky;
    selection = {};
    history.clear();
    path.clear();
    m_dirty = kDirtyAll;
    ++m_generation;
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
    m_dirty = kDirtyAll;
    ++m_generation;
}

}  // namespace caustic::editor
