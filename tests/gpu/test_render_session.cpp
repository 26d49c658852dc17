// The editor's render session (editor/model/render_session.h) driven headless with the real
// renderer on llvmpipe and a clock the test sets: what restarts accumulation and what does not,
// the preview resolution while something is dragged and its end, held updates while meshes
// import, compile errors that keep the last good scene, and the target being reached.
#include "editor/model/render_session.h"
#include "renderer/renderer.h"
#include "tests/gpu/gl_fixture.h"

#include <catch2/catch.hpp>

using namespace caustic;
using namespace caustic::editor;

namespace {

Scene smallScene() {
    Scene s;
    s.render.width = 32;
    s.render.height = 24;
    s.render.samples = 4;
    s.render.maxDepth = 2;
    Material white;
    white.name = "white";
    s.materials.push_back(white);
    s.objects.push_back(test::sphereAt("white", glm::vec3(0.0f), 1.0f));
    s.environment.type = EnvironmentType::Constant;
    return s;
}

// Steps until the session has the scene's target samples (or gives up after `limit` frames).
int stepUntilDone(RenderSession& session, Renderer& r, EditorState& state, double& now, int limit = 200) {
    int frames = 0;
    while (r.samplesDone() < session.target(state.scene) && frames < limit) {
        session.step(r, state, now, false);
        session.endFrame(0.02);
        now += 0.02;
        ++frames;
    }
    return frames;
}

}  // namespace

TEST_CASE("render session: restarts only for what changes the image, and reaches its target", "[gpu][editor]") {
    auto renderer = test::makeRenderer();
    EditorState state;
    state.scene = smallScene();
    RenderSession session;
    double now = 10.0;

    RenderStep first = session.step(*renderer, state, now, false);
    CHECK(first.restarted);
    CHECK(first.compiled);
    CHECK(session.sceneUploaded);
    stepUntilDone(session, *renderer, state, now);
    REQUIRE(renderer->samplesDone() == 4);
    now += 1.0;  // the edit hold is long over
    RenderStep done = session.step(*renderer, state, now, false);
    CHECK(!done.restarted);
    CHECK(done.targetReached);
    CHECK(done.show);
    CHECK(done.width == 32);
    CHECK(done.height == 24);
    const std::uint64_t generation = session.accumulationGeneration;

    // More target samples: no restart, the accumulated samples are kept and rendering goes on.
    RenderSettings more = state.scene.render;
    more.samples = 8;
    REQUIRE(state.apply(makeSetRender(state, more)));
    RenderStep after = session.step(*renderer, state, now, false);
    CHECK(!after.restarted);
    CHECK(session.accumulationGeneration == generation);
    CHECK(renderer->samplesDone() > 4);  // rendering went on from the 4 it had
    stepUntilDone(session, *renderer, state, now);
    CHECK(renderer->samplesDone() == 8);

    // A material no object uses: no restart either.
    REQUIRE(state.apply(makeAddMaterial(state)));
    CHECK(!session.step(*renderer, state, now, false).restarted);
    CHECK(session.accumulationGeneration == generation);

    // The used material's colour: a restart. With a script's cap of 2 samples (below the
    // scene's 8), the session renders exactly 2 after it.
    session.sampleCap = 2;
    Material red = state.scene.materials[0];
    red.albedo = glm::vec3(0.8f, 0.1f, 0.1f);
    REQUIRE(state.apply(makeSetMaterial(state, 0, red)));
    RenderStep restart = session.step(*renderer, state, now, false);
    CHECK(restart.restarted);
    CHECK(restart.compiled);
    CHECK(session.accumulationGeneration > generation);
    CHECK(renderer->samplesDone() <= 2);
    stepUntilDone(session, *renderer, state, now);
    CHECK(renderer->samplesDone() == 2);
    CHECK(!session.busy(renderer.get(), state.scene));
}

