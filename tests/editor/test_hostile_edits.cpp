// Edits the scene file could not hold are refused (issue 12, docs/reliability.md): NaN or
// infinity in a transform, a target of 0 samples. Before, the editor took them and the scene could
// then not be saved ("not saved, the scene is invalid").
#include "editor/model/editor_state.h"
#include "tests/editor/cornell_state.h"
#include "renderer/scene_io.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <limits>

#include <unistd.h>

using namespace caustic;
using namespace caustic::editor;
namespace fs = std::filesystem;

namespace {

using test::kCornell;
EditorState cornell() { return test::openCornell(); }

// The scene still saves (and loads back) after whatever was tried.
void requireSaveable(const EditorState& s) {
    const fs::path file = fs::temp_directory_path() / ("caustic-hostile-edit-" + std::to_string(::getpid()) + ".json");
    std::string error;
    CHECK(saveScene(s.scene, file.string(), &error));
    INFO(error);
    CHECK(loadScene(file.string()));
    fs::remove(file);
}

}  // namespace

TEST_CASE("hostile: a translation of NaN or infinity is refused, naming the place", "[editor][hostile]") {
    for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(), static_cast<float>(1e39)}) {
        INFO(bad);
        EditorState s = cornell();
        const Scene before = s.scene;
        Object o = s.scene.objects[2];
        o.transform.translate.y = bad;
        std::string why;
        CHECK_FALSE(s.apply(makeSetObject(s, 2, o), &why));
        CHECK(why.find("edit refused: objects[2].transform.translate[1]: must be a finite 32-bit float") == 0);
        // A drag step is refused the same way.
        CHECK_FALSE(s.applyContinuous(makeSetObject(s, 2, o), &why));
        CHECK(s.scene == before);
        CHECK_FALSE(s.history.canUndo());
        CHECK_FALSE(s.modified());
        CHECK(s.pendingDirty() == kDirtyNone);
        requireSaveable(s);
    }
}

TEST_CASE("hostile: non-finite light, camera and material values are refused", "[editor][hostile]") {
    EditorState s = cornell();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::string why;
    // A light object's emission and a light's colour.
    const int lamp = findEntity(s.scene, EntityKind::Object, "ceiling light").index;
    REQUIRE(lamp >= 0);
    Object emitter = s.scene.objects[static_cast<size_t>(lamp)];
    emitter.emission.y = nan;
    CHECK_FALSE(s.apply(makeSetObject(s, lamp, emitter), &why));
    CHECK(why.find("objects[" + std::to_string(lamp) + "].emission[1]") != std::string::npos);
    emitter.emission.y = -1.0f;
    CHECK_FALSE(s.apply(makeSetObject(s, lamp, emitter), &why));
    REQUIRE(s.apply(makeAddLight(s, LightType::Rect)));
    Light l = s.scene.lights[0];
    l.color.x = nan;
    CHECK_FALSE(s.apply(makeSetLight(s, 0, l), &why));
    CHECK(why.find("lights[0].color[0]") != std::string::npos);
    REQUIRE(s.undo());  // the added light
    Camera c = s.scene.camera;
    c.fovDegrees = nan;
    CHECK_FALSE(s.apply(makeSetCamera(s, c), &why));
    CHECK(why.find("edit refused: camera.fov: ") == 0);
    Material m = s.scene.materials[0];
    m.albedo = glm::vec3(std::numeric_limits<float>::infinity());
    CHECK_FALSE(s.apply(makeSetMaterial(s, 0, m), &why));
    CHECK(why.find("edit refused: materials[0].albedo[0]: ") == 0);
    Environment e = s.scene.environment;
    e.type = EnvironmentType::Constant;  // intensity belongs to it (a 'none' environment stores none)
    e.intensity = -nan;
    CHECK_FALSE(s.apply(makeSetEnvironment(s, e), &why));
    CHECK(why.find("edit refused: environment.intensity: ") == 0);
    CHECK_FALSE(s.history.canUndo());
    requireSaveable(s);
}

TEST_CASE("hostile: a target of 0 samples is refused, and a valid edit still applies", "[editor][hostile]") {
    EditorState s = cornell();
    RenderSettings r = s.scene.render;
    r.samples = 0;
    std::string why;
    CHECK_FALSE(s.apply(makeSetRender(s, r), &why));
    CHECK(why == "edit refused: render.samples: must be >= 1, got 0");
    CHECK(s.scene.render.samples != 0);
    requireSaveable(s);

    r.samples = 7;
    CHECK(s.apply(makeSetRender(s, r), &why));
    CHECK(s.scene.render.samples == 7);
    Object o = s.scene.objects[0];
    o.transform.translate.x += 0.25f;
    CHECK(s.applyContinuous(makeSetObject(s, 0, o)));
    CHECK(s.history.undoCount() == 2);
    requireSaveable(s);
}
