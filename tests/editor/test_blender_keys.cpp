// The Blender-style key map (issue 15): its bindings, the modal transforms' maths, numpad views and
// hidden objects (editor/model/keymap.h, modal_transform.h).
#include "editor/model/keymap.h"
#include "editor/model/modal_transform.h"

#include <catch2/catch.hpp>

#include <set>
#include <string>

using namespace caustic;
using namespace caustic::editor;

namespace {

ModalStart startAtCentre(ModalKind kind, glm::vec2 mouse) {
    ModalStart s;
    s.kind = kind;
    s.camera.position = {0.0f, 0.0f, 5.0f};
    s.camera.lookAt = {0.0f, 0.0f, 0.0f};
    s.width = s.height = 500;
    s.viewport = {500.0f, 500.0f};
    s.mouse = mouse;
    return s;
}

glm::vec3 turned(const Transform& t, glm::vec3 v) { return glm::vec3(t.toMatrix() * glm::vec4(v, 0.0f)); }

}  // namespace

TEST_CASE("the Blender key map binds G R S, Shift+D, H, Alt+H and the numpad views, no chord twice", "[editor][keys]") {
    std::set<std::string> actions;
    for (KeymapStyle style : {KeymapStyle::Default, KeymapStyle::Blender}) {
        std::set<std::pair<std::string, int>> chords;
        for (const KeyBinding& b : keyBindings(style)) {
            INFO(chordText(b.chord));
            CHECK(chords.insert({chordText(b.chord), int(b.scope == KeyScope::Modal)}).second);
            CHECK_FALSE(b.what.empty());
            if (style == KeymapStyle::Blender) actions.insert(chordText(b.chord));
        }
    }
    for (const char* c : {"G", "R", "S", "Shift+D", "H", "Alt+H", "Numpad1", "Ctrl+Numpad1", "Numpad3", "Numpad7", "X", "Y",
                          "Z", "Escape", "Enter", "Ctrl+Z", "Delete"}) {
        INFO(c);
        CHECK(actions.count(c) == 1);
    }
    // The default map keeps its gizmo keys; the Blender one has none of them.
    bool gizmoInBlender = false;
    for (const KeyBinding& b : keyBindings(KeymapStyle::Blender)) gizmoInBlender |= b.action == Action::GizmoTranslate;
    CHECK_FALSE(gizmoInBlender);
    CHECK(mouseActions(KeymapStyle::Blender).size() > mouseActions(KeymapStyle::Default).size());
}

TEST_CASE("G moves with the mouse and keeps the object under the cursor, X Y Z constrain it", "[editor][keys]") {
    const ModalStart s = startAtCentre(ModalKind::Grab, {250.0f, 250.0f});
    const Transform t = modalTransform(s, ModalAxis::Free, {350.0f, 250.0f});
    CHECK(t.translate.x > 0.1f);
    CHECK(t.translate.y == Approx(0.0f).margin(1e-5));
    CHECK(t.translate.z == Approx(0.0f).margin(1e-5));
    const glm::vec2 shown = projectToViewport(s.camera, s.width, s.height, s.viewport, t.translate);
    CHECK(shown.x == Approx(350.0f).margin(0.5));
    CHECK(shown.y == Approx(250.0f).margin(0.5));
    // Up the screen is +y; along y only, a sideways motion moves nothing.
    CHECK(modalTransform(s, ModalAxis::Y, {250.0f, 150.0f}).translate.y > 0.1f);
    CHECK(glm::length(modalTransform(s, ModalAxis::Y, {350.0f, 250.0f}).translate) == Approx(0.0f).margin(1e-5));
    const Transform alongX = modalTransform(s, ModalAxis::X, {350.0f, 200.0f});
    CHECK(alongX.translate.x == Approx(t.translate.x).epsilon(1e-3));
    CHECK(alongX.translate.y == 0.0f);
    // Back where it started: the start transform.
    CHECK(modalTransform(s, ModalAxis::Free, s.mouse).translate == s.transform.translate);
}

