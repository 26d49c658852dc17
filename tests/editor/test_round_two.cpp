// Issue 15's editor bugs, in the model: the Del key's focus rule, light gizmo edits, status
// figures, and edits that must not restart accumulation.
#include "editor/model/editor_state.h"
#include "editor/model/keymap.h"
#include "editor/model/render_session.h"
#include "editor/model/shortcuts.h"
#include "editor/model/status.h"
#include "editor/model/viewport_math.h"

#include <catch2/catch.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <set>
#include <string>
#include <utility>

using namespace caustic;
using namespace caustic::editor;

TEST_CASE("Del deletes in the viewport or outliner, never while a field has the keys", "[editor][keys]") {
    CHECK(deleteKeyDeletes({false, false, true}));
    CHECK_FALSE(deleteKeyDeletes({true, false, true}));    // a text field: Del deletes a character
    CHECK_FALSE(deleteKeyDeletes({false, true, true}));    // a slider being dragged
    CHECK_FALSE(deleteKeyDeletes({false, false, false}));  // the inspector (or nothing) focused
}

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

TEST_CASE("The sample rate is per second of elapsed time since the restart", "[editor][status]") {
    SampleRateMeter m;
    m.restart(10.0);
    CHECK_FALSE(m.known());
    // Each frame renders 0.01 s of samples in a 0.25 s frame: the wall-clock rate is what counts.
    m.observe(10.25, 0.04, true);
    m.observe(14.0, 0.64, true);
    CHECK(m.samplesPerSecond() == Approx(0.16));
    // Target reached: frames without rendering do not dilute it.
    m.observe(30.0, 0.64, false);
    CHECK(m.samplesPerSecond() == Approx(0.16));
    m.restart(30.0);
    CHECK_FALSE(m.known());
    CHECK(m.samplesPerSecond() == 0.0);
}

TEST_CASE("The ETA is the samples left at the wall-clock rate, durations read as s, min, h", "[editor][status]") {
    SampleRateMeter m;
    m.restart(0.0);
    CHECK(m.etaSeconds(0.0, 16.0) < 0.0);  // no rate yet: unknown
    m.observe(10.0, 4.0, true);             // 0.4 spp/s
    CHECK(m.etaSeconds(4.0, 16.0) == Approx(30.0));
    CHECK(m.etaSeconds(16.0, 16.0) == 0.0);
    CHECK(durationText(-1.0) == "-");
    CHECK(durationText(42.4) == "42 s");
    CHECK(durationText(185.0) == "3 min 05 s");
    CHECK(durationText(7800.0) == "2 h 10 min");
}

TEST_CASE("A shown error clears once its cause is gone", "[editor][status]") {
    const ShownError render{true, 7};
    CHECK(errorResolved(render, true, 7));          // the scene compiles again
    CHECK_FALSE(errorResolved(render, false, 8));   // still failing
    const ShownError refused{false, 7};
    CHECK_FALSE(errorResolved(refused, true, 7));   // nothing edited yet: a preview recompile is no fix
    CHECK(errorResolved(refused, true, 8));         // the next edit went through
}

namespace {

EditorState cornellBox() {
    EditorState s;
    std::string error;
    REQUIRE(s.open(std::string(CAUSTIC_SOURCE_DIR) + "/scenes/cornell-box.json", &error));
    s.takeDirty();
    return s;
}

}  // namespace

TEST_CASE("Changing the target samples keeps the accumulated image", "[editor][dirty]") {
    EditorState s = cornellBox();
    std::uint32_t deferred = kDirtyNone;
    RenderSettings r = s.scene.render;
    r.samples = s.scene.render.samples * 2;
    REQUIRE(s.apply(makeSetRender(s, r)));
    CHECK(s.history.undoCount() == 1);             // still an undo step (and the file changes)
    const std::uint32_t d = s.takeDirty();
    CHECK(d == kDirtyTarget);
    CHECK(dirtyForRenderer(d, &deferred) == kDirtyNone);   // nothing for the renderer: no restart
    // Lower than before: still no restart (the frame loop stops at the target).
    r.samples = 1;
    REQUIRE(s.apply(makeSetRender(s, r)));
    CHECK(dirtyForRenderer(s.takeDirty(), &deferred) == kDirtyNone);
    // The target with something else: that restarts.
    r.samples = 64;
    r.maxDepth = s.scene.render.maxDepth + 1;
    REQUIRE(s.apply(makeSetRender(s, r)));
    CHECK(dirtyForRenderer(s.takeDirty(), &deferred) == kDirtySettings);
    CHECK(deferred == kDirtyNone);
}

