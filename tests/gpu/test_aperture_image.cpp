// The camera's aperture image (integrator/aperture.glsl, renderer/gpu_scene.h ApertureImage):
//   - the thin lens's sampler draws points in proportion to the image's texels: a chi-square test
//     against the image over 16 x 12 cells, and no sample on a texel of zero;
//   - a lens system's stop passes each ray in the image's proportion: the shader's rays and
//     weights equal the CPU's (renderer/lens.h), and the exposure at the film's centre stays 1;
//   - an image that cannot be read, or is black, fails the scene naming camera.aperture_image.
#include "tests/gpu/gl_fixture.h"
#include "tests/support/chi2.h"

#include "renderer/lens.h"

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

using namespace caustic;

namespace {

constexpr int kW = 64, kH = 48;

// An asymmetric mask: a ramp from left to right inside an off-centre disc, a hole in it, and a
// few empty rows.
float maskAt(int x, int y) {
    const double fx = 2.0 * (x + 0.5) / kW - 1.0, fy = 1.0 - 2.0 * (y + 0.5) / kH;
    if (std::hypot(fx - 0.1, fy + 0.05) > 0.85) return 0.0f;
    if (std::hypot(fx + 0.3, fy - 0.3) < 0.2) return 0.0f;
    if (y >= 20 && y < 23) return 0.0f;
    return float(0.1 + 0.9 * (x + 0.5) / kW);
}

ImageReader maskReader() {
    return [](const std::string& path, ImageData* out, std::string* error) {
        if (path.find("mask") != std::string::npos) {
            out->width = kW;
            out->height = kH;
            out->channels = 1;
            out->pixels.resize(std::size_t(kW * kH));
            for (int y = 0; y < kH; ++y)
                for (int x = 0; x < kW; ++x) out->pixels[std::size_t(y * kW + x)] = maskAt(x, y);
            return true;
        }
        if (path.find("black") != std::string::npos) {
            out->width = out->height = 4;
            out->channels = 3;
            out->pixels.assign(48, 0.0f);
            return true;
        }
        *error = path + ": no such generated image";
        return false;
    };
}

Scene apertureScene(const std::string& image, const std::string& lens = "") {
    Scene s;
    s.render.width = 32;
    s.render.height = 32;
    s.materials.push_back({"grey", MaterialType::Diffuse, glm::vec3(0.5f), glm::vec3(0.0f)});
    s.objects.push_back(test::sphereAt("grey", glm::vec3(0.0f), 0.5f));
    s.camera.position = glm::vec3(0.0f, 0.0f, 3.0f);
    s.camera.apertureImage = image;
    if (lens.empty()) s.camera.apertureRadius = 0.1f;
    else s.camera.lens = lens;
    return s;
}

std::vector<glm::vec4> runKernel(Renderer& r, const char* kernel, const std::vector<glm::vec4>& inputs, std::size_t perInput) {
    GLuint buffers[2];
    glCreateBuffers(2, buffers);
    glNamedBufferData(buffers[0], GLsizeiptr(inputs.size() * sizeof(glm::vec4)), inputs.data(), GL_STATIC_DRAW);
    const std::size_t n = inputs.size() / perInput;
    glNamedBufferData(buffers[1], GLsizeiptr(n * perInput * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_READ);
    const GLuint program = test::kernel(kernel);
    r.bindScene(0, 1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, buffers[0]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEST_OUTPUT, buffers[1]);
    glUseProgram(program);
    glProgramUniform1ui(program, glGetUniformLocation(program, "u_count"), GLuint(n));
    glDispatchCompute(GLuint((n + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> out(n * perInput);
    glGetNamedBufferSubData(buffers[1], 0, GLsizeiptr(out.size() * sizeof(glm::vec4)), out.data());
    glDeleteBuffers(2, buffers);
    REQUIRE(glDebugErrorCount() == 0);
    return out;
}

}  // namespace

TEST_CASE("aperture image: the thin lens draws its samples in proportion to the image (chi-square)",
          "[gpu][camera][aperture]") {
    auto renderer = test::makeRenderer();
    renderer->setImageReader(maskReader());
    std::string error;
    REQUIRE(renderer->setScene(apertureScene("mask.png"), &error));
    REQUIRE(renderer->compiled().aperture.width == kW);
    constexpr int n = 200000;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    std::vector<glm::vec4> inputs(n);
    for (glm::vec4& u : inputs) u = glm::vec4(uniform(rng), uniform(rng), 0.0f, 0.0f);
    const std::vector<glm::vec4> points = runKernel(*renderer, "aperture_samples.comp", inputs, 1);
    constexpr int cellsX = 16, cellsY = 12;
    std::vector<double> observed(cellsX * cellsY, 0.0), expected(cellsX * cellsY, 0.0);
    double total = 0.0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            expected[std::size_t((y * cellsY / kH) * cellsX + x * cellsX / kW)] += maskAt(x, y);
            total += maskAt(x, y);
        }
    for (double& e : expected) e *= n / total;
    int onZero = 0, outside = 0, lookups = 0;
    for (const glm::vec4& p : points) {
        if (std::abs(p.x) > 1.0f || std::abs(p.y) > 1.0f) {
            ++outside;
            continue;
        }
        const int x = std::min(int((p.x * 0.5f + 0.5f) * kW), kW - 1), y = std::min(int((0.5f - p.y * 0.5f) * kH), kH - 1);
        onZero += maskAt(x, y) == 0.0f;
        lookups += std::abs(p.z - maskAt(x, y)) > 1e-6f;   // the lookup finds the texel it came from
        observed[std::size_t((y * cellsY / kH) * cellsX + x * cellsX / kW)] += 1.0;
    }
    CHECK(outside == 0);
    CHECK(onZero == 0);
    CHECK(lookups <= 4);   // a point on a texel's edge may round to its neighbour
    const test::Chi2Result r = test::chi2Test(observed, expected, cellsY, cellsX, 0.01, 1);
    INFO(r.report);
    CHECK(r.passed);
}

TEST_CASE("aperture image: a lens system's stop passes rays in the image's proportion, on the GPU as on the CPU",
          "[gpu][camera][aperture][lens]") {
    auto renderer = test::makeRenderer();
    renderer->setImageReader(maskReader());
    std::string error;
    REQUIRE(renderer->setScene(apertureScene("mask.png", std::string(CAUSTIC_SOURCE_DIR) + "/assets/lenses/dgauss-50mm.lens"), &error));
    const LensCamera* cam = renderer->lensCamera();
    REQUIRE(cam != nullptr);
    REQUIRE(cam->aperture.width == kW);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::vector<glm::vec4> inputs;
    std::vector<glm::dvec2> films, us;
    for (int i = 0; i < 4000; ++i) {
        const glm::dvec2 film(cam->filmHalfWidth * (2.0 * uniform(rng) - 1.0), cam->filmHalfHeight * (2.0 * uniform(rng) - 1.0));
        const glm::dvec2 u(uniform(rng), uniform(rng));
        films.push_back(glm::dvec2(glm::vec2(film)));
        us.push_back(glm::dvec2(glm::vec2(u)));
        inputs.push_back(glm::vec4(glm::vec2(film), glm::vec2(u)));
        inputs.push_back(glm::vec4(1.0f, 0.0f, 0.0f, 0.0f));
    }
    const std::vector<glm::vec4> out = runKernel(*renderer, "lens_rays.comp", inputs, 2);
    int verdicts = 0, far = 0, passed = 0;
    std::vector<double> weights;
    for (std::size_t i = 0; i < films.size(); ++i) {
        double w = 0.0;
        const auto cpu = lensCameraRay(*cam, films[i], us[i], 1, &w);
        const bool gpuPasses = out[2 * i + 1].w > 0.5f;
        if (cpu.has_value() != gpuPasses) {
            ++verdicts;
            continue;
        }
        if (!cpu) continue;
        ++passed;
        far += std::abs(w - out[2 * i].w) > 1e-4 * w;
    }
    CHECK(passed > 500);
    CHECK(verdicts <= 4);   // rays at a texel's or an aperture's edge
    CHECK(far <= 4);
    // The exposure at the film's centre is still 1: the image's transmission is normalised out.
    double sum = 0.0;
    for (int j = 0; j < 128; ++j)
        for (int i = 0; i < 128; ++i) {
            double w = 0.0;
            lensCameraRay(*cam, glm::dvec2(0.0), glm::dvec2((i + 0.5) / 128.0, (j + 0.5) / 128.0), -1, &w);
            sum += w;
        }
    CHECK(sum / (128.0 * 128.0) == Approx(1.0).epsilon(0.02));
}

TEST_CASE("aperture image: an image that cannot be read, or is black, fails the scene naming camera.aperture_image",
          "[gpu][camera][aperture]") {
    auto renderer = test::makeRenderer();
    renderer->setImageReader(maskReader());
    std::string error;
    CHECK_FALSE(renderer->setScene(apertureScene("none.png"), &error));
    CHECK(error == "camera.aperture_image: none.png: no such generated image");
    CHECK_FALSE(renderer->setScene(apertureScene("black.png"), &error));
    CHECK(error == "camera.aperture_image: black.png: the image is black everywhere: no light would pass the aperture");
    CHECK_FALSE(renderer->setScene(apertureScene("black.png", std::string(CAUSTIC_SOURCE_DIR) + "/assets/lenses/dgauss-50mm.lens"), &error));
    CHECK(error.find("camera.aperture_image: black.png: the image is black") == 0);
}
