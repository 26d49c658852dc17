// Emitters with a surface (an object's own "emission", one- or two-sided) rendered by the real
// integrator: the surface emits from the right faces only, still scatters by its material, and is
// sampled by next event estimation consistently with what a BSDF-sampled ray sees when it hits it
// (light sampling alone, BSDF sampling alone and MIS agree per image block, for each shape).
// The scene-compilation side is tests/cpu/test_surface_emitters.cpp.
#include "tests/gpu/gl_fixture.h"
#include "tests/support/meshes.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace caustic;

namespace {

constexpr int kSize = 24;

void checkAgree(const Film& a, const Film& b, const char* what) { test::checkBlocksAgree(a, b, what); }

// A grey floor, a rect light above, and the emitter under test (white, emitting) placed so the
// camera sees its front, its back or its underside as well as the light it casts on the floor.
Scene floorScene() {
    Scene s;
    s.render.width = s.render.height = kSize;
    s.render.maxDepth = 3;
    s.render.seed = 5;
    s.materials.push_back({"grey", MaterialType::Diffuse, glm::vec3(0.6f, 0.5f, 0.4f), glm::vec3(0.0f)});
    s.materials.push_back({"white", MaterialType::Diffuse, glm::vec3(0.8f), glm::vec3(0.0f)});
    s.objects.push_back(test::floorQuad("grey", 4.0f));
    Light l;
    l.type = LightType::Rect;
    l.color = glm::vec3(3.0f);
    l.transform.translate = glm::vec3(0.8f, 2.0f, 0.5f);
    l.transform.rotate = glm::vec3(90.0f, 0.0f, 0.0f);
    l.transform.scale = glm::vec3(0.6f, 0.4f, 1.0f);
    s.lights.push_back(l);
    s.camera.position = glm::vec3(0.0f, 2.0f, 3.0f);
    s.camera.lookAt = glm::vec3(0.0f, 0.3f, 0.0f);
    s.camera.fovDegrees = 55.0f;
    return s;
}

Object emitter(Shape shape, glm::vec3 emission, bool twoSided) {
    Object o;
    o.shape = shape;
    o.material = "white";
    o.emission = emission;
    o.twoSided = twoSided;
    return o;
}


}  // namespace

TEST_CASE("surface emitters: MIS, light sampling and BSDF sampling agree for every shape", "[gpu][mis][emitters]") {
    auto renderer = test::makeRenderer();
    Scene s = floorScene();
    SECTION("a one-sided quad, tilted so the camera sees its back and its light on the floor") {
        Object q = emitter(Shape::Quad, glm::vec3(2.0f, 1.5f, 1.0f), false);
        q.transform.translate = glm::vec3(-0.5f, 0.9f, 0.0f);
        q.transform.rotate = glm::vec3(60.0f, 20.0f, 0.0f);  // front (+z) towards -y and away from the camera
        q.transform.scale = glm::vec3(0.6f, 0.4f, 1.0f);
        s.objects.push_back(q);
        test::checkStrategiesAgree(*renderer, s, 64);
    }
    SECTION("a two-sided quad") {
        Object q = emitter(Shape::Quad, glm::vec3(2.0f, 1.5f, 1.0f), true);
        q.transform.translate = glm::vec3(-0.5f, 0.9f, 0.0f);
        q.transform.rotate = glm::vec3(60.0f, 20.0f, 0.0f);
        q.transform.scale = glm::vec3(0.6f, 0.4f, 1.0f);
        s.objects.push_back(q);
        test::checkStrategiesAgree(*renderer, s, 64);
    }
    SECTION("a one-sided sphere and a one-sided box") {
        Object ball = emitter(Shape::Sphere, glm::vec3(1.0f, 1.2f, 1.5f), false);
        ball.transform.translate = glm::vec3(-0.7f, 0.5f, 0.2f);
        ball.transform.scale = glm::vec3(0.45f);
        s.objects.push_back(ball);
        Object box = emitter(Shape::Box, glm::vec3(1.5f, 1.0f, 0.5f), false);
        box.transform.translate = glm::vec3(0.6f, 0.3f, -0.3f);
        box.transform.rotate = glm::vec3(0.0f, 30.0f, 0.0f);
        box.transform.scale = glm::vec3(0.3f);
        s.objects.push_back(box);
        test::checkStrategiesAgree(*renderer, s, 64);
    }
    SECTION("one-sided meshes: an open one (a quad, whose back the floor sees) and a torus") {
        // On a closed mesh a back face is always hidden behind a front face, so only an open
        // mesh shows whether the light sampler skips points whose back faces the shading point.
        test::TempDir dir;
        test::writeObjQuad(dir.file("quad.obj"));
        test::writeObjTorus(dir.file("torus.obj"), 1.0, 0.35, 16, 8);
        Object panel = emitter(Shape::Mesh, glm::vec3(2.0f, 1.5f, 1.0f), false);
        panel.file = dir.file("quad.obj");
        panel.transform.translate = glm::vec3(-0.5f, 0.9f, 0.0f);
        panel.transform.rotate = glm::vec3(-60.0f, 20.0f, 0.0f);  // front (+z) up and towards the camera
        panel.transform.scale = glm::vec3(0.6f, 0.4f, 1.0f);
        s.objects.push_back(panel);
        Object torus = emitter(Shape::Mesh, glm::vec3(1.5f, 1.2f, 1.0f), false);
        torus.file = dir.file("torus.obj");
        torus.transform.translate = glm::vec3(0.7f, 0.4f, -0.2f);
        torus.transform.rotate = glm::vec3(50.0f, 0.0f, 0.0f);
        torus.transform.scale = glm::vec3(0.3f);
        s.objects.push_back(torus);
        test::checkStrategiesAgree(*renderer, s, 64);
    }
}

