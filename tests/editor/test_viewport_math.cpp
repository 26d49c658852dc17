// The viewport's CPU geometry: rays match the GPU camera, picking finds what is under a pixel,
// camera navigation, and the inverse of Transform::toMatrix; plus the frame pacer.
#include "editor/model/editor_state.h"
#include "tests/editor/cornell_state.h"
#include "editor/model/frame_pacer.h"
#include "editor/model/viewport_math.h"
#include "renderer/gpu_scene.h"
#include "tests/support/meshes.h"

#include <catch2/catch.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <random>

using namespace caustic;
using namespace caustic::editor;

namespace {

EditorState cornell() { return test::openCornell(false); }

void checkNear(glm::vec3 a, glm::vec3 b, float eps = 1e-4f) {
    INFO("a = (" << a.x << ", " << a.y << ", " << a.z << "), b = (" << b.x << ", " << b.y << ", " << b.z << ")");
    CHECK(glm::length(a - b) < eps);
}

}  // namespace

TEST_CASE("camera rays match the GPU camera's frame constants", "[editor]") {
    EditorState s = cornell();
    for (auto [w, h, axis, roll] : {std::tuple{256, 256, FovAxis::Smaller, 0.0f}, std::tuple{400, 200, FovAxis::Smaller, 0.0f},
                                    std::tuple{200, 400, FovAxis::Larger, 30.0f}, std::tuple{300, 200, FovAxis::Y, -115.0f},
                                    std::tuple{200, 100, FovAxis::X, 30.0f}}) {
        s.scene.render.width = w;
        s.scene.render.height = h;
        s.scene.camera.fovAxis = axis;
        s.scene.camera.rollDegrees = roll;
        CompiledScene compiled;
        std::string error;
        REQUIRE(compileScene(s.scene, &compiled, &error));
        const gpu::GpuFrame f = makeFrame(s.scene, compiled, 0);
        // shaders/integrator/camera.glsl for pixel (px, py) and jitter j.
        const glm::vec2 pixel(37.25f, 101.5f);
        const float ndcX = 2.0f * pixel.x / float(w) - 1.0f, ndcY = 1.0f - 2.0f * pixel.y / float(h);
        const glm::vec3 gpuDir = glm::normalize(glm::vec3(f.camForward) + ndcX * glm::vec3(f.camRight) + ndcY * glm::vec3(f.camUp));
        const editor::Ray r = cameraRay(s.scene.camera, w, h, pixel);
        checkNear(r.origin, glm::vec3(f.camPosition));
        checkNear(r.direction, gpuDir);
    }
}

TEST_CASE("picking finds the object or light under a pixel", "[editor]") {
    EditorState s = cornell();
    const int w = s.scene.render.width, h = s.scene.render.height;
    auto pickAt = [&](float x, float y) {
        auto hit = pick(s.scene, cameraRay(s.scene.camera, w, h, glm::vec2(x, y) * glm::vec2(float(w), float(h))));
        return hit ? entityName(s.scene, hit->ref) : std::string("nothing");
    };
    CHECK(pickAt(0.5f, 0.25f) == "back");
    CHECK(pickAt(0.05f, 0.5f) == "left");
    CHECK(pickAt(0.95f, 0.5f) == "right");
    CHECK(pickAt(0.5f, 0.98f) == "floor");
    CHECK(pickAt(0.5f, 0.02f) == "ceiling");
    CHECK(pickAt(0.5f, 0.135f) == "ceiling light");     // in front of the ceiling
    // The small box (front right, low): project its centre.
    const Object& small = s.scene.objects[static_cast<size_t>(findEntity(s.scene, EntityKind::Object, "small box").index)];
    const glm::mat4 vp = projectionMatrix(s.scene.camera, w, h, 0.01f, 100.0f) * viewMatrix(s.scene.camera);
    glm::vec4 clip = vp * glm::vec4(small.transform.translate, 1.0f);
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    CHECK(pickAt(0.5f * (ndc.x + 1.0f), 0.5f * (1.0f - ndc.y)) == "small box");
    // Looking away from everything.
    s.scene.camera.lookAt = s.scene.camera.position + glm::vec3(0.0f, 0.0f, 1.0f);
    s.scene.objects.clear();
    s.scene.lights.clear();
    CHECK(pickAt(0.5f, 0.25f) == "nothing");
}

