#include "tests/gpu/gl_fixture.h"

#include "renderer/program_cache.h"

#include "renderer/scene_io.h"
#include "renderer/shader_loader.h"

#include <catch2/catch.hpp>

#include <cmath>

#include <map>

namespace caustic::test {

HeadlessGlContext& glContext() {
    static std::string error;
    static std::unique_ptr<HeadlessGlContext> context = [] {
        useProgramCache(testConfig().programCache);   // as the programs do (renderer/program_cache.h)
        return HeadlessGlContext::create(true, &error);
    }();
    INFO(error);
    REQUIRE(context != nullptr);
    return *context;
}

IntegratorConfig testConfig() { return IntegratorConfig::fromEnvironment(); }

std::unique_ptr<Renderer> makeRenderer(const IntegratorConfig& config) {
    glContext();
    std::string error;
    auto renderer = Renderer::create(defaultShaderDir(), config, &error);
    INFO(error);
    REQUIRE(renderer != nullptr);
    return renderer;
}

unsigned kernel(const std::string& name) {
    static std::map<std::string, unsigned> programs;
    if (auto it = programs.find(name); it != programs.end()) return it->second;
    glContext();
    ShaderLoader loader(defaultShaderDir());
    ShaderSource src;
    std::string err;
    const bool loaded = loader.load(std::string(CAUSTIC_SOURCE_DIR) + "/tests/gpu/kernels/" + name,
                                   resolveIntegratorConfig(testConfig()).defines(), &src, &err);
    INFO(err);
    REQUIRE(loaded);
    const unsigned program = compileComputeProgram(src, name, &err);
    INFO(err);
    REQUIRE(program != 0);
    programs.emplace(name, program);
    return program;
}

Scene sceneFromFile(const std::string& file, int width, int height) {
    SceneLoadResult loaded = loadScene(std::string(CAUSTIC_SOURCE_DIR "/scenes/") + file);
    INFO(loaded.error);
    REQUIRE(loaded);
    Scene s = *loaded.scene;
    s.render.width = width;
    s.render.height = height;
    return s;
}

Scene cornellBox(int size) { return sceneFromFile("cornell-box.json", size, size); }

bool hasDefine(const ShaderDefines& defines, const char* name) {
    for (const auto& [n, v] : defines)
        if (n == name) return true;
    return false;
}

Scene closedEmittingSphere(glm::vec3 albedo, glm::vec3 emission) {
    Scene s;
    s.render.width = s.render.height = 16;
    s.render.maxDepth = 100;  // truncation a^101: negligible for the albedos the tests use
    s.render.seed = 7;
    s.materials.push_back({"shell", MaterialType::Diffuse, albedo, emission});
    Object sphere;
    sphere.shape = Shape::Sphere;
    sphere.material = "shell";
    sphere.transform.scale = glm::vec3(2.0f);
    s.objects.push_back(sphere);
    s.camera.position = glm::vec3(0.3f, -0.2f, 0.5f);
    s.camera.lookAt = glm::vec3(1.0f, 0.0f, 0.0f);
    s.camera.fovDegrees = 90.0f;
    return s;
}

Film renderFilm(Renderer& renderer, const Scene& scene, int samples) {
    std::string error;
    bool ok = renderer.setScene(scene, &error);
    INFO(error);
    REQUIRE(ok);
    renderer.render(samples);
    REQUIRE(renderer.samplesDone() == samples);
    REQUIRE(glDebugErrorCount() == 0);
    return renderer.readFilm();
}

Object floorQuad(const std::string& material, float halfSize) {
    Object floor;
    floor.name = "floor";
    floor.shape = Shape::Quad;
    floor.material = material;
    floor.transform.rotate = glm::vec3(-90.0f, 0.0f, 0.0f);
    floor.transform.scale = glm::vec3(halfSize);
    return floor;
}

Object sphereAt(const std::string& material, glm::vec3 centre, float radius) {
    Object ball;
    ball.shape = Shape::Sphere;
    ball.material = material;
    ball.transform.translate = centre;
    ball.transform.scale = glm::vec3(radius);
    return ball;
}

ImageStats imageStats(const Film& film) {
    ImageStats s;
    const double n = double(film.mean.size());
    glm::dvec3 var(0.0);
    for (size_t i = 0; i < film.mean.size(); ++i) {
        s.mean += glm::dvec3(film.mean[i]);
        var += glm::dvec3(film.varianceOfMean[i]);
    }
    s.mean /= n;
    s.standardError = glm::sqrt(var) / n;
    return s;
}

void checkSameMean(const Film& a, const Film& b, double k) {
    const ImageStats sa = imageStats(a), sb = imageStats(b);
    for (int c = 0; c < 3; ++c) {
        const double se = std::sqrt(sa.standardError[c] * sa.standardError[c] + sb.standardError[c] * sb.standardError[c]);
        INFO("channel " << c << ": " << sa.mean[c] << " vs " << sb.mean[c] << ", combined standard error " << se);
        CHECK(std::abs(sa.mean[c] - sb.mean[c]) < k * se);
    }
}

namespace {

constexpr int kBlocks = 4;

struct BlockStats { glm::dvec3 mean[kBlocks][kBlocks]; glm::dvec3 var[kBlocks][kBlocks]; };

BlockStats blocks(const Film& f) {
    BlockStats b{};
    const int bs = f.width / kBlocks;
    const double n = double(bs) * bs;
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            const size_t i = f.index(x, y);
            b.mean[y / bs][x / bs] += glm::dvec3(f.mean[i]) / n;
            b.var[y / bs][x / bs] += glm::dvec3(f.varianceOfMean[i]) / (n * n);
        }
    return b;
}

}  // namespace

void checkStrategiesAgree(Renderer& r, const Scene& s, int spp) {
    r.setStrategy(STRATEGY_MIS);
    const Film mis = renderFilm(r, s, spp);
    r.setStrategy(STRATEGY_LIGHT_ONLY);
    const Film light = renderFilm(r, s, spp);
    r.setStrategy(STRATEGY_BSDF_ONLY);
    const Film bsdf = renderFilm(r, s, 4 * spp);
    r.setStrategy(STRATEGY_MIS);
    checkBlocksAgree(mis, light, "MIS vs light sampling");
    checkBlocksAgree(mis, bsdf, "MIS vs BSDF sampling");
}

void checkBlocksAgree(const Film& a, const Film& b, const char* what) {
    const BlockStats sa = blocks(a), sb = blocks(b);
    int disagreements = 0;
    double seSum = 0.0, meanSum = 0.0;
    for (int by = 0; by < kBlocks; ++by)
        for (int bx = 0; bx < kBlocks; ++bx)
            for (int c = 0; c < 3; ++c) {
                const double diff = std::abs(sa.mean[by][bx][c] - sb.mean[by][bx][c]);
                const double se = std::sqrt(sa.var[by][bx][c] + sb.var[by][bx][c]);
                seSum += se;
                meanSum += sa.mean[by][bx][c];
                if (diff > 4.0 * se + 1e-6) {
                    ++disagreements;
                    UNSCOPED_INFO(what << ": block (" << bx << ", " << by << ") channel " << c << ": "
                                       << sa.mean[by][bx][c] << " vs " << sb.mean[by][bx][c] << ", combined se " << se);
                }
            }
    INFO(what << ": mean combined standard error " << seSum / meanSum << " of the mean");
    CHECK(disagreements == 0);
    CHECK(seSum < 0.1 * meanSum);
}

}  // namespace caustic::test
