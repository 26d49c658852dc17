// Mesh files through Assimp (OBJ, PLY, glTF 2.0 / GLB, FBX, COLLADA, 3DS, STL and the rest of
// what Assimp 5.2 reads). The only file that includes Assimp; everything past it sees
// renderer/mesh.h.
//
// What an import gives:
//   - triangles only: polygons are triangulated; point and line primitives are dropped (a warning
//     says how many);
//   - normals everywhere (smooth normals generated where the file has none), UVs (first channel,
//     OpenGL convention: v = 0 at the bottom of the image) and tangents (computed when the mesh has
//     UVs and the file has none) kept; identical vertices joined;
//   - the node hierarchy flattened: each (node, mesh) pair becomes one Mesh whose vertices are
//     baked into the file's root space by the node's accumulated transform (normals by its
//     inverse transpose, tangents by its linear part; a mirroring transform swaps the winding so
//     that counter-clockwise stays the front). A mesh used by several nodes is duplicated, not
//     instanced; cameras, lights, animations and skins in the file are ignored with a warning;
//   - every mesh validated (renderer/mesh.h): out-of-range indices, non-finite vertices and
//     zero-area triangles dropped and counted, so everything returned is safe to build a BVH over;
//   - materials in glTF metallic-roughness terms, one per file material, Mesh::material indexing
//     them; for glTF files completed from the file's own JSON (material extensions, samplers,
//     KHR_texture_transform, applied to the UVs; renderer/mesh_import_gltf.h), and the file's
//     embedded images as their bytes (decoded when compiled).
//
// Errors never throw and never crash: a file that cannot be used returns an empty mesh list and an
// error naming the file and what is wrong ("<path>: ..."). A file that loads with problems returns
// its meshes and warnings (each naming the file too).
#pragma once

#include "renderer/mesh.h"

#include <string>
#include <vector>

namespace caustic {

struct MeshImportResult {
    std::vector<Mesh> meshes;
    std::vector<ImportedMaterial> materials;
    std::vector<EmbeddedImage> embedded;  // the file's embedded images ("*N" texture paths)
    std::vector<std::string> warnings;   // what could not be mapped or was repaired
    std::string error;                   // empty on success
    double seconds = 0.0;                // time spent in Assimp and conversion

    bool ok() const { return error.empty(); }
};

// An import slower than this adds a warning (Assimp cannot be interrupted, so there is no hard
// time bound; the warning makes slow files visible).
inline constexpr double kSlowImportSeconds = 5.0;

// Imports in a forked child process (renderer/mesh_import_child.cpp), so that a crash inside
// Assimp on a corrupt file becomes an error ("<path>: the importer crashed (signal 11, SIGSEGV)
// inside Assimp; ..."), not the end of the program. Otherwise the same result as
// importMeshFileInProcess, which is what the child runs.
// A child still running after timeoutSeconds is killed and the import fails ("did not finish
// within ..."): Assimp loops for ever on some corrupt files.
inline constexpr double kImportTimeoutSeconds = 300.0;
MeshImportResult importMeshFile(const std::string& path, double timeoutSeconds = kImportTimeoutSeconds);

// The import in this process: what the child runs, and what the fuzzers call (they must see the
// crashes, and their coverage counters live in this process).
MeshImportResult importMeshFileInProcess(const std::string& path);

// The child's result as bytes and back (everything but `seconds`); deserializeImport returns
// false for a stream that is truncated or malformed.
std::string serializeImport(const MeshImportResult& result);
bool deserializeImport(const std::string& bytes, MeshImportResult* out);

// Whether Assimp has an importer for the file's extension (".obj", ".glb", ...), case-insensitive.
bool isMeshFileExtensionSupported(const std::string& path);

}  // namespace caustic
