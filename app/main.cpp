// caustic: batch rendering from the command line (`caustic --scene file.json`) and, later, the
// editor (`caustic [file.json]`). Thin: parsing is in cli.cpp, rendering in the renderer library.
#include "app/cli.h"
#include "renderer/gl_context.h"
#include "renderer/image_io.h"
#include "renderer/renderer.h"
#include "renderer/scene_io.h"
#include "renderer/shader_loader.h"
#include "renderer/tonemap.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace fs = std::filesystem;
using namespace caustic;

namespace {

constexpr int kExitRenderFailed = 1;
constexpr int kExitUsage = 2;

int fail(const std::string& message, int code = kExitRenderFailed) {
    std::cerr << "caustic: error: " << message << "\n";
    return code;
}

// A flag whose feature is not built yet must say so, never be silently ignored.
std::string notYet(const CliOptions& o) {
    if (o.oidn) return "--oidn: denoising with Open Image Denoise is not available in this build yet";
    if (o.aovs) return "--aovs: AOV output (albedo, normal) is not available in this build yet";
    return "";
}

std::string formatSeconds(double s) {
    char buf[32];
    if (s < 60) std::snprintf(buf, sizeof buf, "%.1f s", s);
    else std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
    return buf;
}

int runBatch(const CliOptions& o) {
    // 1. The scene, with the command line's overrides applied on top.
    SceneLoadResult loaded = loadScene(*o.scene);
    if (!loaded) return fail(loaded.error);
    Scene scene = std::move(*loaded.scene);
    if (o.samples) scene.render.samples = *o.samples;
    if (o.width) scene.render.width = *o.width;
    if (o.height) scene.render.height = *o.height;
    if (o.maxDepth) scene.render.maxDepth = *o.maxDepth;
    if (o.seed) scene.render.seed = *o.seed;
    if (o.envmap) {  // --envmap wins over --sky
        scene.environment = Environment{};
        scene.environment.type = EnvironmentType::Map;
        scene.environment.file = fs::absolute(*o.envmap).string();
    } else if (o.sky) {
        scene.environment = Environment{};
        scene.environment.type = EnvironmentType::Sky;
    }

    // 2. The output folder, checked before any rendering so a typo costs nothing.
    std::error_code ec;
    fs::create_directories(o.outputDir, ec);
    if (ec || !fs::is_directory(o.outputDir)) return fail("--output " + o.outputDir + ": cannot create folder: " + ec.message());
    if (access(o.outputDir.c_str(), W_OK) != 0) return fail("--output " + o.outputDir + ": folder is not writable");
    const std::string stem = (fs::path(o.outputDir) / fs::path(*o.scene).stem()).string();

    // 3. GL, shaders, upload.
    std::string error;
    const char* debugEnv = std::getenv("CAUSTIC_GL_DEBUG");
#ifdef NDEBUG
    const bool debug = debugEnv && *debugEnv && *debugEnv != '0';
#else
    const bool debug = !(debugEnv && *debugEnv == '0');
#endif
    auto context = HeadlessGlContext::create(debug, &error);
    if (!context) return fail(error);
    auto renderer = Renderer::create(defaultShaderDir(), &error);
    if (!renderer) return fail(error);
    renderer->setImageReader(readImage);
    if (!renderer->setScene(scene, &error)) return fail(*o.scene + ": " + error);
    renderer->setStrategy(o.strategy == "light" ? STRATEGY_LIGHT_ONLY
                          : o.strategy == "bsdf" ? STRATEGY_BSDF_ONLY
                                                 : STRATEGY_MIS);

    // 4. Render, with progress on a terminal.
    const int total = scene.render.samples;
    const bool tty = isatty(STDERR_FILENO);
    const auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    double lastPrint = -1.0;
    renderer->render(total, [&](int done) {
        if (!tty) return;
        double t = elapsed();
        if (t - lastPrint < 0.1 && done < total) return;
        lastPrint = t;
        double rate = done / std::max(t, 1e-9);
        std::fprintf(stderr, "\r  %d/%d spp  %.1f spp/s  %s left   ", done, total, rate,
                     formatSeconds((total - done) / std::max(rate, 1e-9)).c_str());
        std::fflush(stderr);
    });
    const double seconds = elapsed();
    if (tty) std::fprintf(stderr, "\r%*s\r", 60, "");
    const Film film = renderer->readFilm();
    const std::uint64_t dropped = renderer->droppedSamples();

    // 5. Files.
    ImageMetadata meta = {
        {"Software", std::string("caustic ") + CAUSTIC_VERSION},
        {"caustic:scene", *o.scene},
        {"caustic:samples", std::to_string(total)},
        {"caustic:seed", std::to_string(scene.render.seed)},
        {"caustic:render_seconds", std::to_string(seconds)},
    };
    // Each path is printed as soon as its file is complete, so a later failure still reports
    // what exists.
    auto wrote = [](const std::string& path) { std::cout << path << std::endl; };
    const bool png = o.png || (!o.hdr && !o.exr);
    if (png) {
        if (!writeImage8(stem + ".png", film.width, film.height, toSrgb8(film, o.reinhard ? ToneMap::Reinhard : ToneMap::Aces), meta, &error))
            return fail(error);
        wrote(stem + ".png");
    }
    if (o.hdr || o.exr) {
        std::vector<float> linear = toLinearRgb(film);
        for (auto [wanted, ext] : {std::pair{o.hdr, ".hdr"}, std::pair{o.exr, ".exr"}}) {
            if (!wanted) continue;
            if (!writeImageFloat(stem + ext, film.width, film.height, linear, meta, &error)) return fail(error);
            wrote(stem + ext);
        }
    }
    std::fprintf(stderr, "caustic: %s: %dx%d, %d spp in %.2f s (%.1f spp/s, %.2f M samples/s) on %s; %llu NaN/Inf samples dropped\n",
                 fs::path(*o.scene).filename().c_str(), film.width, film.height, total, seconds, total / seconds,
                 double(total) * film.width * film.height / seconds * 1e-6, context->info().renderer.c_str(),
                 static_cast<unsigned long long>(dropped));
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        CliParseResult parsed = parseCli(std::vector<std::string>(argv + 1, argv + argc));
        if (!parsed.options) return fail(parsed.error + "\n" + cliUsage(), kExitUsage);
        const CliOptions& o = *parsed.options;
        if (o.help) { std::cout << cliUsage(); return 0; }
        if (o.version) { std::cout << "caustic " << CAUSTIC_VERSION << "\n"; return 0; }
        if (!o.scene) {
            return fail("the editor is not built yet: render in batch mode with --scene <file.json> (see --help)",
                        kExitUsage);
        }
        if (o.editorScene) return fail("unexpected argument '" + *o.editorScene + "' in batch mode", kExitUsage);
        if (std::string why = notYet(o); !why.empty()) return fail(why, kExitUsage);
        return runBatch(o);
    } catch (const std::exception& e) {
        return fail(std::string("unexpected failure: ") + e.what());
    }
}
