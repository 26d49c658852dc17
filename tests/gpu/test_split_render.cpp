// Parts of a split render (issue 17, docs/farm.md): Renderer::setCrop renders a rectangle of the
// image with the same pixels as the whole render, and setSampleBase renders a later range of
// sample indices, so that parts summed equal the whole render (within float32 summation).
#include "renderer/scene_io.h"
#include "tests/gpu/gl_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>

using namespace caustic;

TEST_CASE("a crop holds the whole render's sums for its pixels, and sample ranges add up to the whole", "[gpu][split]") {
    auto renderer = test::makeRenderer();
    SceneLoadResult loaded = loadScene(CAUSTIC_SOURCE_DIR "/scenes/cornell-box.json");
    INFO(loaded.error);
    REQUIRE(loaded);
    Scene s = *loaded.scene;
    s.render.width = 37;   // not a multiple of the kernel's 8x8 tiles
    s.render.height = 21;
    s.render.seed = 3;
    std::string error;
    REQUIRE(renderer->setScene(s, &error));
    renderer->render(10);
    const Accumulators whole = renderer->readAccumulators();

    // A crop with edges off the tile grid: the same floats, bit for bit.
    const PixelRect crop{5, 3, 30, 19};
    renderer->setCrop(crop);
    REQUIRE(renderer->setScene(s, &error));
    CHECK(renderer->region().x0 == 5);
    CHECK(renderer->region().y1 == 19);
    renderer->render(10);
    const Accumulators part = renderer->readAccumulators();
    REQUIRE(part.width == 25);
    REQUIRE(part.height == 16);
    int differing = 0;
    for (int y = 0; y < part.height; ++y)
        for (int x = 0; x < part.width; ++x) {
            const size_t i = size_t(y) * part.width + x, j = size_t(y + crop.y0) * whole.width + size_t(x + crop.x0);
            for (const auto& [a, b] : {std::pair{&part.sum, &whole.sum}, std::pair{&part.sumSq, &whole.sumSq},
                                       std::pair{&part.albedo, &whole.albedo}, std::pair{&part.normal, &whole.normal}})
                differing += (*a)[i] != (*b)[j];
        }
    CHECK(differing == 0);

    // Samples [0, 4) and [4, 10) of the whole image: their float sums add to the whole render's
    // within the summation bound of docs/farm.md, (N + n_max + 2) u relative for these
    // non-negative samples; the counts exactly.
    renderer->setCrop({});
    REQUIRE(renderer->setScene(s, &error));
    renderer->render(4);
    const Accumulators first = renderer->readAccumulators();
    renderer->setSampleBase(4);
    REQUIRE(renderer->setScene(s, &error));
    renderer->render(6);
    const Accumulators second = renderer->readAccumulators();
    renderer->setSampleBase(0);
    const double bound = (10 + 6 + 2) * std::ldexp(1.0, -24);
    int rounded = 0;
    for (size_t i = 0; i < whole.sum.size(); ++i) {
        CHECK(first.sum[i].a + second.sum[i].a == whole.sum[i].a);
        for (int c = 0; c < 3; ++c) {
            const double merged = double(first.sum[i][c]) + double(second.sum[i][c]);
            const double w = whole.sum[i][c];
            INFO("pixel " << i << " channel " << c << ": " << merged << " vs " << w);
            CHECK(std::abs(merged - w) <= bound * std::max(std::abs(merged), std::abs(w)));
            rounded += float(merged) != whole.sum[i][c];
        }
    }
    // Different samples in the second range (not the first range again): the sums differ.
    int same = 0;
    for (size_t i = 0; i < first.sum.size(); ++i) same += first.sum[i] == second.sum[i] * (4.0f / 6.0f);
    CHECK(same < int(first.sum.size()) / 2);
    INFO("pixels whose merged float differs from the whole render's: " << rounded);
    CHECK(glDebugErrorCount() == 0);
}

// --gpu (the farm passes Ray's GPU number): a GPU that is not there is refused, by number, with
// no fallback to another device or to software rendering. On the GPU machine,
// CAUSTIC_TEST_GPU=<n> also checks that GPU n is found (NVIDIA: by EGL_NV_device_cuda's number).
TEST_CASE("the GPU option refuses a GPU that is not there by its number, and uses one that is there", "[gpu][split][gpu_select]") {
    test::glContext();   // the fixture's context first: the checks below must not disturb it
    std::string error;
    auto missing = HeadlessGlContext::create(false, &error, 1023);
    CHECK_FALSE(missing);
    INFO(error);
    CHECK(error.find("--gpu 1023: no such GPU") != std::string::npos);
    if (const char* n = std::getenv("CAUSTIC_TEST_GPU")) {
        auto chosen = HeadlessGlContext::create(false, &error, std::atoi(n));
        INFO(error);
        REQUIRE(chosen);
        CHECK(chosen->info().platform == "EGL device");
        CHECK(chosen->info().renderer.find("llvmpipe") == std::string::npos);
        std::printf("--gpu %s: %s | %s\n", n, chosen->info().vendor.c_str(), chosen->info().renderer.c_str());
        // Its display is the fixture's where both are the same device (EGL displays are one per
        // device), so it is not destroyed here (that would terminate the display); the fixture's
        // context is made current again.
        chosen.release();
        test::glContext().makeCurrent();
    }
    CHECK(glDebugErrorCount() == 0);
}
