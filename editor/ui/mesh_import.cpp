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
    if (!ui.app.renderer) return false;
    auto entry = ui.app.renderer->meshCache().find(key);
    std::error_code ec;
    const auto stamp = fs::last_write_time(key, ec);
    return entry && !ec && entry->stamp == stamp;
}

std::string fileName(const std::string& file) { return fs::path(file).filename().string(); }

// Replaces the current scene by an opened (or recovered) one whose meshes the renderer holds.
void adopt(EditorUi& ui, PendingOpen& open) {
    if (open.recovered) {
        ui.app.state.adoptRecovered(std::move(open.scene), open.file);
        notify(ui, "recovered the autosave; save it to keep it");
        return;
    }
    ui.app.state.adoptOpened(std::move(open.scene), open.file);
    ui.app.recent.add(fs::absolute(open.file).lexically_normal().string());
    std::string ignored;
    ui.app.recent.save(ui.app.recentListPath, &ignored);
    ui.app.renderToFile.reset();
    const std::vector<double> seconds = open.seconds();
    double total = 0.0;
    for (double t : seconds) total += t;
    notify(ui, "opened " + open.file +
                   (seconds.empty() ? std::string()
                                    : " (" + std::to_string(seconds.size()) + " meshes imported, " +
                                          std::to_string(int(total * 1e3 + 0.5)) + " ms in the background)"));
}

}  // namespace

MeshImports::MeshImports() {
    // glfwPostEmptyEvent may be called from any thread; it ends the idle wait of the frame loop.
    m_loader.setOnFinished([] { glfwPostEmptyEvent(); });
}

void MeshImports::importFile(EditorUi& ui, const std::string& file) {
    Edit edit{0, ui.app.state.generation(), file, {}};
    if (cachedAndCurrent(ui, meshCacheKey(ui.app.state.scene, meshFileForScene(ui.app.state, file)))) {
        apply(ui, edit, nullptr);   // e.g. a second instance of a file: nothing to import
        return;
    }
    edit.id = m_loader.request(file);
    m_edits.push_back(std::move(edit));
    notify(ui, "importing " + file + " ...");
}

void MeshImports::setObjectFile(EditorUi& ui, int objectIndex, const std::string& file) {
    const auto& objects = ui.app.state.scene.objects;
    if (objectIndex < 0 || static_cast<size_t>(objectIndex) >= objects.size() ||
        objects[static_cast<size_t>(objectIndex)].shape != Shape::Mesh) {
        notify(ui, "select a mesh object to change its file", true);
        return;
    }
    Edit edit{0, ui.app.state.generation(), file, objects[static_cast<size_t>(objectIndex)].name};
    if (cachedAndCurrent(ui, meshCacheKey(ui.app.state.scene, meshFileForScene(ui.app.state, file)))) {
        apply(ui, edit, nullptr);
        return;
    }
    edit.id = m_loader.request(file);
    m_edits.push_back(std::move(edit));
    notify(ui, "importing " + file + " ...");
}

void MeshImports::openScene(EditorUi& ui, Scene scene, const std::string& file, bool recovered) {
    if (m_open) dropOpen();   // superseded: its imports stop, its scene is never adopted
    scene.sourcePath = file;  // mesh files resolve against the file's folder (as compileScene does)
    auto open = std::make_shared<PendingOpen>(std::move(scene), file, recovered,
                                              [&ui](const std::string& key) { return cachedAndCurrent(ui, key); });
    open->generation = ui.app.state.generation();
    open->revision = ui.app.state.history.revision();
    if (open->ready()) {   // nothing to import (no meshes, or all held): as before, at once
        adopt(ui, *open);
        return;
    }
    const std::vector<std::string> keys = open->toImport();
    for (std::size_t i = 0; i < keys.size(); ++i) open->requested(i, m_loader.request(keys[i]));
    m_open = std::move(open);
}

void MeshImports::dropOpen() {
    if (m_open) m_loader.cancel(m_open->ids());
    m_open.reset();
}

void MeshImports::finishOpen(EditorUi& ui) {
    if (!m_open) return;
    if (m_open->generation != ui.app.state.generation()) {   // New meanwhile
        notify(ui, "dropped the open of " + fileName(m_open->file) + ": another scene was made or opened meanwhile");
        dropOpen();
        return;
    }
    if (m_open->failed()) {
        const bool recovered = m_open->recovered;
        showError(ui, std::string(recovered ? "could not recover the autosave; the current scene and the autosave are kept"
                                            : "could not open the scene; the current one is kept") +
                          ".\n" + (m_open->file.empty() ? std::string("autosave") : m_open->file) + ": " + m_open->error());
        // A recovery that failed keeps the autosave on disk: the clean exit removes it only
        // when no recovered scene is left unanswered (it is offered again at the next start).
        if (recovered) ui.app.recovered = std::make_pair(std::move(m_open->scene), m_open->file);
        dropOpen();
        return;
    }
    if (!m_open->ready()) return;
    std::shared_ptr<PendingOpen> open = std::move(m_open);
    m_open.reset();
    // The renderer gets the meshes first, under the keys its compile looks up: the compile that
    // the adoption triggers only uploads them.
    if (ui.app.renderer)
        for (auto& [key, mesh] : open->meshes()) ui.app.renderer->meshCache().insert(key, mesh);
    // Edited while the meshes imported: the unsaved-changes prompt asks first (Cancel keeps it).
    if (ui.app.state.modified() && ui.app.state.history.revision() != open->revision) {
        ui.afterUnsavedPrompt = [&ui, open] {
            if (ui.app.state.generation() == open->generation) adopt(ui, *open);
        };
        ui.unsavedPromptRequested = true;
        notify(ui, fileName(open->file) + " is ready, but the current scene was edited meanwhile");
        return;
    }
    adopt(ui, *open);
}

