// Participating media (shaders/integrator/medium.glsl and the medium vertices of path.glsl),
// tested as the surface models are: the Henyey-Greenstein sampling by chi-square, free-flight
// sampling for bias and bounded weights, and whole renders against closed forms and independent
// integrals:
//   - transmittance through an index-matched slab, a sphere and the scene's fog: exp(-sigma_t d);
//   - single scattering in a thin slab under a uniform environment: its closed form (exponential
//     integrals, by quadrature here);
//   - the volumetric white furnace: an albedo-1 medium, chromatic and anisotropic, behind an
//     index-matched boundary and inside glass, under a uniform environment returns it exactly;
//   - with albedo < 1, the light lost matches a random walk written here on the CPU;
//   - MIS, light sampling alone and phase sampling alone agree in fog with boundaries.
#include "tests/gpu/gl_fixture.h"
#include "tests/support/chi2.h"

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

using namespace caustic;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string defineOf(const ShaderDefines& defines, const std::string& name) {
    for (const auto& [k, v] : defines)
        if (k == name) return v;
    return "(absent)";
}

// Runs tests/gpu/kernels/medium.comp (its header says what each mode writes).
struct KernelArgs {
    GLuint mode = 0, count = 0, outputs = 1, rows = 0, cols = 1, sub = 1, seed = 1234;
    float g = 0.0f, tMax = 1.0f;
    glm::vec3 sigmaA{0.0f}, sigmaS{0.0f}, beta{1.0f};
};
std::vector<glm::vec4> runMediumKernel(const KernelArgs& a) {
    static std::unique_ptr<Renderer> renderer = [] {
        auto r = test::makeRenderer();
        Scene s;
        s.render.width = s.render.height = 1;
        std::string error;
        REQUIRE(r->setScene(s, &error));
        return r;
    }();
    static GLuint out = [] {
        GLuint b = 0;
        glCreateBuffers(1, &b);
        return b;
    }();
    const GLuint p = test::kernel("medium.comp");
    const size_t n = size_t(a.count) * a.outputs;
    glNamedBufferData(out, GLsizeiptr(n * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_READ);
    renderer->bindScene(0, 1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEST_OUTPUT, out);
    glUseProgram(p);
    auto u = [&](const char* name) { return glGetUniformLocation(p, name); };
    glProgramUniform1ui(p, u("u_mode"), a.mode);
    glProgramUniform1ui(p, u("u_count"), a.count);
    glProgramUniform1ui(p, u("u_seed"), a.seed);
    glProgramUniform1ui(p, u("u_rows"), a.rows);
    glProgramUniform1ui(p, u("u_cols"), a.cols);
    glProgramUniform1ui(p, u("u_sub"), a.sub);
    glProgramUniform1f(p, u("u_g"), a.g);
    glProgramUniform1f(p, u("u_tMax"), a.tMax);
    glProgramUniform3f(p, u("u_sigmaA"), a.sigmaA.x, a.sigmaA.y, a.sigmaA.z);
    glProgramUniform3f(p, u("u_sigmaS"), a.sigmaS.x, a.sigmaS.y, a.sigmaS.z);
    glProgramUniform3f(p, u("u_beta"), a.beta.x, a.beta.y, a.beta.z);
    glDispatchCompute((a.count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> r(n);
    glGetNamedBufferSubData(out, 0, GLsizeiptr(n * sizeof(glm::vec4)), r.data());
    REQUIRE(glGetError() == GL_NO_ERROR);
    return r;
}

Material volume(const std::string& name, glm::vec3 sigmaA, glm::vec3 sigmaS, float g) {
    Material m;
    m.name = name;
    m.type = MaterialType::Volume;
    m.sigmaA = sigmaA;
    m.sigmaS = sigmaS;
    m.scatterAnisotropy = g;
    return m;
}

// A camera on +z at distance 5 looking at the origin (fov in degrees) under a constant white
// environment, with one object of material `m` at the origin: a unit sphere, or a box with the
// given half extents.
Scene underWhiteSky(const Material& m, Shape shape, glm::vec3 halfExtents, float fov, int size, int maxDepth) {
    Scene s;
    s.render.width = s.render.height = size;
    s.render.maxDepth = maxDepth;
    s.render.seed = 5;
    s.materials.push_back(m);
    Object o;
    o.name = "medium";
    o.shape = shape;
    o.material = m.name;
    o.transform.scale = halfExtents;
    s.objects.push_back(o);
    s.environment.type = EnvironmentType::Constant;
    s.environment.radiance = glm::vec3(1.0f);
    s.camera.position = glm::vec3(0.0f, 0.0f, 5.0f);
    s.camera.lookAt = glm::vec3(0.0f);
    s.camera.fovDegrees = fov;
    return s;
}

// E2(x) = int_0^1 exp(-x / mu) dmu, by the midpoint rule.
double expIntegral2(double x) {
    constexpr int N = 4000;
    double sum = 0.0;
    for (int i = 0; i < N; ++i) {
        const double mu = (i + 0.5) / N;
        sum += std::exp(-x / mu);
    }
    return sum / N;
}

}  // namespace

TEST_CASE("media: Henyey-Greenstein sampling follows its pdf (chi-square), which integrates to 1",
          "[gpu][media][chi2]") {
    constexpr GLuint rows = 64, cols = 8, samples = 1u << 20;
    const float gs[] = {-0.8f, -0.3f, 0.0f, 0.0005f, 0.4f, 0.9f};
    for (float g : gs) {
        INFO("g " << g);
        KernelArgs a;
        a.mode = 0;
        a.count = samples;
        a.outputs = 2;
        a.g = g;
        const std::vector<glm::vec4> s = runMediumKernel(a);
        KernelArgs c;
        c.mode = 1;
        c.count = rows * cols;
        c.rows = rows;
        c.cols = cols;
        c.sub = 64;
        c.g = g;
        const std::vector<glm::vec4> cells = runMediumKernel(c);
        std::vector<double> observed(rows * cols, 0.0), expected(rows * cols, 0.0);
        double integral = 0.0, meanCos = 0.0;
        int pdfMismatch = 0;
        for (GLuint i = 0; i < samples; ++i) {
            const glm::dvec3 w(s[2 * i]);
            REQUIRE(std::abs(glm::length(w) - 1.0) < 1e-4);
            // The pdf returned is the phase function's value there (the sample's weight is 1).
            if (std::abs(s[2 * i].w - s[2 * i + 1].x) > 1e-4 * s[2 * i + 1].x) ++pdfMismatch;
            meanCos += w.z;
            const int row = std::clamp(int(std::acos(std::clamp(w.z, -1.0, 1.0)) / kPi * rows), 0, int(rows) - 1);
            double phi = std::atan2(w.y, w.x);
            if (phi < 0.0) phi += 2.0 * kPi;
            const int col = std::clamp(int(phi / (2.0 * kPi) * cols), 0, int(cols) - 1);
            observed[size_t(row) * cols + size_t(col)] += 1.0;
        }
        for (size_t i = 0; i < cells.size(); ++i) {
            integral += cells[i].x;
            expected[i] = double(cells[i].x) * samples;
        }
        CHECK(pdfMismatch == 0);
        CHECK(integral == Approx(1.0).margin(2e-3));
        // The mean cosine of Henyey-Greenstein is g (its defining property), within 5 standard
        // errors (the variance of the cosine is at most 1).
        meanCos /= samples;
        CHECK(std::abs(meanCos - g) < 5.0 / std::sqrt(double(samples)));
        const test::Chi2Result r = test::chi2Test(observed, expected, rows, cols, 0.01, int(std::size(gs)));
        std::printf("chi2 henyey-greenstein g %+.4f  integral %.5f  mean cos %.4f  chi2 %.1f dof %d p %.3g\n", g,
                    integral, meanCos, r.statistic, r.dof, r.pValue);
        INFO(r.report);
        CHECK(r.passed);
    }
}

TEST_CASE("media: free-flight sampling of a chromatic medium is unbiased and its weights are bounded",
          "[gpu][media]") {
    // Per channel c, with sigma_t = sigma_a + sigma_s and a segment of length T:
    //   E[weight 1{passes}] = exp(-sigma_t T)                       (the transmittance)
    //   E[weight 1{scatters}] = sigma_s / sigma_t (1 - exp(-sigma_t T))
    //   E[weight t 1{scatters}] = sigma_s (1 - exp(-sigma_t T) (1 + sigma_t T)) / sigma_t^2
    // (the integrals of sigma_s exp(-sigma_t t) f(t) over [0, T]); and with channel probabilities
    // p_c = beta_c / sum(beta), no weight exceeds sigma_s,c / (p_c sigma_t,c) (scattering) or
    // 1 / p_c (passing): the one-sample MIS over channels cannot make fireflies.
    constexpr GLuint n = 1u << 20;
    struct Case { glm::vec3 sigmaA, sigmaS, beta; float tMax; };
    const Case cases[] = {
        {{0.1f, 0.5f, 1.0f}, {1.5f, 0.4f, 2.0f}, {1.0f, 0.5f, 0.2f}, 1.3f},
        {{0.0f, 0.0f, 0.0f}, {0.2f, 3.0f, 0.0f}, {0.3f, 0.3f, 0.4f}, 0.7f},   // a channel that never interacts
        {{0.2f, 0.2f, 0.2f}, {0.8f, 0.8f, 0.8f}, {1.0f, 1.0f, 1.0f}, 1e30f},  // grey, unbounded: weight = albedo
    };
    for (const Case& k : cases) {
        INFO("sigma_a " << k.sigmaA.x << " " << k.sigmaA.y << " " << k.sigmaA.z << ", sigma_s " << k.sigmaS.x << " "
                        << k.sigmaS.y << " " << k.sigmaS.z << ", T " << k.tMax);
        KernelArgs a;
        a.mode = 2;
        a.count = n;
        a.outputs = 2;
        a.sigmaA = k.sigmaA;
        a.sigmaS = k.sigmaS;
        a.beta = k.beta;
        a.tMax = k.tMax;
        const std::vector<glm::vec4> r = runMediumKernel(a);
        const glm::dvec3 st = glm::dvec3(k.sigmaA) + glm::dvec3(k.sigmaS), ss(k.sigmaS);
        const glm::dvec3 pc = glm::dvec3(k.beta) / double(k.beta.x + k.beta.y + k.beta.z);
        const double T = k.tMax;
        glm::dvec3 sum[3] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
        glm::dvec3 sq[3] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
        int overBound = 0, badT = 0;
        for (GLuint i = 0; i < n; ++i) {
            const glm::dvec3 w(r[2 * i]);
            const bool scattered = r[2 * i].w > 0.5f;
            const double t = r[2 * i + 1].x;
            if (scattered ? !(t >= 0.0 && t < T) : t != double(k.tMax)) ++badT;
            const glm::dvec3 f[3] = {scattered ? glm::dvec3(0.0) : w, scattered ? w : glm::dvec3(0.0),
                                     scattered ? w * t : glm::dvec3(0.0)};
            for (int j = 0; j < 3; ++j) {
                sum[j] += f[j];
                sq[j] += f[j] * f[j];
            }
            for (int c = 0; c < 3; ++c) {
                const double bound = scattered ? (st[c] > 0.0 ? ss[c] / (pc[c] * st[c]) : 0.0) : 1.0 / pc[c];
                if (w[c] > bound * (1.0 + 1e-4) + 1e-7) ++overBound;
            }
        }
        CHECK(badT == 0);
        CHECK(overBound == 0);
        const bool unbounded = T > 1e20;
        for (int c = 0; c < 3; ++c) {
            const double e = std::exp(-st[c] * T);
            const double expected[3] = {
                e, st[c] > 0.0 ? ss[c] / st[c] * (1.0 - e) : 0.0,
                st[c] > 0.0 ? ss[c] * (1.0 - (unbounded ? 0.0 : e * (1.0 + st[c] * T))) / (st[c] * st[c]) : 0.0};
            for (int j = 0; j < 3; ++j) {
                const double mean = sum[j][c] / n, se = std::sqrt(std::max(0.0, sq[j][c] / n - mean * mean) / n);
                INFO("channel " << c << " moment " << j << ": mean " << mean << " expected " << expected[j] << " se "
                                << se);
                CHECK(std::abs(mean - expected[j]) <= 5.0 * se + 1e-6);
            }
        }
        if (k.sigmaA.x == k.sigmaA.y && k.sigmaS.x == k.sigmaS.y && k.sigmaA.y == k.sigmaA.z &&
            k.sigmaS.y == k.sigmaS.z) {
            // A grey medium: every scattering event weighs exactly the albedo.
            const double albedo = ss.x / st.x;
            for (GLuint i = 0; i < n; ++i)
                if (r[2 * i].w > 0.5f) REQUIRE(std::abs(r[2 * i].x - albedo) < 1e-5);
        }
    }
}

TEST_CASE("media: an index-matched slab, a sphere and the scene's fog transmit exp(-sigma_t d)", "[gpu][media]") {
    // max_depth 0: only emission seen along the camera ray, through the medium, which free-flight
    // sampling estimates without bias as exp(-sigma_t d) (scattered paths end there). An
    // absorbing-only medium draws nothing and is exact per pixel; a scattering one is checked on
    // the image mean within 4 standard errors. The camera sees the constant environment (1)
    // through a slab of thickness 2 h or the unit sphere, in a 1 degree view; or an emitter 8 away
    // through the scene's fog.
    auto renderer = test::makeRenderer();
    const glm::vec3 sigmaA(0.3f, 0.6f, 0.1f), sigmaS(0.5f, 0.2f, 1.4f);
    const glm::dvec3 sigmaT = glm::dvec3(sigmaA) + glm::dvec3(sigmaS);
    SECTION("absorbing only: exact per pixel") {
        const Scene s = underWhiteSky(volume("m", sigmaA, glm::vec3(0.0f), 0.0f), Shape::Box, {4.0f, 4.0f, 0.4f}, 1.0f, 8, 0);
        const Film f = test::renderFilm(*renderer, s, 4);
        CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_MEDIA") == "5u");  // absorbing, boundaries
        const glm::dvec3 expected = glm::exp(-glm::dvec3(sigmaA) * 0.8);
        for (const glm::vec3& p : f.mean)
            for (int c = 0; c < 3; ++c) REQUIRE(std::abs(p[c] - expected[c]) <= 1e-3 * expected[c]);
    }
    SECTION("scattering slab and sphere: the image mean") {
        for (Shape shape : {Shape::Box, Shape::Sphere}) {
            const bool box = shape == Shape::Box;
            const Scene s = underWhiteSky(volume("m", sigmaA, sigmaS, 0.5f), shape,
                                          box ? glm::vec3(4.0f, 4.0f, 0.4f) : glm::vec3(1.0f), 1.0f, 8, 0);
            const test::ImageStats st = test::imageStats(test::renderFilm(*renderer, s, 4096));
            CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_MEDIA") == "7u");
            // The sphere's chords lie in [2 sqrt(1 - b^2), 2], b < 0.062 (as in test_absorption.cpp).
            const double d = box ? 0.8 : 2.0 * std::sqrt(1.0 - 0.031 * 0.031);
            const glm::dvec3 expected = glm::exp(-sigmaT * d);
            for (int c = 0; c < 3; ++c) {
                INFO((box ? "slab" : "sphere") << " channel " << c << ": mean " << st.mean[c] << " expected "
                                               << expected[c] << " se " << st.standardError[c]);
                CHECK(std::abs(st.mean[c] - expected[c]) <= 4.0 * st.standardError[c] + (box ? 1e-4 : 4e-3) * expected[c]);
                CHECK(st.standardError[c] < 0.02 * expected[c]);
            }
        }
    }
    SECTION("the scene's fog") {
        Scene s;
        s.render.width = s.render.height = 8;
        s.render.maxDepth = 0;
        s.materials.push_back({"black", MaterialType::Diffuse, glm::vec3(0.0f), glm::vec3(0.0f)});
        Object emitter;
        emitter.name = "emitter";
        emitter.shape = Shape::Quad;
        emitter.material = "black";
        emitter.emission = glm::vec3(1.0f);
        emitter.twoSided = true;
        emitter.transform.translate = glm::vec3(0.0f, 0.0f, -3.0f);
        emitter.transform.scale = glm::vec3(20.0f);
        s.objects.push_back(emitter);
        s.camera.position = glm::vec3(0.0f, 0.0f, 5.0f);
        s.camera.lookAt = glm::vec3(0.0f);
        s.camera.fovDegrees = 1.0f;
        s.environment.mediumSigmaA = sigmaA * 0.1f;
        s.environment.mediumSigmaS = sigmaS * 0.1f;
        s.environment.mediumAnisotropy = -0.3f;
        const test::ImageStats st = test::imageStats(test::renderFilm(*renderer, s, 4096));
        CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_MEDIA") == "3u");  // absorbing, scattering
        const glm::dvec3 expected = glm::exp(-sigmaT * 0.1 * 8.0);
        for (int c = 0; c < 3; ++c) {
            INFO("channel " << c << ": mean " << st.mean[c] << " expected " << expected[c] << " se " << st.standardError[c]);
            CHECK(std::abs(st.mean[c] - expected[c]) <= 4.0 * st.standardError[c] + 1e-4 * expected[c]);
        }
    }
}

TEST_CASE("media: single scattering in a thin slab under a uniform sky equals its closed form", "[gpu][media]") {
    // An isotropic slab of thickness d (index-matched, wide enough to be infinite: 50 x its
    // thickness on each side, exp(-sigma_t 50) of it left), seen along its normal under radiance 1
    // with max_depth 1 (emission seen directly, and scattered once): at depth s the camera ray
    // keeps exp(-sigma_t s), and the light scattered towards it from every direction is, per
    // hemisphere, 1 / (4 pi) int exp(-sigma_t z / mu) 2 pi dmu = E2(sigma_t z) / 2 with z the
    // distance to that face. So
    //   L = exp(-sigma_t d) + sigma_s int_0^d exp(-sigma_t s) (E2(sigma_t s) + E2(sigma_t (d - s))) / 2 ds.
    // Next event estimation and phase sampling (by MIS) both reach the sky through the boundary.
    const double sigmaS = 2.0, sigmaA = 0.5, d = 0.4, sigmaT = sigmaS + sigmaA;
    double single = 0.0;
    constexpr int N = 800;
    for (int i = 0; i < N; ++i) {
        const double s = (i + 0.5) / N * d;
        single += std::exp(-sigmaT * s) * 0.5 * (expIntegral2(sigmaT * s) + expIntegral2(sigmaT * (d - s)));
    }
    single *= sigmaS * d / N;
    const double expected = std::exp(-sigmaT * d) + single;
    auto renderer = test::makeRenderer();
    const Scene s = underWhiteSky(volume("m", glm::vec3(float(sigmaA)), glm::vec3(float(sigmaS)), 0.0f), Shape::Box,
                                  {float(50.0 * d), float(50.0 * d), float(d / 2.0)}, 1.0f, 8, 1);
    for (std::uint32_t strategy : {STRATEGY_MIS, STRATEGY_LIGHT_ONLY, STRATEGY_BSDF_ONLY}) {
        renderer->setStrategy(strategy);
        const test::ImageStats st = test::imageStats(test::renderFilm(*renderer, s, 2048));
        INFO("strategy " << strategy << ": mean " << st.mean.g << " expected " << expected << " (single scattering "
                         << single << ") se " << st.standardError.g);
        for (int c = 0; c < 3; ++c) CHECK(std::abs(st.mean[c] - expected) <= 4.0 * st.standardError[c] + 1e-4);
        CHECK(st.standardError.g < 0.01 * single);
    }
    renderer->setStrategy(STRATEGY_MIS);
}

TEST_CASE("media: single scattering of point lights in fog equals its integral (equiangular + free flight)",
          "[gpu][media][equiangular]") {
    // The scene's fog, isotropic, two point lights and nothing else, max_depth 1: along a camera ray
    // o + t d the light scattered once towards the camera from a light of intensity I at c is
    //   L = int_0^inf sigma_s exp(-sigma_t t) / (4 pi) I exp(-sigma_t r) / r^2 dt,  r = |o + t d - c|,
    // which with t = delta + D tan(theta) (delta = (c - o) . d, D the light's distance from the line)
    // is sigma_s I / (4 pi D) int exp(-sigma_t (t + r)) dtheta over theta in [atan(-delta / D), pi / 2):
    // a smooth integrand, by the midpoint rule per pixel centre here. Both distance strategies (free
    // flight with next event estimation, and the equiangular sample) and their MIS weights take part.
    const double sigmaS = 0.4, sigmaA = 0.1, sigmaT = sigmaS + sigmaA;
    struct PointLight { glm::dvec3 c; double intensity; };
    const PointLight lights[] = {{{0.6, 0.3, 0.0}, 3.0}, {{-0.2, -0.5, 2.0}, 1.5}};
    Scene s;
    s.render.width = s.render.height = 8;
    s.render.maxDepth = 1;
    s.render.seed = 3;
    for (const PointLight& p : lights) {
        Light l;
        l.name = "point " + std::to_string(s.lights.size());
        l.type = LightType::Point;
        l.position = glm::vec3(p.c);
        l.color = glm::vec3(float(p.intensity));
        s.lights.push_back(l);
    }
    s.camera.position = glm::vec3(0.0f, 0.0f, 5.0f);
    s.camera.lookAt = glm::vec3(0.0f);
    s.camera.fovDegrees = 4.0f;
    s.environment.mediumSigmaA = glm::vec3(float(sigmaA));
    s.environment.mediumSigmaS = glm::vec3(float(sigmaS));
    auto radiance = [&](glm::dvec3 o, glm::dvec3 d) {
        double sum = 0.0;
        for (const PointLight& p : lights) {
            const double delta = glm::dot(p.c - o, d), D = glm::length(p.c - (o + delta * d));
            const double a = std::atan(-delta / D), b = 0.5 * kPi;
            constexpr int N = 20000;
            double integral = 0.0;
            for (int i = 0; i < N; ++i) {
                const double theta = a + (i + 0.5) / N * (b - a);
                const double t = delta + D * std::tan(theta), r = D / std::cos(theta);
                integral += std::exp(-sigmaT * (t + r));
            }
            sum += sigmaS * p.intensity / (4.0 * kPi * D) * integral * (b - a) / N;
        }
        return sum;
    };
    // The pixel centres' rays (square image, fov 4 degrees on both axes).
    const double tanHalf = std::tan(2.0 * kPi / 180.0);
    double expected = 0.0;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const glm::dvec3 d = glm::normalize(glm::dvec3((2.0 * (x + 0.5) / 8 - 1.0) * tanHalf,
                                                           (1.0 - 2.0 * (y + 0.5) / 8) * tanHalf, -1.0));
            expected += radiance(glm::dvec3(0.0, 0.0, 5.0), d) / 64.0;
        }
    auto renderer = test::makeRenderer();
    const test::ImageStats st = test::imageStats(test::renderFilm(*renderer, s, 4096));
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << ": mean " << st.mean[c] << " expected " << expected << " se " << st.standardError[c]);
        CHECK(std::abs(st.mean[c] - expected) <= 4.0 * st.standardError[c] + 2e-4 * expected);
        CHECK(st.standardError[c] < 0.005 * expected);
    }
}

