// Light selection by the light tree (shaders/lights/light_select.glsl, renderer/light_tree.h),
// through a test kernel on the real shader code: at any shading point selectLight chooses each
// light as often as its pmf says (chi-square), the pmf it returns is the one lightSelectPmf
// recomputes for MIS, and the pmfs sum to 1 less the probability of choosing none. That happens
// when the walk reaches a node whose children both have zero importance (their bounds lie below
// the receiver's horizon or behind their emitters) although the node's own looser bounds did not:
// a wasted sample, never a bias, since every light that can light the point has a non-zero pmf
// (checked for sphere and point lights against their exact geometry). With every light above the
// horizon the pmfs sum to exactly 1. Then the point of it: with many small lights the tree's
// estimate is far less noisy than uniform selection's, with the same mean.
#include "tests/gpu/gl_fixture.h"
#include "tests/support/chi2.h"
#include "tests/support/meshes.h"

#include <glad/gl.h>
#include <glm/gtc/type_ptr.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

using namespace caustic;

namespace {

// A scene with lights of every kind: sphere, one- and two-sided rect, point and spot lights in
// random places, an emissive box and an emissive mesh, and (optionally) a constant environment.
Scene manyLights(int spheres, bool environment, test::TempDir& dir) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    auto in = [&](float a, float b) { return a + (b - a) * u(rng); };
    Scene s;
    s.render.width = s.render.height = 16;
    s.materials.push_back({"grey", MaterialType::Diffuse, glm::vec3(0.5f), glm::vec3(0.0f)});
    s.materials.push_back({"glow", MaterialType::Diffuse, glm::vec3(0.2f), glm::vec3(2.0f, 1.0f, 0.5f)});
    for (int i = 0; i < spheres; ++i) {
        Light l;
        l.type = LightType::Sphere;
        l.position = glm::vec3(in(-3, 3), in(0.5f, 3), in(-3, 3));
        l.radius = in(0.01f, 0.1f);
        l.color = glm::vec3(in(1, 50), in(1, 50), in(1, 50));
        s.lights.push_back(l);
    }
    for (int i = 0; i < 12; ++i) {
        Light l;
        l.type = LightType::Rect;
        l.twoSided = i % 3 == 0;
        l.transform.translate = glm::vec3(in(-3, 3), in(0.5f, 3), in(-3, 3));
        l.transform.rotate = glm::vec3(in(0, 360), in(0, 360), 0.0f);
        l.transform.scale = glm::vec3(in(0.05f, 0.3f), in(0.05f, 0.3f), 1.0f);
        l.color = glm::vec3(in(1, 10));
        s.lights.push_back(l);
    }
    for (int i = 0; i < 8; ++i) {
        Light l;
        l.type = i % 2 ? LightType::Spot : LightType::Point;
        l.position = glm::vec3(in(-3, 3), in(0.5f, 3), in(-3, 3));
        l.direction = glm::vec3(in(-1, 1), -1.0f, in(-1, 1));
        l.color = glm::vec3(in(0.5f, 5));
        s.lights.push_back(l);
    }
    Object box;
    box.shape = Shape::Box;
    box.material = "glow";
    box.transform.translate = glm::vec3(1.5f, 0.3f, -1.0f);
    box.transform.scale = glm::vec3(0.2f);
    s.objects.push_back(box);
    test::writeObjTorus(dir.file("torus.obj"), 1.0, 0.35, 16, 8);
    Object torus;
    torus.shape = Shape::Mesh;
    torus.file = dir.file("torus.obj");
    torus.material = "glow";
    torus.transform.translate = glm::vec3(-1.5f, 1.0f, 1.0f);
    torus.transform.scale = glm::vec3(0.3f);
    s.objects.push_back(torus);
    if (environment) {
        s.environment.type = EnvironmentType::Constant;
        s.environment.radiance = glm::vec3(0.3f);
    }
    return s;
}

