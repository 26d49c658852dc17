// Material textures through the real GLSL (bsdf/texture.glsl, bsdf/material.glsl) with generated
// images (the GPU test binary does not link OpenImageIO): sRGB decoding, exact texel values of a
// non-square texture (nothing resized), the mip chain's averages, a flat normal map changing
// nothing (per point and in a render), and uv / tangent derivation on quads and spheres.
#include "renderer/gpu_scene.h"
#include "tests/gpu/gl_fixture.h"

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <cmath>

using namespace caustic;

namespace {

ImageData solid(int w, int h, glm::vec3 c) {
    ImageData img;
    img.width = w;
    img.height = h;
    img.channels = 3;
    for (int i = 0; i < w * h; ++i) img.pixels.insert(img.pixels.end(), {c.r, c.g, c.b});
    return img;
}

// 5 x 3, every texel different (value = (x + 10 y) / 100 in red, its row in green).
ImageData ramp() {
    ImageData img;
    img.width = 5;
    img.height = 3;
    img.channels = 2;  // grey + alpha, to exercise the expansion
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) img.pixels.insert(img.pixels.end(), {float(x + 10 * y) / 100.0f, 0.5f});
    return img;
}

ImageReader generatedReader() {
    return [](const std::string& path, ImageData* out, std::string* error) {
        if (path.find("grey50") != std::string::npos) *out = solid(4, 4, glm::vec3(0.5f));
        else if (path.find("flat") != std::string::npos) *out = solid(8, 8, glm::vec3(0.5f, 0.5f, 1.0f));
        else if (path.find("ramp") != std::string::npos) *out = ramp();
        else { *error = path + ": no such generated image"; return false; }
        return true;
    };
}

GLuint textureKernel() { return test::kernel("bsdf_texture.comp"); }

std::vector<glm::vec4> runKernel(Renderer& r, GLuint mode, const std::vector<glm::vec4>& inputs, GLuint outputs,
                                 GLuint texture = 0, float lod = 0.0f, GLuint prim = 0, GLuint material = 0) {
    GLuint p = textureKernel();
    const GLuint count = GLuint(inputs.size());
    GLuint buffers[2];
    glCreateBuffers(2, buffers);
    glNamedBufferData(buffers[0], GLsizeiptr(inputs.size() * sizeof(glm::vec4)), inputs.data(), GL_STATIC_DRAW);
    glNamedBufferData(buffers[1], GLsizeiptr(count * outputs * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_READ);
    r.bindScene(0, 1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, buffers[0]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEST_OUTPUT, buffers[1]);
    glUseProgram(p);
    glProgramUniform1ui(p, glGetUniformLocation(p, "u_mode"), mode);
    glProgramUniform1ui(p, glGetUniformLocation(p, "u_count"), count);
    glProgramUniform1ui(p, glGetUniformLocation(p, "u_texture"), texture);
    glProgramUniform1f(p, glGetUniformLocation(p, "u_lod"), lod);
    glProgramUniform1ui(p, glGetUniformLocation(p, "u_prim"), prim);
    glProgramUniform1ui(p, glGetUniformLocation(p, "u_material"), material);
    glDispatchCompute((count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> out(size_t(count) * outputs);
    glGetNamedBufferSubData(buffers[1], 0, GLsizeiptr(out.size() * sizeof(glm::vec4)), out.data());
    glDeleteBuffers(2, buffers);
    REQUIRE(glDebugErrorCount() == 0);
    return out;
}

Scene texturedScene() {
    Scene s;
    s.render.width = s.render.height = 1;
    Material a{"albedo", MaterialType::Diffuse, glm::vec3(0.8f), glm::vec3(0.0f)};
    a.albedoTexture = "grey50.png";
    Material r{"ramp", MaterialType::Conductor, glm::vec3(0.8f), glm::vec3(0.0f)};
    r.roughnessTexture = "ramp.png";
    Material n{"flat", MaterialType::Diffuse, glm::vec3(0.8f), glm::vec3(0.0f)};
    n.normalTexture = "flat.png";
    s.materials = {a, r, n};
    Object quad;
    quad.shape = Shape::Quad;
    quad.material = "flat";
    quad.transform.rotate = glm::vec3(-30.0f, 20.0f, 0.0f);
    quad.transform.scale = glm::vec3(2.0f, 0.5f, 1.0f);
    Object sphere;
    sphere.shape = Shape::Sphere;
    sphere.material = "flat";
    sphere.transform.translate = glm::vec3(0.0f, 0.0f, -5.0f);
    sphere.transform.rotate = glm::vec3(10.0f, 50.0f, 0.0f);
    sphere.transform.scale = glm::vec3(1.0f, 2.0f, 0.7f);
    s.objects = {quad, sphere};
    return s;
}

}  // namespace

TEST_CASE("textures: sRGB albedo maps decode to linear, values and mips are exact", "[gpu][bsdf][texture]") {
    auto renderer = test::makeRenderer();
    renderer->setImageReader(generatedReader());
    std::string error;
    REQUIRE(renderer->setScene(texturedScene(), &error));
    const CompiledScene& c = renderer->compiled();
    REQUIRE(c.textures.size() == 3);
    CHECK(c.materials[0].textures.x == 1u);
    CHECK(c.materials[1].textures.z == 2u);
    CHECK(c.materials[1].info.x == MAT_ROUGH_CONDUCTOR);  // a roughness map makes a conductor rough
    CHECK(c.materials[2].textures.y == 3u);

    // sRGB 0.5 is linear 0.2140 (IEC 61966-2-1), at every level and anywhere (repeat wrapping).
    std::vector<glm::vec4> uv = {{0.5f, 0.5f, 0, 0}, {0.1f, 0.9f, 0, 0}, {-3.3f, 7.7f, 0, 0}};
    for (float lod : {0.0f, 0.5f, 1.0f, 5.0f}) {
        for (const glm::vec4& v : runKernel(*renderer, 0, uv, 1, 0, lod)) {
            CHECK(v.r == Approx(0.21404).margin(2e-4));
            CHECK(v.a == Approx(1.0f));
        }
    }

    // The 5 x 3 ramp (linear: a roughness map): texel centres read back exactly (up to halves).
    // Texture v is up: the image's top row (y = 0) is v near 1.
    {
        const gpu::GpuTexture& t = c.textures[1];
        CHECK(t.info.y == 5u);
        CHECK(t.info.z == 3u);
        CHECK(t.info.w == 3u);  // 5x3, 2x1, 1x1
        std::vector<glm::vec4> centres;
        for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 5; ++x) centres.emplace_back((float(x) + 0.5f) / 5.0f, 1.0f - (float(y) + 0.5f) / 3.0f, 0, 0);
        std::vector<glm::vec4> v = runKernel(*renderer, 0, centres, 1, 1, 0.0f);
        for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 5; ++x) {
                INFO("texel " << x << ", " << y);
                CHECK(v[size_t(y * 5 + x)].r == Approx(float(x + 10 * y) / 100.0f).margin(1e-3));
                CHECK(v[size_t(y * 5 + x)].a == Approx(0.5f).margin(1e-3));
            }
        // The last level: 2x2 box filtering, odd sizes dropping their last row / column
        // (5x3 -> 2x1 = (0.055, 0.075) -> 1x1 = 0.065); lods beyond the chain clamp to it.
        std::vector<glm::vec4> top = runKernel(*renderer, 0, {{0.3f, 0.3f, 0, 0}}, 1, 1, 10.0f);
        CHECK(top[0].r == Approx(0.065f).margin(1e-3));
    }
}

