// A shader source that stops compiling while a renderer runs (the editor's "Reload shaders", a
// developer editing shaders/): the editor builds a fresh renderer from the new sources and keeps
// the old one unless Renderer::checkSource says the whole integrator compiles
// (editor/ui/editor_app.cpp, reloadShaders). On llvmpipe create() builds no integrator (each scene
// gets its own, session 15), so create() alone proves nothing there: this checks that
// checkSource and setScene both fail with the broken file's name, and that the renderer made
// from the good sources still renders.
#include "renderer/shader_loader.h"
#include "tests/gpu/gl_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

using namespace caustic;
using namespace caustic::test;
namespace fs = std::filesystem;

TEST_CASE("a broken shader source fails checkSource and setScene by name, and the last renderer still renders",
          "[gpu][editor]") {
    glContext();
    auto good = makeRenderer();
    const Scene scene = cornellBox(16);
    const Film before = renderFilm(*good, scene, 1);

    const fs::path dir = fs::temp_directory_path() / ("caustic-reload-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::copy(defaultShaderDir(), dir, fs::copy_options::recursive);
    {
        std::ofstream env(dir / "lights" / "environment.glsl", std::ios::app);
        env << "\nthis is not GLSL (\n";
    }

    std::string error;
    auto fresh = Renderer::create(dir.string(), &error);
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
    fs::remove_all(dir);

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