TEST_CASE("media: the volumetric white furnace returns the environment exactly", "[gpu][media][furnace]") {
    // An albedo-1 medium (sigma_a = 0) under radiance 1 everywhere: whatever the path does inside,
    // it leaves with its weight intact, so every pixel's expectation is 1. The coefficients are
    // chromatic (the spectral MIS must keep each channel's weight at 1 on average) and the phase
    // function anisotropic; behind an index-matched boundary, and inside smooth glass (whose
    // interface loses nothing either; rough glass's single-scattering GGX interface does, so it has
    // no furnace of its own here).
    auto renderer = test::makeRenderer();
    const glm::vec3 sigmaS(0.6f, 2.0f, 5.0f);
    Material glass;
    glass.name = "m";
    glass.type = MaterialType::Dielectric;
    glass.ior = 1.33f;
    glass.transmissionDepth = 1.0f;
    glass.transmissionScatter = sigmaS;                       // sigma_s = scatter / depth
    glass.transmissionColor = glm::exp(-sigmaS);              // sigma_t = -ln(colour) / depth = sigma_s
    glass.scatterAnisotropy = -0.4f;
    struct Case { const char* name; Material m; };
    for (const Case& k : {Case{"volume", volume("m", glm::vec3(0.0f), sigmaS, 0.6f)}, Case{"smooth glass", glass}}) {
        Scene s = underWhiteSky(k.m, Shape::Sphere, glm::vec3(1.0f), 30.0f, 16, 1024);
        s.render.russianRoulette = RussianRoulette::Mitsuba;
        const test::ImageStats st = test::imageStats(test::renderFilm(*renderer, s, 512));
        for (int c = 0; c < 3; ++c) {
            INFO(k.name << " channel " << c << ": mean " << st.mean[c] << " se " << st.standardError[c]);
            CHECK(std::abs(st.mean[c] - 1.0) <= 4.0 * st.standardError[c] + 1e-4);
            CHECK(st.standardError[c] < 0.01);
        }
    }
}

