// (header comment to come)
#include "renderer/scene_io.h"
#include "tests/gpu/gl_fixture.h"

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdio>
#include <ctime>

using namespace caustic;

namespace {

Scene cornell128(std::uint32_t seed) {
    SceneLoadResult loaded = loadScene(CAUSTIC_SOURCE_DIR "/scenes/cornell-box.json");
    INFO(loaded.error);
    REQUIRE(loaded);
    Scene s = *loaded.scene;
    s.render.width = s.render.height = 128;
    s.render.seed = seed;
    return s;
}

}  // namespace

TEST_CASE("regenerate the converged Cornell box mean (hidden; prints tests/data JSON)", "[.][cornell-regenerate]") {
    const int spp = std::getenv("CAUSTIC_REFERENCE_SPP") ? std::atoi(std::getenv("CAUSTIC_REFERENCE_SPP")) : 4096;
    auto renderer = test::makeRenderer();
    Scene s = cornell128(20240601u);
    auto t0 = std::chrono::steady_clock::now();
    Film film = test::renderFilm(*renderer, s, spp);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    test::ImageStats st = test::imageStats(film);
    std::printf("spp %d seed %u max_depth %d seconds %.1f dropped %llu\n", spp, s.render.seed, s.render.maxDepth,
                seconds, (unsigned long long)renderer->droppedSamples());
    std::printf("mean [%.9g, %.9g, %.9g]\nstandard_error [%.9g, %.9g, %.9g]\n", st.mean.x, st.mean.y, st.mean.z,
                st.standardError.x, st.standardError.y, st.standardError.z);
}
