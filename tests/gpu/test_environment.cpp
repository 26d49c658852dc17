// The environment map light through the real GLSL: its sampler against its pdf (chi-square over
// the map's texels, the directions binned back into texels by an independent CPU mapping that
// also undoes the rotation), the mean of 1/pdf against the solid angle of the map's non-black
// part, a furnace with a constant map, and MIS consistency with a sun-like hot spot.
#include "tests/gpu/gl_fixture.h"
#include "tests/support/chi2.h"

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <cmath>

using namespace caustic;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kW = 32, kH = 16;

// A sky: a gradient, a small very bright sun, and black below v = 0.75 (a "ground" that must get
// no samples: the bilinear filter extends the support by half a texel row).
ImageData generatedSky(bool constant) {
    ImageData img;
    img.width = kW;
    img.height = kH;
    img.channels = 3;
    img.pixels.resize(size_t(kW) * kH * 3);
    for (int j = 0; j < kH; ++j)
        for (int i = 0; i < kW; ++i) {
            float* p = &img.pixels[(size_t(j) * kW + i) * 3];
            float v = (float(j) + 0.5f) / float(kH);
            glm::vec3 c = constant ? glm::vec3(1.0f) : glm::vec3(0.2f + 0.5f * v, 0.3f + 0.4f * v, 0.6f);
            if (!constant && (i == 9 || i == 10) && j == 4) c = glm::vec3(400.0f, 380.0f, 300.0f);
            if (!constant && j >= 12) c = glm::vec3(0.0f);
            p[0] = c.r; p[1] = c.g; p[2] = c.b;
        }
    return img;
}

// A 40 x 15 map (sampling tables of 160 x 60 cells: neither a power of two) with black runs in
// both directions: the lower rows and a band of columns, so that some CDF entries repeat.
ImageData oddSky() {
    ImageData img;
    img.width = 40;
    img.height = 15;
    img.channels = 3;
    img.pixels.resize(size_t(img.width) * img.height * 3);
    for (int j = 0; j < img.height; ++j)
        for (int i = 0; i < img.width; ++i) {
            float* p = &img.pixels[(size_t(j) * img.width + i) * 3];
            const bool black = j >= 11 || (i >= 14 && i < 22);
            const float v = black ? 0.0f : (i == 30 && j == 3 ? 500.0f : 0.1f + 0.05f * float((i * 7 + j * 3) % 11));
            p[0] = p[1] = p[2] = v;
        }
    return img;
}

ImageReader generatedReader() {
    return [](const std::string& path, ImageData* out, std::string* error) {
        if (path.find("odd") != std::string::npos) *out = oddSky();
        else if (path.find("constant") != std::string::npos) *out = generatedSky(true);
        else if (path.find("sky") != std::string::npos) *out = generatedSky(false);
        else { *error = path + ": no such generated image"; return false; }
        return true;
    };
}

Scene envScene(const std::string& file, float rotation) {
    Scene s;
    s.render.width = s.render.height = 1;
    s.environment.type = EnvironmentType::Map;
    s.environment.file = file;
    s.environment.rotation = rotation;
    return s;
}

GLuint envKernel() { return test::kernel("env_sampling.comp"); }

