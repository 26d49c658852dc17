// caustic: batch rendering from the command line (`caustic --scene file.json`) and the editor
// (`caustic [file.json]`). Thin: parsing is in cli.cpp, rendering in the renderer library.
#include "app/cli.h"
#include "app/commands.h"
#include "editor/ui/editor_app.h"
#include "app/contact_sheet.h"
#include "app/outputs.h"
#include "app/part_file.h"
#include "renderer/denoise.h"
#include "renderer/program_cache.h"
#include "renderer/gl_context.h"
#include "renderer/image_io.h"
#include "renderer/renderer.h"
#include "renderer/scene_io.h"
#include "renderer/shader_loader.h"
#include "renderer/tonemap.h"

#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace fs = std::filesystem;
using namespace caustic;

namespace {

constexpr int kExitUsage = kExitBadUsage;

int fail(const std::string& message, int code = kExitFailed) { return commandFailed(message, code); }

std::string formatSeconds(double s) {
    char buf[32];
    if (s < 60) std::snprintf(buf, sizeof buf, "%.1f s", s);
    else std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
    return buf;
}

// Splits "a,b,[1,2,3]" at the top-level commas (not inside brackets, braces or quotes).
std::vector<std::string> splitValues(const std::string& text) {
    std::vector<std::string> out;
    std::string current;
    int depth = 0;
    bool quoted = false;
    for (char c : text) {
        if (c == '"') quoted = !quoted;
        if (!quoted && (c == '[' || c == '{')) ++depth;
        if (!quoted && (c == ']' || c == '}')) --depth;
        if (c == ',' && depth == 0 && !quoted) {
            out.push_back(current);
            current.clear();
        } else {
            current += c;
        }
    }
    out.push_back(current);
    return out;
}

// One image to render: the overrides that make it, and its label on a contact sheet.
struct Variant {
    std::vector<SceneOverride> overrides;
    std::string label, fileSuffix;
};

// The grid of --sweep values (the first sweep varies fastest), each with the --set overrides.
bool makeVariants(const CliOptions& o, std::vector<Variant>* out, std::string* error) {
    Variant base;
    for (const std::string& text : o.sets) {
        SceneOverride ov;
        if (!parseSceneOverride(text, &ov, error)) { *error = "--set: " + *error; return false; }
        base.overrides.push_back(ov);
    }
    std::vector<Variant> variants = {base};
    for (const std::string& text : o.sweeps) {
        SceneOverride ov;
        if (!parseSceneOverride(text, &ov, error)) { *error = "--sweep: " + *error; return false; }
        const std::vector<std::string> values = splitValues(ov.value);
        std::vector<Variant> grown;
        for (const Variant& v : variants)
            for (size_t i = 0; i < values.size(); ++i) {
                if (values[i].empty()) { *error = "--sweep " + text + ": empty value"; return false; }
                Variant n = v;
                n.overrides.push_back({ov.path, values[i]});
                n.label += (n.label.empty() ? "" : "\n") + ov.path + "=" + values[i];  // one line per sweep
                n.fileSuffix += '-';  // two appends: "-" + to_string trips GCC 12's false -Wrestrict (bug 105329)
                n.fileSuffix += std::to_string(i);
                grown.push_back(n);
            }
        variants = std::move(grown);
    }
    // The first sweep should vary along the sheet's rows: reorder so its index changes fastest.
    if (o.sweeps.size() > 1) {
        const size_t first = splitValues(o.sweeps[0].substr(o.sweeps[0].find('=') + 1)).size();
        const size_t rest = variants.size() / first;
        std::vector<Variant> ordered;
        for (size_t r = 0; r < rest; ++r)
            for (size_t f = 0; f < first; ++f) ordered.push_back(variants[f * rest + r]);
        variants = std::move(ordered);
    }
    *out = std::move(variants);
    return true;
}

// The command line's own settings on top of the (overridden) scene file.
void applyFlags(const CliOptions& o, Scene& scene) {
    if (o.samples) scene.render.samples = *o.samples;
    // One of --width and --height alone keeps the scene's aspect ratio (the other is scaled and
    // rounded, at least 1 and at most the largest image); both set the size as given.
    const int sceneWidth = scene.render.width, sceneHeight = scene.render.height;
    const auto scaled = [](int given, int num, int den) {
        return int(std::clamp<long long>((2LL * given * num + den) / (2LL * den), 1, kMaxRenderSide));
    };
    if (o.width) scene.render.width = *o.width;
    if (o.height) scene.render.height = *o.height;
    if (o.width && !o.height && sceneWidth > 0) scene.render.height = scaled(*o.width, sceneHeight, sceneWidth);
    if (o.height && !o.width && sceneHeight > 0) scene.render.width = scaled(*o.height, sceneWidth, sceneHeight);
    if (o.maxDepth) scene.render.maxDepth = *o.maxDepth;
    if (o.seed) scene.render.seed = *o.seed;
    if (o.envmap) {  // --envmap wins over --sky
        scene.environment = Environment{};
        scene.environment.type = EnvironmentType::Map;
        scene.environment.file = fs::absolute(*o.envmap).string();
    } else if (o.sky) {
        scene.environment = Environment{};
        scene.environment.type = EnvironmentType::Sky;
        if (o.skyPreset) applySkyPreset(*findSkyPreset(*o.skyPreset), scene.environment);  // checked by parseCli
    }
}

// Host memory a render of `pixels` pixels needs at its peak, per pixel: the four RGBA32F film
// images (which llvmpipe keeps in host memory), their read-back copies (Renderer::readFilm), the
// Film and its copy for the written image (52 bytes each), and the 8-bit and float output
// images, AOVs and EXR layers; rounded up. Per variant of a sweep, the contact sheet keeps 3 more.
constexpr double kBytesPerPixel = 64 + 64 + 2 * 52 + 3 + 12 + 24 + 60;

// MemAvailable from /proc/meminfo in bytes, or 0 when unknown.
double availableMemory() {
    std::FILE* f = std::fopen("/proc/meminfo", "r");
    if (!f) return 0;
    char line[256];
    double bytes = 0;
    while (std::fgets(line, sizeof line, f)) {
        unsigned long long kb = 0;
        if (std::sscanf(line, "MemAvailable: %llu kB", &kb) == 1) {
            bytes = double(kb) * 1024.0;
            break;
        }
    }
    std::fclose(f);
    return bytes;
}

// A render that cannot fit in memory fails before anything starts, with the numbers, instead of
// "std::bad_alloc" (or the kernel's OOM killer) minutes later.
std::string memoryProblem(const Scene& scene, std::size_t variants) {
    const double pixels = double(scene.render.width) * double(scene.render.height);
    const double needed = pixels * (kBytesPerPixel + 6.0 * double(variants > 1 ? variants : 0));
    const double available = availableMemory();
    if (available <= 0 || needed <= available) return "";
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "render size %dx%d needs about %.1f GiB of memory, only %.1f GiB is available; "
                  "render smaller (--width, --height)",
                  scene.render.width, scene.render.height, needed / (1u << 30), available / (1u << 30));
    return buf;
}

