// Mesh import tests: small files written here (good, broken, empty, missing), then every model of
// Debian's assimp-testmodels package: each file either loads into finite, valid meshes (and a
// NaN-free BVH) or fails with a message naming the file.
#include "renderer/bvh.h"
#include "renderer/gpu_scene.h"
#include "renderer/mesh_import.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

using namespace caustic;
namespace fs = std::filesystem;

namespace {

// Where Debian's assimp-testmodels package (setup.sh installs it) puts the models.
const char* const kTestModelsDir = "/usr/share/assimp/models";

struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / ("caustic_mesh_import_" + std::to_string(::getpid()));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::string write(const std::string& name, const std::string& text) const {
        const fs::path p = path / name;
        std::ofstream(p, std::ios::binary) << text;
        return p.string();
    }
};

const char* const kCubeObj =
    "# a unit cube, quads, no normals\n"
    "mtllib cube.mtl\n"
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
    "usemtl red\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

const char* const kCubeMtl =
    "newmtl red\nKd 0.8 0.1 0.05\nKe 0 0 0\nNs 100\nmap_Kd textures/red.png\n";

// Checks everything a renderer relies on; returns a description of the first problem ("" if none).
std::string checkMesh(const Mesh& m, std::size_t materials) {
    const std::size_t n = m.positions.size();
    if (m.triangles.empty()) return "no triangles";
    if (m.normals.size() != n) return "normals missing or wrong count";
    if (!m.uvs.empty() && m.uvs.size() != n) return "uv count";
    if (!m.tangents.empty() && m.tangents.size() != n) return "tangent count";
    if (m.material >= static_cast<int>(materials)) return "material index out of range";
    for (const glm::vec3& p : m.positions)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return "non-finite position";
    for (const glm::vec3& v : m.normals)
        if (!(std::abs(glm::length(v) - 1.0f) < 1e-3f)) return "normal not unit length";
    for (const glm::vec2& v : m.uvs)
        if (!std::isfinite(v.x) || !std::isfinite(v.y)) return "non-finite uv";
    for (const glm::vec4& v : m.tangents)
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) || std::abs(v.w) != 1.0f) return "bad tangent";
    for (const glm::uvec3& t : m.triangles) {
        if (t.x >= n || t.y >= n || t.z >= n) return "index out of range";
        const glm::vec3 c = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
        if (c == glm::vec3(0.0f)) return "degenerate triangle";
    }
    return "";
}

std::string checkResult(const MeshImportResult& r) {
    if (!r.ok()) return r.meshes.empty() ? "" : "error with meshes";
    if (r.meshes.empty()) return "success without meshes";
    for (const Mesh& m : r.meshes) {
        std::string why = checkMesh(m, r.materials.size());
        if (!why.empty()) return "mesh '" + m.name + "': " + why;
    }
    return "";
}

