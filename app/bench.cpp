// caustic-bench: the speed benchmark (never a test). Renders the standard scenes at fixed
// settings after a warm-up and prints samples and rays per second, timed both by the wall clock
// and by a GL_TIME_ELAPSED query around the same work. Links no OpenImageIO, so the binary is
// small enough to carry to the GPU machine.
//   caustic-bench [--size N] [--samples N] [--max-depth N] [--repeat N] [scene.json ...]
#include "renderer/gl_context.h"
#include "renderer/hdr_file.h"
#include "renderer/renderer.h"
#include "renderer/scene_io.h"
#include "renderer/shader_loader.h"

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace caustic;

int main(int argc, char** argv) {
    int size = 256, samples = 64, maxDepth = 8, repeat = 3;
    std::vector<std::string> scenes;
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
        else if (a.rfind("--", 0) == 0) {
            std::fprintf(stderr, "usage: caustic-bench [--size N] [--samples N] [--max-depth N] [--repeat N] [scene.json ...]\n");
            return a == "--help" ? 0 : 2;
        } else scenes.push_back(a);
    }
    if (scenes.empty()) scenes.push_back(std::string(CAUSTIC_SOURCE_DIR) + "/scenes/cornell-box.json");

    std::string error;
    auto context = HeadlessGlContext::create(false, &error);
    if (!context) { std::fprintf(stderr, "caustic-bench: %s\n", error.c_str()); return 1; }
    auto renderer = Renderer::create(defaultShaderDir(), &error);
    if (!renderer) { std::fprintf(stderr, "caustic-bench: %s\n", error.c_str()); return 1; }
    renderer->setImageReader(readRadianceHdr);  // environment maps without OpenImageIO
    std::printf("# %s | %s | %s\n", context->info().vendor.c_str(), context->info().renderer.c_str(),
                context->info().version.c_str());
    std::printf("%-24s %10s %6s %5s %9s %9s %12s %12s %10s\n", "scene", "size", "spp", "depth", "wall s", "gpu s",
                "Msamples/s", "Mrays/s", "rays/smp");
    GLuint query = 0;
    glGenQueries(1, &query);
    for (const std::string& file : scenes) {
        SceneLoadResult loaded = loadScene(file);
        if (!loaded) { std::fprintf(stderr, "caustic-bench: %s\n", loaded.error.c_str()); return 1; }
        Scene scene = *loaded.scene;
        scene.render.width = scene.render.height = size;
        scene.render.maxDepth = maxDepth;
        if (!renderer->setScene(scene, &error)) { std::fprintf(stderr, "caustic-bench: %s\n", error.c_str()); return 1; }
        renderer->render(std::max(1, samples / 8));  // warm-up: shader JIT, caches, clocks
        std::vector<double> wall, gpu, rays;
        for (int r = 0; r < repeat; ++r) {
            renderer->resetAccumulation();
            auto t0 = std::chrono::steady_clock::now();
            glBeginQuery(GL_TIME_ELAPSED, query);
            renderer->render(samples);
            glEndQuery(GL_TIME_ELAPSED);
            GLuint64 ns = 0;
            glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);  // waits; the work is done already
            wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            gpu.push_back(double(ns) * 1e-9);
            rays.push_back(double(renderer->raysTraced()));
        }
        auto median = [](std::vector<double> v) { std::sort(v.begin(), v.end()); return v[v.size() / 2]; };
        const double w = median(wall), g = median(gpu), n = median(rays);
        const double pixelSamples = double(samples) * size * size;
        const std::string name = file.substr(file.find_last_of('/') + 1);
        // llvmpipe answers timer queries with 0: print n/a rather than a made-up figure.
        char gpuText[16] = "n/a";
        if (g > 1e-3 * w) std::snprintf(gpuText, sizeof gpuText, "%.3f", g);
        std::printf("%-24s %4dx%-5d %6d %5d %9.3f %9s %12.2f %12.2f %10.2f\n", name.c_str(), size, size, samples,
                    maxDepth, w, gpuText, pixelSamples / w * 1e-6, n / w * 1e-6, n / pixelSamples);
    }
    glDeleteQueries(1, &query);
    return 0;
}
