// The gizmo on lights: each light type offers only the handles it has, and a rotation changes a
// light only where the light has a direction (editor/model/viewport_math.h).
#include "editor/model/editor_state.h"
#include "editor/model/viewport_math.h"

#include <catch2/catch.hpp>

#include <glm/gtc/matrix_transform.hpp>

using namespace caustic;
using namespace caustic::editor;

namespace {

EditorState stateWithLight(LightType type) {
    EditorState st;
    Light l;
    l.name = "light";
    l.type = type;
    l.position = {1.0f, 2.0f, 3.0f};
    l.direction = {0.0f, -1.0f, 0.0f};
    st.scene.lights.push_back(l);
    st.takeDirty();
    return st;
}

// What ImGuizmo's world-space rotate hands back: the delta rotation about the gizmo's centre.
glm::mat4 rotatedAboutCentre(const glm::mat4& m, float degrees, glm::vec3 axis) {
    glm::mat4 r = glm::rotate(glm::mat4(1.0f), glm::radians(degrees), axis) * m;
    r[3] = m[3];
    return r;
}

}  // namespace

TEST_CASE("The gizmo offers each light only what it has", "[editor][gizmo]") {
    for (LightType type : {LightType::Point, LightType::Sphere, LightType::Spot, LightType::Rect}) {
        const EditorState st = stateWithLight(type);
        const GizmoOps ops = gizmoOpsFor(st.scene, {EntityKind::Light, 0});
        CHECK(ops.translate);
        CHECK(ops.rotate == (type == LightType::Spot || type == LightType::Rect));
        CHECK(ops.scale == (type == LightType::Rect));
    }
}

TEST_CASE("Rotating a point or sphere light changes nothing and records no undo step", "[editor][gizmo]") {
    for (LightType type : {LightType::Point, LightType::Sphere}) {
        EditorState st = stateWithLight(type);
        const Light before = st.scene.lights[0];
        const glm::mat4 m = rotatedAboutCentre(lightGizmoMatrix(before), 40.0f, {1.0f, 0.0f, 0.0f});
        REQUIRE(st.applyContinuous(makeSetLight(st, 0, lightFromGizmo(before, m))));
        st.seal();
        CHECK(st.scene.lights[0] == before);
        CHECK(st.history.undoCount() == 0);
        CHECK(st.pendingDirty() == kDirtyNone);   // no restart
        CHECK_FALSE(st.modified());
    }
}

TEST_CASE("Rotating a spot light turns its direction, turning it about its axis does nothing", "[editor][gizmo]") {
    EditorState st = stateWithLight(LightType::Spot);
    const Light before = st.scene.lights[0];
    const glm::mat4 m0 = lightGizmoMatrix(before);
    CHECK(glm::length(glm::vec3(m0[2]) - before.direction) < 1e-6f);
    CHECK(glm::length(glm::vec3(m0[3]) - before.position) < 1e-6f);

    // About its own axis: the same light, no step.
    REQUIRE(st.apply(makeSetLight(st, 0, lightFromGizmo(before, rotatedAboutCentre(m0, 75.0f, before.direction)))));
    CHECK(st.history.undoCount() == 0);
    CHECK(st.pendingDirty() == kDirtyNone);

    // 90 degrees about +x turns -y into -z; the position stays.
    REQUIRE(st.apply(makeSetLight(st, 0, lightFromGizmo(before, rotatedAboutCentre(m0, 90.0f, {1.0f, 0.0f, 0.0f})))));
    const Light& after = st.scene.lights[0];
    CHECK(glm::length(after.direction - glm::vec3(0.0f, 0.0f, -1.0f)) < 1e-5f);
    CHECK(glm::length(after.position - before.position) < 1e-6f);
    CHECK(st.history.undoCount() == 1);
    CHECK((st.takeDirty() & kDirtyLights) != 0);
    REQUIRE(st.undo());
    CHECK(st.scene.lights[0] == before);

    // Moving it moves it.
    glm::mat4 moved = m0;
    moved[3] += glm::vec4(0.5f, 0.0f, 0.0f, 0.0f);
    const Light t = lightFromGizmo(before, moved);
    CHECK(t.position.x == Approx(1.5f));
    CHECK(t.direction == before.direction);
}