TEST_CASE("media: with albedo < 1 the light lost matches a random walk on the CPU", "[gpu][media]") {
    // A unit sphere of grey extinction sigma_t = 2 and albedo (0.8, 0.5, 0.2), g = 0.3, under
    // radiance 1: a path that leaves after N scattering events carries albedo^N, so the image mean
    // is E[albedo^N] over the camera's rays (1 where they miss). The reference walks here: the same
    // pinhole rays (square image, 20 degrees), exponential free flights, Henyey-Greenstein
    // directions by rejection from the uniform sphere (not the shader's inversion).
    const double sigmaT = 2.0, g = 0.3;
    const glm::dvec3 albedo(0.8, 0.5, 0.2);
    const double tanHalf = std::tan(10.0 * kPi / 180.0);
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    auto hgPdfRatio = [&](double mu) { return std::pow((1.0 + g * g - 2.0 * g) / (1.0 + g * g - 2.0 * g * mu), 1.5); };
    constexpr int walks = 400000;
    glm::dvec3 sum(0.0), sq(0.0);
    for (int i = 0; i < walks; ++i) {
        glm::dvec3 o(0.0, 0.0, 5.0);
        glm::dvec3 d = glm::normalize(glm::dvec3((2.0 * U(rng) - 1.0) * tanHalf, (2.0 * U(rng) - 1.0) * tanHalf, -1.0));
        // Entry into the unit sphere.
        const double b = glm::dot(o, d), c = glm::dot(o, o) - 1.0, disc = b * b - c;
        glm::dvec3 value(1.0);
        if (disc > 0.0) {
            glm::dvec3 p = o + (-b - std::sqrt(disc)) * d;
            int n = 0;
            for (;;) {
                const double t = -std::log(1.0 - U(rng)) / sigmaT;
                // Distance to the sphere's boundary from inside.
                const double bb = glm::dot(p, d), cc = glm::dot(p, p) - 1.0;
                const double exit = -bb + std::sqrt(std::max(0.0, bb * bb - cc));
                if (t >= exit) break;
                p += t * d;
                ++n;
                double mu;
                do mu = 2.0 * U(rng) - 1.0;
                while (U(rng) > hgPdfRatio(mu));
                const double phi = 2.0 * kPi * U(rng), s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
                const glm::dvec3 a = std::abs(d.x) > 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
                const glm::dvec3 t1 = glm::normalize(glm::cross(a, d)), t2 = glm::cross(d, t1);
                d = glm::normalize(mu * d + s * (std::cos(phi) * t1 + std::sin(phi) * t2));
                if (n > 2000) break;
            }
            value = glm::pow(albedo, glm::dvec3(n));
        }
        sum += value;
        sq += value * value;
    }
    const glm::dvec3 ref = sum / double(walks);
    const glm::dvec3 refSe = glm::sqrt((sq / double(walks) - ref * ref) / double(walks));
    auto renderer = test::makeRenderer();
    const Scene s = underWhiteSky(volume("m", glm::vec3(albedo * -sigmaT + sigmaT), glm::vec3(albedo * sigmaT), float(g)),
                                  Shape::Sphere, glm::vec3(1.0f), 20.0f, 16, 1024);
    const test::ImageStats st = test::imageStats(test::renderFilm(*renderer, s, 1024));
    for (int c = 0; c < 3; ++c) {
        const double se = std::sqrt(st.standardError[c] * st.standardError[c] + refSe[c] * refSe[c]);
        INFO("channel " << c << ": caustic " << st.mean[c] << " random walk " << ref[c] << " combined se " << se);
        CHECK(std::abs(st.mean[c] - ref[c]) <= 4.0 * se);
        CHECK(1.0 - ref[c] > 20.0 * se);  // the test resolves the loss itself
    }
}

