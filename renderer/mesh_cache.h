// The mesh cache as code outside the renderer sees it (the editor's background import): the entry
// type, opaque here (renderer/gpu_scene.h defines it), the key of a mesh object's file, and the
// function that prepares an entry off the render thread. The same declarations as gpu_scene.h's.
#pragma once

#include <string>

namespace caustic {

struct Scene;
struct MeshCacheEntry;

// The cache key (and the path compileScene imports) of a mesh object's file: relative to the
// scene file's folder when relative, lexically normalised.
std::string meshCacheKey(const Scene& scene, const std::string& file);

// Imports a model file (Assimp), merges its meshes, maps its materials and builds the BVH:
// everything a MeshCacheEntry holds, stamped with the file's time as it was before the import.
// Pure CPU work with no shared state, so it may run on any thread. On failure *error names the
// file and the reason ("<file>: ...").
bool prepareMesh(const std::string& file, MeshCacheEntry* entry, std::string* error);

}  // namespace caustic
