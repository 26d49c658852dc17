// A shader source that stops compiling while a renderer runs (the editor's "Reload shaders", a
// developer editing shaders/): the editor builds a fresh renderer from the new sources and keeps
// the old one unless Renderer::checkSource says the whole integrator compiles
// (editor/ui/editor_app.cpp, reloadShaders). On llvmpipe create() builds no integrator (each scene
// gets its own), so create() alone proves nothing there: this checks that
// checkSource and setScene both fail with the broken file's name, and that the renderer made
// from the good sources still renders.
#include "editor/model/render_session.h"
#include "renderer/shader_loader.h"
#include "tests/gpu/gl_fixture.h"
#include "tests/support/meshes.h"  // TempDir

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>


using namespace caustic;
using namespace caustic::test;
namespace fs = std::filesystem;

namespace {

// A copy of the shaders whose lights/environment.glsl does not compile.
fs::path brokenShaderDir(const TempDir& tmp) {
    const fs::path dir = tmp.path / "shaders";
    fs::copy(defaultShaderDir(), dir, fs::copy_options::recursive);
    std::ofstream env(dir / "lights" / "environment.glsl", std::ios::app);
    env << "\nthis is not GLSL (\n";
    return dir;
}

}  // namespace

TEST_CASE("a broken shader source fails checkSource and setScene by name, and the last renderer still renders",
          "[gpu][editor]") {
    glContext();
    auto good = makeRenderer();
    const Scene scene = cornellBox(16);
    const Film before = renderFilm(*good, scene, 1);

    const TempDir tmp;
    const fs::path dir = brokenShaderDir(tmp);

    std::string error;
    auto fresh = Renderer::create(dir.string(), testConfig(), &error);
    if (!fresh) {
        // Where create() builds the general integrator (specialisation off: NVIDIA), it fails here.
        CHECK(error.find("lights/environment.glsl") != std::string::npos);
    } else {
        CHECK_FALSE(fresh->checkSource(&error));
        INFO(error);
        CHECK(error.find("lights/environment.glsl") != std::string::npos);
        // A scene's own program is built from the same sources: it fails too, with the name.
        std::string sceneError;
        CHECK_FALSE(fresh->setScene(scene, &sceneError));
        INFO(sceneError);
        CHECK(sceneError.find("lights/environment.glsl") != std::string::npos);
    }

    // The renderer made from the good sources is untouched: its next samples accumulate.
    good->render(1);
    CHECK(good->samplesDone() == 2);
    const Film after = good->readFilm();
    REQUIRE(after.width == before.width);
    REQUIRE(after.height == before.height);
    // Two samples of the lit box: every channel's mean is positive and finite.
    const ImageStats stats = imageStats(after);
    for (int c = 0; c < 3; ++c) CHECK((stats.mean[c] > 0.0 && std::isfinite(stats.mean[c])));
}

// A scene's own program that fails to build leaves the general one rendering (selectProgram): the
// image is the scene's, only slower, so the renderer says so (programFellBack) and caustic-bench
// marks the row FALLBACK; compare.py and ab.py refuse such rows. Without it an A/B of a shader
// change that broke only the specialised build would measure the general program.
TEST_CASE("a scene program that fails to build falls back to the general one, which renders the same image and is reported",
          "[gpu][bench]") {
    glContext();
    IntegratorConfig specialising = testConfig();
    specialising.specialize = true;  // every driver builds the scene's program
    const Scene scene = cornellBox(16);
    auto good = makeRenderer(specialising);
    const Film reference = renderFilm(*good, scene, 2);
    CHECK_FALSE(good->programFellBack());

    // Broken only where the scene's features are defined: the specialised build, not the general.
    const TempDir tmp;
    const fs::path dir = tmp.path / "shaders";
    fs::copy(defaultShaderDir(), dir, fs::copy_options::recursive);
    {
        const fs::path features = dir / "scene" / "features.glsl";
        std::ifstream in(features);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::ofstream out(features, std::ios::trunc);
        out << "#ifdef CAUSTIC_MATERIALS\n#error a specialised build broken on purpose\n#endif\n" << text;
    }
    std::string error;
    auto fallback = Renderer::create(dir.string(), specialising, &error);
    INFO(error);
    REQUIRE(fallback);
    REQUIRE(fallback->setScene(scene, &error));
    CHECK(fallback->programFellBack());
    const Film film = renderFilm(*fallback, scene, 2);
    CHECK(fallback->programFellBack());

    // The general program computes what the scene's would have (shaders/scene/features.glsl):
    // the same samples, pixel by pixel.
    REQUIRE(film.width == reference.width);
    REQUIRE(film.height == reference.height);
    double worst = 0.0;
    for (size_t i = 0; i < film.mean.size(); ++i)
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, double(std::abs(film.mean[i][c] - reference.mean[i][c])) /
                                        std::max(1e-3, double(std::abs(reference.mean[i][c]))));
    INFO("largest relative difference " << worst);
    CHECK(worst < 1e-4);
}

// With deferred builds (the editor) setScene compiles nothing, so a source that does not compile
// shows at the first dispatch: the render session says so (behind, with the file's name in the
// error) instead of rendering nothing without a word.
TEST_CASE("with deferred builds a broken source is reported by the render session, by name", "[gpu][editor]") {
    glContext();
    const TempDir tmp;
    const fs::path dir = brokenShaderDir(tmp);
    std::string error;
    auto fresh = Renderer::create(dir.string(), testConfig(), &error);
    if (!fresh) {
        CHECK(error.find("lights/environment.glsl") != std::string::npos);   // create() built the general one
        return;
    }
    fresh->setDeferredProgramBuilds(true);
    editor::EditorState state;
    state.scene = cornellBox(16);
    editor::RenderSession session;
    double now = 10.0;
    std::string shown;
    for (int frame = 0; frame < 4; ++frame, now += 0.05) {
        const editor::RenderStep step = session.step(*fresh, state, now, false);
        if (!step.error.empty()) shown = step.error;
    }
    CHECK(session.behind);
    INFO(session.renderError);
    CHECK(session.renderError.find("lights/environment.glsl") != std::string::npos);
    CHECK(shown == session.renderError);   // handed to the UI once
    CHECK(fresh->samplesDone() == 0);      // nothing rendered is nothing counted
}
