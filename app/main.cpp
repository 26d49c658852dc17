// caustic: batch rendering from the command line (`caustic --scene file.json`) and the editor
// (`caustic [file.json]`). Thin: parsing is in cli.cpp, rendering in the renderer library.
#include "app/cli.h"
#include "editor/ui/editor_app.h"
#include "app/contact_sheet.h"
#include "renderer/denoise.h"
#include "renderer/gl_context.h"
#include "renderer/image_io.h"
#include "renderer/renderer.h"
#include "renderer/scene_io.h"
#include "renderer/shader_loader.h"
#include "renderer/tonemap.h"

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

constexpr int kExitRenderFailed = 1;
constexpr int kExitUsage = 2;

int fail(const std::string& message, int code = kExitRenderFailed) {
    std::cerr << "caustic: error: " << message << "\n";
    return code;
}

// A flag whose feature is not in this build must say so before anything renders.
std::string notAvailable(const CliOptions& o) {
    std::string error;
    if (o.oidn && !denoiserAvailable()) {
        denoise(Film{}, {}, nullptr, &error);
        return "--oidn: " + error;
    }
    return "";
}

// The AOVs as images: albedo as it is (linear reflectance); the normal remapped from [-1, 1] to
// [0, 1] (files without negative values: PNG, Radiance) or as it is (EXR).
std::vector<float> flatten(const std::vector<glm::vec3>& v, bool remapSigned = false) {
    std::vector<float> out(v.size() * 3);
    for (size_t i = 0; i < v.size(); ++i)
        for (int c = 0; c < 3; ++c) out[i * 3 + c] = remapSigned ? v[i][c] * 0.5f + 0.5f : v[i][c];
    return out;
}

