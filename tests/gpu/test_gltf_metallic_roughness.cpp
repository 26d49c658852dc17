// A glTF file's metallic-roughness texture through import, compile and the real integrator: a
// quad whose texture is smooth (G = 0.2) on its left half and rough (G = 1) on its right, all
// metal (B = 1), under a constant sky. The compiled material must be a layered surface with the
// roughness slot wired to the baked texture (roughness in R, metalness in G: MAT_FLAG_METAL_TEXTURE), and the image must show the two roughnesses: the smooth half reflects
// nearly all the sky (alpha 0.04), the rough half loses the light single-scattering GGX loses at
// alpha 1; the same file without the texture (roughness factor 1 everywhere) shows both halves
// alike.
#include "tests/gpu/gl_fixture.h"

#include "renderer/gpu_scene.h"

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <string>
#include <vector>

using namespace caustic;
namespace fs = std::filesystem;

namespace {

// Writes quad.gltf + quad.bin into dir: the square [-1, 1]^2 at z = 0 facing +z, u = (x + 1) / 2,
// one material (base colour 0.9, metallic 1, roughness 1) with the texture "mr.png" or none.
fs::path writeQuad(const fs::path& dir, bool withTexture) {
    fs::create_directories(dir);
    const float positions[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const float normals[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const float uvs[] = {0, 1, 1, 1, 1, 0, 0, 0};   // glTF: v = 0 at the image's top
    const std::uint16_t indices[] = {0, 1, 2, 0, 2, 3};
    std::ofstream bin(dir / "quad.bin", std::ios::binary);
    bin.write(reinterpret_cast<const char*>(positions), sizeof positions);
    bin.write(reinterpret_cast<const char*>(normals), sizeof normals);
    bin.write(reinterpret_cast<const char*>(uvs), sizeof uvs);
    bin.write(reinterpret_cast<const char*>(indices), sizeof indices);
    bin.close();
    const std::string texture = withTexture ? R"(, "metallicRoughnessTexture": {"index": 0})" : "";
    const std::string images = withTexture ? R"("textures": [{"source": 0}], "images": [{"uri": "mr.png"}],)" : "";
    std::ofstream gltf(dir / "quad.gltf");
    gltf << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
  "materials": [{"name": "brushed", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1],
                 "metallicFactor": 1, "roughnessFactor": 1)" << texture << R"(}}],
  )" << images << R"(
  "buffers": [{"uri": "quad.bin", "byteLength": 140}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                  {"buffer": 0, "byteOffset": 96, "byteLength": 32}, {"buffer": 0, "byteOffset": 128, "byteLength": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}]})";
    return dir / "quad.gltf";
}

// mr.png, generated: R (occlusion) 0, G = 0.2 on the left half, 1 on the right, B = 1.
ImageReader generatedReader() {
    return [](const std::string& path, ImageData* out, std::string* error) {
        if (fs::path(path).filename() != "mr.png") {
            *error = path + ": no such generated image";
            return false;
        }
        out->width = 16;
        out->height = 4;
        out->channels = 3;
        out->pixels.clear();
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 16; ++x) out->pixels.insert(out->pixels.end(), {0.0f, x < 8 ? 0.2f : 1.0f, 1.0f});
        return true;
    };
}

Scene quadScene(const fs::path& file) {
    Scene s;
    s.render.width = 32;
    s.render.height = 16;
    s.render.maxDepth = 1;
    s.camera.position = glm::vec3(0, 0, 4);
    s.camera.lookAt = glm::vec3(0);
    s.camera.fovAxis = FovAxis::X;
    s.camera.fovDegrees = 20.0f;   // sees x in [-0.7, 0.7]: the quad fills the image
    s.environment.type = EnvironmentType::Constant;
    Object quad;
    quad.shape = Shape::Mesh;
    quad.file = file.string();     // no material: the file's own
    s.objects.push_back(quad);
    return s;
}

// Mean green value of the film's columns [x0, x1).
double columnsMean(const Film& film, int x0, int x1) {
    double sum = 0.0;
    int n = 0;
    for (int y = 0; y < film.height; ++y)
        for (int x = x0; x < x1; ++x, ++n) sum += film.mean[film.index(x, y)].g;
    return sum / n;
}

}  // namespace

TEST_CASE("a glTF metallic-roughness texture drives the imported material's roughness", "[gpu][materials][mesh]") {
    const fs::path dir = fs::temp_directory_path() / ("caustic-gltf-mr-" + std::to_string(::getpid()));
    const fs::path textured = writeQuad(dir / "textured", true);
    const fs::path constant = writeQuad(dir / "constant", false);

    // Compiled: the file's material (Assimp may add a default one after it) is a surface with its
    // roughness slot wired to the baked metallic-roughness texture, and no albedo or normal map.
    CompiledScene compiled;
    std::string error;
    REQUIRE(compileScene(quadScene(textured), generatedReader(), &compiled, &error));
    INFO(error);
    REQUIRE_FALSE(compiled.materials.empty());
    CHECK(compiled.materials[0].info.x == MAT_SURFACE);
    CHECK((compiled.materials[0].info.y & MAT_FLAG_METAL_TEXTURE) != 0u);
    CHECK(compiled.materials[0].textures.z != 0u);
    CHECK(compiled.materials[0].textures.x == 0u);
    CHECK(compiled.materials[0].textures.y == 0u);
    REQUIRE(compiled.textures.size() == 1);
    CHECK(compiled.textures[0].info.y == 16u);   // the texture's own size
    CompiledScene plain;
    REQUIRE(compileScene(quadScene(constant), generatedReader(), &plain, &error));
    REQUIRE_FALSE(plain.materials.empty());
    CHECK(plain.materials[0].info.x == MAT_SURFACE);
    CHECK(plain.materials[0].albedo.w == 1.0f);  // metalness 1 from the factor
    CHECK(plain.materials[0].textures.z == 0u);
    CHECK(plain.textures.empty());

    auto renderer = test::makeRenderer();
    renderer->setImageReader(generatedReader());
    const Film a = test::renderFilm(*renderer, quadScene(textured), 64);
    const Film b = test::renderFilm(*renderer, quadScene(constant), 64);
    // Columns 0-11 see u < 0.44 and 20-31 u > 0.56 (the camera sees x in [-0.7, 0.7]).
    const double smooth = columnsMean(a, 0, 12), rough = columnsMean(a, 20, 32);
    const double plainLeft = columnsMean(b, 0, 12), plainRight = columnsMean(b, 20, 32);
    INFO("textured: left " << smooth << " right " << rough << "; constant: left " << plainLeft << " right " << plainRight);
    // Alpha 0.04 at normal view loses under 1% (the furnace table of docs/materials.md): the
    // metal's F0 of 0.9 (F82-tint Fresnel, white tint: Schlick's). Alpha 1 keeps 1 - ln 2 = 0.3069
    // of F = 1 at normal incidence, so about 0.9 x 0.3069 = 0.276 (the camera's rays are within
    // 10 degrees of the normal).
    CHECK(smooth == Approx(0.9).epsilon(0.03));
    CHECK(rough == Approx(0.9 * 0.3069).epsilon(0.04));
    CHECK(rough == Approx(plainRight).epsilon(0.05));   // the texture's G = 1 is the factor's roughness
    CHECK(plainLeft == Approx(plainRight).epsilon(0.05));
    CHECK(smooth > 1.5 * plainLeft);                     // and the texture is what changed the left half
    fs::remove_all(dir);
}
