#include "editor/ui/mesh_import.h"

#include "editor/ui/editor_ui.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace fs = std::filesystem;

namespace caustic::editor {
namespace {

// The renderer already holds this file, imported from its current contents.
bool cachedAndCurrent(const EditorUi& ui, const std::string& key) {
    if (!ui.renderer) return false;
    auto entry = ui.renderer->meshCache().find(key);
    std::error_code ec;
    const auto stamp = fs::last_write_time(key, ec);
    return entry && !ec && entry->stamp == stamp;
}

std::string fileName(const std::string& file) { return fs::path(file).filename().string(); }

}  // namespace

MeshImports::MeshImports() {
    // glfwPostEmptyEvent may be called from any thread; it ends the idle wait of the frame loop.
    m_loader.setOnFinished([] { glfwPostEmptyEvent(); });
}

void MeshImports::importFile(EditorUi& ui, const std::string& file) {
    Edit edit{0, ui.state.generation(), file, {}};
    if (cachedAndCurrent(ui, meshCacheKey(ui.state.scene, meshFileForScene(ui.state, file)))) {
        apply(ui, edit, nullptr);   // e.g. a second instance of a file: nothing to import
        return;
    }
    edit.id = m_loader.request(file);
    m_edits.push_back(std::move(edit));
    notify(ui, "importing " + file + " ...");
}

void MeshImports::setObjectFile(EditorUi& ui, int objectIndex, const std::string& file) {
    const auto& objects = ui.state.scene.objects;
    if (objectIndex < 0 || static_cast<size_t>(objectIndex) >= objects.size() ||
        objects[static_cast<size_t>(objectIndex)].shape != Shape::Mesh) {
        notify(ui, "select a mesh object to change its file", true);
        return;
    }
    Edit edit{0, ui.state.generation(), file, objects[static_cast<size_t>(objectIndex)].name};
    if (cachedAndCurrent(ui, meshCacheKey(ui.state.scene, meshFileForScene(ui.state, file)))) {
        apply(ui, edit, nullptr);
        return;
    }
    edit.id = m_loader.request(file);
    m_edits.push_back(std::move(edit));
    notify(ui, "importing " + file + " ...");
}

void MeshImports::finish(EditorUi& ui) {
    for (const MeshLoadResult& result : m_loader.poll()) {
        auto it = std::find_if(m_edits.begin(), m_edits.end(), [&](const Edit& e) { return e.id == result.id; });
        if (it == m_edits.end()) continue;
        const Edit edit = *it;
        m_edits.erase(it);
        m_seconds.push_back(result.seconds);
        apply(ui, edit, &result);
    }
}

void MeshImports::apply(EditorUi& ui, const Edit& edit, const MeshLoadResult* result) {
    if (edit.generation != ui.state.generation()) {
        notify(ui, "dropped the import of " + fileName(edit.file) + ": another scene was opened meanwhile");
        return;
    }
    if (result && !result->ok()) {
        showError(ui, "could not import the mesh; the scene is unchanged.\n" + result->error);
        return;
    }
    // The renderer gets the prepared mesh first (under the key its compile will look up), then
    // the edit: the compile it triggers finds the mesh and only uploads it.
    const std::string objectFile = meshFileForScene(ui.state, edit.file);
    if (result && ui.renderer) ui.renderer->meshCache().insert(meshCacheKey(ui.state.scene, objectFile), result->mesh);
    std::string done = result ? " (" + std::to_string(result->mesh->blas.triangles.size()) + " triangles, " +
                                    std::to_string(int(result->seconds * 1e3 + 0.5)) + " ms in the background)"
                              : std::string();
    if (edit.objectName.empty()) {
        ui.state.apply(makeImportMesh(ui.state, edit.file));
        notify(ui, "imported " + fileName(edit.file) + done);
        return;
    }
    const EntityRef ref = findEntity(ui.state.scene, EntityKind::Object, edit.objectName);
    auto command = ref ? makeSetMeshFile(ui.state, ref.index, edit.file) : nullptr;
    if (!command) {
        notify(ui, "'" + edit.objectName + "' is no longer a mesh object; " + fileName(edit.file) + " was not applied", true);
        return;
    }
    ui.state.apply(std::move(command));
    notify(ui, "'" + edit.objectName + "' now uses " + fileName(edit.file) + done);
}

std::string MeshImports::status() const {
    const std::vector<std::string> files = m_loader.pending();
    if (files.empty()) return pending() ? "importing ..." : std::string();
    std::string s = "importing ";
    for (size_t i = 0; i < files.size(); ++i) s += (i ? ", " : "") + fileName(files[i]);
    return s + " ...";
}

MeshBoundsLookup meshBoundsLookup(const EditorUi& ui) {
    return [&ui](const Object& o) -> std::optional<std::pair<glm::vec3, glm::vec3>> {
        if (!ui.renderer) return std::nullopt;
        auto entry = ui.renderer->meshCache().find(meshCacheKey(ui.state.scene, o.file));
        if (!entry || entry->blas.bvh.empty()) return std::nullopt;
        const Aabb b = entry->blas.bvh.nodes.front().bounds();
        return std::make_pair(b.min, b.max);
    };
}

}  // namespace caustic::editor