TEST_CASE("media: MIS, light sampling alone and phase sampling alone agree in fog with boundaries",
          "[gpu][media][mis]") {
    // The Cornell box filled with fog (the scene's medium), with a chromatic, forward-scattering
    // sphere of smoke behind an index-matched boundary and a glass sphere with a scattering
    // interior: each strategy estimates the same integral (next event estimation at surface and
    // medium vertices through boundaries, phase and BSDF sampling hitting the light).
    auto renderer = test::makeRenderer();
    Scene s = test::cornellBox(16);
    s.render.maxDepth = 6;
    s.environment.mediumSigmaA = glm::vec3(0.05f);
    s.environment.mediumSigmaS = glm::vec3(0.25f, 0.3f, 0.35f);
    s.environment.mediumAnisotropy = 0.3f;
    s.materials.push_back(volume("smoke", glm::vec3(0.2f, 0.4f, 0.8f), glm::vec3(2.0f, 1.5f, 1.0f), 0.5f));
    Material glass;
    glass.name = "milky glass";
    glass.type = MaterialType::Dielectric;
    glass.ior = 1.5f;
    glass.transmissionDepth = 0.5f;
    glass.transmissionColor = glm::vec3(0.5f, 0.6f, 0.7f);
    glass.transmissionScatter = glm::vec3(0.4f);
    s.materials.push_back(glass);
    s.objects.push_back(test::sphereAt("smoke", glm::vec3(-0.35f, 0.3f, 0.0f), 0.3f));
    s.objects.push_back(test::sphereAt("milky glass", glm::vec3(0.4f, -0.5f, 0.3f), 0.25f));
    test::checkStrategiesAgree(*renderer, s, 512);
    CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_MEDIA") == "7u");
}

