// Emitters with a surface (an object's own "emission", docs/scene-format.md): what compileScene
// makes of them. The object keeps its material's scattering in a copy that carries the emission;
// one-sided emitters flag their primitives (or instance) so that the back sees no emission, and
// their lights say so too: no LIGHT_FLAG_TWO_SIDED, and light-tree bounds whose normal cone holds
// only the front normals (a quad's: its front normal with theta_o = 0). The rendering side of the
// same contract is tests/gpu/test_surface_emitters.cpp.
#include "renderer/gpu_scene.h"
#include "renderer/scene_io.h"
#include "tests/support/meshes.h"

#include <catch2/catch.hpp>

#include <numbers>

using namespace caustic;

namespace {

Scene baseScene() {
    Scene s;
    s.materials.push_back({"white", MaterialType::Diffuse, glm::vec3(0.8f, 0.7f, 0.6f), glm::vec3(0.0f)});
    s.materials.push_back({"glow", MaterialType::Diffuse, glm::vec3(0.5f), glm::vec3(2.0f)});
    return s;
}

Object object(Shape shape, const char* material, glm::vec3 emission = glm::vec3(0.0f), bool twoSided = false) {
    Object o;
    o.shape = shape;
    o.material = material;
    o.emission = emission;
    o.twoSided = twoSided;
    return o;
}

CompiledScene compile(const Scene& s) {
    CompiledScene c;
    std::string error;
    const bool ok = compileScene(s, &c, &error);
    INFO(error);
    REQUIRE(ok);
    return c;
}

}  // namespace

TEST_CASE("an object's own emission: a one-sided quad keeps its material and emits from its front", "[emitters]") {
    Scene s = baseScene();
    s.objects.push_back(object(Shape::Quad, "white"));  // the material's plain users stay plain
    Object lamp = object(Shape::Quad, "white", glm::vec3(3.0f, 2.0f, 1.0f));
    lamp.transform.rotate = glm::vec3(90.0f, 0.0f, 0.0f);  // front (+z) to -y
    s.objects.push_back(lamp);
    const CompiledScene c = compile(s);
    REQUIRE(c.primitives.size() == 2);
    REQUIRE(c.lights.size() == 1);
    const gpu::GpuPrimitive& plain = c.primitives[0];
    const gpu::GpuPrimitive& p = c.primitives[1];
    CHECK(plain.info.w == 0u);
    CHECK(plain.info.z == 0u);  // not a light
    CHECK(glm::vec3(c.materials[plain.info.y].emission) == glm::vec3(0.0f));  // (w: the normal map's scale)
    CHECK(p.info.w == PRIM_FLAG_ONE_SIDED_EMITTER);
    CHECK(p.info.z == 1u);  // light 0
    const gpu::GpuMaterial& m = c.materials[p.info.y];
    CHECK(p.info.y != plain.info.y);
    CHECK(glm::vec3(m.emission) == glm::vec3(3.0f, 2.0f, 1.0f));
    CHECK(glm::vec3(m.albedo) == glm::vec3(0.8f, 0.7f, 0.6f));  // it still reflects, as white
    CHECK(m.info.x == MAT_DIFFUSE);
    const gpu::GpuLight& l = c.lights[0];
    CHECK(l.info.x == LIGHT_RECT);
    CHECK((l.info.y & LIGHT_FLAG_TWO_SIDED) == 0u);
    CHECK(glm::vec3(l.color) == glm::vec3(3.0f, 2.0f, 1.0f));
    const LightBounds& b = c.lightBounds[0];
    CHECK(b.cosThetaO == 1.0f);
    CHECK(b.axis.x == Approx(0.0f).margin(1e-6));
    CHECK(b.axis.y == Approx(-1.0f));
    CHECK(b.axis.z == Approx(0.0f).margin(1e-6));
    CHECK(b.cosThetaE == 0.0f);

    SECTION("two_sided: both faces, and normals every way") {
        s.objects[1].twoSided = true;
        const CompiledScene t = compile(s);
        CHECK(t.primitives[1].info.w == 0u);
        CHECK((t.lights[0].info.y & LIGHT_FLAG_TWO_SIDED) != 0u);
        CHECK(t.lightBounds[0].cosThetaO == -1.0f);
        CHECK(t.lightPower[0] == Approx(2.0f * c.lightPower[0]));
    }
}

