// The sky presets through the real integrator: a scene read from JSON with "preset", seen by a
// narrow camera looking below the horizon, at 45 degrees and straight up, must show the radiance
// docs/scene-format.md gives (the preset's colour times its intensity, blended by
// sqrt(max(y, 0))).
#include "tests/gpu/gl_fixture.h"

#include "renderer/scene_io.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace caustic;

namespace {

// The image mean seen along `direction` through a 0.5-degree camera, escaped rays only.
glm::dvec3 skyAlong(Renderer& renderer, Scene s, glm::vec3 direction) {
    s.render.width = s.render.height = 4;
    s.render.maxDepth = 0;
    s.camera.position = glm::vec3(0.0f);
    s.camera.lookAt = direction;
    s.camera.up = std::abs(direction.y) > 0.9f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
    s.camera.fovDegrees = 0.5f;
    return test::imageStats(test::renderFilm(renderer, s, 2)).mean;
}

void checkClose(const glm::dvec3& got, const glm::vec3& expected, double relative) {
    INFO("got (" << got.r << ", " << got.g << ", " << got.b << "), expected (" << expected.r << ", "
                 << expected.g << ", " << expected.b << ")");
    for (int c = 0; c < 3; ++c) CHECK(got[c] == Approx(expected[c]).epsilon(relative).margin(1e-6));
}

}  // namespace

TEST_CASE("the original sky preset: a dark teal horizon, a white zenith, at fill-light strength", "[gpu][environment]") {
    auto renderer = test::makeRenderer();
    const SceneLoadResult loaded =
        parseScene(R"({"version": 1, "environment": {"type": "sky", "preset": "original"}})", "sky.json");
    INFO(loaded.error);
    REQUIRE(loaded);
    const Scene& s = *loaded.scene;
    // The documented values: horizon (0.1, 0.3, 0.35), zenith (1, 1, 1), intensity 0.3.
    const glm::vec3 horizon = 0.3f * glm::vec3(0.1f, 0.3f, 0.35f), zenith = glm::vec3(0.3f);
    checkClose(skyAlong(*renderer, s, glm::vec3(0, -0.5f, -1)), horizon, 1e-3);  // below: the horizon's
    checkClose(skyAlong(*renderer, s, glm::vec3(0, 1, 0)), zenith, 1e-3);
    // At 45 degrees the blend is sqrt(sin 45) = 0.841 of the way to the zenith (a half-degree field:
    // y varies by 0.3%, the blend by under 0.2%).
    const float t = std::sqrt(std::sqrt(0.5f));
    checkClose(skyAlong(*renderer, s, glm::vec3(0, 1, -1)), glm::mix(horizon, zenith, t), 3e-3);
    // Dark teal: green and blue well above red at the horizon, and the whole sky far dimmer than
    // the default preset's (fill light, not key light): its zenith is 0.3 against 1.
    const glm::dvec3 h = skyAlong(*renderer, s, glm::vec3(1, -0.2f, 0));
    CHECK(h.g > 2.5 * h.r);
    CHECK(h.b > h.g);
    const SceneLoadResult plain = parseScene(R"({"version": 1, "environment": {"type": "sky"}})", "sky.json");
    REQUIRE(plain);
    const glm::dvec3 keyZenith = skyAlong(*renderer, *plain.scene, glm::vec3(0, 1, 0));
    checkClose(keyZenith, glm::vec3(0.3f, 0.5f, 1.0f), 1e-3);
    CHECK(keyZenith.b > 3.0 * zenith.b);
}