std::vector<glm::vec4> runKernel(Renderer& r, GLuint mode, GLuint count, const std::vector<glm::vec4>& input = {}) {
    GLuint program = envKernel();
    GLuint out = 0;
    glCreateBuffers(1, &out);
    glNamedBufferData(out, count * sizeof(glm::vec4), input.empty() ? nullptr : input.data(), GL_DYNAMIC_READ);
    r.bindScene(0, 1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEST_OUTPUT, out);
    glUseProgram(program);
    glProgramUniform1ui(program, glGetUniformLocation(program, "u_mode"), mode);
    glProgramUniform1ui(program, glGetUniformLocation(program, "u_light"), GLuint(r.compiled().envLightIndex));
    glProgramUniform1ui(program, glGetUniformLocation(program, "u_count"), count);
    glDispatchCompute((count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> results(count);
    glGetNamedBufferSubData(out, 0, count * sizeof(glm::vec4), results.data());
    glDeleteBuffers(1, &out);
    REQUIRE(glDebugErrorCount() == 0);
    return results;
}

// The map texel a world direction falls in, written independently of the GLSL: undo the
// rotation about +y, then theta from +y and phi from -z towards +x (docs/scene-format.md).
glm::ivec2 texelOf(glm::dvec3 d, double rotationDegrees) {
    double a = -rotationDegrees * kPi / 180.0;
    glm::dvec3 l(std::cos(a) * d.x + std::sin(a) * d.z, d.y, -std::sin(a) * d.x + std::cos(a) * d.z);
    double theta = std::acos(std::clamp(l.y, -1.0, 1.0));
    double phi = std::atan2(l.x, -l.z);
    double u = phi / (2.0 * kPi) + 0.5, v = theta / kPi;
    return {std::min(int(u * kW), kW - 1), std::min(int(v * kH), kH - 1)};
}

}  // namespace

TEST_CASE("environment map sampling matches its pdf (chi-square per texel)", "[gpu][lights][envmap]") {
    auto renderer = test::makeRenderer();
    renderer->setImageReader(generatedReader());
    const int kTests = 2;
    for (float rotation : {0.0f, 40.0f}) {
        INFO("rotation " << rotation);
        std::string error;
        REQUIRE(renderer->setScene(envScene("sky", rotation), &error));
        const GLuint n = 1u << 20;
        std::vector<glm::vec4> samples = runKernel(*renderer, 0, n);
        // The pdf is constant over each cell of the sampling table (s x s cells per texel).
        const int cs = renderer->compiled().envMap.tableScale, cw = kW * cs, chh = kH * cs;
        CHECK(cs == 4);  // a small map gets the finest table
        std::vector<glm::vec4> pdfs = runKernel(*renderer, 1, GLuint(cw * chh));
        std::vector<double> observed(kW * kH, 0.0), expected(kW * kH, 0.0);
        int invalid = 0;
        for (const glm::vec4& s : samples) {
            invalid += !(s.w > 0.0f);
            glm::ivec2 t = texelOf(glm::dvec3(s), rotation);
            observed[size_t(t.y) * kW + t.x] += 1.0;
        }
        // Integral of the pdf over a texel: the sum over its cells of pdf(centre) * sin(theta_centre)
        // * dtheta * dphi, exact because pdf * sin(theta) is constant across a cell.
        double total = 0.0;
        for (int c = 0; c < cw * chh; ++c) {
            double p = double(pdfs[c].x) * pdfs[c].y * (kPi / chh) * (2.0 * kPi / cw);
            const int texel = (c / cw / cs) * kW + (c % cw) / cs;
            expected[size_t(texel)] += p * n;
            total += p;
        }
        CHECK(invalid == 0);
        CHECK(total == Approx(1.0).epsilon(1e-4));  // the pdf integrates to one
        test::Chi2Result r = test::chi2Test(observed, expected, kH, kW, 0.01, kTests);
        INFO(r.report);
        CHECK(r.passed);
        // The black ground beyond the dilation gets no samples at all.
        for (int j = 13; j < kH; ++j)
            for (int i = 0; i < kW; ++i) CHECK(observed[size_t(j) * kW + i] == 0.0);
    }
}

TEST_CASE("environment map: mean 1/pdf is the solid angle of its support", "[gpu][lights][envmap]") {
    auto renderer = test::makeRenderer();
    renderer->setImageReader(generatedReader());
    std::string error;
    REQUIRE(renderer->setScene(envScene("sky", 25.0f), &error));
    const GLuint n = 1u << 18;
    std::vector<glm::vec4> samples = runKernel(*renderer, 0, n);
    double sum = 0.0, sumSq = 0.0;
    for (const glm::vec4& s : samples) {
        double inv = s.w > 0.0f ? 1.0 / s.w : 0.0;
        sum += inv;
        sumSq += inv * inv;
    }
    double mean = sum / n, se = std::sqrt((sumSq / n - mean * mean) / (n - 1));
    // Rows 0..11 are lit, and the upper half of row 12 through the filter (quarter-texel cells): the
    // band theta in [0, 12.5 pi / 16] has solid angle 2 pi (1 - cos(12.5 pi / 16)).
    REQUIRE(renderer->compiled().envMap.tableScale == 4);
    double support = 2.0 * kPi * (1.0 - std::cos(12.5 * kPi / kH));
    INFO("mean 1/pdf " << mean << " +- " << se << ", support " << support);
    CHECK(std::abs(mean - support) < 4.0 * se + 1e-4 * support);
}

TEST_CASE("environment map: the guided interval search finds what a search of the whole CDF finds", "[gpu][lights][envmap]") {
    // Every entry of both CDFs, every bucket boundary k / G of their guide tables, each also one
    // float step below and above, and random u: the shader's guided search (envFindInterval)
    // against a binary search over the whole CDF, on the GPU, and the CPU's search of its own
    // tables, index for index.
    auto renderer = test::makeRenderer();
    renderer->setImageReader(generatedReader());
    std::string error;
    REQUIRE(renderer->setScene(envScene("odd", 0.0f), &error));
    const EnvironmentMap& env = renderer->compiled().envMap;
    const int w = env.width * env.tableScale, h = env.height * env.tableScale;
    REQUIRE(w == 160);
    REQUIRE(h == 60);
    CHECK(env.marginalGuideLog2 == 5);      // 32 buckets for 60 rows
    CHECK(env.conditionalGuideLog2 == 7);   // 128 for 160 columns
    std::vector<glm::vec4> queries;
    auto add = [&](float u, int row, int table) {
        for (float v : {u, std::nextafter(u, 0.0f), std::nextafter(u, 1.0f)})
            if (v >= 0.0f && v < 1.0f) queries.emplace_back(v, float(row), float(table), 0.0f);
    };
    std::uint32_t state = 12345u;
    auto random = [&] { state = state * 1664525u + 1013904223u; return float(state >> 8) * 0x1p-24f; };
    for (int table = 0; table < 2; ++table)
        for (int row = 0; row < (table == 0 ? 1 : h); ++row) {
            const float* cdf = table == 0 ? env.marginalCdf.data() : &env.conditionalCdf[size_t(row) * (w + 1)];
            const int n = table == 0 ? h : w, buckets = 1 << (table == 0 ? env.marginalGuideLog2 : env.conditionalGuideLog2);
            for (int k = 0; k <= n; ++k) add(cdf[k], row, table);
            for (int k = 0; k <= buckets; ++k) add(float(k) / float(buckets), row, table);
            for (int r = 0; r < 64; ++r) add(random(), row, table);
        }
    const std::vector<glm::vec4> results = runKernel(*renderer, 2, GLuint(queries.size()), queries);
    // The CPU's answer from its own tables: the largest i < n with cdf[i] <= u. The GPU reads the
    // tables packed into one buffer (renderer/gpu_frame.cpp, packTables), so this also checks the
    // packing and the offsets the shader reads them at.
    auto cpuIndex = [&](const glm::vec4& q) {
        const int table = int(q.z), row = int(q.y);
        const float* cdf = table == 0 ? env.marginalCdf.data() : &env.conditionalCdf[size_t(row) * (w + 1)];
        const int n = table == 0 ? h : w;
        int i = 0;
        while (i + 1 < n && cdf[i + 1] <= q.x) ++i;
        return float(i);
    };
    int mismatches = 0;
    for (size_t q = 0; q < queries.size(); ++q) {
        const float expected = cpuIndex(queries[q]);
        if (results[q].x != results[q].y || results[q].y != expected) {
            if (++mismatches <= 5)
                UNSCOPED_INFO("u " << queries[q].x << " row " << queries[q].y << " table " << queries[q].z << ": guided "
                                   << results[q].x << ", whole " << results[q].y << ", CPU " << expected);
        }
    }
    INFO(queries.size() << " queries");
    CHECK(queries.size() > 50000);
    CHECK(mismatches == 0);
}

TEST_CASE("a constant environment map is a white furnace", "[gpu][integrator][envmap]") {
    auto renderer = test::makeRenderer();
    renderer->setImageReader(generatedReader());
    Scene s = envScene("constant", 10.0f);
    s.render.width = s.render.height = 16;
    s.render.maxDepth = 10;
    s.materials.push_back({"grey", MaterialType::Diffuse, glm::vec3(0.8f), glm::vec3(0.0f)});
    Object sphere;
    sphere.shape = Shape::Sphere;
    sphere.material = "grey";
    s.objects.push_back(sphere);
    s.camera.position = glm::vec3(0.0f, 0.0f, 4.0f);
    s.camera.fovDegrees = 10.0f;
    Film film = test::renderFilm(*renderer, s, 32);
    test::ImageStats st = test::imageStats(film);
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << " mean " << st.mean[c] << " se " << st.standardError[c]);
        CHECK(std::abs(st.mean[c] - 0.8) < 4.0 * st.standardError[c] + 1e-5);
        CHECK(st.standardError[c] < 0.01);
    }
}

