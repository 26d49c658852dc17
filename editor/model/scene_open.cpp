#include "editor/model/scene_open.h"

#include <algorithm>
#include <filesystem>

namespace caustic::editor {

std::vector<SceneMeshFile> sceneMeshFiles(const Scene& scene) {
    std::vector<SceneMeshFile> files;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const Object& o = scene.objects[i];
        if (o.shape != Shape::Mesh) continue;
        std::string key = meshCacheKey(scene, o.file);
        if (std::any_of(files.begin(), files.end(), [&](const SceneMeshFile& f) { return f.key == key; })) continue;
        files.push_back({std::move(key), static_cast<int>(i), o.name});
    }
    return files;
}

PendingOpen::PendingOpen(Scene s, std::string f, bool rec, const std::function<bool(const std::string&)>& held)
    : scene(std::move(s)), file(std::move(f)), recovered(rec) {
    for (SceneMeshFile& m : sceneMeshFiles(scene))
        if (!held || !held(m.key)) m_needs.push_back({std::move(m), 0, nullptr, 0.0, false});
}

std::vector<std::string> PendingOpen::toImport() const {
    std::vector<std::string> keys;
    for (const Need& n : m_needs) keys.push_back(n.mesh.key);
    return keys;
}

void PendingOpen::requested(std::size_t index, std::uint64_t id) { m_needs.at(index).id = id; }

std::vector<std::uint64_t> PendingOpen::ids() const {
    std::vector<std::uint64_t> out;
    for (const Need& n : m_needs)
        if (!n.done && n.id) out.push_back(n.id);
    return out;
}

bool PendingOpen::take(const MeshLoadResult& result) {
    auto it = std::find_if(m_needs.begin(), m_needs.end(), [&](const Need& n) { return n.id && n.id == result.id && !n.done; });
    if (it == m_needs.end()) return false;
    it->done = true;
    it->seconds = result.seconds;
    it->entry = result.mesh;
    if (!result.ok() && m_error.empty()) {
        const std::string why = result.error.empty() ? it->mesh.key + ": could not be imported" : result.error;
        m_error = "objects[" + std::to_string(it->mesh.objectIndex) + "] ('" + it->mesh.objectName + "').file: " + why;
    }
    return true;
}

bool PendingOpen::ready() const {
    return std::all_of(m_needs.begin(), m_needs.end(), [](const Need& n) { return n.done; });
}

std::string PendingOpen::status() const {
    const std::size_t n = m_needs.size();
    const std::size_t done = static_cast<std::size_t>(std::count_if(m_needs.begin(), m_needs.end(), [](const Need& x) { return x.done; }));
    const std::string name = file.empty() ? std::string("the autosave") : std::filesystem::path(file).filename().string();
    if (done >= n) return "opening " + name + " ...";
    return "opening " + name + ": importing " + std::to_string(done + 1) + " of " + std::to_string(n) +
           " meshes ...";
}

std::vector<std::pair<std::string, std::shared_ptr<const MeshCacheEntry>>> PendingOpen::meshes() const {
    std::vector<std::pair<std::string, std::shared_ptr<const MeshCacheEntry>>> out;
    for (const Need& n : m_needs)
        if (n.entry) out.emplace_back(n.mesh.key, n.entry);
    return out;
}

std::vector<double> PendingOpen::seconds() const {
    std::vector<double> out;
    for (const Need& n : m_needs)
        if (n.done) out.push_back(n.seconds);
    return out;
}

}  // namespace caustic::editor
