// caustic-bench: the speed benchmark (never a test). Renders the standard scenes at fixed
// settings after a warm-up and prints samples and rays per second, timed by the wall clock and by
// a GL_TIME_ELAPSED query around the same work, and samples per CPU second of the process (every
// thread: on llvmpipe the renderer's own CPU time, which a shared machine's load moves less). Links no OpenImageIO, so the binary is
// small enough to carry to the GPU machine.
//   caustic-bench [--size N] [--samples N] [--max-depth N] [--repeat N] [--rays] [--oidn] [--out DIR] [--dump-program FILE] [--interactive N] [--set path=value ...] [scene.json ...]
// --set path=value: as caustic's --set, applied to every scene (e.g. render.sampler=independent).
// --rays: also traversal alone (shaders/bench/rays.comp): primary rays, then one cosine-
//   distributed bounce from their hits, in M rays/s (timer queries, median of --repeat runs).
// --dump-program FILE: writes the driver's binary of the integrator program (NVIDIA's holds its
//   assembly, with register and local-memory use: look with `strings`).
// --interactive N: also N frames as the editor renders them (Renderer::renderFor with the editor's
//   budget of 1/30 s less 2 ms, nothing else in the frame), with an edit every tenth frame,
//   alternately moving the first object (kDirtyTransforms) and adding or removing a small sphere
//   (kDirtyGeometry): frame times and edit -> finished frame times.
// --out DIR: writes each render as DIR/<scene>.ppm (ACES, sRGB), to look at what was measured.
// With $CAUSTIC_WALK_STATS=1 the integrator also counts its mesh walks (Renderer::walkStats) and a
// "walks" line per mesh scene gives, per sample, the walk loops' iterations its SIMD groups paid
// for and those their lanes worked: counts that a loaded machine does not move, for judging a
// change to the walk's schedule (docs/performance.md, "How to measure"). The counting itself slows the
// render (a ballot per iteration): read the rates of such a run as nothing.
// --oidn: also denoises each render with Open Image Denoise and reports the device and the time.
#include "renderer/denoise.h"
#include "renderer/program_cache.h"
#include "renderer/dirty.h"
#include "renderer/file_util.h"
#include "renderer/gl_context.h"
#include "renderer/renderer.h"
#include "renderer/scene_io.h"
#include "renderer/shader_loader.h"
#include "renderer/tonemap.h"

#include <glad/gl.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace caustic;

namespace {

// CPU seconds this process has used (every thread: llvmpipe's workers too). On a machine shared
// with other work, CPU time per sample moves much less with the load than wall time does.
double cpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// Primary rays, then one diffuse bounce from their hits, each pass timed by a GL_TIME_ELAPSED
// query (median of `repeat`); returns a table row. Rays that miss everything still count as
// traced; the hit fraction is printed so a scene that is mostly sky is visible as such.
std::string traceRays(Renderer& renderer, unsigned program, GLuint query, const std::string& name, int size, int repeat) {
    const size_t pixels = size_t(size) * size;
    GLuint hits = 0;
    glCreateBuffers(1, &hits);
    glNamedBufferData(hits, GLsizeiptr(pixels * 2 * sizeof(float) * 4), nullptr, GL_DYNAMIC_COPY);
    double seconds[2] = {}, hitFraction[2] = {};
    bool timerQueries = true;
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<double> gpuTimes, wallTimes;
        for (int r = 0; r < repeat + 1; ++r) {  // the first run warms up
            for (int p = 0; p <= pass; ++p) {
                renderer.bindScene(0, 1);
                const std::uint32_t zero[4] = {0, 0, 0, 0};
                glNamedBufferSubData(renderer.countersBuffer(), 0, sizeof zero, zero);
                glUseProgram(program);
                glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEST_OUTPUT, hits);
                glUniform1ui(glGetUniformLocation(program, "u_pass"), GLuint(p));
                glUniform1ui(glGetUniformLocation(program, "u_sample"), GLuint(r));
                glFinish();
                const auto t0 = std::chrono::steady_clock::now();
                if (p == pass) glBeginQuery(GL_TIME_ELAPSED, query);
                glDispatchCompute(GLuint(size + 7) / 8, GLuint(size + 7) / 8, 1);
                if (p == pass) glEndQuery(GL_TIME_ELAPSED);
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
                glFinish();
                if (p == pass && r > 0)
                    wallTimes.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            }
            GLuint64 ns = 0;
            glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
            if (r > 0) gpuTimes.push_back(double(ns) * 1e-9);
            std::uint32_t found = 0;
            glGetNamedBufferSubData(renderer.countersBuffer(), 0, sizeof found, &found);
            hitFraction[pass] = double(found) / double(pixels);
        }
        // llvmpipe answers timer queries with ~0: fall back to the wall clock there.
        const double gpu = median(gpuTimes), wall = median(wallTimes);
        if (gpu < 1e-3 * wall) timerQueries = false;
        seconds[pass] = timerQueries ? gpu : wall;
    }
    glDeleteBuffers(1, &hits);
    renderer.resetAccumulation();
    char line[256];
    // Diffuse rays start only from pixels whose primary ray hit something.
    std::snprintf(line, sizeof line, "rays %-19s %4dx%-5d  primary %8.1f Mrays/s (hit %.2f)   diffuse %8.1f Mrays/s (hit %.2f)   timed by %s",
                  name.c_str(), size, size, double(pixels) / seconds[0] * 1e-6, hitFraction[0],
                  double(pixels) * hitFraction[0] / seconds[1] * 1e-6, hitFraction[1] / std::max(hitFraction[0], 1e-9),
                  timerQueries ? "GL_TIME_ELAPSED" : "wall clock");
    return line;
}

