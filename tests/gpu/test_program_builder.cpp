// Builds in the background (renderer/program_builder.h, Renderer::setProgramBuilder): a renderer
// whose program is still being built renders nothing and returns at once (the builder is held, so
// this holds however slow the machine), then renders the same image as one that built it itself;
// a stand-in renders meanwhile only where it renders the scene right; a source that does not
// compile is reported as it is without the builder; a renderer gone before its build finishes
// leaves nothing behind.
#include "renderer/program_builder.h"
#include "renderer/program_cache.h"
#include "renderer/renderer.h"
#include "tests/gpu/gl_fixture.h"
#include "tests/support/meshes.h"  // TempDir

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

using namespace caustic;
using namespace caustic::test;
namespace fs = std::filesystem;

namespace {

std::shared_ptr<ProgramBuilder> startBuilder() {
    std::string error;
    ProgramBuilder::WorkerContext context = glContext().sharedWorkerContext(&error);
    INFO(error);
    REQUIRE(context.makeCurrent);
    auto builder = ProgramBuilder::start(std::move(context), &error);
    INFO(error);
    REQUIRE(builder);
    return builder;
}

// Waits (no time limit: a loaded machine builds slowly) until the builder has nothing left.
void drain(const ProgramBuilder& builder) {
    while (builder.outstanding() > 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

// A scene whose program no other test of this process builds (its own mix of kinds), so the
// builder really compiles (the on-disk cache is off for it), and which the general program cannot
// stand in for (a random walk under a surface: kGeneralMedia leaves it out), so that nothing
// renders until its own program is built, with either back-end's defaults.
Scene ownScene() {
    Scene s = cornellBox(24);
    s.materials[0].type = MaterialType::Surface;
    s.materials[0].subsurfaceWeight = 1.0f;
    s.materials[1].type = MaterialType::Conductor;   // a kind the box does not have
    s.render.samples = 4;
    return s;
}

struct NoProgramCache {
    std::string old = programCacheDir();
    NoProgramCache() { useProgramCache("off"); }
    ~NoProgramCache() { useProgramCache(old.empty() ? std::string("off") : old); }
};

}  // namespace

TEST_CASE("program builder: while the program builds nothing renders, then the image is the one built here",
          "[gpu][programs]") {
    glContext();
    const NoProgramCache noCache;   // set before the worker reads it
    const Scene scene = ownScene();
    auto builder = startBuilder();
    builder->hold(true);

    auto background = makeRenderer();
    background->setProgramBuilder(builder);
    std::string error;
    REQUIRE(background->setScene(scene, &error));   // returns without building
    CHECK(background->programPending());
    CHECK(builder->outstanding() == 0);

    // The first dispatch asks for the program and returns with nothing rendered; so does every
    // one while the build has not finished (held here).
    for (int i = 0; i < 3; ++i) {
        const Renderer::Progress p = background->renderFor(0.5, 4);
        CHECK(p.samplesCompleted == 0);
        CHECK(p.pixelSamples == 0);
        CHECK(background->waitingForBuild());
        CHECK(background->programPending());
        CHECK(background->programError().empty());
    }
    CHECK(background->samplesDone() == 0);
    CHECK(builder->outstanding() == 1);   // asked for once, not once per dispatch

    builder->hold(false);
    drain(*builder);
    CHECK(builder->completed() == 1);
    CHECK_FALSE(background->programPending());   // done: taken at the next dispatch
    background->render(4);
    CHECK_FALSE(background->waitingForBuild());
    REQUIRE(background->samplesDone() == 4);
    CHECK_FALSE(background->programFellBack());
    const Film fromWorker = background->readFilm();

    // The same program built on this thread renders the same samples bit for bit.
    auto here = makeRenderer();
    const Film built = renderFilm(*here, scene, 4);
    REQUIRE(built.mean.size() == fromWorker.mean.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < built.mean.size(); ++i) differ += built.mean[i] != fromWorker.mean[i];
    CHECK(differ == 0);
    CHECK(glDebugErrorCount() == 0);
}

TEST_CASE("program builder: the general program stands in only where it renders the scene right",
          "[gpu][programs]") {
    glContext();
    auto builder = startBuilder();
    IntegratorConfig config = testConfig();
    config.specialize = true;   // a program per scene, so that the general one is another (NVIDIA's default has none)
    auto r = makeRenderer(config);
    r->setProgramBuilder(builder);
    std::string error;
    REQUIRE(r->checkSource(&error));   // the general program, built here
    Scene scene = cornellBox(16);
    scene.materials[1].type = MaterialType::Mirror;   // another mix of kinds than other tests'
    builder->hold(true);
    REQUIRE(r->setScene(scene, &error));
    // Its own program is held: the general one renders meanwhile, samples that count.
    r->render(2);
    CHECK_FALSE(r->waitingForBuild());
    CHECK(r->standingIn());
    CHECK(r->programPending());
    CHECK(builder->outstanding() == 1);
    CHECK(r->samplesDone() == 2);
    const Film standIn = r->readFilm();

    // A scene whose media the general program leaves out (a random walk): nothing renders.
    Scene walk = scene;
    walk.materials[0].type = MaterialType::Surface;
    walk.materials[0].subsurfaceWeight = 1.0f;
    REQUIRE(r->setScene(walk, &error));
    const Renderer::Progress p = r->renderFor(0.5, 2);
    CHECK(p.samplesCompleted == 0);
    CHECK(p.pixelSamples == 0);
    CHECK(r->waitingForBuild());
    builder->hold(false);
    drain(*builder);
    r->render(2);
    CHECK(r->samplesDone() == 2);
    CHECK_FALSE(r->waitingForBuild());
    CHECK_FALSE(r->standingIn());

    // Back to the first scene, its own program built now: the stand-in's samples were the same.
    REQUIRE(r->setScene(scene, &error));
    r->render(2);
    CHECK_FALSE(r->standingIn());
    const Film own = r->readFilm();
    REQUIRE(own.mean.size() == standIn.mean.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < own.mean.size(); ++i)
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, double(std::abs(own.mean[i][c] - standIn.mean[i][c])) /
                                        std::max(1e-3, double(std::abs(own.mean[i][c]))));
    CHECK(worst < 1e-3);   // the same samples; the programs' arithmetic may differ in the last bits
}

TEST_CASE("program builder: a source that does not compile is reported by name, and no sample counts",
          "[gpu][programs]") {
    glContext();
    const TempDir tmp;
    const fs::path dir = tmp.path / "shaders";
    fs::copy(defaultShaderDir(), dir, fs::copy_options::recursive);
    std::ofstream(dir / "lights" / "environment.glsl", std::ios::app) << "\nthis is not GLSL (\n";

    auto builder = startBuilder();
    std::string error;
    auto r = Renderer::create(dir.string(), testConfig(), &error);
    if (!r) {   // where create() builds the general program (NVIDIA) it fails already
        CHECK(error.find("lights/environment.glsl") != std::string::npos);
        return;
    }
    r->setProgramBuilder(builder);
    REQUIRE(r->setScene(cornellBox(8), &error));
    // The scene's program fails on the worker, then the general one: then the error shows.
    for (int i = 0; i < 1000000 && r->programError().empty(); ++i) {
        r->renderFor(0.1, 1);
        drain(*builder);
    }
    INFO(r->programError());
    CHECK(r->programError().find("lights/environment.glsl") != std::string::npos);
    CHECK(r->samplesDone() == 0);
    CHECK_FALSE(r->programPending());
    CHECK(builder->completed() == 2);
}

TEST_CASE("program builder: a renderer gone before its build finishes leaves no program and no error",
          "[gpu][programs]") {
    glContext();
    const NoProgramCache noCache;
    auto builder = startBuilder();
    builder->hold(true);
    {
        auto r = makeRenderer();
        r->setProgramBuilder(builder);
        std::string error;
        Scene scene = ownScene();
        scene.materials[2].type = MaterialType::Dielectric;
        REQUIRE(r->setScene(scene, &error));
        r->renderFor(0.1, 1);
        CHECK(builder->outstanding() == 1);
    }
    builder->hold(false);
    drain(*builder);
    CHECK(builder->completed() == 1);   // abandoned before it started: counted, never compiled
    CHECK(builder->compiled() == 0);
    builder.reset();                     // joins the worker, which releases its context
    CHECK(glDebugErrorCount() == 0);
}