bool bvhFinite(const Bvh& bvh) {
    for (const BvhNode& n : bvh.nodes)
        for (int a = 0; a < 3; ++a)
            if (std::isnan(n.boundsMin[a]) || std::isnan(n.boundsMax[a])) return false;
    return true;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("Import a cube OBJ: triangulated, normals generated, material mapped", "[mesh]") {
    TempDir dir;
    const std::string path = dir.write("cube.obj", kCubeObj);
    dir.write("cube.mtl", kCubeMtl);
    const MeshImportResult r = importMeshFile(path);
    INFO(r.error);
    REQUIRE(r.ok());
    REQUIRE(r.meshes.size() == 1);
    const Mesh& m = r.meshes[0];
    CHECK(checkMesh(m, r.materials.size()).empty());
    CHECK(m.triangles.size() == 12);
    REQUIRE(m.material >= 0);
    const ImportedMaterial& mat = r.materials[static_cast<std::size_t>(m.material)];
    CHECK(mat.name == "red");
    CHECK(mat.baseColor.x == Approx(0.8f));
    CHECK(mat.baseColor.y == Approx(0.1f));
    CHECK(mat.metallic == 0.0f);
    CHECK(mat.roughness < 0.5f);  // Ns 100 is shiny
    CHECK(mat.baseColorTexture == (dir.path / "textures" / "red.png").string());
    // Outward winding: every face normal points away from the centre.
    for (const glm::uvec3& t : m.triangles) {
        const glm::vec3 c = (m.positions[t.x] + m.positions[t.y] + m.positions[t.z]) / 3.0f;
        const glm::vec3 n = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
        CHECK(glm::dot(n, c) > 0.0f);
    }
    const MeshBlas blas = buildBlas(m.positions, m.triangles);
    CHECK(blas.bvh.primIndices.size() == 12);
    CHECK(intersectBlas(blas, m.positions, Ray{{0, 0, 5}, {0, 0, -1}}).t == Approx(4.0f));
}

TEST_CASE("Import a PLY with UVs keeps them and computes tangents", "[mesh]") {
    TempDir dir;
    const std::string path = dir.write("quad.ply",
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "property float s\nproperty float t\nelement face 1\nproperty list uchar int vertex_indices\n"
        "end_header\n0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n");
    const MeshImportResult r = importMeshFile(path);
    INFO(r.error);
    REQUIRE(r.ok());
    REQUIRE(r.meshes.size() == 1);
    const Mesh& m = r.meshes[0];
    CHECK(checkMesh(m, r.materials.size()).empty());
    CHECK(m.triangles.size() == 2);
    REQUIRE(m.uvs.size() == m.positions.size());
    REQUIRE(m.tangents.size() == m.positions.size());
    for (const glm::vec4& t : m.tangents) CHECK(glm::dot(glm::vec3(t), glm::vec3(1, 0, 0)) == Approx(1.0f).margin(1e-4));
    for (const glm::vec3& n : m.normals) CHECK(n.z == Approx(1.0f).margin(1e-4));
}

TEST_CASE("Broken mesh files fail with a message naming the file", "[mesh]") {
    TempDir dir;
    SECTION("missing file") {
        const std::string path = (dir.path / "nothere.obj").string();
        const MeshImportResult r = importMeshFile(path);
        CHECK_FALSE(r.ok());
        CHECK(contains(r.error, path));
        CHECK(r.meshes.empty());
    }
    SECTION("a directory") {
        const fs::path sub = dir.path / "folder.obj";
        fs::create_directories(sub);
        const MeshImportResult r = importMeshFile(sub.string());
        CHECK(contains(r.error, sub.string()));
        CHECK(contains(r.error, "directory"));
    }
    SECTION("an empty file") {
        const std::string path = dir.write("empty.obj", "");
        const MeshImportResult r = importMeshFile(path);
        CHECK(contains(r.error, path));
        CHECK(contains(r.error, "empty"));
    }
    SECTION("an unknown extension") {
        const std::string path = dir.write("notes.xyzzy", "hello");
        const MeshImportResult r = importMeshFile(path);
        CHECK(contains(r.error, path));
    }
    SECTION("an index out of range") {
        const std::string path = dir.write("badindex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 99\n");
        const MeshImportResult r = importMeshFile(path);
        INFO(r.error);
        // Either refused, or loaded without the bad triangle: never an out-of-range index.
        CHECK(checkResult(r).empty());
        if (!r.ok()) CHECK(contains(r.error, path));
    }
    SECTION("only bad indices") {
        const std::string path = dir.write("allbad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 7 8 9\n");
        const MeshImportResult r = importMeshFile(path);
        CHECK_FALSE(r.ok());
        CHECK(contains(r.error, path));
    }
    SECTION("NaN and infinite coordinates") {
        const std::string path = dir.write("nan.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nv inf 1 1\nf 1 2 3\nf 1 2 4\nf 2 3 5\nf 4 5 1\n");
        const MeshImportResult r = importMeshFile(path);
        INFO(r.error);
        CHECK(checkResult(r).empty());
        if (r.ok()) {
            std::size_t tris = 0;
            for (const Mesh& m : r.meshes) tris += m.triangles.size();
            CHECK(tris == 1);
            // What was dropped is reported, naming the file.
            REQUIRE_FALSE(r.warnings.empty());
            CHECK(contains(r.warnings[0], path));
        } else {
            CHECK(contains(r.error, path));
        }
    }
    SECTION("only degenerate triangles") {
        const std::string path = dir.write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
        const MeshImportResult r = importMeshFile(path);
        CHECK_FALSE(r.ok());
        CHECK(contains(r.error, path));
    }
    SECTION("points and lines only") {
        const std::string path = dir.write("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\np 1\n");
        const MeshImportResult r = importMeshFile(path);
        CHECK_FALSE(r.ok());
        CHECK(contains(r.error, path));
    }
    SECTION("a header that declares more than the file holds") {
        // Refused from the header, before anything is allocated for 3.5 billion vertices (an
        // attempt would run out of memory or hang until the test's time-out; no clock is read).
        const std::string path = dir.write("huge.off", "OFF\n3535235358 6 0\n0 0 0\n1 0 0\n0 1 0\n");
        const MeshImportResult r = importMeshFile(path);
        CHECK(contains(r.error, path));
        CHECK(contains(r.error, "3535235358"));
    }
}

TEST_CASE("Triangles and lines mixed: lines dropped with a warning", "[mesh]") {
    TempDir dir;
    const std::string path = dir.write("mixed.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl 1 3\n");
    const MeshImportResult r = importMeshFile(path);
    INFO(r.error);
    REQUIRE(r.ok());
    CHECK(checkResult(r).empty());
    const bool warned = std::any_of(r.warnings.begin(), r.warnings.end(),
                                    [&](const std::string& w) { return contains(w, path) && contains(w, "line"); });
    CHECK(warned);
}

TEST_CASE("Every model of assimp-testmodels loads cleanly or fails with a message naming it", "[mesh][testmodels]") {
    // Not skipped when missing: the walk is the proof that real third-party files are handled.
    INFO("no " << kTestModelsDir << ": run setup.sh (it installs Debian's assimp-testmodels package)");
    REQUIRE(fs::is_directory(kTestModelsDir));

    std::vector<std::string> files;
    std::size_t otherFiles = 0;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(kTestModelsDir)) {
        if (!e.is_regular_file()) continue;
        // Textures, .bin buffers, .mtl libraries, readmes: not models (Assimp has no importer
        // for their extension).
        if (isMeshFileExtensionSupported(e.path().string())) files.push_back(e.path().string());
        else ++otherFiles;
    }
    std::sort(files.begin(), files.end());
    // The package holds ~410 model files; far fewer means the walk did not see the package.
    REQUIRE(files.size() > 300);

    // Only results are asserted: how long an import takes depends on the machine and its load
    // (the slowest file is reported, not judged; import speed belongs in a benchmark).
    const auto t0 = std::chrono::steady_clock::now();
    std::size_t loaded = 0, failed = 0, triangles = 0;
    std::string slowest;
    double slowestSeconds = 0.0;
    for (const std::string& path : files) {
        INFO(path);
        const MeshImportResult r = importMeshFile(path);
        INFO("error: " << r.error);
        CHECK(checkResult(r).empty());
        if (!r.ok()) {
            ++failed;
            CHECK(contains(r.error, path));
            continue;
        }
        ++loaded;
        for (const std::string& w : r.warnings) CHECK(contains(w, path));
        for (const Mesh& m : r.meshes) {
            triangles += m.triangles.size();
            const MeshBlas blas = buildBlas(m.positions, m.triangles);
            CHECK(bvhFinite(blas.bvh));
            CHECK(blas.bvh.primIndices.size() == m.triangles.size());
        }
        if (r.seconds > slowestSeconds) {
            slowestSeconds = r.seconds;
            slowest = path;
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    INFO(files.size() << " model files (" << loaded << " loaded, " << failed << " refused, "
         << triangles << " triangles), " << otherFiles << " other files, " << seconds << " s; slowest "
         << slowest << ", " << slowestSeconds << " s");
    CHECK(loaded > 250);
}

namespace {

// A Quake 1 model (MDL version 6, "IDPO": one triangle, one frame) with a 2x2 skin of palette
// indices 1, 2 (top row) and 3, 4, and a colormap.lmp beside it: Assimp's MDL importer reads the
// palette from there and hands the skin over as raw texels (an aiTexture with mHeight != 0).
struct QuakeMdl {
    std::string bytes;
    template <typename T> void put(T v) { bytes.append(reinterpret_cast<const char*>(&v), sizeof v); }
};

std::string quakeMdlWithSkin() {
    QuakeMdl m;
    m.bytes = "IDPO";
    m.put<std::int32_t>(6);                                                        // version
    for (float v : {1.0f, 1.0f, 1.0f, 0.0f, 0.0f, 0.0f, 2.0f, 0.0f, 0.0f, 0.0f}) m.put(v);  // scale, origin, radius, eye
    for (std::int32_t v : {1, 2, 2, 3, 1, 1, 0, 0}) m.put(v);   // skins, skin w, h, verts, tris, frames, sync, flags
    m.put(1.0f);                                                                   // size
    m.put<std::int32_t>(0);                                                        // a single skin
    for (unsigned char index : {1, 2, 3, 4}) m.put(index);
    for (std::int32_t v : {0, 0, 0, 0, 1, 0, 0, 0, 1}) m.put(v);                   // texture coordinates
    for (std::int32_t v : {1, 0, 1, 2}) m.put(v);                                  // front-facing triangle 0 1 2
    m.put<std::int32_t>(0);                                                        // a simple frame
    for (unsigned char v : {0, 0, 0, 0, 1, 1, 0, 0}) m.put(v);                     // its bounding box
    m.bytes += std::string("frame").append(11, '\0');
    for (unsigned char v : {0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0}) m.put(v);         // three vertices
    return m.bytes;
}

}  // namespace

TEST_CASE("an embedded texture of raw texels (MDL skins) is read as RGBA, row 0 first", "[mesh]") {
    TempDir dir;
    // The palette: index i is (10 i, 100 + i, 200 + i), so red and blue tell a swap apart.
    std::string palette(768, '\0');
    for (int i = 0; i < 256; ++i) {
        palette[size_t(3 * i)] = char(10 * (i % 25));
        palette[size_t(3 * i + 1)] = char(100 + i % 100);
        palette[size_t(3 * i + 2)] = char(200 + i % 50);
    }
    dir.write("colormap.lmp", palette);
    const std::string path = dir.write("skinned.mdl", quakeMdlWithSkin());
    const MeshImportResult r = importMeshFile(path);
    INFO(r.error);
    REQUIRE(r.ok());
    REQUIRE(r.materials.size() == 1);
    REQUIRE(r.materials[0].baseColorTexture == "*0");
    REQUIRE(r.embedded.size() == 1);
    CHECK(r.embedded[0].raw());
    const FileTextures files{path, &r.embedded, r.materials[0].wrap};
    ImageData image;
    std::string error;
    INFO(error);
    REQUIRE(readTextureImage(ImageReader{}, &files, "*0", &image, &error));
    REQUIRE(image.width == 2);
    REQUIRE(image.height == 2);
    REQUIRE(image.channels == 4);
    for (int i = 0; i < 4; ++i) {
        INFO("texel " << i);
        const int index = i + 1;
        CHECK(image.pixels[size_t(4 * i + 0)] == Approx(10 * index / 255.0));
        CHECK(image.pixels[size_t(4 * i + 1)] == Approx((100 + index) / 255.0));
        CHECK(image.pixels[size_t(4 * i + 2)] == Approx((200 + index) / 255.0));
        CHECK(image.pixels[size_t(4 * i + 3)] == Approx(1.0));
    }
}

TEST_CASE("raw texels that do not match their size are refused by name", "[mesh]") {
    ImageData image;
    std::string error;
    EmbeddedImage e;
    e.width = 2;
    e.height = 2;
    e.bytes = std::string(15, '\x7f');
    CHECK_FALSE(rawTexelImage(e, "m.mdl (embedded image 0)", &image, &error));
    CHECK(error == "m.mdl (embedded image 0): 15 bytes of raw texels for 2x2 (16 expected)");
    e.width = 70000;
    e.bytes.clear();
    CHECK_FALSE(rawTexelImage(e, "m.mdl (embedded image 0)", &image, &error));
    CHECK(error.find("m.mdl (embedded image 0): declares 70000x2 pixels, more than the limit") == 0);
}

TEST_CASE("the MDL models of assimp-testmodels read their embedded skins", "[mesh][testmodels]") {
    INFO("no " << kTestModelsDir << ": run setup.sh (it installs Debian's assimp-testmodels package)");
    REQUIRE(fs::is_directory(kTestModelsDir));
    // The two 3D GameStudio models store their skins as raw texels; the Half-Life one names its
    // embedded texture ("Material2.bmp") instead of "*0".
    for (const char* model : {"MDL/MDL3 (3DGS A4)/minigun.MDL", "MDL/MDL5 (3DGS A5)/minigun_mdl5.mdl",
                              "MDL/MDL (HL1)/man.mdl"}) {
        const std::string path = (fs::path(kTestModelsDir) / model).string();
        INFO(path);
        const MeshImportResult r = importMeshFile(path);
        INFO(r.error);
        REQUIRE(r.ok());
        REQUIRE_FALSE(r.materials.empty());
        const ImportedMaterial& m = r.materials[0];
        REQUIRE(m.baseColorTexture.size() > 1);
        CHECK(m.baseColorTexture[0] == '*');
        const FileTextures files{path, &r.embedded, m.wrap};
        ImageData image;
        std::string error;
        const bool read = readTextureImage(ImageReader{}, &files, m.baseColorTexture, &image, &error);
        INFO(error);
        REQUIRE(read);
        CHECK(image.channels == 4);
        CHECK(image.width > 1);
        CHECK(image.height > 1);
        // A real skin, not one colour.
        CHECK(std::any_of(image.pixels.begin(), image.pixels.end(), [&](float v) { return v != image.pixels[0]; }));
    }
}
