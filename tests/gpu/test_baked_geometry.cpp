// Baked primitives (Renderer::setBakeGeometry, renderer_programs.cpp bakedPrimitiveTests): a batch
// render's scene-specialised program for a scene of a few analytic primitives holds their hit
// records as constants instead of fetching them (1.8x on llvmpipe for the Cornell box,
// docs/performance.md), and a scene of a few meshes and primitives its top level's entries
// (CAUSTIC_BAKED_TOP_LEVEL). It must be an optimisation and nothing else: the same image, bit for
// bit, as the program that fetches the records, for quads, spheres and mesh instances; and an
// edit that moves a primitive or a mesh must build a new program, never render the old geometry.
#include "renderer/scene_io.h"
#include "tests/gpu/gl_fixture.h"

#include <catch2/catch.hpp>

#include <cstdlib>

using namespace caustic;

namespace {

// The Cornell box (18 quads) with a glass sphere and a mirror sphere: both shape tests baked.
Scene boxWithSpheres() {
    Scene s = test::cornellBox(32);
    s.render.maxDepth = 6;
    s.materials.push_back({"glass ball", MaterialType::Transmission, glm::vec3(1.0f), glm::vec3(0.0f)});
    s.materials.push_back({"mirror ball", MaterialType::Mirror, glm::vec3(0.9f), glm::vec3(0.0f)});
    s.objects.push_back(test::sphereAt("glass ball", glm::vec3(-0.3f, -0.6f, 0.3f), 0.3f));
    s.objects.push_back(test::sphereAt("mirror ball", glm::vec3(0.4f, 0.4f, -0.2f), 0.2f));
    return s;
}

// The same with a small glass knot (a mesh instance) on the floor.
Scene withKnot(Scene s) {
    Object knot;
    knot.name = "knot";
    knot.shape = Shape::Mesh;
    knot.file = CAUSTIC_SOURCE_DIR "/assets/knot.obj";
    knot.material = "glass ball";
    knot.transform.translate = glm::vec3(-0.1f, 0.2f, 0.5f);
    knot.transform.scale = glm::vec3(0.25f);
    s.objects.push_back(knot);
    return s;
}

// Three knots whose boxes overlap (one inside another's box, one crossing it), so that rays meet
// several instances in one traversal and the nearest-first order among them decides the hit.
Scene withKnots(Scene s) {
    s = withKnot(std::move(s));
    Object second = s.objects.back();
    second.name = "knot 2";
    second.material = "mirror ball";
    second.transform.translate = glm::vec3(0.0f, 0.25f, 0.45f);
    second.transform.rotate = glm::vec3(0.0f, 40.0f, 10.0f);
    second.transform.scale = glm::vec3(0.2f);
    s.objects.push_back(second);
    Object third = second;
    third.name = "knot 3";
    third.material = s.materials.front().name;
    third.transform.translate = glm::vec3(-0.35f, -0.3f, 0.1f);
    third.transform.rotate = glm::vec3(90.0f, 0.0f, 0.0f);
    third.transform.scale = glm::vec3(0.3f, 0.2f, 0.25f);
    s.objects.push_back(third);
    return s;
}

// A renderer that specialises (the default on llvmpipe; forced elsewhere, e.g. NVIDIA), with
// baking on or off.
std::unique_ptr<Renderer> specialisingRenderer(bool bake) {
    IntegratorConfig config = test::testConfig();
    config.specialize = true;
    std::unique_ptr<Renderer> r = test::makeRenderer(config);
    r->setBakeGeometry(bake);
    return r;
}

int differingPixels(const Film& a, const Film& b) {
    REQUIRE(a.mean.size() == b.mean.size());
    int differ = 0;
    for (size_t i = 0; i < a.mean.size(); ++i) differ += a.mean[i] != b.mean[i];
    return differ;
}

void requireSameFilm(const Film& a, const Film& b) {
    const int differ = differingPixels(a, b);
    INFO(differ << " of " << a.mean.size() << " pixels differ");
    CHECK(differ == 0);
}

// Renders `scene` with the baking renderer, applies `move` through update() (the editor's path),
// and checks that the baked renderer built a new program whose image is the fetching renderer's,
// and that the move changed at least minChanged pixels (so that the comparison could fail).
template <class Move>
void checkMoveRebuilds(Renderer& baked, Renderer& fetching, Scene scene, Move move, int minChanged) {
    const Film before = test::renderFilm(baked, scene, 2);
    const unsigned programBefore = baked.program();
    move(scene);
    std::string error;
    REQUIRE(baked.update(scene, kDirtyTransforms, &error));
    baked.render(2);
    const Film after = baked.readFilm();
    CHECK(baked.program() != programBefore);
    requireSameFilm(after, test::renderFilm(fetching, scene, 2));
    const int changed = differingPixels(after, before);
    INFO(changed << " pixels changed by the move");
    CHECK(changed > minChanged);
}

}  // namespace

