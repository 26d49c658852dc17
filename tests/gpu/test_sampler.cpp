// The integrator's sampler (shaders/lib/sampler.glsl), run through a test kernel: the Sobol
// sampler's first 2^k samples of a pixel are a (0, k, 2)-net in every 2-D slot (every elementary
// interval of area 2^-k holds exactly one point) and stratified in every 1-D slot; scrambling
// differs per pixel and per slot; each point is uniform over pixels (unbiased); and a render
// split into dispatches is bit-identical to one run, for both samplers (test_integrator.cpp
// covers the default one).
#include "renderer/scene_io.h"
#include "tests/gpu/gl_fixture.h"

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <vector>

using namespace caustic;

namespace {

struct Query {
    unsigned count = 256, pixel = 0, first = 0, slot = 0, seed = 0, type = SAMPLER_SOBOL;
    bool perPixel = false;
};

std::vector<glm::vec4> samplePoints(const Query& q) {
    const GLuint program = test::kernel("sampler_points.comp");
    GLuint out = 0;
    glCreateBuffers(1, &out);
    glNamedBufferData(out, GLsizeiptr(q.count * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_READ);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEST_OUTPUT, out);
    glUseProgram(program);
    auto set = [&](const char* name, unsigned v) { glProgramUniform1ui(program, glGetUniformLocation(program, name), v); };
    set("u_count", q.count);
    set("u_pixel", q.pixel);
    set("u_first", q.first);
    set("u_slot", q.slot);
    set("u_seed", q.seed);
    set("u_type", q.type);
    set("u_perPixel", q.perPixel ? 1u : 0u);
    glDispatchCompute((q.count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> r(q.count);
    glGetNamedBufferSubData(out, 0, GLsizeiptr(q.count * sizeof(glm::vec4)), r.data());
    glDeleteBuffers(1, &out);
    REQUIRE(glDebugErrorCount() == 0);
    return r;
}

// Number of elementary intervals [i / 2^a, (i+1) / 2^a) x [j / 2^(k-a), ...) that do not hold
// exactly one of the 2^k points, summed over a = 0..k.
int netViolations(const std::vector<glm::vec4>& pts, int k) {
    int bad = 0;
    for (int a = 0; a <= k; ++a) {
        const int nx = 1 << a, ny = 1 << (k - a);
        std::vector<int> cells(size_t(nx) * ny, 0);
        for (const glm::vec4& p : pts) {
            const int x = std::min(int(p.x * float(nx)), nx - 1), y = std::min(int(p.y * float(ny)), ny - 1);
            ++cells[size_t(y) * nx + x];
        }
        for (int c : cells) bad += c != 1;
    }
    return bad;
}

int strataViolations1D(const std::vector<glm::vec4>& pts) {
    const int n = int(pts.size());
    std::vector<int> cells(n, 0);
    for (const glm::vec4& p : pts) ++cells[size_t(std::min(int(p.z * float(n)), n - 1))];
    int bad = 0;
    for (int c : cells) bad += c != 1;
    return bad;
}

// Pearson's chi-square over equal-probability bins, against a generous bound (p ~ 1e-6).
double chiSquareUniform(const std::vector<int>& bins, int samples) {
    const double expected = double(samples) / double(bins.size());
    double x2 = 0;
    for (int b : bins) x2 += (b - expected) * (b - expected) / expected;
    return x2;
}

}  // namespace

TEST_CASE("Sobol sampler: the first 2^k samples of a pixel are a (0, k, 2)-net in every slot", "[gpu][sampler]") {
    test::glContext();
    for (unsigned slot : {0u, 1u, 2u, 6u, 13u, 40u}) {
        for (unsigned pixel : {0u, 1u, 4097u, 123456u}) {
            for (int k : {4, 8, 10}) {
                Query q;
                q.count = 1u << k;
                q.pixel = pixel;
                q.slot = slot;
                q.seed = 3;
                const std::vector<glm::vec4> pts = samplePoints(q);
                INFO("slot " << slot << " pixel " << pixel << " 2^" << k << " samples");
                CHECK(netViolations(pts, k) == 0);
                CHECK(strataViolations1D(pts) == 0);
                for (const glm::vec4& p : pts) {
                    REQUIRE(p.x >= 0.0f);
                    REQUIRE(p.x < 1.0f);
                    REQUIRE(p.y >= 0.0f);
                    REQUIRE(p.y < 1.0f);
                }
            }
        }
    }
    // Progressive: samples [2^k, 2^(k+1)) are a net too, so any power-of-two prefix is.
    Query q;
    q.count = 256;
    q.first = 256;
    q.slot = 5;
    CHECK(netViolations(samplePoints(q), 8) == 0);
    // The independent sampler is not stratified (a sanity check that the test can fail).
    q.first = 0;
    q.type = SAMPLER_INDEPENDENT;
    CHECK(netViolations(samplePoints(q), 8) > 0);
}

TEST_CASE("Sobol sampler: scrambling differs per pixel, slot and seed, and points are uniform over pixels", "[gpu][sampler]") {
    test::glContext();
    auto asSet = [](const std::vector<glm::vec4>& pts) {
        std::set<std::pair<float, float>> s;
        for (const glm::vec4& p : pts) s.insert({p.x, p.y});
        return s;
    };
    Query a;
    a.slot = 3;
    const auto base = asSet(samplePoints(a));
    for (int variant = 0; variant < 3; ++variant) {
        Query b = a;
        if (variant == 0) b.pixel = 1;
        if (variant == 1) b.slot = 4;
        if (variant == 2) b.seed = 1;
        const auto other = asSet(samplePoints(b));
        int common = 0;
        for (const auto& p : other) common += base.count(p) != 0;
        INFO("variant " << variant << ": " << common << " of 256 points in common");
        CHECK(common < 8);
    }
    // Sample 0 (and sample 5) over 65536 pixels: uniform in 16 x 16 bins (unbiased estimates),
    // and the slots' values independent of each other (a 2-D histogram of slot 2 against slot 3).
    for (unsigned first : {0u, 5u}) {
        Query q;
        q.count = 65536;
        q.perPixel = true;
        q.first = first;
        q.slot = 2;
        const std::vector<glm::vec4> s2 = samplePoints(q);
        q.slot = 3;
        const std::vector<glm::vec4> s3 = samplePoints(q);
        std::vector<int> bins2d(256, 0), pairBins(256, 0);
        for (size_t i = 0; i < s2.size(); ++i) {
            ++bins2d[size_t(std::min(int(s2[i].y * 16), 15)) * 16 + size_t(std::min(int(s2[i].x * 16), 15))];
            ++pairBins[size_t(std::min(int(s3[i].x * 16), 15)) * 16 + size_t(std::min(int(s2[i].x * 16), 15))];
        }
        // 255 degrees of freedom: mean 255, sd 22.6; 400 is beyond p = 1e-6.
        const double x2 = chiSquareUniform(bins2d, 65536), x2pair = chiSquareUniform(pairBins, 65536);
        INFO("sample " << first << ": chi2 of the 2-D point over pixels " << x2 << ", of slot 2 x against slot 3 x " << x2pair);
        CHECK(x2 < 400.0);
        CHECK(x2pair < 400.0);
    }
    // Within one pixel, two slots' samples are paired at random (padding), not index by index:
    // slot 2's x against slot 3's x over 4096 samples.
    Query q;
    q.count = 4096;
    q.slot = 2;
    const std::vector<glm::vec4> p2 = samplePoints(q);
    q.slot = 3;
    const std::vector<glm::vec4> p3 = samplePoints(q);
    std::vector<int> bins(256, 0);
    for (size_t i = 0; i < p2.size(); ++i)
        ++bins[size_t(std::min(int(p3[i].x * 16), 15)) * 16 + size_t(std::min(int(p2[i].x * 16), 15))];
    const double x2 = chiSquareUniform(bins, 4096);
    INFO("chi2 of slot 2 against slot 3 within a pixel: " << x2);
    CHECK(x2 < 400.0);
}

TEST_CASE("both samplers give the same bytes however the samples are split, and different samplers agree", "[gpu][sampler]") {
    auto renderer = test::makeRenderer();
    Scene s = test::sceneFromFile("dof.json", 48, 27);
    s.render.maxDepth = 4;
    s.render.seed = 9;
    Film films[2];
    for (SamplerType type : {SamplerType::Sobol, SamplerType::Independent}) {
        s.render.sampler = type;
        INFO("sampler " << int(type));
        Film whole = test::renderFilm(*renderer, s, 10);
        std::string error;
        REQUIRE(renderer->setScene(s, &error));
        renderer->render(3);
        renderer->render(4);
        renderer->render(3);
        Film split = renderer->readFilm();
        REQUIRE(whole.mean.size() == split.mean.size());
        CHECK(std::memcmp(whole.mean.data(), split.mean.data(), whole.mean.size() * sizeof(glm::vec3)) == 0);
        films[int(type)] = whole;
    }
    CHECK(std::memcmp(films[0].mean.data(), films[1].mean.data(), films[0].mean.size() * sizeof(glm::vec3)) != 0);
    test::checkSameMean(films[0], films[1]);
}