namespace {

// Two coloured emitters side by side behind the origin and a dim sky, for refraction to show: a
// wrong IOR anywhere in a glass object in front moves the colours' boundary.
Scene refractionStage() {
    Scene s;
    s.render.width = s.render.height = 32;
    s.render.maxDepth = 32;
    s.render.seed = 9;
    s.materials.push_back({"black", MaterialType::Diffuse, glm::vec3(0.0f), glm::vec3(0.0f)});
    for (int side = 0; side < 2; ++side) {
        Object e;
        e.name = side == 0 ? "left" : "right";
        e.shape = Shape::Quad;
        e.material = "black";
        e.emission = side == 0 ? glm::vec3(2.0f, 0.4f, 0.1f) : glm::vec3(0.1f, 0.5f, 2.0f);
        e.transform.translate = glm::vec3(side == 0 ? -1.5f : 1.5f, 0.3f, -3.0f);
        e.transform.scale = glm::vec3(1.5f, 3.0f, 1.0f);
        s.objects.push_back(e);
    }
    s.environment.type = EnvironmentType::Constant;
    s.environment.radiance = glm::vec3(0.2f);
    s.camera.position = glm::vec3(0.0f, 0.0f, 5.0f);
    s.camera.lookAt = glm::vec3(0.0f);
    s.camera.fovDegrees = 28.0f;
    return s;
}

Material glassMaterial(const std::string& name, float ior, int priority) {
    Material m;
    m.name = name;
    m.type = MaterialType::Dielectric;
    m.ior = ior;
    m.priority = priority;
    return m;
}

}  // namespace