TEST_CASE("baked primitives: quads and spheres as constants of the program give the fetching program's image bit for bit",
          "[gpu][integrator][bake]") {
    REQUIRE(std::getenv("CAUSTIC_BAKE_GEOMETRY") == nullptr);  // it would override both renderers
    const Scene scene = boxWithSpheres();
    auto fetching = specialisingRenderer(false), baked = specialisingRenderer(true);
    const Film reference = test::renderFilm(*fetching, scene, 4);
    const Film film = test::renderFilm(*baked, scene, 4);
    // The baked renderer really baked (and the other did not): otherwise this compares a program
    // with itself.
    CHECK_FALSE(test::hasDefine(fetching->featureDefines(), "CAUSTIC_BAKED_PRIMITIVES"));
    CHECK(test::hasDefine(baked->featureDefines(), "CAUSTIC_BAKED_PRIMITIVES"));
    requireSameFilm(film, reference);
    // Something was rendered: the box is lit.
    CHECK(test::imageStats(film).mean.r > 0.01);

    // With a mesh the top level is baked instead (the instances' records and the primitives, in a
    // fixed order instead of the top-level tree; the meshes' own BVHs are walked as before).
    const Scene withMesh = withKnot(scene);
    const Film meshReference = test::renderFilm(*fetching, withMesh, 2);
    const Film meshFilm = test::renderFilm(*baked, withMesh, 2);
    CHECK_FALSE(test::hasDefine(baked->featureDefines(), "CAUSTIC_BAKED_PRIMITIVES"));
    CHECK(test::hasDefine(baked->featureDefines(), "CAUSTIC_BAKED_TOP_LEVEL"));
    CHECK_FALSE(test::hasDefine(fetching->featureDefines(), "CAUSTIC_BAKED_TOP_LEVEL"));
    // ... and walks each step's continuation and shadow rays together (integrator/path.glsl).
    CHECK(test::hasDefine(baked->featureDefines(), "CAUSTIC_PAIRED_TRACE"));
    CHECK_FALSE(test::hasDefine(fetching->featureDefines(), "CAUSTIC_PAIRED_TRACE"));
    requireSameFilm(meshFilm, meshReference);
    // The knot is in the picture: the image differs from the box's without it (same seed and
    // sample count, so only pixels whose paths meet the knot differ).
    const Film box = test::renderFilm(*fetching, scene, 2);
    const int knotPixels = differingPixels(meshFilm, box);
    INFO(knotPixels << " pixels see the knot");
    CHECK(knotPixels > 30);

    // Several instances with overlapping boxes: the baked top level walks the instances a ray
    // meets nearest first, in one loop; the image is still the fetching program's.
    const Scene knots = withKnots(scene);
    const Film knotsReference = test::renderFilm(*fetching, knots, 2);
    const Film knotsFilm = test::renderFilm(*baked, knots, 2);
    CHECK(test::hasDefine(baked->featureDefines(), "CAUSTIC_BAKED_TOP_LEVEL"));
    requireSameFilm(knotsFilm, knotsReference);
    const int morePixels = differingPixels(knotsFilm, meshFilm);
    INFO(morePixels << " pixels see the second and third knots");
    CHECK(morePixels > 30);
}

TEST_CASE("baked primitives: an edit that moves a primitive builds a new program, never renders the old geometry",
          "[gpu][integrator][bake]") {
    REQUIRE(std::getenv("CAUSTIC_BAKE_GEOMETRY") == nullptr);
    auto baked = specialisingRenderer(true), fetching = specialisingRenderer(false);
    // The mirror ball and a box.
    checkMoveRebuilds(*baked, *fetching, boxWithSpheres(), [](Scene& s) {
        for (Object& o : s.objects)
            if (o.material == "mirror ball") o.transform.translate += glm::vec3(-0.5f, 0.0f, 0.3f);
        s.objects[s.objects.size() - 3].transform.translate.x += 0.05f;
    }, 50);
    // A baked top level: the mesh instance.
    checkMoveRebuilds(*baked, *fetching, withKnot(boxWithSpheres()), [](Scene& s) {
        s.objects.back().transform.translate += glm::vec3(-0.4f, 0.3f, 0.0f);
    }, 20);
}