bool MeshImports::refreshing(EditorUi& ui) {
    if (!ui.app.renderer) return false;
    bool waiting = false;
    for (const SceneMeshFile& f : sceneMeshFiles(ui.app.state.scene)) {
        if (m_refresh.count(f.key)) {
            waiting = true;
            continue;
        }
        if (cachedAndCurrent(ui, f.key)) continue;
        std::error_code ec;
        const auto stamp = fs::last_write_time(f.key, ec);
        if (auto it = m_refreshFailed.find(f.key); it != m_refreshFailed.end() && it->second == stamp) continue;
        m_refresh[f.key] = m_loader.request(f.key);
        notify(ui, "importing " + fileName(f.key) + " again (it changed on disk) ...");
        waiting = true;
    }
    return waiting;
}

void MeshImports::finish(EditorUi& ui) {
    for (const MeshLoadResult& result : m_loader.poll()) {
        if (m_open && m_open->take(result)) {
            m_openSeconds.push_back(result.seconds);
            continue;
        }
        if (auto r = std::find_if(m_refresh.begin(), m_refresh.end(), [&](const auto& e) { return e.second == result.id; });
            r != m_refresh.end()) {
            const std::string key = r->first;
            m_refresh.erase(r);
            m_seconds.push_back(result.seconds);
            if (result.ok() && ui.app.renderer) {
                m_refreshFailed.erase(key);
                ui.app.renderer->meshCache().insert(key, result.mesh);
                ui.app.session.heldDirty |= kDirtyGeometry;   // the new contents replace the old on screen
                notify(ui, "imported " + fileName(key) + " again (" + std::to_string(int(result.seconds * 1e3 + 0.5)) +
                               " ms in the background)");
            } else {
                std::error_code ec;
                m_refreshFailed[key] = fs::last_write_time(key, ec);
                notify(ui, result.error, true);
            }
            continue;
        }
        auto it = std::find_if(m_edits.begin(), m_edits.end(), [&](const Edit& e) { return e.id == result.id; });
        if (it == m_edits.end()) continue;
        const Edit edit = *it;
        m_edits.erase(it);
        m_seconds.push_back(result.seconds);
        apply(ui, edit, &result);
    }
    finishOpen(ui);
}

void MeshImports::apply(EditorUi& ui, const Edit& edit, const MeshLoadResult* result) {
    if (edit.generation != ui.app.state.generation()) {
        notify(ui, "dropped the import of " + fileName(edit.file) + ": another scene was opened meanwhile");
        return;
    }
    if (result && !result->ok()) {
        showError(ui, "could not import the mesh; the scene is unchanged.\n" + result->error);
        return;
    }
    // The renderer gets the prepared mesh first (under the key its compile will look up), then
    // the edit: the compile it triggers finds the mesh and only uploads it.
    const std::string objectFile = meshFileForScene(ui.app.state, edit.file);
    if (result && ui.app.renderer) ui.app.renderer->meshCache().insert(meshCacheKey(ui.app.state.scene, objectFile), result->mesh);
    std::string done = result ? " (" + std::to_string(result->mesh->blas.triangles.size()) + " triangles, " +
                                    std::to_string(int(result->seconds * 1e3 + 0.5)) + " ms in the background)"
                              : std::string();
    if (edit.objectName.empty()) {
        // The file's own materials stay (the mesh is in the renderer's cache when it was imported before).
        std::shared_ptr<const MeshCacheEntry> entry = result ? result->mesh : nullptr;
        if (!entry && ui.app.renderer) entry = ui.app.renderer->meshCache().find(meshCacheKey(ui.app.state.scene, objectFile));
        ui.app.state.apply(makeImportMesh(ui.app.state, edit.file, entry && fileHasOwnMaterials(entry->imported)));
        notify(ui, "imported " + fileName(edit.file) + done);
        return;
    }
    const EntityRef ref = findEntity(ui.app.state.scene, EntityKind::Object, edit.objectName);
    auto command = ref ? makeSetMeshFile(ui.app.state, ref.index, edit.file) : nullptr;
    if (!command) {
        notify(ui, "'" + edit.objectName + "' is no longer a mesh object; " + fileName(edit.file) + " was not applied", true);
        return;
    }
    ui.app.state.apply(std::move(command));
    notify(ui, "'" + edit.objectName + "' now uses " + fileName(edit.file) + done);
}

std::string MeshImports::status() const {
    std::string s = m_open ? m_open->status() : std::string();
    for (const auto& [key, id] : m_refresh) s += (s.empty() ? "importing " : "; importing ") + fileName(key) + " again ...";
    if (m_edits.empty()) return s;
    s += s.empty() ? "importing " : "; importing ";
    for (size_t i = 0; i < m_edits.size(); ++i) s += (i ? ", " : "") + fileName(m_edits[i].file);
    return s + " ...";
}

MeshBoundsLookup meshBoundsLookup(const EditorUi& ui) {
    return [&ui](const Object& o) -> std::optional<std::pair<glm::vec3, glm::vec3>> {
        if (!ui.app.renderer) return std::nullopt;
        auto entry = ui.app.renderer->meshCache().find(meshCacheKey(ui.app.state.scene, o.file));
        if (!entry || entry->blas.bvh.empty()) return std::nullopt;
        const Aabb b = entry->blas.bvh.nodes.front().bounds();
        return std::make_pair(b.min, b.max);
    };
}

}  // namespace caustic::editor
