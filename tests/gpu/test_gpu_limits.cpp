// GL limits and errors (issue 12, docs/reliability.md): an environment map wider than the GL
// texture limit rendered black, because nothing checked GL_MAX_TEXTURE_SIZE before the upload or
// glGetError after it. llvmpipe's limit is 16384, so a map of 16385 x 2 pixels (made in memory by
// an injected image reader: no giant file) is the real case. setScene must fail naming the file;
// with the limit check disabled (limits set to 0, "unknown"), the driver's own refusal must come
// back as an error from glGetError (after which the next scene uploads everything). After the
// refusal by the check, the renderer still holds the last good scene and goes on accumulating it.
#include "renderer/scene_io.h"
#include "tests/gpu/gl_fixture.h"

#include <catch2/catch.hpp>

using namespace caustic;

namespace {

Scene mapLitScene(const std::string& file) {
    Scene s = test::closedEmittingSphere(glm::vec3(0.5f), glm::vec3(1.0f));
    s.environment.type = EnvironmentType::Map;
    s.environment.file = file;
    return s;
}

// Any file reads as a grey map `width` x 2 pixels.
ImageReader wideMapReader(int width) {
    return [width](const std::string&, ImageData* out, std::string*) {
        out->width = width;
        out->height = 2;
        out->channels = 3;
        out->pixels.assign(std::size_t(width) * 2 * 3, 0.5f);
        return true;
    };
}

}  // namespace

TEST_CASE("an environment map wider than the GL texture limit is an error naming the file, not a black render", "[gpu][limits]") {
    auto renderer = test::makeRenderer();
    const std::int64_t limit = renderer->limits().maxTextureSize;
    INFO("GL_MAX_TEXTURE_SIZE " << limit);
    REQUIRE(limit >= 1024);
    REQUIRE(renderer->limits().maxStorageBlockSize >= (1 << 24));
    // A good scene first: what the renderer must keep after the failures.
    const Scene good = test::closedEmittingSphere(glm::vec3(0.5f), glm::vec3(1.0f));
    const Film before = test::renderFilm(*renderer, good, 4);

    renderer->setImageReader(wideMapReader(int(limit) + 1));
    std::string error;
    CHECK_FALSE(renderer->setScene(mapLitScene("wide.hdr"), &error));
    CHECK(error == "environment.file: wide.hdr: the map is " + std::to_string(limit + 1) +
                       " x 2 pixels; this GPU's textures may be at most " + std::to_string(limit) +
                       " per side (GL_MAX_TEXTURE_SIZE); resample the map");
    CHECK(glDebugErrorCount() == 0);   // refused before anything reached the driver
    // The last good scene is still there, its accumulation untouched: 4 more samples continue it
    // to the image a fresh 8-sample render of it gives.
    CHECK(renderer->samplesDone() == 4);
    renderer->render(4);
    const Film continued = renderer->readFilm();
    const Film fresh = test::renderFilm(*test::makeRenderer(), good, 8);
    test::checkSameMean(continued, fresh, 1e-3);
    CHECK(test::imageStats(continued).mean.x > 0.5 * test::imageStats(before).mean.x);

    // Without the check, the driver refuses the texture: that must be an error too.
    const GpuLimits real = renderer->limits();
    renderer->setLimits(GpuLimits{});
    error.clear();
    CHECK_FALSE(renderer->setScene(mapLitScene("wide.hdr"), &error));
    CHECK(error.rfind("uploading the scene to the GPU failed: GL_INVALID_VALUE", 0) == 0);
    CHECK(takeGlDebugErrors() > 0);   // provoked on purpose
    renderer->setLimits(real);

    // A map at the limit itself renders.
    renderer->setImageReader(wideMapReader(int(limit)));
    CHECK(renderer->setScene(mapLitScene("wide.hdr"), &error));
    renderer->render(1);
    CHECK(glDebugErrorCount() == 0);
}