TEST_CASE("MIS, light sampling and BSDF sampling agree under an environment map", "[gpu][mis][envmap]") {
    auto renderer = test::makeRenderer();
    renderer->setImageReader(generatedReader());
    Scene s = envScene("sky", 70.0f);
    s.render.width = s.render.height = 16;
    s.render.maxDepth = 2;
    s.materials.push_back({"grey", MaterialType::Diffuse, glm::vec3(0.5f), glm::vec3(0.0f)});
    Object ball;
    ball.shape = Shape::Sphere;
    ball.material = "grey";
    s.objects.push_back(ball);
    Object floor;
    floor.shape = Shape::Quad;
    floor.material = "grey";
    floor.transform.translate = glm::vec3(0.0f, -1.0f, 0.0f);
    floor.transform.rotate = glm::vec3(-90.0f, 0.0f, 0.0f);
    floor.transform.scale = glm::vec3(3.0f);
    s.objects.push_back(floor);
    s.camera.position = glm::vec3(0.0f, 1.0f, 4.0f);
    s.camera.fovDegrees = 40.0f;
    std::vector<test::ImageStats> stats;
    std::vector<double> variance;
    for (std::uint32_t strategy : {STRATEGY_MIS, STRATEGY_LIGHT_ONLY, STRATEGY_BSDF_ONLY}) {
        renderer->setStrategy(strategy);
        Film f = test::renderFilm(*renderer, s, strategy == STRATEGY_BSDF_ONLY ? 512 : 64);
        stats.push_back(test::imageStats(f));
    }
    renderer->setStrategy(STRATEGY_MIS);
    for (int k : {1, 2})
        for (int c = 0; c < 3; ++c) {
            double se = std::hypot(stats[0].standardError[c], stats[k].standardError[c]);
            INFO("strategy " << k << " channel " << c << ": " << stats[0].mean[c] << " vs " << stats[k].mean[c]
                             << " (se " << se << ")");
            CHECK(std::abs(stats[0].mean[c] - stats[k].mean[c]) < 4.0 * se);
        }
}
