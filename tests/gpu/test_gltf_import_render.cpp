// The generated glTF test files (tests/gltf/make_test_gltf.py) through import, compile and the
// real integrator: the .glb and its .gltf twin (PNGs in buffer views against data URIs) must
// render the same image, bit for bit (the renderer is deterministic and the two files hold the
// same data), and the material must arrive as a layered surface with its three textures and the
// base colour texture's sampler (clamp in u, mirror in v).
#include "tests/gpu/gl_fixture.h"

#include "renderer/gpu_scene.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>

using namespace caustic;
namespace fs = std::filesystem;

namespace {

Scene quadScene(const fs::path& file) {
    Scene s;
    s.render.width = 24;
    s.render.height = 24;
    s.render.maxDepth = 2;
    s.camera.position = glm::vec3(0, 0, 4);
    s.camera.lookAt = glm::vec3(0);
    s.camera.fovDegrees = 30.0f;
    s.environment.type = EnvironmentType::Sky;
    Object quad;
    quad.shape = Shape::Mesh;
    quad.file = file.string();  // the file's own materials
    s.objects.push_back(quad);
    return s;
}

}  // namespace

TEST_CASE("a .glb and its .gltf twin import and render the same image", "[gpu][materials][mesh][gltf]") {
    const fs::path data = fs::path(CAUSTIC_SOURCE_DIR) / "tests" / "data" / "gltf";
    CompiledScene compiled;
    std::string error;
    REQUIRE(compileScene(quadScene(data / "quad.glb"), ImageReader{}, &compiled, &error));
    INFO(error);
    REQUIRE_FALSE(compiled.materials.empty());
    const gpu::GpuMaterial& m = compiled.materials[0];
    CHECK(m.info.x == MAT_SURFACE);
    CHECK((m.info.y & MAT_FLAG_METAL_TEXTURE) != 0u);
    CHECK(m.textures.x != 0u);
    CHECK(m.textures.y != 0u);
    CHECK(m.textures.z != 0u);
    CHECK(m.params.y == Approx(1.4f));   // KHR_materials_ior
    CHECK(m.emission.w == Approx(0.5f)); // the normal map's scale
    REQUIRE(compiled.textures.size() >= 3);
    const gpu::GpuTexture& base = compiled.textures[m.textures.x - 1];
    CHECK(base.info.y == 4u);
    CHECK(((base.info.w >> 8) & 3u) == TEXTURE_WRAP_CLAMP);
    CHECK(((base.info.w >> 10) & 3u) == TEXTURE_WRAP_MIRROR);

    auto renderer = test::makeRenderer();
    const Film a = test::renderFilm(*renderer, quadScene(data / "quad.glb"), 8);
    const Film b = test::renderFilm(*renderer, quadScene(data / "quad.gltf"), 8);
    REQUIRE(a.mean.size() == b.mean.size());
    double largest = 0.0, lo = 1e30, hi = 0.0;
    for (size_t i = 0; i < a.mean.size(); ++i) {
        largest = std::max(largest, double(glm::length(a.mean[i] - b.mean[i])));
        lo = std::min(lo, double(a.mean[i].r));
        hi = std::max(hi, double(a.mean[i].r));
    }
    INFO("largest difference " << largest << ", red from " << lo << " to " << hi);
    CHECK(largest == 0.0);
    CHECK(hi - lo > 0.2);  // the texture is there: the checker's red and blue squares differ
}
