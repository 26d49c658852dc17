// caustic-bvh-bench: the BVH benchmark (not a test). Generates a finely tessellated displaced
// sphere (>= 1M triangles by default, vertices shared), then reports, each a median of several
// runs: build time and rate (M triangles/s) and SAH cost for several build settings, refit time
// after moving the vertices, CPU traversal rate (M rays/s) for primary-like rays (a pinhole
// camera looking at the mesh) and for random rays (random origins inside the bounds, random
// directions), and for a TLAS of many instances how the SAH cost and the traversal rate of a
// refit tree degrade as instances move (the measurement behind kBvhRebuildFactor).
//   caustic-bvh-bench [--tris N] [--repeat N] [--rays N] [--quick]
#include "renderer/bvh.h"
#include "renderer/mesh.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <thread>
#include <vector>

using namespace caustic;

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

struct MeshData {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
};

// A UV sphere of rings x segments quads (two triangles each), radius displaced by a few octaves of
// sines so the surface has detail at every scale; poles are single shared vertices.
MeshData displacedSphere(std::size_t targetTris, float phase) {
    const auto n = static_cast<std::uint32_t>(std::ceil(std::sqrt(static_cast<double>(targetTris) / 4.0)));
    const std::uint32_t rings = n, segs = 2 * n;
    MeshData m;
    auto radius = [phase](float th, float ph) {
        float r = 1.0f;
        float amp = 0.08f, f = 3.0f;
        for (int o = 0; o < 5; ++o) {
            r += amp * std::sin(f * th + phase + static_cast<float>(o)) * std::cos(f * ph * 0.5f + 1.7f * static_cast<float>(o));
            amp *= 0.5f;
            f *= 2.7f;
        }
        return r;
    };
    Mesh sphere = makeUvSphere(rings, segs, radius);
    m.positions = std::move(sphere.positions);
    m.triangles = std::move(sphere.triangles);
    return m;
}