TEST_CASE("transformFromMatrix inverts Transform::toMatrix", "[editor]") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> angle(-179.0f, 179.0f), pitch(-89.0f, 89.0f), scale(0.1f, 3.0f), pos(-5.0f, 5.0f);
    for (int i = 0; i < 200; ++i) {
        Transform t;
        t.translate = {pos(rng), pos(rng), pos(rng)};
        t.rotate = {angle(rng), pitch(rng), angle(rng)};
        t.scale = {scale(rng), scale(rng), scale(rng)};
        if (i % 10 == 0) t.scale.x = -t.scale.x;
        const glm::mat4 m = t.toMatrix();
        const Transform back = transformFromMatrix(m);
        const glm::mat4 m2 = back.toMatrix();
        for (int c = 0; c < 4; ++c) checkNear(glm::vec3(m[c]), glm::vec3(m2[c]), 2e-4f);
        checkNear(back.translate, t.translate);
    }
    // Gimbal lock (pitch +-90) still reproduces the matrix.
    for (float b : {90.0f, -90.0f}) {
        Transform t;
        t.rotate = {30.0f, b, 10.0f};
        const glm::mat4 m = t.toMatrix(), m2 = transformFromMatrix(m).toMatrix();
        for (int c = 0; c < 4; ++c) checkNear(glm::vec3(m[c]), glm::vec3(m2[c]), 1e-4f);
    }
    Transform plain;
    const Transform back = transformFromMatrix(plain.toMatrix());
    checkNear(back.rotate, glm::vec3(0.0f));
    checkNear(back.scale, glm::vec3(1.0f));
}

TEST_CASE("camera navigation: orbit keeps the distance, pan moves both ends, dolly, fly, frame", "[editor]") {
    Camera c;
    c.position = {0.0f, 0.0f, 4.0f};
    c.lookAt = {0.0f, 0.0f, 0.0f};
    const Camera o = orbit(c, 90.0f, 0.0f);
    CHECK(glm::length(o.position - o.lookAt) == Approx(4.0f));
    checkNear(o.position, glm::vec3(4.0f, 0.0f, 0.0f));
    const Camera up = orbit(c, 0.0f, 30.0f);
    CHECK(up.position.y > 0.0f);
    CHECK(glm::length(up.position) == Approx(4.0f));
    const Camera pole = orbit(c, 0.0f, 120.0f);   // clamped below the pole
    CHECK(pole.position.y < 4.0f);
    CHECK(std::abs(pole.position.z) > 1e-3f);
    const Camera p = pan(c, 0.1f, 0.0f);
    checkNear(p.position - c.position, p.lookAt - c.lookAt);
    CHECK(p.lookAt.x < 0.0f);   // dragging right moves the view's content right: the camera left
    const Camera d = dolly(c, 0.5f);
    checkNear(d.position, glm::vec3(0.0f, 0.0f, 2.0f));
    const Camera f = fly(c, glm::vec3(0.0f, 0.0f, 1.0f));
    checkNear(f.position, glm::vec3(0.0f, 0.0f, 3.0f));
    checkNear(f.lookAt, glm::vec3(0.0f, 0.0f, -1.0f));
    const Camera framed = frameBounds(c, glm::vec3(9.0f), glm::vec3(11.0f), 1.0f);
    checkNear(framed.lookAt, glm::vec3(10.0f));
    checkNear(glm::normalize(framed.position - framed.lookAt), glm::vec3(0.0f, 0.0f, 1.0f));
    CHECK(glm::length(framed.position - framed.lookAt) > std::sqrt(3.0f));
}

