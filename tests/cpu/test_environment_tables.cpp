// The environment map's sampling tables on the CPU (renderer/environment_map.cpp): the guide
// tables that shorten the shader's interval search. The GPU test "environment map: the guided
// interval search finds what a search of the whole CDF finds" checks the search itself.
#include "renderer/gpu_scene.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>

using namespace caustic;

namespace {

ImageData noiseMap(int width, int height, std::uint32_t seed) {
    ImageData img;
    img.width = width;
    img.height = height;
    img.channels = 3;
    img.pixels.resize(size_t(width) * height * 3);
    std::uint32_t s = seed;
    for (size_t p = 0; p < size_t(width) * height; ++p) {
        s = s * 1664525u + 1013904223u;
        // A quarter of the texels black (runs of repeated CDF entries), the rest spread over 2^8.
        const float v = (s >> 30) == 0u ? 0.0f : float(1u << ((s >> 20) & 7u));
        for (int c = 0; c < 3; ++c) img.pixels[p * 3 + c] = v;
    }
    return img;
}

// guide[k] must be the largest i < n with cdf[i] <= k / G: checked with std::upper_bound.
void checkGuide(const float* cdf, int n, const float* guide, int log2) {
    const int buckets = 1 << log2;
    for (int k = 0; k <= buckets; ++k) {
        const double x = double(k) / buckets;
        const long expected = long(std::upper_bound(cdf, cdf + n, x, [](double a, float b) { return a < double(b); }) - cdf) - 1;
        if (long(guide[k]) != expected) {
            FAIL("bucket " << k << " of " << buckets << ": guide " << guide[k] << ", expected " << expected);
        }
    }
}

}  // namespace

TEST_CASE("environment map guide tables: each entry is the largest index at or below its bucket's start", "[envmap]") {
    struct Case { int width, height, marginalLog2, conditionalLog2; };
    // 37 x 23 at 4 cells per texel (148 x 92); 3000 x 1500 at one cell (4.5 M cells); 8192 x 600:
    // 2^22 / 600 rows leaves 4096 buckets a row for 8192 columns, the cap on the guides' size.
    for (const Case c : {Case{37, 23, 6, 7}, Case{3000, 1500, 10, 11}, Case{8192, 600, 9, 12}}) {
        INFO(c.width << " x " << c.height);
        EnvironmentMap env;
        std::string error;
        REQUIRE(buildEnvironmentMap(noiseMap(c.width, c.height, 7u), &env, &error));
        const int w = env.width * env.tableScale, h = env.height * env.tableScale;
        CHECK(env.marginalGuideLog2 == c.marginalLog2);
        CHECK(env.conditionalGuideLog2 == c.conditionalLog2);
        REQUIRE(env.marginalGuide.size() == (size_t(1) << env.marginalGuideLog2) + 1);
        REQUIRE(env.conditionalGuide.size() == size_t(h) * ((size_t(1) << env.conditionalGuideLog2) + 1));
        CHECK(env.conditionalGuide.size() <= (size_t(1) << 22) + size_t(h));
        checkGuide(env.marginalCdf.data(), h, env.marginalGuide.data(), env.marginalGuideLog2);
        const size_t stride = (size_t(1) << env.conditionalGuideLog2) + 1;
        for (int j = 0; j < h; ++j)
            checkGuide(&env.conditionalCdf[size_t(j) * (w + 1)], w, &env.conditionalGuide[size_t(j) * stride],
                       env.conditionalGuideLog2);
    }
}
