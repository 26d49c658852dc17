// Path regeneration (CAUSTIC_REGENERATE, integrator/path.comp): a lane whose path has ended
// starts its pixel's next sample within the same dispatch, instead of waiting for the other
// lanes' paths (1.4x on llvmpipe, docs/performance.md). It must change nothing but the speed:
// each sample keeps the random numbers of (seed, pixel, sample index) and is summed in order, so
// the image must be the nested loops' bit for bit, with many samples per dispatch, for paths that
// escape to an environment at different depths, end by Russian roulette, or probe glass.
#include "renderer/scene_io.h"
#include "tests/gpu/gl_fixture.h"

#include <catch2/catch.hpp>

#include <cstdlib>

using namespace caustic;

namespace {

// Renders `scene` with regeneration forced on or off. A dispatch of 60 s makes each dispatch
// after the first hold as many samples as the renderer allows (64), so that lanes do start later
// samples within a dispatch.
Film renderWith(bool regenerate, const Scene& scene, int samples) {
    IntegratorConfig config = test::testConfig();
    config.regenerate = regenerate;
    config.dispatchSeconds = 60.0;
    auto r = test::makeRenderer(config);
    CHECK(test::hasDefine(r->config().defines(), "CAUSTIC_REGENERATE") == regenerate);
    return test::renderFilm(*r, scene, samples);
}

void requireSameImage(const Scene& scene, int samples) {
    const Film nested = renderWith(false, scene, samples);
    const Film regenerated = renderWith(true, scene, samples);
    REQUIRE(nested.mean.size() == regenerated.mean.size());
    int differ = 0, lit = 0;
    for (size_t i = 0; i < nested.mean.size(); ++i) {
        differ += nested.mean[i] != regenerated.mean[i];
        lit += nested.mean[i].x + nested.mean[i].y + nested.mean[i].z > 0.0f;
    }
    for (size_t i = 0; i < nested.albedo.size(); ++i)
        differ += nested.albedo[i] != regenerated.albedo[i] || nested.normal[i] != regenerated.normal[i] ||
                  nested.varianceOfMean[i] != regenerated.varianceOfMean[i] || nested.count[i] != regenerated.count[i];
    INFO(differ << " differences in the mean, variance, count and AOV images of " << nested.mean.size() << " pixels");
    CHECK(differ == 0);
    CHECK(lit > int(nested.mean.size()) / 2);  // an image, not a black one
}

}  // namespace

TEST_CASE("path regeneration: two knots under a sky give the nested loops' image bit for bit", "[regenerate]") {
    // Paths that escape to the environment map after 0 to 7 bounces: the lanes' paths end at
    // different times, which is what regeneration fills.
    Scene s = test::sceneFromFile("mesh-knot.json", 40, 24);
    // The GPU tests read no image files: the procedural sky instead of the HDR map (escaping
    // paths are what matters here).
    s.environment = Environment{};
    s.environment.type = EnvironmentType::Sky;
    requireSameImage(s, 24);
}

TEST_CASE("path regeneration: a Cornell box with glass probes and Russian roulette gives the same image bit for bit",
          "[regenerate]") {
    Scene s = test::cornellBox(24);
    s.render.maxDepth = 12;  // Russian roulette ends most paths before the cap
    s.materials.push_back({"glass ball", MaterialType::Transmission, glm::vec3(1.0f), glm::vec3(0.0f)});
    s.objects.push_back(test::sphereAt("glass ball", glm::vec3(-0.3f, -0.6f, 0.3f), 0.3f));
    REQUIRE(s.render.glassSplit);
    requireSameImage(s, 24);
}