TEST_CASE("an object's own emission on spheres, boxes and meshes", "[emitters]") {
    SECTION("a material's emission stays two-sided, an object's is one-sided") {
        Scene s = baseScene();
        s.objects.push_back(object(Shape::Sphere, "glow"));
        s.objects.push_back(object(Shape::Sphere, "white", glm::vec3(1.0f)));
        s.objects[1].transform.translate = glm::vec3(3.0f, 0.0f, 0.0f);
        const CompiledScene c = compile(s);
        REQUIRE(c.lights.size() == 2);
        CHECK(c.primitives[0].info.w == 0u);
        CHECK((c.lights[0].info.y & LIGHT_FLAG_TWO_SIDED) != 0u);
        CHECK(c.primitives[1].info.w == PRIM_FLAG_ONE_SIDED_EMITTER);
        CHECK(c.lights[1].info.x == LIGHT_SPHERE);
        CHECK((c.lights[1].info.y & LIGHT_FLAG_TWO_SIDED) == 0u);
        // The object's emission replaces the material's: a glowing material made to emit 5.
        s.objects[0].emission = glm::vec3(5.0f);
        const CompiledScene d = compile(s);
        CHECK(glm::vec3(d.materials[d.primitives[0].info.y].emission) == glm::vec3(5.0f));
        CHECK(glm::vec3(d.materials[0].emission) == glm::vec3(0.0f));  // white untouched
        CHECK(glm::vec3(d.materials[1].emission) == glm::vec3(2.0f));  // glow untouched
    }
    SECTION("a box: six one-sided faces, each facing out") {
        Scene s = baseScene();
        s.objects.push_back(object(Shape::Box, "white", glm::vec3(1.0f)));
        s.objects[0].transform.scale = glm::vec3(0.5f, 1.0f, 2.0f);
        const CompiledScene c = compile(s);
        REQUIRE(c.lights.size() == 6);
        for (size_t i = 0; i < 6; ++i) {
            INFO("face " << i);
            CHECK(c.primitives[i].info.w == PRIM_FLAG_ONE_SIDED_EMITTER);
            CHECK((c.lights[i].info.y & LIGHT_FLAG_TWO_SIDED) == 0u);
            const LightBounds& b = c.lightBounds[i];
            CHECK(b.cosThetaO == 1.0f);
            // The face's centre lies along its normal from the box's centre (the origin).
            const glm::vec3 centre = 0.5f * (b.boundsMin + b.boundsMax);
            CHECK(glm::dot(b.axis, centre) > 0.4f);
            CHECK(glm::length(glm::cross(b.axis, centre)) < 1e-5f);
        }
    }
    SECTION("meshes: the instance carries the flag; the normal cone follows the front faces") {
        test::TempDir dir;
        test::writeObjQuad(dir.file("quad.obj"));
        test::writeObjSphere(dir.file("ball.obj"), 6, 12);
        Scene s = baseScene();
        Object flat = object(Shape::Mesh, "white", glm::vec3(2.0f));
        flat.file = dir.file("quad.obj");
        flat.transform.rotate = glm::vec3(0.0f, 90.0f, 0.0f);  // +z to +x
        s.objects.push_back(flat);
        Object ball = object(Shape::Mesh, "white", glm::vec3(2.0f));
        ball.file = dir.file("ball.obj");
        ball.transform.translate = glm::vec3(0.0f, 3.0f, 0.0f);
        s.objects.push_back(ball);
        Object glowing = object(Shape::Mesh, "glow");  // a material's emission: two-sided
        glowing.file = dir.file("ball.obj");
        glowing.transform.translate = glm::vec3(0.0f, -3.0f, 0.0f);
        s.objects.push_back(glowing);
        const CompiledScene c = compile(s);
        REQUIRE(c.instances.size() == 3);
        REQUIRE(c.lights.size() == 3);
        CHECK(c.instances[0].flags == PRIM_FLAG_ONE_SIDED_EMITTER);
        CHECK(c.instances[1].flags == PRIM_FLAG_ONE_SIDED_EMITTER);
        CHECK(c.instances[2].flags == 0u);
        CHECK((c.lights[0].info.y & LIGHT_FLAG_TWO_SIDED) == 0u);
        CHECK((c.lights[1].info.y & LIGHT_FLAG_TWO_SIDED) == 0u);
        CHECK((c.lights[2].info.y & LIGHT_FLAG_TWO_SIDED) != 0u);
        // The flat one: every normal is +x.
        CHECK(c.lightBounds[0].axis.x == Approx(1.0f));
        CHECK(c.lightBounds[0].cosThetaO > 0.9999f);
        // The closed one: its normals point every way.
        CHECK(c.lightBounds[1].cosThetaO == -1.0f);
        CHECK(c.lightBounds[2].cosThetaO == -1.0f);
        CHECK(c.lightPower[0] == Approx(std::numbers::pi * 2.0 * 4.0).epsilon(1e-5));  // pi L A, one side
    }
}

TEST_CASE("an object's emission survives saving, and its sidedness is written with it", "[emitters][scene_io]") {
    Scene s = baseScene();
    s.objects.push_back(object(Shape::Quad, "white", glm::vec3(1.0f, 2.0f, 3.0f), true));
    s.objects.push_back(object(Shape::Sphere, "white"));
    const std::string json = sceneToJson(s);
    INFO(json);
    const SceneLoadResult back = parseScene(json, "saved.json");
    INFO(back.error);
    REQUIRE(back);
    CHECK(back.scene->objects == s.objects);
    // A plain object writes neither key.
    CHECK(json.find("\"two_sided\": true") != std::string::npos);
    CHECK(json.find("two_sided\": false") == std::string::npos);
}