std::vector<glm::vec4> runKernel(Renderer& r, unsigned mode, unsigned count, glm::vec3 p, glm::vec3 n, bool twoSided) {
    const GLuint program = test::kernel("light_select.comp");
    GLuint out = 0;
    glCreateBuffers(1, &out);
    glNamedBufferData(out, GLsizeiptr(count * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_READ);
    r.bindScene(0, 1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEST_OUTPUT, out);
    glUseProgram(program);
    glProgramUniform1ui(program, glGetUniformLocation(program, "u_mode"), mode);
    glProgramUniform1ui(program, glGetUniformLocation(program, "u_count"), count);
    glProgramUniform1ui(program, glGetUniformLocation(program, "u_twoSided"), twoSided ? 1u : 0u);
    glProgramUniform3fv(program, glGetUniformLocation(program, "u_point"), 1, glm::value_ptr(p));
    glProgramUniform3fv(program, glGetUniformLocation(program, "u_normal"), 1, glm::value_ptr(n));
    glDispatchCompute((count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> res(count);
    glGetNamedBufferSubData(out, 0, GLsizeiptr(count * sizeof(glm::vec4)), res.data());
    glDeleteBuffers(1, &out);
    REQUIRE(glDebugErrorCount() == 0);
    return res;
}

}  // namespace

TEST_CASE("light tree: the selection pmf sums to 1 and matches how often each light is chosen", "[gpu][lights][tree]") {
    auto renderer = test::makeRenderer();
    test::TempDir dir;
    struct Receiver { glm::vec3 p, n; bool twoSided; };
    const Receiver receivers[] = {
        {{0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, false},       // on the floor, facing up
        {{0.5f, 1.5f, -0.5f}, glm::normalize(glm::vec3(1, -0.3f, 0.2f)), false},  // among the lights
        {{-2.0f, 2.0f, 2.0f}, {0.0f, 0.0f, 1.0f}, true},       // a transmitting receiver
        {{8.0f, 1.0f, 0.0f}, {-1.0f, 0.0f, 0.0f}, false},      // outside the lights' bounds
        {{0.0f, -1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, false},      // every light above the horizon
    };
    for (bool env : {false, true}) {
        Scene s = manyLights(200, env, dir);
        std::string error;
        REQUIRE(renderer->setScene(s, &error));
        const unsigned lights = unsigned(renderer->compiled().lights.size());
        REQUIRE(lights > 200);
        for (const Receiver& rc : receivers) {
            INFO("environment " << env << ", receiver at (" << rc.p.x << ", " << rc.p.y << ", " << rc.p.z << ")");
            const std::vector<glm::vec4> pmf = runKernel(*renderer, 0, lights, rc.p, rc.n, rc.twoSided);
            double sum = 0;
            int nonZero = 0, missing = 0;
            // The compiled lights: the emissive objects' first, then the scene's lights, then the
            // environment.
            const unsigned first = lights - unsigned(s.lights.size()) - (env ? 1u : 0u);
            for (unsigned i = 0; i < lights; ++i) {
                sum += pmf[i].x;
                nonZero += pmf[i].x > 0.0f;
                // A sphere or point light with any part above the receiver's horizon (or any
                // part at all, for a transmitting receiver) must be possible to choose.
                if (i < first || i >= first + s.lights.size() || pmf[i].x > 0.0f) continue;
                const Light& l = s.lights[i - first];
                if (l.type == LightType::Sphere || l.type == LightType::Point) {
                    const float r = l.type == LightType::Sphere ? l.radius : 0.0f;
                    if (rc.twoSided || glm::dot(rc.n, l.position - rc.p) > -r) ++missing;
                }
            }
            CHECK(sum <= 1.0 + 1e-4);
            if (rc.p.y < 0.0f) CHECK(sum == Approx(1.0).epsilon(1e-4));
            CHECK(missing == 0);
            CHECK(nonZero > 20);  // the tree does not give every sample to a few lights
            constexpr unsigned kSamples = 1u << 20;
            const std::vector<glm::vec4> picks = runKernel(*renderer, 1, kSamples, rc.p, rc.n, rc.twoSided);
            std::vector<double> observed(lights, 0.0), expected(lights, 0.0);
            int none = 0, mismatches = 0;
            for (const glm::vec4& r : picks) {
                if (r.x < 0.0f) { ++none; continue; }
                const auto li = static_cast<unsigned>(r.x);
                REQUIRE(li < lights);
                observed[li] += 1.0;
                if (std::abs(r.y - r.z) > 1e-5f * r.z || std::abs(r.y - pmf[li].x) > 1e-5f * pmf[li].x) ++mismatches;
            }
            CHECK(mismatches == 0);
            for (unsigned i = 0; i < lights; ++i) expected[i] = pmf[i].x * kSamples;
            observed.push_back(double(none));  // the last cell: no light chosen
            expected.push_back(std::max(0.0, 1.0 - sum) * kSamples);
            const test::Chi2Result chi = test::chi2Test(observed, expected, 1, int(lights) + 1, 0.01, 8);
            INFO(chi.report);
            CHECK(chi.passed);
        }
    }
}

TEST_CASE("light tree: with many small lights, far less noise than uniform selection, the same mean", "[gpu][lights][tree]") {
    auto renderer = test::makeRenderer();
    // A floor under a 12 x 12 grid of point lights of very different strengths (point lights: the
    // camera does not see them, so the variance is the light selection's alone).
    Scene s;
    s.render.width = s.render.height = 24;
    s.render.maxDepth = 1;
    s.render.seed = 5;
    s.materials.push_back({"grey", MaterialType::Diffuse, glm::vec3(0.5f), glm::vec3(0.0f)});
    s.objects.push_back(test::floorQuad("grey", 3.0f));
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j) {
            Light l;
            l.type = LightType::Point;
            l.position = glm::vec3(-3.0f + 6.0f * (float(i) + 0.5f) / 12, 0.3f + 0.3f * u(rng),
                                   -3.0f + 6.0f * (float(j) + 0.5f) / 12);
            l.color = glm::vec3(u(rng) < 0.2f ? 4.0f : 0.2f);
            s.lights.push_back(l);
        }
    s.camera.position = glm::vec3(0.0f, 4.0f, 4.0f);
    s.camera.lookAt = glm::vec3(0.0f);
    s.camera.fovDegrees = 50.0f;
    Film tree = test::renderFilm(*renderer, s, 64);
    s.render.lightSelection = LightSelection::Uniform;
    Film uniform = test::renderFilm(*renderer, s, 64);
    double varTree = 0, varUniform = 0;
    for (size_t i = 0; i < tree.mean.size(); ++i) {
        varTree += glm::dot(glm::dvec3(tree.varianceOfMean[i]), glm::dvec3(1.0));
        varUniform += glm::dot(glm::dvec3(uniform.varianceOfMean[i]), glm::dvec3(1.0));
    }
    test::checkSameMean(tree, uniform);
    INFO("summed pixel variance: tree " << varTree << ", uniform " << varUniform);
    CHECK(varTree < 0.2 * varUniform);
}