TEST_CASE("render session: a drag previews at a reduced size, and full size returns after it", "[gpu][editor]") {
    auto renderer = test::makeRenderer();
    EditorState state;
    state.scene = smallScene();
    RenderSession session;
    double now = 5.0;
    session.step(*renderer, state, now, false);
    // Tell the pacer that a sample is very slow (1 s for the 768 pixels), as on a slow machine.
    for (int i = 0; i < 20; ++i) session.pacer.record(1, 32 * 24, 1.0);

    session.noteInteraction(now);
    Camera moved = state.scene.camera;
    moved.position.x += 0.1f;
    REQUIRE(state.apply(makeSetCamera(state, moved)));
    RenderStep drag = session.step(*renderer, state, now, false);
    CHECK(drag.restarted);
    CHECK(session.previewDivisor > 1);
    CHECK(drag.width == 32 / session.previewDivisor);
    CHECK(!drag.targetReached);

    // The drag ends; after the hold the image refines back to full resolution (restarts).
    session.interacting = false;
    now += kInteractionHold + 0.01;
    int restarts = 0;
    for (int frame = 0; frame < 200 && session.previewDivisor > 1; ++frame) {
        restarts += session.step(*renderer, state, now, false).restarted;
        now += 0.02;
    }
    CHECK(restarts >= 1);
    CHECK(session.previewDivisor == 1);
}

TEST_CASE("render session: held updates wait, a failed compile keeps the last good scene", "[gpu][editor]") {
    auto renderer = test::makeRenderer();
    EditorState state;
    state.scene = smallScene();
    RenderSession session;
    double now = 1.0;
    session.step(*renderer, state, now, false);
    now += 1.0;

    // Meshes importing again: the edit waits, the renderer keeps accumulating the old scene.
    Material grey = state.scene.materials[0];
    grey.albedo = glm::vec3(0.3f);
    REQUIRE(state.apply(makeSetMaterial(state, 0, grey)));
    const std::uint64_t generation = session.accumulationGeneration;
    CHECK(!session.step(*renderer, state, now, true).restarted);
    CHECK(session.heldDirty != kDirtyNone);
    CHECK(session.accumulationGeneration == generation);
    // The hold ends: the edit goes.
    CHECK(session.step(*renderer, state, now, false).restarted);
    CHECK(session.heldDirty == kDirtyNone);

    // A mesh whose file is missing: the compile fails with the file's name; rendering goes on.
    Object mesh;
    mesh.shape = Shape::Mesh;
    mesh.file = "no-such-file.obj";
    mesh.material = "white";
    state.scene.objects.push_back(mesh);
    state.markDirty(kDirtyGeometry);
    RenderStep failed = session.step(*renderer, state, now, false);
    CHECK(failed.restarted);
    CHECK(!failed.compiled);
    CHECK(failed.error.find("no-such-file.obj") != std::string::npos);
    CHECK(session.renderError == failed.error);
    CHECK(session.sceneUploaded);
    CHECK(failed.show);  // the last good scene is still shown
    // Removing it compiles again and clears the error.
    state.scene.objects.pop_back();
    state.markDirty(kDirtyGeometry);
    RenderStep fixed = session.step(*renderer, state, now, false);
    CHECK(fixed.compiled);
    CHECK(session.renderError.empty());
}

TEST_CASE("render session: the viewport renders at its panel's size, Render to file at the output's", "[gpu][editor]") {
    auto renderer = test::makeRenderer();
    EditorState state;
    state.scene = smallScene();  // 32 x 24 output
    RenderSession session;
    double now = 1.0;
    session.setViewport(320, 200, true);
    // The output's 4:3 fitted into 320 x 200: 267 x 200.
    CHECK(session.viewportResolution(state.scene) == glm::ivec2(267, 200));
    RenderStep s = session.step(*renderer, state, now, false);
    CHECK(s.restarted);
    CHECK(s.width == 267);
    CHECK(s.height == 200);
    CHECK(session.renderedSize == glm::ivec2(267, 200));
    stepUntilDone(session, *renderer, state, now);
    now += 1.0;
    // All samples, but not at the output size: nothing for Render to file yet.
    CHECK(!session.step(*renderer, state, now, false).targetReached);
    // The panel grows: a restart at the new size. "1:1" (not fit): the output resolution.
    session.setViewport(640, 480, true);
    CHECK(session.step(*renderer, state, now, false).restarted);
    CHECK(session.renderedSize == glm::ivec2(640, 480));
    session.setViewport(640, 480, false);
    CHECK(session.step(*renderer, state, now, false).restarted);
    CHECK(session.renderedSize == glm::ivec2(32, 24));
    // Render to file: the output size whatever the panel, and the target is reached there.
    session.setViewport(640, 480, true);
    session.outputSize = true;
    session.step(*renderer, state, now, false);
    CHECK(session.renderedSize == glm::ivec2(32, 24));
    stepUntilDone(session, *renderer, state, now);
    CHECK(session.step(*renderer, state, now, false).targetReached);
}

