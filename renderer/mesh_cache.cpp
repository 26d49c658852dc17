// The mesh cache's entries: a model file imported and prepared once per path and stamp.
#include "renderer/gpu_scene.h"

#include "renderer/mesh_import.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <utility>

namespace caustic {

std::string meshCacheKey(const Scene& scene, const std::string& file) {
    return std::filesystem::path(resolveScenePath(scene, file)).lexically_normal().string();
}

bool prepareMesh(const std::string& file, MeshCacheEntry* entry, std::string* error) {
    std::error_code ec;
    entry->stamp = std::filesystem::last_write_time(file, ec);   // before: a later write invalidates it
    MeshImportResult imported = importMeshFile(file);
    if (!imported.ok()) {
        *error = imported.error;
        return false;
    }
    entry->warnings = imported.warnings;
    entry->imported = imported.materials;
    entry->embedded = std::move(imported.embedded);
    for (const ImportedMaterial& im : imported.materials) {
        std::vector<std::string> unmapped;
        entry->materials.push_back(mapImportedMaterial(im, &unmapped));
        for (const std::string& u : unmapped) entry->mappingWarnings.push_back(file + ": " + u);
    }
    if (entry->materials.empty()) entry->materials.push_back(Material{});  // files without materials
    std::vector<glm::uvec3> tris;
    for (const Mesh& mesh : imported.meshes) {
        const std::uint32_t slot = mesh.material >= 0 && std::size_t(mesh.material) < entry->materials.size()
                                       ? std::uint32_t(mesh.material) : 0u;
        entry->triangleSlot.insert(entry->triangleSlot.end(), mesh.triangles.size(), slot);
        const auto base = static_cast<std::uint32_t>(entry->positions.size());
        for (size_t v = 0; v < mesh.positions.size(); ++v) {
            entry->positions.push_back(mesh.positions[v]);
            gpu::GpuVertex gv{};
            const glm::vec3 n = mesh.normals.empty() ? glm::vec3(0.0f) : mesh.normals[v];
            const glm::vec2 uv = mesh.uvs.empty() ? glm::vec2(0.0f) : mesh.uvs[v];
            const glm::vec3 t = mesh.tangents.empty() ? glm::vec3(0.0f) : glm::vec3(mesh.tangents[v]);
            gv.normalU = glm::vec4(n, uv.x);
            gv.tangentV = glm::vec4(t, uv.y);
            entry->vertices.push_back(gv);
        }
        for (const glm::uvec3& t : mesh.triangles) tris.push_back(t + glm::uvec3(base));
    }
    if (tris.empty()) {
        *error = file + ": the file has no triangles";
        return false;
    }
    entry->blas = buildBlas(entry->positions, tris);
    if (entry->blas.bvh.empty()) {
        *error = file + ": no valid triangles (all are degenerate or not finite)";
        return false;
    }
    std::vector<WideBvhNode> wide;
    if (!collapseBvh4(entry->blas.bvh, 0, wide)) {
        *error = file + ": more triangles than the GPU's BVHs can index (2^27)";
        return false;
    }
    entry->wideNodes.reserve(wide.size());
    for (const WideBvhNode& w : wide) entry->wideNodes.push_back(quantizeWideNode(w));
    return true;
}

}  // namespace caustic