std::string interactive(Renderer& renderer, Scene scene, int frames, const std::string& name) {
    using Clock = std::chrono::steady_clock;
    std::string error;
    renderer.setBakeGeometry(false);  // as the editor renders: its edits must not rebuild the program
    if (!renderer.setScene(scene, &error)) return "interactive " + name + ": " + error;
    const double budget = 1.0 / 30.0 - 0.002;
    std::vector<double> frameMs, moveMs, addMs;
    long long pixelSamples = 0;
    const auto start = Clock::now();
    Object extra;   // what a geometry edit adds and removes: a small sphere
    extra.name = "bench sphere";
    extra.shape = Shape::Sphere;
    extra.material = scene.materials.empty() ? std::string() : scene.materials.front().name;
    extra.transform.scale = glm::vec3(0.05f);
    for (int i = 0; i < frames; ++i) {
        // Every tenth frame an edit: moving the first object (kDirtyTransforms), or every other
        // time adding or removing a sphere (kDirtyGeometry).
        const int kind = i % 10 != 5 || scene.objects.empty() ? 0 : ((i / 10) % 2 == 0 ? 1 : 2);
        const auto t0 = Clock::now();
        if (kind == 1) {
            scene.objects[0].transform.translate.x += (i / 20) % 2 == 0 ? 0.01f : -0.01f;
            if (!renderer.update(scene, kDirtyTransforms, &error)) return "interactive " + name + ": " + error;
        } else if (kind == 2 && !extra.material.empty()) {
            if (scene.objects.back().name == extra.name) scene.objects.pop_back();
            else scene.objects.push_back(extra);
            if (!renderer.update(scene, kDirtyGeometry, &error)) return "interactive " + name + ": " + error;
        }
        pixelSamples += renderer.renderFor(budget, 1 << 20).pixelSamples;
        glFinish();
        const double ms = std::chrono::duration<double>(Clock::now() - t0).count() * 1e3;
        (kind == 0 ? frameMs : kind == 1 ? moveMs : addMs).push_back(ms);
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    const double pixels = double(scene.render.width) * scene.render.height;
    auto pct = [](std::vector<double> v, double q) {
        if (v.empty()) return 0.0;
        std::sort(v.begin(), v.end());
        return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
    };
    char line[400];
    std::snprintf(line, sizeof line,
                  "interactive %-19s %4dx%-5d  frame ms median %.1f p95 %.1f max %.1f   move->frame ms median %.1f max %.1f"
                  "   add/remove->frame ms median %.1f max %.1f   %.1f spp/s",
                  name.c_str(), scene.render.width, scene.render.height, pct(frameMs, 0.5), pct(frameMs, 0.95),
                  pct(frameMs, 1.0), pct(moveMs, 0.5), pct(moveMs, 1.0), pct(addMs, 0.5), pct(addMs, 1.0),
                  double(pixelSamples) / pixels / seconds);
    return line;
}

std::string denoiseOnce(const Film& film, const std::string& name) {
    DenoiseResult result;
    std::string error;
    std::vector<double> times;
    for (int r = 0; r < 4; ++r) {  // the first run creates the device and loads the weights
        auto t0 = std::chrono::steady_clock::now();
        if (!denoise(film, DenoiseOptions{}, &result, &error)) return "oidn " + name + ": " + error;
        if (r > 0) times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    char line[256];
    std::snprintf(line, sizeof line, "oidn %-19s %4dx%-5d  %.1f ms (median of 3, guides prefiltered) on %s", name.c_str(),
                  film.width, film.height, median(times) * 1e3, result.device.c_str());
    return line;
}

}  // namespace

int main(int argc, char** argv) {
    int size = 256, samples = 64, maxDepth = 8, repeat = 3;
    bool traceOnly = false, oidn = false;
    std::string outDir, dumpProgram;
    int interactiveFrames = 0;
    std::vector<std::string> scenes;
    std::vector<SceneOverride> overrides;
    std::setvbuf(stdout, nullptr, _IOLBF, 0);  // each row as it is measured, even if the run is cut short
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto next = [&](int* v) {
            if (i + 1 >= argc || (*v = std::atoi(argv[++i])) <= 0) {
                std::fprintf(stderr, "caustic-bench: %s needs a positive integer\n", a.c_str());
                std::exit(2);
            }
        };
        if (a == "--size") next(&size);
        else if (a == "--samples") next(&samples);
        else if (a == "--max-depth") next(&maxDepth);
        else if (a == "--repeat") next(&repeat);
        else if (a == "--rays") traceOnly = true;
        else if (a == "--interactive") next(&interactiveFrames);
        else if (a == "--oidn") oidn = true;
        else if (a == "--out" && i + 1 < argc) outDir = argv[++i];
        else if (a == "--dump-program" && i + 1 < argc) dumpProgram = argv[++i];
        else if (a == "--set" && i + 1 < argc) {
            SceneOverride ov;
            std::string error;
            if (!parseSceneOverride(argv[++i], &ov, &error)) {
                std::fprintf(stderr, "caustic-bench: --set: %s\n", error.c_str());
                return 2;
            }
            overrides.push_back(ov);
        }
        else if (a.rfind("--", 0) == 0) {
            std::fprintf(stderr, "usage: caustic-bench [--size N] [--samples N] [--max-depth N] [--repeat N] [--rays] [--oidn] [--out DIR] [--dump-program FILE] [--interactive N] [--set path=value ...] [scene.json ...]\n");
            return a == "--help" ? 0 : 2;
        } else scenes.push_back(a);
    }
    if (scenes.empty()) scenes.push_back(std::string(CAUSTIC_SOURCE_DIR) + "/scenes/cornell-box.json");

    std::string error;
    auto context = HeadlessGlContext::create(false, &error);
    if (!context) { std::fprintf(stderr, "caustic-bench: %s\n", error.c_str()); return 1; }
    std::vector<std::string> configWarnings;
    const IntegratorConfig config = IntegratorConfig::fromEnvironment(&configWarnings);
    for (const std::string& w : configWarnings) std::fprintf(stderr, "caustic-bench: %s\n", w.c_str());
    useProgramCache(config.programCache);
    auto renderer = Renderer::create(defaultShaderDir(), config, &error);
    if (!renderer) { std::fprintf(stderr, "caustic-bench: %s\n", error.c_str()); return 1; }
    renderer->setImageReader(readImageWithoutOpenImageIo);  // HDR, PNG and JPEG without OpenImageIO
    renderer->setBakeGeometry(true);            // as batch mode renders (app/main.cpp)
    std::printf("# %s | %s | %s\n", context->info().vendor.c_str(), context->info().renderer.c_str(),
                context->info().version.c_str());
    std::printf("# %s\n", renderer->config().describe().c_str());
    std::printf("%-24s %10s %6s %5s %9s %9s %12s %12s %10s %9s %14s\n", "scene", "size", "spp", "depth", "wall s", "gpu s",
                "Msamples/s", "Mrays/s", "rays/smp", "cpu s", "Msamples/cpu-s");
    GLuint query = 0;
    glGenQueries(1, &query);
    unsigned raysProgram = 0;
    if (traceOnly) {
        ShaderLoader loader(defaultShaderDir());
        ShaderSource source;
        if (!loader.load(defaultShaderDir() + "/bench/rays.comp", renderer->config().defines(), &source, &error) ||
            !(raysProgram = compileComputeProgram(source, "bench/rays.comp", &error))) {
            std::fprintf(stderr, "caustic-bench: %s\n", error.c_str());
            return 1;
        }
    }
    std::vector<std::string> extra;  // the --rays and --oidn tables, printed after the main one
    if (!dumpProgram.empty()) {
        GLint length = 0;
        glGetProgramiv(renderer->program(), GL_PROGRAM_BINARY_LENGTH, &length);
        std::string binary(static_cast<size_t>(std::max(length, 0)), '\0');
        GLenum format = 0;
        if (length > 0) glGetProgramBinary(renderer->program(), length, &length, &format, binary.data());
        binary.resize(static_cast<size_t>(std::max(length, 0)));
        if (binary.empty() || !writeFileAtomically(dumpProgram, binary, &error))
            std::fprintf(stderr, "caustic-bench: no program binary written (%s)\n", binary.empty() ? "the driver gave none" : error.c_str());
    }
    for (const std::string& file : scenes) {
        SceneLoadResult loaded = loadScene(file, overrides);
        if (!loaded) { std::fprintf(stderr, "caustic-bench: %s\n", loaded.error.c_str()); return 1; }
        Scene scene = *loaded.scene;
        scene.render.width = scene.render.height = size;
        scene.render.maxDepth = maxDepth;
        if (!renderer->setScene(scene, &error)) { std::fprintf(stderr, "caustic-bench: %s\n", error.c_str()); return 1; }
        renderer->render(std::max(1, samples / 8));  // warm-up: shader JIT, caches, clocks
        std::vector<double> wall, gpu, rays, cpu;
        for (int r = 0; r < repeat; ++r) {
            renderer->resetAccumulation();
            auto t0 = std::chrono::steady_clock::now();
            const double c0 = cpuSeconds();
            glBeginQuery(GL_TIME_ELAPSED, query);
            renderer->render(samples);
            glEndQuery(GL_TIME_ELAPSED);
            GLuint64 ns = 0;
            glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);  // waits; the work is done already
            wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            gpu.push_back(double(ns) * 1e-9);
            cpu.push_back(cpuSeconds() - c0);
            rays.push_back(double(renderer->raysTraced()));
        }
        const WalkStats walks = renderer->walkStats();  // of the last repetition
        const double w = median(wall), g = median(gpu), n = median(rays), c = median(cpu);
        const double pixelSamples = double(samples) * size * size;
        const std::string name = file.substr(file.find_last_of('/') + 1);
        // llvmpipe answers timer queries with 0: print n/a rather than a made-up figure.
        char gpuText[16] = "n/a";
        if (g > 1e-3 * w) std::snprintf(gpuText, sizeof gpuText, "%.3f", g);
        // The GPU machine has been seen to drop queued work silently: check the image holds
        // exactly the samples asked for before believing the rate.
        const Film film = renderer->readFilm();
        const float counted = film.count[film.index(size / 2, size / 2)] + 0.5f;
        const char* complete = int(counted) == samples + 0 ? "" : "  INCOMPLETE: the image holds fewer samples";
        // A scene program that failed to build leaves the general one rendering (right, slower):
        // its rates are not the scene program's, and an A/B of a shader change would compare the
        // wrong programs without this mark (as when a type error sits in a specialised-only path).
        const char* fellBack = renderer->programFellBack() ? "  FALLBACK: the general program (the scene's failed to build)" : "";
        std::printf("%-24s %4dx%-5d %6d %5d %9.3f %9s %12.3f %12.3f %10.2f %9.3f %14.3f%s%s\n", name.c_str(), size, size,
                    samples, maxDepth, w, gpuText, pixelSamples / w * 1e-6, n / w * 1e-6, n / pixelSamples, c,
                    pixelSamples / std::max(c, 1e-9) * 1e-6, complete, fellBack);
        if (walks.groupSteps > 0) {
            // CAUSTIC_WALK_STATS: per sample, the walk loops' iterations the groups paid for and
            // those their lanes worked, and the share of lanes busy.
            char line[320];
            std::snprintf(line, sizeof line,
                          "walks %-19s %4dx%-5d  per sample: %.3f group iterations, %.3f lane iterations, %.3f trees; "
                          "lanes busy %.1f %% of %u",
                          name.c_str(), size, size, double(walks.groupSteps) / pixelSamples,
                          double(walks.laneSteps) / pixelSamples, double(walks.trees) / pixelSamples,
                          100.0 * double(walks.laneSteps) / (double(walks.groupSteps) * std::max(walks.subgroupSize, 1u)),
                          walks.subgroupSize);
            extra.push_back(line);
        }
        if (!outDir.empty()) {
            const std::vector<std::uint8_t> rgb = toSrgb8(film, ToneMap::Aces);
            std::string ppm = "P6\n" + std::to_string(size) + " " + std::to_string(size) + "\n255\n";
            ppm.append(rgb.begin(), rgb.end());
            const std::string path = outDir + "/" + name.substr(0, name.rfind('.')) + ".ppm";
            if (!writeFileAtomically(path, ppm, &error)) std::fprintf(stderr, "caustic-bench: %s\n", error.c_str());
        }
        if (interactiveFrames > 0) {
            extra.push_back(interactive(*renderer, scene, interactiveFrames, name));
            renderer->setBakeGeometry(true);
        }
        if (traceOnly) extra.push_back(traceRays(*renderer, raysProgram, query, name, size, repeat));
        if (oidn) extra.push_back(denoiseOnce(film, name));
    }
    for (const std::string& line : extra) std::printf("%s\n", line.c_str());
    glDeleteQueries(1, &query);
    return 0;
}