TEST_CASE("media: nested dielectrics by priority equal the scene built with explicit interfaces",
          "[gpu][media][nested]") {
    // Water (1.33) inside a glass ball (1.5). By priority: a glass sphere of radius 1 and a water
    // sphere of radius 0.85 of higher priority, each with its own (absolute) IOR; the integrator
    // takes the water's surface relative to the glass around it. Explicitly: the glass sphere and
    // an inner interface of relative IOR 1.33 / 1.5, no priorities (the relative-IOR model of a
    // scene without nesting). The two must be the same image, block by block.
    auto renderer = test::makeRenderer();
    Scene byPriority = refractionStage();
    byPriority.materials.push_back(glassMaterial("glass", 1.5f, 0));
    byPriority.materials.push_back(glassMaterial("water", 1.33f, 1));
    byPriority.objects.push_back(test::sphereAt("glass", glm::vec3(0.0f), 1.0f));
    byPriority.objects.push_back(test::sphereAt("water", glm::vec3(0.0f), 0.85f));
    Scene explicitInterfaces = refractionStage();
    explicitInterfaces.materials.push_back(glassMaterial("glass", 1.5f, 0));
    explicitInterfaces.materials.push_back(glassMaterial("glass to water", 1.33f / 1.5f, 0));
    explicitInterfaces.objects.push_back(test::sphereAt("glass", glm::vec3(0.0f), 1.0f));
    explicitInterfaces.objects.push_back(test::sphereAt("glass to water", glm::vec3(0.0f), 0.85f));
    const Film a = test::renderFilm(*renderer, byPriority, 256);
    CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_MEDIA") == "8u");  // MEDIA_NESTED
    const Film b = test::renderFilm(*renderer, explicitInterfaces, 256);
    CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_MEDIA") == "0u");
    test::checkSameMean(a, b);
    test::checkBlocksAgree(a, b, "priority vs explicit interfaces");
    // The test's own power: water given the glass's IOR (no inner interface at all) is visibly
    // another image.
    Scene noWater = refractionStage();
    noWater.materials.push_back(glassMaterial("glass", 1.5f, 0));
    noWater.objects.push_back(test::sphereAt("glass", glm::vec3(0.0f), 1.0f));
    const Film c = test::renderFilm(*renderer, noWater, 256);
    int differ = 0;
    for (size_t i = 0; i < a.mean.size(); ++i)
        for (int ch = 0; ch < 3; ++ch)
            if (std::abs(a.mean[i][ch] - c.mean[i][ch]) > 6.0 * std::sqrt(a.varianceOfMean[i][ch] + c.varianceOfMean[i][ch]))
                ++differ;
    INFO(differ << " of " << 3 * a.mean.size() << " pixel channels differ by more than 6 standard errors");
    CHECK(differ > int(a.mean.size()) / 10);
}