std::vector<Ray> primaryRays(int w, int h, const glm::vec3& eye, const glm::vec3& target) {
    glm::vec3 f = glm::normalize(target - eye), r = glm::normalize(glm::cross(f, {0, 1, 0}));
    glm::vec3 u = glm::cross(r, f);
    const float tanHalf = std::tan(glm::radians(30.0f) * 0.5f);
    std::vector<Ray> rays;
    rays.reserve(static_cast<std::size_t>(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float px = (2.0f * (static_cast<float>(x) + 0.5f) / static_cast<float>(w) - 1.0f) * tanHalf;
            float py = (1.0f - 2.0f * (static_cast<float>(y) + 0.5f) / static_cast<float>(h)) * tanHalf;
            rays.push_back({eye, glm::normalize(f + px * r + py * u)});
        }
    return rays;
}

std::vector<Ray> randomRays(std::size_t n, const Aabb& b, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    std::normal_distribution<float> nd;
    std::vector<Ray> rays(n);
    for (Ray& r : rays) {
        r.origin = b.min + glm::vec3(u01(rng), u01(rng), u01(rng)) * (b.max - b.min);
        r.dir = glm::normalize(glm::vec3(nd(rng), nd(rng), nd(rng)));
    }
    return rays;
}

// M rays/s for closest-hit on one thread (the CPU traversal is the test reference, not the
// renderer: one thread keeps the figure comparable between machines).
template <class F>
double raysPerSecond(const std::vector<Ray>& rays, F&& trace, std::size_t* hits) {
    std::size_t h = 0;
    auto t0 = Clock::now();
    for (const Ray& r : rays) h += trace(r);
    double s = seconds(t0, Clock::now());
    if (hits) *hits = h;
    return static_cast<double>(rays.size()) / s * 1e-6;
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t tris = 1u << 20;
    int repeat = 5;
    std::size_t nRays = 1u << 20;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto next = [&]() -> long {
            long v = i + 1 < argc ? std::atol(argv[++i]) : 0;
            if (v <= 0) {
                std::fprintf(stderr, "caustic-bvh-bench: %s needs a positive integer\n", a.c_str());
                std::exit(2);
            }
            return v;
        };
        if (a == "--tris") tris = static_cast<std::size_t>(next());
        else if (a == "--repeat") repeat = static_cast<int>(next());
        else if (a == "--rays") nRays = static_cast<std::size_t>(next());
        else if (a == "--quick") { repeat = 1; nRays = 1u << 17; }
        else {
            std::printf("usage: caustic-bvh-bench [--tris N] [--repeat N] [--rays N] [--quick]\n");
            return a == "--help" ? 0 : 2;
        }
    }

    auto tg = Clock::now();
    MeshData mesh = displacedSphere(tris, 0.0f);
    std::printf("mesh: displaced sphere, %zu triangles, %zu vertices (generated in %.2f s)\n",
                mesh.triangles.size(), mesh.positions.size(), seconds(tg, Clock::now()));
    std::printf("threads available: %u\n\n", std::thread::hardware_concurrency());

    struct Config { const char* name; BvhBuildOptions opt; };
    std::vector<Config> configs;
    auto add = [&](const char* name, int bins, bool all, std::uint32_t leaf, bool sah, int threads) {
        BvhBuildOptions o;
        o.bins = bins;
        o.allAxes = all;
        o.maxLeafSize = leaf;
        o.sah = sah;
        o.threads = threads;
        configs.push_back({name, o});
    };
    add("default: 16 bins, 3 axes, leaf<=8, threads", 16, true, 8, true, 0);
    add("16 bins, 3 axes, leaf<=8, 1 thread", 16, true, 8, true, 1);
    add("baseline: 12 bins, longest axis, leaf<=8", 12, false, 8, true, 0);
    add("12 bins, 3 axes, leaf<=8", 12, true, 8, true, 0);
    add("32 bins, 3 axes, leaf<=8", 32, true, 8, true, 0);
    add("16 bins, 3 axes, leaf<=4", 16, true, 4, true, 0);
    add("16 bins, 3 axes, leaf<=1", 16, true, 1, true, 0);
    add("median split, leaf<=4", 16, true, 4, false, 0);

    const std::vector<Ray> primary = primaryRays(1024, std::max<int>(1, static_cast<int>(nRays / 1024)),
                                                 {0.0f, 0.6f, 3.2f}, {0.0f, 0.0f, 0.0f});
    Aabb meshBounds;
    for (const glm::vec3& p : mesh.positions) meshBounds.grow(p);
    const std::vector<Ray> random = randomRays(nRays, meshBounds, 7);

    std::printf("%-44s %9s %9s %9s %6s %6s %10s %10s\n", "build", "time ms", "Mtris/s", "SAH cost",
                "depth", "leaf", "prim Mr/s", "rand Mr/s");
    MeshBlas defaultBlas;
    for (std::size_t c = 0; c < configs.size(); ++c) {
        std::vector<double> times;
        MeshBlas blas;
        for (int r = 0; r < repeat; ++r) {
            auto t0 = Clock::now();
            blas = buildBlas(mesh.positions, mesh.triangles, configs[c].opt);
            times.push_back(seconds(t0, Clock::now()));
        }
        double t = median(times);
        BvhStats st = bvhStats(blas.bvh);
        auto trace = [&](const Ray& ray) { return intersectBlas(blas, mesh.positions, ray).hit() ? 1 : 0; };
        double prim = raysPerSecond(primary, trace, nullptr);
        double rnd = raysPerSecond(random, trace, nullptr);
        std::printf("%-44s %9.1f %9.2f %9.2f %6d %6.2f %10.2f %10.2f\n", configs[c].name, t * 1e3,
                    static_cast<double>(mesh.triangles.size()) / t * 1e-6,
                    static_cast<double>(sahCost(blas.bvh)), st.depth, st.meanLeafCount, prim, rnd);
        std::fflush(stdout);
        if (c == 0) defaultBlas = std::move(blas);
    }

    // Refit: the vertices move (a different displacement phase), same triangles.
    {
        MeshData moved = displacedSphere(tris, 0.4f);
        std::vector<double> times;
        MeshBlas blas = defaultBlas;
        for (int r = 0; r < std::max(repeat, 5); ++r) {
            auto t0 = Clock::now();
            refitBlas(blas, (r % 2) ? mesh.positions : moved.positions);
            times.push_back(seconds(t0, Clock::now()));
        }
        refitBlas(blas, moved.positions);
        MeshBlas fresh = buildBlas(moved.positions, moved.triangles);
        std::printf("\nBLAS refit (%zu triangles, vertices moved): median %.2f ms; SAH cost %.2f "
                    "refit vs %.2f fresh build (x%.3f)\n",
                    mesh.triangles.size(), median(times) * 1e3, static_cast<double>(sahCost(blas.bvh)),
                    static_cast<double>(sahCost(fresh.bvh)),
                    static_cast<double>(sahCost(blas.bvh) / sahCost(fresh.bvh)));
    }

    // Any-hit rate.
    {
        auto occ = [&](const Ray& ray) { return occludedBlas(defaultBlas, mesh.positions, ray) ? 1 : 0; };
        std::size_t hits = 0;
        double rnd = raysPerSecond(random, occ, &hits);
        std::printf("any-hit, random rays: %.2f M rays/s (%zu of %zu occluded)\n", rnd, hits, random.size());
    }

    // TLAS: a grid of instances of a small mesh; refit after moving them by growing amounts,
    // against a fresh build of the same placement.
    {
        SceneBvh scene;
        MeshData small = displacedSphere(2000, 0.0f);
        scene.blases.push_back(buildBlas(small.positions, small.triangles));
        std::vector<std::vector<glm::vec3>> pos{small.positions};
        const int side = 40;
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f);
        std::vector<glm::vec3> base, drift;
        for (int z = 0; z < side; ++z)
            for (int x = 0; x < side; ++x) {
                glm::vec3 p{static_cast<float>(x) * 3.0f, 0.0f, static_cast<float>(z) * 3.0f};
                base.push_back(p);
                drift.push_back(glm::normalize(glm::vec3(u(rng), u(rng), u(rng))));
                scene.instances.push_back({0u, glm::translate(glm::mat4(1.0f), p)});
            }
        auto t0 = Clock::now();
        buildTlas(scene);
        double buildMs = seconds(t0, Clock::now()) * 1e3;
        Aabb wb = scene.tlas.nodes[0].bounds();
        std::vector<Ray> rays = randomRays(nRays / 4, wb, 11);
        auto traceScene = [&](const SceneBvh& s) {
            return [&s, &pos](const Ray& ray) {
                return intersectScene(s, pos, ray).hit() ? 1 : 0;
            };
        };
        std::printf("\nTLAS: %zu instances of %zu triangles; build %.2f ms\n", scene.instances.size(),
                    small.triangles.size(), buildMs);
        std::printf("%10s %12s %12s %10s %12s %12s %10s\n", "move", "refit ms", "SAH refit", "SAH fresh",
                    "ratio", "Mr/s refit", "Mr/s fresh");
        for (float amount : {0.0f, 1.0f, 3.0f, 6.0f, 12.0f, 25.0f, 50.0f}) {
            for (std::size_t i = 0; i < base.size(); ++i)
                scene.instances[i].objectToWorld = glm::translate(glm::mat4(1.0f), base[i] + amount * drift[i]);
            std::vector<double> times;
            for (int r = 0; r < 5; ++r) {
                auto t1 = Clock::now();
                refitTlas(scene);
                times.push_back(seconds(t1, Clock::now()));
            }
            SceneBvh fresh = scene;
            buildTlas(fresh);
            double a = raysPerSecond(rays, traceScene(scene), nullptr);
            double b = raysPerSecond(rays, traceScene(fresh), nullptr);
            float cr = sahCost(scene.tlas), cf = sahCost(fresh.tlas);
            std::printf("%10.1f %12.3f %12.2f %10.2f %12.2f %12.2f %10.2f%s\n", static_cast<double>(amount),
                        median(times) * 1e3, static_cast<double>(cr), static_cast<double>(cf),
                        static_cast<double>(cr / cf), a, b,
                        needsRebuild(scene.tlas) ? "  (needsRebuild)" : "");
        }
    }
    return 0;
}
