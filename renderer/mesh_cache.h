// The mesh cache: imported meshes kept between compiles, the key of a mesh object's file, and the
// function that prepares an entry off the render thread (the editor's background import uses
// these without the rest of the scene compiler, renderer/gpu_scene.h).
#pragma once

#include "renderer/bvh.h"
#include "renderer/image.h"
#include "renderer/mesh.h"
#include "renderer/scene.h"
#include "shaders/shared/layout.h"

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace caustic {

// Imported meshes kept between compiles (keyed by file, checked against the file's time), so an
// edit that does not touch a mesh never re-imports it or rebuilds its BVH.
struct MeshCacheEntry {
    MeshBlas blas;
    // The BVH's 4-wide form, made once per import at base 0 (appendWideBvh places it in a
    // scene's layout), whatever walk the renderer uses: an import's result never depends on the
    // configuration. (For a 1M-triangle mesh the collapse takes about 170 ms on the 2-core VM.)
    std::vector<gpu::GpuWideBvhNode> wideNodes;
    std::vector<glm::vec3> positions;
    std::vector<gpu::GpuVertex> vertices;
    std::vector<std::uint32_t> triangleSlot;   // per triangle (original order): its file material
    std::vector<Material> materials;           // the file's materials, mapped (mapImportedMaterial)
    std::vector<ImportedMaterial> imported;    // the same as the file gives them: those with a
                                               // metallic-roughness texture are mapped again once
                                               // it is read (compileScene, bakeMetallicRoughness)
    std::vector<EmbeddedImage> embedded;       // the file's embedded images ("*N" texture paths)
    std::vector<std::string> mappingWarnings;  // what of them could not be mapped
    std::vector<std::string> warnings;
    std::filesystem::file_time_type stamp;
};
// Keyed by meshCacheKey(). Not thread-safe: the renderer owns it and uses it on its GL thread;
// the editor prepares entries off-thread (prepareMesh) and inserts them on that thread, before
// the edit that uses them, so the compile that follows finds them and imports nothing.
struct MeshCache {
    std::map<std::string, std::shared_ptr<const MeshCacheEntry>> entries;

    // Adds or replaces the entry for key (compileScene uses it while entry->stamp matches the
    // file's current time).
    void insert(const std::string& key, std::shared_ptr<const MeshCacheEntry> entry) { entries[key] = std::move(entry); }
    // The entry for key, or null.
    std::shared_ptr<const MeshCacheEntry> find(const std::string& key) const {
        auto it = entries.find(key);
        return it == entries.end() ? nullptr : it->second;
    }
};

// The cache key (and the path compileScene imports) of a mesh object's file: relative to the
// scene file's folder when relative, lexically normalised.
std::string meshCacheKey(const Scene& scene, const std::string& file);

// Imports a model file (Assimp), merges its meshes, maps its materials and builds the BVH:
// everything a MeshCacheEntry holds, stamped with the file's time as it was before the import.
// Pure CPU work with no shared state, so it may run on any thread. On failure *error names the
// file and the reason ("<file>: ...").
bool prepareMesh(const std::string& file, MeshCacheEntry* entry, std::string* error);

}  // namespace caustic
