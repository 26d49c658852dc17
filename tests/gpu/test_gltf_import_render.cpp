// The generated glTF test files (tests/gltf/make_test_gltf.py) through import, compile and the
// real integrator: the .glb and its .gltf twin (PNGs in buffer views against data URIs) must
// render the same image, bit for bit (the renderer is deterministic and the two files hold the
// same data), and the material must arrive as a layered surface with its three textures and the
// base colour texture's sampler (clamp in u, mirror in v).
#include "tests/gpu/gl_fixture.h"

#include "renderer/gpu_scene.h"

#include <glad/gl.h>

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

// textureSampleLod (shaders/bsdf/texture.glsl) of texture `index` at each uv, level 0, through the
// test kernel tests/gpu/kernels/bsdf_texture.comp (mode 0).
std::vector<glm::vec4> sampleTexture(Renderer& r, GLuint index, const std::vector<glm::vec4>& uvs) {
    const GLuint p = test::kernel("bsdf_texture.comp");
    GLuint buffers[2];
    glCreateBuffers(2, buffers);
    glNamedBufferData(buffers[0], GLsizeiptr(uvs.size() * sizeof(glm::vec4)), uvs.data(), GL_STATIC_DRAW);
    glNamedBufferData(buffers[1], GLsizeiptr(uvs.size() * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_READ);
    r.bindScene(0, 1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, buffers[0]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEST_OUTPUT, buffers[1]);
    glUseProgram(p);
    glProgramUniform1ui(p, glGetUniformLocation(p, "u_mode"), 0);
    glProgramUniform1ui(p, glGetUniformLocation(p, "u_count"), GLuint(uvs.size()));
    glProgramUniform1ui(p, glGetUniformLocation(p, "u_texture"), index);
    glProgramUniform1f(p, glGetUniformLocation(p, "u_lod"), 0.0f);
    glDispatchCompute(GLuint(uvs.size() + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> out(uvs.size());
    glGetNamedBufferSubData(buffers[1], 0, GLsizeiptr(out.size() * sizeof(glm::vec4)), out.data());
    glDeleteBuffers(2, buffers);
    return out;
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

    // The sampler's wrap modes in the shader: u clamps to the edge texel, v mirrors (period 2).
    std::string why;
    REQUIRE(renderer->setScene(quadScene(data / "quad.glb"), &why));
    const GLuint texture = renderer->compiled().materials[0].textures.x - 1;
    const std::vector<glm::vec4> uv = {{0.875f, 0.375f, 0, 0}, {3.6f, 0.375f, 0, 0}, {0.125f, 0.625f, 0, 0},
                                       {0.125f, 1.375f, 0, 0}, {0.125f, 0.375f, 0, 0}, {0.125f, -0.375f, 0, 0}};
    const std::vector<glm::vec4> v = sampleTexture(*renderer, texture, uv);
    CHECK(glm::length(v[1] - v[0]) < 1e-4f);  // u 3.6 clamps to the last column's centre (u 0.875)
    CHECK(glm::length(v[3] - v[2]) < 1e-4f);  // v 1.375 mirrors to 0.625
    CHECK(glm::length(v[5] - v[4]) < 1e-4f);  // v -0.375 mirrors to 0.375
    CHECK(glm::length(v[2] - v[4]) > 0.3f);   // and those are different checker squares
    REQUIRE(glDebugErrorCount() == 0);
}

TEST_CASE("the CPU texture sampler (picking's alpha masks) agrees with the shader's", "[gpu][gltf][alpha]") {
    // sampleTextureLevel0 (renderer/textures.cpp) against textureSampleLod at level 0, texel for
    // texel: the quad's base colour (u clamped, v mirrored) and the leaf's (repeating), at random
    // uv far outside [0, 1] too, and at texel centres and edges.
    const fs::path data = fs::path(CAUSTIC_SOURCE_DIR) / "tests" / "data" / "gltf";
    auto renderer = test::makeRenderer();
    for (const char* file : {"quad.glb", "leaf.glb"}) {
        INFO(file);
        std::string why;
        REQUIRE(renderer->setScene(quadScene(data / file), &why));
        const CompiledScene& c = renderer->compiled();
        const GLuint texture = c.materials[0].textures.x - 1;
        std::vector<glm::vec4> uv;
        std::uint32_t s = 99u;
        auto random = [&] { s = s * 1664525u + 1013904223u; return float(s >> 8) * 0x1p-24f; };
        for (int i = 0; i < 2000; ++i) uv.emplace_back(6.0f * random() - 3.0f, 6.0f * random() - 3.0f, 0.0f, 0.0f);
        const int w = int(c.textures[texture].info.y), h = int(c.textures[texture].info.z);
        for (int k = -2 * w; k <= 2 * w; ++k) uv.emplace_back(float(k) / float(2 * w), float(k) / float(2 * h), 0.0f, 0.0f);
        const std::vector<glm::vec4> gpu = sampleTexture(*renderer, texture, uv);
        float worst = 0.0f;
        for (size_t i = 0; i < uv.size(); ++i) {
            const glm::vec4 cpu = sampleTextureLevel0(c, texture, glm::vec2(uv[i]));
            for (int k = 0; k < 4; ++k) worst = std::max(worst, std::abs(cpu[k] - gpu[i][k]));
        }
        INFO("largest difference " << worst);
        CHECK(worst < 1e-5f);
    }
}