TEST_CASE("textures: a flat normal map changes nothing, and uvs and tangents on quads and spheres",
          "[gpu][bsdf][texture]") {
    auto renderer = test::makeRenderer();
    renderer->setImageReader(generatedReader());
    std::string error;
    REQUIRE(renderer->setScene(texturedScene(), &error));
    const CompiledScene& c = renderer->compiled();
    // Points on the quad (from its corner and edges) and on the sphere (object-space points mapped
    // through the object's transform).
    const gpu::GpuPrimitive& q = c.primitives[0];
    std::vector<glm::vec4> quadPoints, spherePoints;
    std::vector<glm::vec2> quadUv;
    for (int i = 0; i < 64; ++i) {
        float a = (float(i % 8) + 0.5f) / 8.0f, b = (float(i / 8) + 0.5f) / 8.0f;
        quadPoints.emplace_back(glm::vec3(q.a) + a * glm::vec3(q.b) + b * glm::vec3(q.c), 0.0f);
        quadUv.emplace_back(a, b);
    }
    const glm::mat4 m = texturedScene().objects[1].transform.toMatrix();
    for (int i = 0; i < 64; ++i) {
        float theta = 0.2f + 2.7f * float(i / 8) / 7.0f, phi = 6.0f * float(i % 8) / 8.0f - 3.0f;
        glm::vec3 po(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
        spherePoints.emplace_back(glm::vec3(m * glm::vec4(po, 1.0f)), 0.0f);
    }
    for (GLuint prim : {0u, 1u}) {
        std::vector<glm::vec4> r = runKernel(*renderer, 1, prim == 0 ? quadPoints : spherePoints, 2, 0, 0.0f, prim, 2);
        for (size_t i = 0; i < r.size() / 2; ++i) {
            INFO("primitive " << prim << " point " << i);
            glm::vec3 ns(r[2 * i]), ng(r[2 * i + 1]);
            CHECK(glm::length(ns - ng) < 1e-3f);
            if (prim == 0) {
                CHECK(r[2 * i].w == Approx(quadUv[i].x).margin(1e-4));
                CHECK(r[2 * i + 1].w == Approx(quadUv[i].y).margin(1e-4));
            }
        }
    }
    // A render of the same scene with and without the flat normal map: the same image.
    Scene lit = texturedScene();
    lit.render.width = lit.render.height = 16;
    lit.camera.position = glm::vec3(0.0f, 0.0f, 4.0f);
    lit.environment.type = EnvironmentType::Sky;
    Scene plain = lit;
    plain.materials[2].normalTexture.clear();
    Film a = test::renderFilm(*renderer, lit, 16);
    Film b = test::renderFilm(*renderer, plain, 16);
    test::ImageStats sa = test::imageStats(a), sb = test::imageStats(b);
    for (int k = 0; k < 3; ++k) CHECK(std::abs(sa.mean[k] - sb.mean[k]) <= 1e-3 * sb.mean[k] + 1e-6);
}