TEST_CASE("a closed one-sided emitting shell is dark inside, two-sided it gives Le / (1 - a)", "[gpu][emitters]") {
    // The shell emits from its front, the outside, so the camera inside sees neither emission nor
    // anything for the albedo to reflect: exactly black. Two-sided, the closed form.
    auto renderer = test::makeRenderer();
    const glm::vec3 albedo(0.5f, 0.25f, 0.75f), Le(1.0f, 2.0f, 0.5f);
    Scene s = test::closedEmittingSphere(albedo, glm::vec3(0.0f));
    s.objects[0].emission = Le;
    const Film dark = test::renderFilm(*renderer, s, 16);
    for (const glm::vec3& m : dark.mean) REQUIRE(m == glm::vec3(0.0f));
    s.objects[0].twoSided = true;
    const test::ImageStats st = test::imageStats(test::renderFilm(*renderer, s, 64));
    for (int c = 0; c < 3; ++c) {
        const double expected = Le[c] / (1.0 - albedo[c]);
        INFO("channel " << c << ": " << st.mean[c] << " +- " << st.standardError[c] << ", expected " << expected);
        CHECK(std::abs(st.mean[c] - expected) <= 4.0 * st.standardError[c] + 1e-4 * expected);
        CHECK(st.standardError[c] < 0.01 * expected);
    }
}

TEST_CASE("a one-sided emitter seen from behind is its material, from the front its emission too", "[gpu][emitters]") {
    // A white quad filling the view, lit by a light behind the camera. From the front at max depth
    // 0 every pixel is Le exactly; from behind, 0; and at depth 1 the back looks exactly as
    // bright as the same quad without emission (per block, statistically).
    auto renderer = test::makeRenderer();
    Scene s;
    s.render.width = s.render.height = kSize;
    s.render.seed = 9;
    s.materials.push_back({"white", MaterialType::Diffuse, glm::vec3(0.8f), glm::vec3(0.0f)});
    s.camera.position = glm::vec3(0.0f, 0.0f, 2.0f);
    s.camera.lookAt = glm::vec3(0.0f);
    s.camera.fovDegrees = 40.0f;
    const glm::vec3 Le(3.0f, 2.0f, 1.0f);
    Object wall = emitter(Shape::Quad, Le, false);
    wall.material = "white";
    wall.transform.scale = glm::vec3(3.0f);
    s.objects.push_back(wall);
    Light l;
    l.type = LightType::Sphere;
    l.color = glm::vec3(2.0f);
    l.position = glm::vec3(0.5f, 0.5f, 4.0f);
    l.radius = 1.0f;
    s.lights.push_back(l);
    s.render.maxDepth = 0;
    for (const glm::vec3& m : test::renderFilm(*renderer, s, 4).mean) REQUIRE(m == Le);
    s.objects[0].transform.rotate = glm::vec3(0.0f, 180.0f, 0.0f);  // its front now faces away
    for (const glm::vec3& m : test::renderFilm(*renderer, s, 4).mean) REQUIRE(m == glm::vec3(0.0f));
    s.render.maxDepth = 1;
    const Film back = test::renderFilm(*renderer, s, 128);
    s.objects[0].emission = glm::vec3(0.0f);
    const Film plain = test::renderFilm(*renderer, s, 128);
    checkAgree(back, plain, "the back of a one-sided emitter vs the same quad without emission");
    CHECK(test::imageStats(back).mean.x > 0.01);  // it reflects
}
