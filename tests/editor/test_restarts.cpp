// Which edits restart accumulation: a new target sample count and a material no object uses keep
// the accumulated image until something that changes it goes to the renderer (dirtyForRenderer,
// editor/model/editor_state.h).
#include "editor/model/editor_state.h"

#include <catch2/catch.hpp>

#include <string>

using namespace caustic;
using namespace caustic::editor;

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