TEST_CASE("A material no object uses restarts nothing until something else does", "[editor][dirty]") {
    EditorState s = cornellBox();
    std::uint32_t deferred = kDirtyNone;
    REQUIRE(s.apply(makeAddMaterial(s)));
    const int added = s.selection.index;
    REQUIRE(s.selection.kind == EntityKind::Material);
    CHECK(s.takeDirty() == kDirtyUnseen);
    CHECK(dirtyForRenderer(kDirtyUnseen, &deferred) == kDirtyNone);
    // Its parameters, while unused: no restart either.
    Material m = s.scene.materials[static_cast<size_t>(added)];
    m.albedo = glm::vec3(0.1f, 0.9f, 0.1f);
    REQUIRE(s.apply(makeSetMaterial(s, added, m)));
    CHECK(dirtyForRenderer(s.takeDirty(), &deferred) == kDirtyNone);
    // A used material's parameters restart, and carry the deferred table change along.
    Material used = s.scene.materials[0];
    REQUIRE(std::any_of(s.scene.objects.begin(), s.scene.objects.end(), [&](const Object& o) { return o.material == used.name; }));
    used.albedo *= 0.5f;
    REQUIRE(s.apply(makeSetMaterial(s, 0, used)));
    const std::uint32_t d = dirtyForRenderer(s.takeDirty(), &deferred);
    CHECK((d & kDirtyMaterials) != 0);
    CHECK((d & kDirtyGeometry) != 0);   // the deferred addition: a full recompile
    CHECK(deferred == kDirtyNone);
    // Assigning the new material to an object is seen: a restart.
    Object o = s.scene.objects[0];
    o.material = s.scene.materials[static_cast<size_t>(added)].name;
    REQUIRE(s.apply(makeSetObject(s, 0, o)));
    CHECK(dirtyForRenderer(s.takeDirty(), &deferred) != kDirtyNone);
    // Now that it is used, editing it restarts.
    m.albedo = glm::vec3(0.2f);
    REQUIRE(s.apply(makeSetMaterial(s, added, m)));
    CHECK(s.takeDirty() == kDirtyMaterials);
    // Undo of the material's addition (after the object's undo) is unseen again.
    REQUIRE(s.undo());   // the used material's edit
    REQUIRE(s.undo());   // the assignment
    REQUIRE(s.undo());   // the other material's edit
    s.takeDirty();
    REQUIRE(s.undo());   // the first albedo edit
    REQUIRE(s.undo());   // the addition
    CHECK(s.takeDirty() == kDirtyUnseen);
    // A new scene hands over everything and drops what was deferred.
    deferred = kDirtyGeometry;
    CHECK(dirtyForRenderer(kDirtyAll, &deferred) == kDirtyAll);
    CHECK(deferred == kDirtyNone);
}

TEST_CASE("The key map: every action has one binding, no chord does two things in one place", "[editor][keys]") {
    std::set<int> actions;
    std::set<std::pair<int, std::string>> chords;  // (scope, chord)
    for (const KeyBinding& b : keyBindings()) {
        actions.insert(static_cast<int>(b.action));
        INFO(chordText(b.chord));
        CHECK(chords.insert({static_cast<int>(b.scope), chordText(b.chord)}).second);
        CHECK(!b.what.empty());
    }
    CHECK(actions.size() == keyBindings().size());
    CHECK(actions.size() == static_cast<std::size_t>(Action::GizmoLocal) + 1);
    // A viewport key shadowing a global one would do both.
    for (const KeyBinding& v : keyBindings())
        for (const KeyBinding& g : keyBindings())
            if (v.scope == KeyScope::Viewport && g.scope == KeyScope::Global) CHECK(chordText(v.chord) != chordText(g.chord));
    CHECK(chordText({"Z", true, true}) == "Ctrl+Shift+Z");
    CHECK(chordText({"F6", false, false}) == "F6");
}

TEST_CASE("Idle pacing starts a second after the last input, never while dragging or in scripts", "[editor][status]") {
    RenderSession session;
    session.noteInput(10.0);
    CHECK_FALSE(session.idle(10.5));
    CHECK(session.idle(10.0 + kIdleAfter + 0.01));
    session.interacting = true;
    CHECK_FALSE(session.idle(20.0));
    session.interacting = false;
    session.idlePacing = false;  // a script drives the frames
    CHECK_FALSE(session.idle(20.0));
    session.idlePacing = true;
    session.noteInput(19.9);
    CHECK_FALSE(session.idle(20.0));
}