TEST_CASE("frame selected fits the selection's bounds", "[editor]") {
    EditorState s = cornell();
    const EntityRef box = findEntity(s.scene, EntityKind::Object, "small box");
    auto b = entityBounds(s.scene, box);
    REQUIRE(b);
    CHECK(b->first.y == Approx(-1.0f).margin(1e-3));   // it stands on the floor
    auto all = sceneBounds(s.scene);
    REQUIRE(all);
    checkNear(all->first, glm::vec3(-1.0f), 0.02f);   // the large box reaches 1 cm below the floor
    checkNear(all->second, glm::vec3(1.0f), 0.02f);
    CHECK_FALSE(entityBounds(s.scene, {EntityKind::Camera, -1}));
}

TEST_CASE("frame selection knows a mesh's bounds: its local box under the object's transform", "[editor]") {
    Scene scene;
    Object mesh;
    mesh.name = "knot";
    mesh.shape = Shape::Mesh;
    mesh.file = "knot.obj";
    mesh.transform.translate = glm::vec3(10.0f, 0.0f, 0.0f);
    mesh.transform.rotate = glm::vec3(0.0f, 0.0f, 90.0f);   // x -> y
    mesh.transform.scale = glm::vec3(2.0f);
    scene.objects.push_back(mesh);
    const EntityRef ref{EntityKind::Object, 0};

    // Unknown extent (not imported yet): nothing to frame.
    CHECK_FALSE(entityBounds(scene, ref));
    CHECK_FALSE(sceneBounds(scene));

    const MeshBoundsLookup lookup = [](const Object& o) -> std::optional<std::pair<glm::vec3, glm::vec3>> {
        if (o.file != "knot.obj") return std::nullopt;
        return std::make_pair(glm::vec3(-1.0f, -0.5f, -0.25f), glm::vec3(3.0f, 0.5f, 0.25f));
    };
    auto b = entityBounds(scene, ref, lookup);
    REQUIRE(b);
    // Rotated 90 degrees about z: local x [-1, 3] becomes world y [-2, 6] after the scale, local
    // y [-0.5, 0.5] becomes world x [-1, 1] (around the translation), z is only scaled.
    CHECK(b->first.x == Approx(9.0f).margin(1e-4));
    CHECK(b->second.x == Approx(11.0f).margin(1e-4));
    CHECK(b->first.y == Approx(-2.0f).margin(1e-4));
    CHECK(b->second.y == Approx(6.0f).margin(1e-4));
    CHECK(b->first.z == Approx(-0.5f).margin(1e-4));
    CHECK(b->second.z == Approx(0.5f).margin(1e-4));
    auto all = sceneBounds(scene, lookup);
    REQUIRE(all);
    CHECK(all->first.x == Approx(9.0f).margin(1e-4));

    // Framing those bounds looks at their centre.
    const Camera framed = frameBounds(scene.camera, b->first, b->second, 1.0f);
    CHECK(framed.lookAt.x == Approx(10.0f).margin(1e-4));
    CHECK(framed.lookAt.y == Approx(2.0f).margin(1e-4));

    // The renderer's own copy gives the same box: prepareMesh's BVH root.
    test::TempDir dir;
    const std::string file = dir.file("quad.obj");
    test::writeObjQuad(file);
    MeshCacheEntry entry;
    std::string error;
    REQUIRE(prepareMesh(file, &entry, &error));
    const Aabb root = entry.blas.bvh.nodes.front().bounds();
    CHECK(root.min.x == Approx(-1.0f));
    CHECK(root.max.y == Approx(1.0f));
}

TEST_CASE("snapping rounds to the step", "[editor]") {
    checkNear(snapTo(glm::vec3(0.26f, -0.74f, 1.0f), 0.25f), glm::vec3(0.25f, -0.75f, 1.0f));
    checkNear(snapTo(glm::vec3(0.26f), 0.0f), glm::vec3(0.26f));
}