// 8-bit with no tone curve: linear values in [0, 1], sRGB-encoded (albedo) or stored as they are
// (the remapped normal, which is data, not colour).
std::vector<std::uint8_t> to8Bit(const std::vector<float>& v, bool srgb) {
    std::vector<std::uint8_t> out(v.size());
    for (size_t i = 0; i < v.size(); ++i) {
        const float x = std::clamp(v[i], 0.0f, 1.0f);
        out[i] = static_cast<std::uint8_t>(std::lround((srgb ? srgbEncode(x) : x) * 255.0f));
    }
    return out;
}

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

    // Every variant's scene is loaded and validated before anything renders.
    std::vector<Scene> scenes;
    for (const Variant& v : variants) {
        SceneLoadResult loaded = loadScene(*o.scene, v.overrides);
        if (!loaded) return fail(loaded.error);
        applyFlags(o, *loaded.scene);
        scenes.push_back(std::move(*loaded.scene));
    }
    for (const Scene& scene : scenes)
        if (std::string why = memoryProblem(scene, scenes.size()); !why.empty()) return fail(*o.scene + ": " + why);

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
    auto context = HeadlessGlContext::create(debug, &error);
    if (!context) return fail(error);
    auto renderer = Renderer::create(defaultShaderDir(), &error);
    if (!renderer) return fail(error);
    renderer->setImageReader(readImage);
    renderer->setStrategy(o.strategy == "light" ? STRATEGY_LIGHT_ONLY
                          : o.strategy == "bsdf" ? STRATEGY_BSDF_ONLY
                                                 : STRATEGY_MIS);

    // Each path is printed as soon as its file is complete, so a later failure still reports
    // what exists.
    auto wrote = [](const std::string& path) { std::cout << path << std::endl; };
    const ToneMap toneMap = o.reinhard ? ToneMap::Reinhard : ToneMap::Aces;
    const bool png = o.png || (!o.hdr && !o.exr);
    const bool tty = isatty(STDERR_FILENO);
    std::vector<SheetCell> cells;
    for (size_t vi = 0; vi < variants.size(); ++vi) {
        const Scene& scene = scenes[vi];
        if (!renderer->setScene(scene, &error)) return fail(*o.scene + ": " + error);
        if (vi == 0)  // what mesh import repaired or could not map: the same for every variant
            for (const std::string& w : renderer->compiled().warnings) std::cerr << "caustic: warning: " << w << "\n";

        // Render, with progress on a terminal; a time budget renders in steps until it is spent.
        const int total = scene.render.samples;
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
        const Film raw = renderer->readFilm();
        Film film = raw;  // what the files show: the denoised image with --oidn
        std::string denoiser;
        if (o.oidn) {
            DenoiseOptions dopt;
            dopt.useGuides = o.oidnGuides != "none";
            dopt.prefilterGuides = o.oidnGuides == "prefilter";
            DenoiseResult denoised;
            const auto t0 = std::chrono::steady_clock::now();
            if (!denoise(raw, dopt, &denoised, &error)) return fail("--oidn: " + error);
            const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            film.mean = std::move(denoised.image);
            denoiser = "Open Image Denoise " + denoiserVersion() + ", filter RT, hdr, guides " +
                       (dopt.useGuides ? (dopt.prefilterGuides ? "albedo+normal prefiltered" : "albedo+normal") : "none") +
                       ", device " + denoised.device;
            std::fprintf(stderr, "caustic: denoised in %.2f s: %s\n", dt, denoiser.c_str());
        }
        const std::uint64_t dropped = renderer->droppedSamples();
        const int done = renderer->samplesDone();

        ImageMetadata meta = {
            {"Software", std::string("caustic ") + CAUSTIC_VERSION},
            {"caustic:scene", *o.scene},
            {"caustic:samples", std::to_string(done)},
            {"caustic:seed", std::to_string(scene.render.seed)},
            {"caustic:render_seconds", std::to_string(seconds)},
        };
        if (!variants[vi].label.empty()) meta.push_back({"caustic:variant", variants[vi].label});
        if (!denoiser.empty()) meta.push_back({"caustic:denoiser", denoiser});
        const std::string base = stem + variants[vi].fileSuffix;
        std::vector<std::uint8_t> srgb = toSrgb8(film, toneMap, o.exposure);
        // AOV files carry the same metadata plus what they are.
        auto aovMeta = [&](const char* pass) {
            ImageMetadata m = meta;
            m.push_back({"caustic:pass", pass});
            return m;
        };
        const std::vector<float> albedo = o.aovs ? flatten(raw.albedo) : std::vector<float>{};
        const std::vector<float> normal01 = o.aovs ? flatten(raw.normal, true) : std::vector<float>{};
        if (png) {
            if (!writeImage8(base + ".png", film.width, film.height, srgb, meta, &error)) return fail(error);
            wrote(base + ".png");
            if (o.aovs) {
                if (!writeImage8(base + "-albedo.png", film.width, film.height, to8Bit(albedo, true), aovMeta("albedo"), &error))
                    return fail(error);
                wrote(base + "-albedo.png");
                if (!writeImage8(base + "-normal.png", film.width, film.height, to8Bit(normal01, false), aovMeta("normal"), &error))
                    return fail(error);
                wrote(base + "-normal.png");
            }
        }
        const std::vector<float> linear = toLinearRgb(film);
        if (o.hdr) {
            if (!writeImageFloat(base + ".hdr", film.width, film.height, linear, meta, &error)) return fail(error);
            wrote(base + ".hdr");
            if (o.aovs) {
                if (!writeImageFloat(base + "-albedo.hdr", film.width, film.height, albedo, aovMeta("albedo"), &error))
                    return fail(error);
                wrote(base + "-albedo.hdr");
                if (!writeImageFloat(base + "-normal.hdr", film.width, film.height, normal01, aovMeta("normal"), &error))
                    return fail(error);
                wrote(base + "-normal.hdr");
            }
        }
        if (o.exr) {
            // One file: R, G, B hold the final image (what viewers without layer support show);
            // with --aovs the named layers raw, denoised (with --oidn), albedo and normal follow
            // (the normal as it is, in [-1, 1]).
            std::vector<ImageLayer> layers = {{"", &linear}};
            std::vector<float> rawRgb, normal;
            if (o.aovs) {
                rawRgb = toLinearRgb(raw);
                normal = flatten(raw.normal);
                layers.push_back({"raw", &rawRgb});
                if (o.oidn) layers.push_back({"denoised", &linear});
                layers.push_back({"albedo", &albedo});
                layers.push_back({"normal", &normal});
            }
            if (!writeExrLayers(base + ".exr", film.width, film.height, layers, o.half, meta, &error)) return fail(error);
            wrote(base + ".exr");
        }
        std::string oneLineLabel = variants[vi].label;
        std::replace(oneLineLabel.begin(), oneLineLabel.end(), '\n', ' ');
        std::fprintf(stderr, "caustic: %s%s%s: %dx%d, %d spp in %.2f s (%.1f spp/s, %.2f M samples/s) on %s; %llu NaN/Inf samples dropped\n",
                     fs::path(*o.scene).filename().c_str(), oneLineLabel.empty() ? "" : " ",
                     oneLineLabel.empty() ? "" : ("[" + oneLineLabel + "]").c_str(), film.width, film.height,
                     done, seconds, done / seconds, double(done) * film.width * film.height / seconds * 1e-6,
                     context->info().renderer.c_str(), static_cast<unsigned long long>(dropped));
        if (!o.sweeps.empty()) cells.push_back({film.width, film.height, std::move(srgb), variants[vi].label});
    }
    if (!o.sweeps.empty()) {
        const int columns = static_cast<int>(splitValues(o.sweeps[0].substr(o.sweeps[0].find('=') + 1)).size());
        Sheet sheet = makeContactSheet(cells, columns);
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
        if (!o.scene) return editor::runEditor(o.editorScene);   // `caustic [scene.json]`: the editor
        if (o.editorScene) return fail("unexpected argument '" + *o.editorScene + "' in batch mode", kExitUsage);
        if (std::string why = notAvailable(o); !why.empty()) return fail(why);
        return runBatch(o);
    } catch (const std::bad_alloc&) {
        return fail("out of memory (the render size, the scene's meshes and images must fit in memory)");
    } catch (const std::exception& e) {
        return fail(std::string("unexpected failure: ") + e.what());
    }
}
