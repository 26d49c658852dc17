// Fuzz harness: the mesh importer (renderer/mesh_import.h importMeshFileInProcess: Assimp, then caustic's
// conversion and validation) on arbitrary bytes.
// Input: a file extension on the first line ("obj", "gltf", "ply", ...: it picks Assimp's
// importer), then the file's bytes. An extension Assimp does not read ends the run.
// Properties: a refusal carries a message naming the file; an accepted import gives meshes that
// are safe to build a BVH over and shade (what validateMesh promises): indices in range, finite
// used positions, finite unit normals and finite UVs and tangents where present, attribute arrays
// empty or one per vertex, material indices in range; every warning names the file.
// Seeds: assets/knot.obj and Debian's assimp-testmodels (tests/fuzz/run.sh builds them).
// Built a second time as caustic_fuzz_mesh_common with CAUSTIC_FUZZ_MESH_FORMATS set to the
// formats scenes are made of (OBJ, PLY, STL, OFF, glTF, GLB, FBX): every other extension ends the
// run. The full harness spends most of its time restarting after crashes inside Assimp's other
// importers (MDL, ASE, COB, MD5, 3DS, COLLADA: contained by the child-process import, not
// fixable here), so the formats that matter most get few executions; this one gives them the
// fuzzer to themselves (docs/reliability.md, "Fuzzing").
#include "renderer/mesh_import.h"
#include "tests/fuzz/fuzz_common.h"

#include <algorithm>
#include <cmath>

using namespace caustic;

namespace {
bool finite(const glm::vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }
bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const glm::vec4& v) { return finite(glm::vec3(v)) && std::isfinite(v.w); }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view in(reinterpret_cast<const char*>(data), size);
    const auto [ext, body] = fuzz::splitFirstLine(in);
    if (ext.empty() || ext.size() > 12) return 0;
    for (const char c : ext)
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'))) return 0;
#ifdef CAUSTIC_FUZZ_MESH_FORMATS
    {
        const std::string_view formats = CAUSTIC_FUZZ_MESH_FORMATS;  // "obj,ply,..."
        bool listed = false;
        for (std::size_t at = 0; at <= formats.size();) {
            const std::size_t end = std::min(formats.find(',', at), formats.size());
            listed = listed || formats.substr(at, end - at) == ext;
            at = end + 1;
        }
        if (!listed) return 0;
    }
#endif
    const std::string dotExt = fuzz::dotted(ext);
    if (!isMeshFileExtensionSupported("input" + dotExt)) return 0;
    const std::string file = fuzz::ScratchDir::get().write(reinterpret_cast<const std::uint8_t*>(body.data()),
                                                            body.size(), dotExt);
    const MeshImportResult r = importMeshFileInProcess(file);   // in this process: crashes must show
    for (const std::string& w : r.warnings) FUZZ_CHECK(w.rfind(file, 0) == 0, "a warning does not name the file: " + w);
    if (!r.ok()) {
        FUZZ_CHECK(r.error.rfind(file, 0) == 0, "the error does not name the file: " + r.error);
        FUZZ_CHECK(r.meshes.empty(), "meshes returned with an error");
        return 0;
    }
    for (const Mesh& m : r.meshes) {
        const std::size_t n = m.positions.size();
        FUZZ_CHECK(m.normals.empty() || m.normals.size() == n, "normals per vertex");
        FUZZ_CHECK(m.uvs.empty() || m.uvs.size() == n, "uvs per vertex");
        FUZZ_CHECK(m.tangents.empty() || m.tangents.size() == n, "tangents per vertex");
        FUZZ_CHECK(m.material >= -1 && m.material < int(r.materials.size()), std::to_string(m.material));
        for (const glm::uvec3& t : m.triangles)
            for (int k = 0; k < 3; ++k) {
                FUZZ_CHECK(t[k] < n, "index " + std::to_string(t[k]) + " of " + std::to_string(n));
                FUZZ_CHECK(finite(m.positions[t[k]]), "a used position is not finite");
            }
        for (const glm::vec3& v : m.normals) {
            FUZZ_CHECK(finite(v), "a normal is not finite");
            FUZZ_CHECK(std::abs(glm::length(v) - 1.0f) < 1e-3f, "a normal of length " + std::to_string(glm::length(v)));
        }
        for (const glm::vec2& v : m.uvs) FUZZ_CHECK(finite(v), "a UV is not finite");
        for (const glm::vec4& v : m.tangents) FUZZ_CHECK(finite(v), "a tangent is not finite");
    }
    return 0;
}