TEST_CASE("the frame pacer turns measured speed into a preview size", "[editor]") {
    FramePacer p;
    CHECK(p.previewDivisor(16 * 65536, 0.025) == 1);   // nothing measured yet
    p.record(2, 65536, 0.02);                     // 10 ms per sample at 256x256
    CHECK(p.previewDivisor(65536, 0.025) == 1);
    CHECK(p.previewDivisor(16 * 65536, 0.025) == 4);   // 160 ms / 16 < 25 ms (a power of two: 3 would do)
    CHECK(p.previewDivisor(4 * 65536, 0.025) == 2);    // 40 ms / 4 < 25 ms
    CHECK(p.previewDivisor(1000 * 65536, 0.025) == 8); // at most 8
    p.record(1, 65536, 0.1);   // the scene became heavier: the estimate follows quickly
    CHECK(p.secondsPerSample(65536) > 0.05);
}

TEST_CASE("light outlines: a rect's corners and normal, a sphere's silhouette, a spot's cone, a point's axes",
          "[editor]") {
    Camera cam;
    cam.position = glm::vec3(0, 0, 5);
    cam.lookAt = glm::vec3(0, 0, 0);
    // A rect light 2 x 1 (scale 1, 0.5) turned to face down (+z to -y), at y = 2.
    Light rect;
    rect.type = LightType::Rect;
    rect.transform.translate = glm::vec3(0, 2, 0);
    rect.transform.rotate = glm::vec3(90, 0, 0);
    rect.transform.scale = glm::vec3(1, 0.5f, 1);
    auto lines = lightOutline(rect, cam, 0.5f);
    REQUIRE(lines.size() == 2);
    REQUIRE(lines[0].size() == 5);
    for (const glm::vec3& p : lines[0]) {
        CHECK(p.y == Approx(2.0f).margin(1e-5));
        CHECK(std::abs(p.x) == Approx(1.0f).margin(1e-5));
        CHECK(std::abs(p.z) == Approx(0.5f).margin(1e-5));
    }
    CHECK(lines[0].front() == lines[0].back());
    // The normal: from the centre, 0.5 long, down (+z rotated 90 degrees about x is -y).
    CHECK(glm::length(lines[1][1] - lines[1][0]) == Approx(0.5f));
    CHECK(lines[1][1].y == Approx(1.5f).margin(1e-5));

    // A sphere light: every silhouette point at the radius, perpendicular to the view towards it.
    Light sphere;
    sphere.type = LightType::Sphere;
    sphere.position = glm::vec3(1, 0, 0);
    sphere.radius = 0.3f;
    lines = lightOutline(sphere, cam, 0.5f);
    REQUIRE(lines.size() == 1);
    const glm::vec3 view = glm::normalize(cam.position - sphere.position);
    for (const glm::vec3& p : lines[0]) {
        CHECK(glm::length(p - sphere.position) == Approx(0.3f));
        CHECK(glm::dot(p - sphere.position, view) == Approx(0.0f).margin(1e-5));
    }

    // A spot: the circle at `size` along the direction with radius size tan(outer); four edges.
    Light spot;
    spot.type = LightType::Spot;
    spot.position = glm::vec3(0, 3, 0);
    spot.direction = glm::vec3(0, -2, 0);
    spot.outerAngle = 30.0f;
    lines = lightOutline(spot, cam, 1.0f);
    REQUIRE(lines.size() == 5);
    for (const glm::vec3& p : lines[0]) {
        CHECK(p.y == Approx(2.0f));
        CHECK(glm::length(glm::vec2(p.x, p.z)) == Approx(std::tan(glm::radians(30.0f))));
    }
    for (size_t i = 1; i < 5; ++i) CHECK(lines[i][0] == spot.position);

    Light point;
    point.position = glm::vec3(0.5f, 0, 0);
    lines = lightOutline(point, cam, 2.0f);
    REQUIRE(lines.size() == 3);
    for (const auto& l : lines) CHECK(glm::length(l[1] - l[0]) == Approx(1.0f));
}