TEST_CASE("media: a lower-priority object inside a higher one is not there (false interfaces)",
          "[gpu][media][nested]") {
    // A water sphere of priority 1 inside a glass sphere of priority 2: where both are, the glass
    // is, so the water's surface is a false interface crossed unchanged by rays and shadow rays,
    // and the image is the glass sphere's alone. With a scattering interior in the water, it would
    // scatter only outside the glass: here it lies wholly inside, so nothing scatters either.
    auto renderer = test::makeRenderer();
    Scene glassOnly = refractionStage();
    glassOnly.materials.push_back(glassMaterial("glass", 1.5f, 2));
    glassOnly.objects.push_back(test::sphereAt("glass", glm::vec3(0.0f), 1.0f));
    Scene both = glassOnly;
    Material water = glassMaterial("water", 1.33f, 1);
    water.transmissionDepth = 0.2f;
    water.transmissionColor = glm::vec3(0.2f, 0.5f, 0.9f);
    water.transmissionScatter = glm::vec3(0.3f);
    both.materials.push_back(water);
    both.objects.push_back(test::sphereAt("water", glm::vec3(0.1f, 0.0f, 0.0f), 0.8f));
    const Film a = test::renderFilm(*renderer, glassOnly, 256);
    const Film b = test::renderFilm(*renderer, both, 256);
    CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_MEDIA") == "11u");  // absorbing, scattering, nested
    test::checkSameMean(a, b);
    test::checkBlocksAgree(a, b, "glass vs glass with a lower-priority water inside");
}

TEST_CASE("media: a scene without media compiles them out, specialised or not", "[gpu][media]") {
    auto renderer = test::makeRenderer();
    std::string error;
    Scene s = test::cornellBox(8);
    REQUIRE(renderer->setScene(s, &error));
    CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_MEDIA") == "0u");
    s.environment.mediumSigmaS = glm::vec3(0.1f);
    REQUIRE(renderer->setScene(s, &error));
    CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_MEDIA") == "3u");
}