TEST_CASE("render session: after an edit the image refines by halves, each step after a whole sample", "[gpu][editor]") {
    auto renderer = test::makeRenderer();
    EditorState state;
    state.scene = smallScene();
    state.scene.render.samples = 64;
    RenderSession session;
    session.setViewport(256, 192, true);
    double now = 1.0;
    session.step(*renderer, state, now, false);
    for (int i = 0; i < 20; ++i) session.pacer.record(1, 256 * 192, 2.0);  // a slow machine
    Camera moved = state.scene.camera;
    moved.position.y += 0.1f;
    REQUIRE(state.apply(makeSetCamera(state, moved)));
    session.step(*renderer, state, now, false);
    REQUIRE(session.previewDivisor == FramePacer::kMaxDivisor);
    now += kInteractionHold + 0.01;
    std::vector<int> divisors = {session.previewDivisor};
    for (int frame = 0; frame < 400 && session.previewDivisor > 1; ++frame) {
        const int before = session.previewDivisor;
        const int samplesBefore = renderer->samplesDone();
        session.step(*renderer, state, now, false);
        session.endFrame(0.02);
        now += 0.02;
        if (session.previewDivisor != before) {
            CHECK(session.previewDivisor * 2 == before);  // one step at a time
            CHECK(samplesBefore >= 1);                    // after a whole sample at the coarser size
            divisors.push_back(session.previewDivisor);
        }
    }
    CHECK(divisors == std::vector<int>{8, 4, 2, 1});
    CHECK(session.renderedSize == glm::ivec2(256, 192));
}

TEST_CASE("render session: with deferred builds a frame announces the program build before the frame that builds it", "[gpu][editor]") {
    auto renderer = test::makeRenderer();
    renderer->setDeferredProgramBuilds(true);
    EditorState state;
    state.scene = smallScene();
    RenderSession session;
    double now = 10.0;
    // The first scene: setScene builds nothing; two frames say "building", the third renders.
    RenderStep first = session.step(*renderer, state, now, false);
    CHECK(first.compiled);
    CHECK(session.buildingShaders);
    CHECK(renderer->programPending());
    CHECK(renderer->samplesDone() == 0);
    now += 0.05;
    session.step(*renderer, state, now, false);
    CHECK(session.buildingShaders);
    CHECK(renderer->programPending());
    now += 0.05;
    session.step(*renderer, state, now, false);
    CHECK_FALSE(renderer->programPending());
    CHECK_FALSE(session.buildingShaders);
    CHECK((renderer->samplesDone() > 0 || renderer->bandInProgress()));
    // An edit that needs no new program (a colour) renders at once.
    Material grey = state.scene.materials[0];
    grey.albedo = glm::vec3(0.3f);
    REQUIRE(state.apply(makeSetMaterial(state, 0, grey)));
    now += 1.0;
    RenderStep edit = session.step(*renderer, state, now, false);
    CHECK(edit.restarted);
    CHECK_FALSE(session.buildingShaders);
    // One that does (a mirror: a new material kind in the specialised program, where the
    // configuration specialises; else the general program serves it too).
    Material mirror = state.scene.materials[0];
    mirror.type = MaterialType::Mirror;
    REQUIRE(state.apply(makeSetMaterial(state, 0, mirror)));
    now += 1.0;
    session.step(*renderer, state, now, false);
    if (renderer->config().specialize) {
        CHECK(session.buildingShaders);
        const int before = renderer->samplesDone();
        now += 0.05;
        session.step(*renderer, state, now, false);
        CHECK(renderer->samplesDone() == before);   // nothing rendered with a program of another scene
        now += 0.05;
        session.step(*renderer, state, now, false);
        CHECK_FALSE(session.buildingShaders);
    } else {
        CHECK_FALSE(session.buildingShaders);
    }
}