TEST_CASE("R turns about the view axis by the angle the mouse sweeps, S scales by its distance", "[editor][keys]") {
    // From right of the object's image to below it: a quarter turn clockwise on screen.
    const ModalStart r = startAtCentre(ModalKind::Rotate, {350.0f, 250.0f});
    const Transform q = modalTransform(r, ModalAxis::Free, {250.0f, 350.0f});
    const glm::vec3 x = turned(q, {1.0f, 0.0f, 0.0f});
    CHECK(x.x == Approx(0.0f).margin(1e-4));
    CHECK(x.y == Approx(-1.0f).margin(1e-4));   // right -> down: clockwise as the camera sees it
    // About world y only: y stays.
    const Transform aboutY = modalTransform(r, ModalAxis::Y, {250.0f, 350.0f});
    CHECK(turned(aboutY, {0.0f, 1.0f, 0.0f}).y == Approx(1.0f).margin(1e-4));
    CHECK(turned(aboutY, {1.0f, 0.0f, 0.0f}).y == Approx(0.0f).margin(1e-4));
    const ModalStart s = startAtCentre(ModalKind::Scale, {300.0f, 250.0f});
    CHECK(modalTransform(s, ModalAxis::Free, {350.0f, 250.0f}).scale.x == Approx(2.0f));
    CHECK(modalTransform(s, ModalAxis::Free, {350.0f, 250.0f}).scale.z == Approx(2.0f));
    const Transform sx = modalTransform(s, ModalAxis::X, {250.0f, 350.0f});
    CHECK(sx.scale.x == Approx(2.0f));
    CHECK(sx.scale.y == Approx(1.0f));
}

TEST_CASE("numpad views look at the look-at point from an axis at the same distance", "[editor][keys]") {
    Camera c;
    c.position = {3.0f, 1.0f, 4.0f};
    c.lookAt = {0.0f, 1.0f, 0.0f};
    const Camera front = axisView(c, {0.0f, 0.0f, 1.0f});
    CHECK(front.position.x == Approx(0.0f).margin(1e-6));
    CHECK(front.position.y == Approx(1.0f));
    CHECK(front.position.z == Approx(5.0f));
    const Camera top = axisView(c, {0.0f, 1.0f, 0.0f});
    CHECK(top.position.y == Approx(6.0f));
    CHECK(top.up == glm::vec3(0.0f, 0.0f, -1.0f));   // not parallel to the view
    CHECK(axisView(c, {-1.0f, 0.0f, 0.0f}).position.x == Approx(-5.0f));
}

TEST_CASE("hidden objects are left out of the viewport's scene, with their indices mapped", "[editor][keys]") {
    Scene s;
    for (const char* n : {"a", "b", "c"}) {
        Object o;
        o.name = n;
        s.objects.push_back(o);
    }
    std::vector<int> index;
    const Scene v = withoutHidden(s, {"b"}, &index);
    REQUIRE(v.objects.size() == 2);
    CHECK(v.objects[1].name == "c");
    CHECK(index == std::vector<int>{0, 2});
    CHECK(withoutHidden(s, {}, &index).objects.size() == 3);
}

TEST_CASE("Blender keys: G then Z lifts (the scene is Y-up, Blender's Z is up), Y moves in depth", "[editor][keys]") {
    CHECK(constraintAxis('X', true) == ModalAxis::X);
    CHECK(constraintAxis('Z', true) == ModalAxis::Y);
    CHECK(constraintAxis('Y', true) == ModalAxis::Z);
    // The default key map names the scene's own axes.
    CHECK(constraintAxis('X', false) == ModalAxis::X);
    CHECK(constraintAxis('Y', false) == ModalAxis::Y);
    CHECK(constraintAxis('Z', false) == ModalAxis::Z);
    // And the constrained move goes where the axis says: G, Z, mouse up lifts the object.
    ModalStart start;
    start.kind = ModalKind::Grab;
    start.camera.position = glm::vec3(0.0f, 1.0f, 5.0f);
    start.camera.lookAt = glm::vec3(0.0f, 1.0f, 0.0f);
    start.viewport = glm::vec2(400.0f, 300.0f);
    start.mouse = glm::vec2(200.0f, 150.0f);
    const Transform moved = modalTransform(start, constraintAxis('Z', true), glm::vec2(200.0f, 100.0f));
    CHECK(moved.translate.y > 0.1f);
    CHECK(moved.translate.x == Approx(0.0f).margin(1e-5));
    CHECK(moved.translate.z == Approx(0.0f).margin(1e-5));
}