int runBatch(const CliOptions& o) {
    if (o.timeBudget && o.samples) return fail("use --samples or --time, not both", kExitUsage);
    std::vector<Variant> variants;
    std::string error;
    if (!makeVariants(o, &variants, &error)) return fail(error, kExitUsage);
    if (o.variant) {   // the farm's sweeps: one task per variant
        if (o.sweeps.empty()) return fail("--variant needs --sweep", kExitUsage);
        if (size_t(*o.variant) >= variants.size())
            return fail("--variant " + std::to_string(*o.variant) + ": the sweeps make " + std::to_string(variants.size()) +
                            " variants (0 to " + std::to_string(variants.size() - 1) + ")", kExitUsage);
        variants = {variants[size_t(*o.variant)]};
    }
    // A part of a split render (docs/farm.md) writes only its part file: the image is made by
    // caustic merge, from all the parts.
    const bool part = o.sampleRange || o.crop;
    if (part) {
        if (o.timeBudget) return fail("--time cannot make a part (--sample-range / --crop): a part's samples must be known", kExitUsage);
        if (o.png || o.hdr || o.exr || o.half || o.oidn || o.aovs || o.exposure != 0.0f || o.reinhard)
            return fail("a part (--sample-range / --crop) writes only its part file: give the output options "
                        "(--png, --hdr, --exr, --half, --oidn, --aovs, --reinhard, --exposure) to caustic merge",
                        kExitUsage);
        if (o.sampleRange && o.samples && o.sampleRange->end > std::uint32_t(*o.samples))
            return fail("--sample-range " + std::to_string(o.sampleRange->begin) + ":" + std::to_string(o.sampleRange->end) +
                            " goes past --samples " + std::to_string(*o.samples), kExitUsage);
    }

    // Every variant's scene is loaded and validated before anything renders.
    std::vector<Scene> scenes;
    for (const Variant& v : variants) {
        SceneLoadResult loaded = loadScene(*o.scene, v.overrides);
        if (!loaded) return fail(loaded.error);
        applyFlags(o, *loaded.scene);
        scenes.push_back(std::move(*loaded.scene));
    }
    if (o.listVariants) {   // what the farm needs to plan: each variant and its image
        const int columns = o.sweeps.empty() ? 1 : static_cast<int>(splitValues(o.sweeps[0].substr(o.sweeps[0].find('=') + 1)).size());
        for (size_t i = 0; i < variants.size(); ++i)
            std::cout << nlohmann::json{{"index", i}, {"label", variants[i].label}, {"suffix", variants[i].fileSuffix},
                                        {"width", scenes[i].render.width}, {"height", scenes[i].render.height},
                                        {"samples", scenes[i].render.samples}, {"seed", scenes[i].render.seed},
                                        {"columns", columns}}
                             .dump()
                      << "\n";
        return 0;
    }
    PixelRect crop;   // empty: the whole image
    if (o.crop) {
        crop = {o.crop->x0, o.crop->y0, o.crop->x1, o.crop->y1};
        for (const Scene& scene : scenes)   // variants may differ in size (--sweep render.width=...)
            if (crop.x1 > scene.render.width || crop.y1 > scene.render.height)
                return fail("--crop " + std::to_string(crop.x0) + ":" + std::to_string(crop.x1) + "," + std::to_string(crop.y0) +
                                ":" + std::to_string(crop.y1) + ": outside the " + std::to_string(scene.render.width) + "x" +
                                std::to_string(scene.render.height) + " image of " + *o.scene,
                            kExitUsage);
    }
    for (const Scene& scene : scenes) {
        Scene sized = scene;   // what is held in memory: the crop
        if (o.crop) { sized.render.width = crop.x1 - crop.x0; sized.render.height = crop.y1 - crop.y0; }
        if (std::string why = memoryProblem(sized, scenes.size()); !why.empty()) return fail(*o.scene + ": " + why);
    }

    // The output folder, checked before any rendering so a typo costs nothing.
    std::error_code ec;
    fs::create_directories(o.outputDir, ec);
    if (ec || !fs::is_directory(o.outputDir)) return fail("--output " + o.outputDir + ": cannot create folder: " + ec.message());
    if (access(o.outputDir.c_str(), W_OK) != 0) return fail("--output " + o.outputDir + ": folder is not writable");
    const std::string stem = (fs::path(o.outputDir) / fs::path(*o.scene).stem()).string();

    // GL and shaders, once for all variants.
    const char* debugEnv = std::getenv("CAUSTIC_GL_DEBUG");
#ifdef NDEBUG
    const bool debug = debugEnv && *debugEnv && *debugEnv != '0';
#else
    const bool debug = !(debugEnv && *debugEnv == '0');
#endif
    auto context = HeadlessGlContext::create(debug, &error, o.gpu ? *o.gpu : -1);
    if (!context) return fail(error);
    // The integrator's configuration: the device's defaults, and the documented CAUSTIC_*
    // variables for measuring (renderer/integrator_config.h).
    std::vector<std::string> configWarnings;
    const IntegratorConfig config = IntegratorConfig::fromEnvironment(&configWarnings);
    for (const std::string& w : configWarnings) std::fprintf(stderr, "caustic: %s\n", w.c_str());
    useProgramCache(config.programCache);
    auto renderer = Renderer::create(defaultShaderDir(), config, &error);
    if (!renderer) return fail(error);
    renderer->setImageReader(readImage);
    // Batch geometry never changes while a variant renders: a scene of a few analytic primitives
    // gets them as constants of its program on llvmpipe (Renderer::setBakeGeometry).
    renderer->setBakeGeometry(true);
    renderer->setStrategy(o.strategy == "light" ? STRATEGY_LIGHT_ONLY
                          : o.strategy == "bsdf" ? STRATEGY_BSDF_ONLY
                                                 : STRATEGY_MIS);

    // Each path is printed as soon as its file is complete, so a later failure still reports
    // what exists.
    auto wrote = [](const std::string& path) { std::cout << path << std::endl; };
    const bool tty = isatty(STDERR_FILENO);
    std::vector<SheetCell> cells;
    for (size_t vi = 0; vi < variants.size(); ++vi) {
        const Scene& scene = scenes[vi];
        renderer->setCrop(crop);
        renderer->setSampleBase(o.sampleRange ? o.sampleRange->begin : 0);
        if (!renderer->setScene(scene, &error)) return fail(*o.scene + ": " + error);
        if (vi == 0)  // what mesh import repaired or could not map: the same for every variant
            for (const std::string& w : renderer->compiled().warnings) std::cerr << "caustic: warning: " << w << "\n";

        // Render, with progress on a terminal; a time budget renders in steps until it is spent.
        const int total = o.sampleRange ? int(o.sampleRange->end - o.sampleRange->begin) : scene.render.samples;
        const auto start = std::chrono::steady_clock::now();
        auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
        double lastPrint = -1.0;
        auto progress = [&](int done) {
            if (!tty) return;
            const double t = elapsed();
            if (t - lastPrint < 0.1) return;
            lastPrint = t;
            const double rate = done / std::max(t, 1e-9);
            if (o.timeBudget)
                std::fprintf(stderr, "\r  %d spp  %.1f spp/s  %s left   ", done, rate,
                             formatSeconds(std::max(0.0, *o.timeBudget - t)).c_str());
            else
                std::fprintf(stderr, "\r  %d/%d spp  %.1f spp/s  %s left   ", done, total, rate,
                             formatSeconds((total - done) / std::max(rate, 1e-9)).c_str());
            std::fflush(stderr);
        };
        if (o.timeBudget) {
            // Steps sized from the measured rate, so the budget is overshot by at most a step.
            int step = 1;
            while (elapsed() < *o.timeBudget) {
                const double before = elapsed();
                renderer->render(step, progress);
                const double perSample = (elapsed() - before) / step;
                const double left = *o.timeBudget - elapsed();
                step = static_cast<int>(std::clamp(std::min(left, 0.5) / std::max(perSample, 1e-9), 1.0, 4096.0));
                if (left <= 0.0) break;
            }
        } else {
            renderer->render(total, progress);
        }
        const double seconds = elapsed();
        if (tty) std::fprintf(stderr, "\r%*s\r", 60, "");
        const std::uint64_t dropped = renderer->droppedSamples();
        const int done = renderer->samplesDone();
        if (part) {
            Part p;
            p.info.scene = *o.scene;
            p.info.renderHash = renderIdentityHash(scene, o.strategy);
            p.info.version = CAUSTIC_VERSION;
            p.info.variant = variants[vi].label;
            p.info.seed = scene.render.seed;
            p.info.width = scene.render.width;
            p.info.height = scene.render.height;
            p.info.sample0 = renderer->sampleBase();
            p.info.sample1 = renderer->sampleBase() + std::uint32_t(done);
            p.info.crop = renderer->region();
            p.info.seconds = seconds;
            p.info.dropped = dropped;
            p.sums = renderer->readAccumulators();
            const std::string path = partFileName(stem + variants[vi].fileSuffix, p.info);
            if (!writePart(path, p, &error)) return fail(error);
            wrote(path);
            std::fprintf(stderr, "caustic: %s: part, samples [%u, %u) of pixels %d:%d,%d:%d in %.2f s; %llu NaN/Inf samples dropped\n",
                         fs::path(*o.scene).filename().c_str(), p.info.sample0, p.info.sample1, p.info.crop.x0,
                         p.info.crop.x1, p.info.crop.y0, p.info.crop.y1, seconds, static_cast<unsigned long long>(dropped));
            continue;
        }
        const Film raw = renderer->readFilm();
        ImageMetadata meta = {
            {"Software", std::string("caustic ") + CAUSTIC_VERSION},
            {"caustic:scene", *o.scene},
            {"caustic:samples", std::to_string(done)},
            {"caustic:seed", std::to_string(scene.render.seed)},
            {"caustic:render_seconds", std::to_string(seconds)},
        };
        if (!variants[vi].label.empty()) meta.push_back({"caustic:variant", variants[vi].label});
        std::vector<std::uint8_t> srgb;
        if (!writeOutputs(o, stem + variants[vi].fileSuffix, raw, meta, &srgb, &error)) return fail(error);
        const Film& film = raw;
        std::string oneLineLabel = variants[vi].label;
        std::replace(oneLineLabel.begin(), oneLineLabel.end(), '\n', ' ');
        std::fprintf(stderr, "caustic: %s%s%s: %dx%d, %d spp in %.2f s (%.1f spp/s, %.2f M samples/s) on %s; %llu NaN/Inf samples dropped\n",
                     fs::path(*o.scene).filename().c_str(), oneLineLabel.empty() ? "" : " ",
                     oneLineLabel.empty() ? "" : ("[" + oneLineLabel + "]").c_str(), film.width, film.height,
                     done, seconds, done / seconds, double(done) * film.width * film.height / seconds * 1e-6,
                     context->info().renderer.c_str(), static_cast<unsigned long long>(dropped));
        if (!o.sweeps.empty() && !o.variant) cells.push_back({film.width, film.height, std::move(srgb), variants[vi].label});
    }
    if (!o.sweeps.empty() && !o.variant && !part) {
        const int columns = static_cast<int>(splitValues(o.sweeps[0].substr(o.sweeps[0].find('=') + 1)).size());
        Sheet sheet;
        if (!makeContactSheet(cells, columns, &sheet, &error)) return fail(error);
        ImageMetadata meta = {{"Software", std::string("caustic ") + CAUSTIC_VERSION}, {"caustic:scene", *o.scene}};
        if (!writeImage8(stem + "-sheet.png", sheet.width, sheet.height, sheet.rgb, meta, &error)) return fail(error);
        wrote(stem + "-sheet.png");
    }
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
        if (o.command == "merge") return runMerge(o);
        if (o.command == "compare") return runCompare(o);
        if (o.command == "sheet") return runSheet(o);
        if (!o.scene) return editor::runEditor(o.editorScene);   // `caustic [scene.json]`: the editor
        if (o.editorScene) return fail("unexpected argument '" + *o.editorScene + "' in batch mode", kExitUsage);
        if (std::string why = outputsNotAvailable(o); !why.empty()) return fail(why);
        return runBatch(o);
    } catch (const std::bad_alloc&) {
        return fail("out of memory (the render size, the scene's meshes and images must fit in memory)");
    } catch (const std::exception& e) {
        return fail(std::string("unexpected failure: ") + e.what());
    }
}
