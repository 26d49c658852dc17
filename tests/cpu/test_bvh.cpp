// BVH tests: the two-level BVH against brute force (same hit, same t, same primitive except exact
// ties), any-hit agreement, refit against a fresh build, watertightness of the ray/triangle test
// through the hierarchy, robustness to broken input, and the SAH doing better than a median split.
#include "renderer/bvh.h"
#include "renderer/mesh.h"

#include <catch2/catch.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <random>
#include <set>
#include <vector>

using namespace caustic;

namespace {

struct TestMesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
};

// Independent triangles with random corners in [-1, 1]^3, sized from tiny to large.
TestMesh randomSoup(std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::uniform_real_distribution<float> s(0.0f, 1.0f);
    TestMesh m;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3 c{u(rng), u(rng), u(rng)};
        const float size = 0.3f * s(rng) * s(rng);
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (int k = 0; k < 3; ++k) m.positions.push_back(c + size * glm::vec3(u(rng), u(rng), u(rng)));
        m.triangles.push_back({base, base + 1, base + 2});
    }
    return m;
}

// A closed UV sphere of radius r (renderer/mesh.h).
TestMesh uvSphere(std::uint32_t rings, std::uint32_t segs, float r = 1.0f) {
    Mesh sphere = makeUvSphere(rings, segs, [r](float, float) { return r; });
    return TestMesh{std::move(sphere.positions), std::move(sphere.triangles)};
}

// A closed torus around the y axis (major radius R, minor radius r), shared vertices.
TestMesh torus(std::uint32_t nu, std::uint32_t nv, float R = 1.0f, float r = 0.35f) {
    TestMesh m;
    constexpr float kTwoPi = 6.28318530717959f;
    for (std::uint32_t i = 0; i < nu; ++i)
        for (std::uint32_t j = 0; j < nv; ++j) {
            const float a = kTwoPi * static_cast<float>(i) / static_cast<float>(nu);
            const float b = kTwoPi * static_cast<float>(j) / static_cast<float>(nv);
            m.positions.push_back({(R + r * std::cos(b)) * std::cos(a), r * std::sin(b), (R + r * std::cos(b)) * std::sin(a)});
        }
    auto v = [nu, nv](std::uint32_t i, std::uint32_t j) { return (i % nu) * nv + (j % nv); };
    for (std::uint32_t i = 0; i < nu; ++i)
        for (std::uint32_t j = 0; j < nv; ++j) {
            m.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
            m.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
        }
    return m;
}

Aabb boundsOf(const TestMesh& m) {
    Aabb b;
    for (const glm::vec3& p : m.positions) b.grow(p);
    return b;
}

// Random rays: origins in the bounds enlarged by half their size, random directions; every
// other ray aimed at a random point of a random triangle, so that many rays hit.
std::vector<Ray> randomRays(const TestMesh& m, std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> nd;
    const Aabb b = boundsOf(m);
    const glm::vec3 ext = b.max - b.min;
    std::vector<Ray> rays(n);
    for (std::size_t i = 0; i < n; ++i) {
        Ray& r = rays[i];
        r.origin = b.min - 0.5f * ext + 2.0f * ext * glm::vec3(u(rng), u(rng), u(rng));
        if (i % 2 == 0 || m.triangles.empty()) {
            r.dir = glm::vec3(nd(rng), nd(rng), nd(rng));
        } else {
            const glm::uvec3 t = m.triangles[std::min<std::size_t>(m.triangles.size() - 1, static_cast<std::size_t>(u(rng) * static_cast<float>(m.triangles.size())))];
            float a = u(rng), c = u(rng);
            if (a + c > 1.0f) { a = 1.0f - a; c = 1.0f - c; }
            const glm::vec3 target = m.positions[t.x] + a * (m.positions[t.y] - m.positions[t.x]) + c * (m.positions[t.z] - m.positions[t.x]);
            r.dir = target - r.origin;
        }
    }
    return rays;
}

// Brute force: every triangle with the same intersection test, in index order.
RayHit bruteForce(const TestMesh& m, const Ray& ray, float tMax = std::numeric_limits<float>::infinity()) {
    const WatertightRay wr(ray);
    RayHit best;
    best.t = tMax;
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
        const glm::uvec3 t = m.triangles[i];
        float th, u, v;
        if (intersectTriangle(wr, m.positions[t.x], m.positions[t.y], m.positions[t.z], best.t, &th, &u, &v)) {
            best.t = th;
            best.primitive = static_cast<std::uint32_t>(i);
            best.u = u;
            best.v = v;
        }
    }
    if (!best.hit()) best.t = std::numeric_limits<float>::infinity();
    return best;
}

// The t at which one given triangle is hit (inf when it is not).
float triangleT(const TestMesh& m, std::uint32_t prim, const Ray& ray) {
    const glm::uvec3 t = m.triangles[prim];
    float th, u, v;
    if (intersectTriangle(WatertightRay(ray), m.positions[t.x], m.positions[t.y], m.positions[t.z],
                          std::numeric_limits<float>::infinity(), &th, &u, &v))
        return th;
    return std::numeric_limits<float>::infinity();
}

bool closeT(float a, float b) { return std::abs(a - b) <= 1e-5f * std::max(std::abs(a), std::abs(b)); }

// Counts mismatches between the BVH and brute force over the rays (closest hit and any hit).
struct Mismatches {
    std::size_t closest = 0, any = 0, hits = 0;
};

Mismatches compareBlas(const TestMesh& m, const MeshBlas& blas, const std::vector<Ray>& rays) {
    Mismatches mm;
    for (const Ray& ray : rays) {
        const RayHit bf = bruteForce(m, ray);
        const RayHit h = intersectBlas(blas, m.positions, ray);
        if (bf.hit()) ++mm.hits;
        bool ok = h.hit() == bf.hit();
        if (ok && bf.hit()) {
            ok = closeT(h.t, bf.t) &&
                 (h.primitive == bf.primitive || closeT(triangleT(m, h.primitive, ray), bf.t));
        }
        if (!ok) ++mm.closest;
        // Any hit, unbounded and bounded just before / after the closest hit.
        if (occludedBlas(blas, m.positions, ray) != bf.hit()) ++mm.any;
        if (bf.hit()) {
            if (!occludedBlas(blas, m.positions, ray, bf.t * 1.0001f)) ++mm.any;
            if (occludedBlas(blas, m.positions, ray, bf.t * 0.9999f) != bruteForce(m, ray, bf.t * 0.9999f).hit()) ++mm.any;
        }
    }
    return mm;
}

bool finiteNode(const BvhNode& n) {
    for (int a = 0; a < 3; ++a)
        if (std::isnan(n.boundsMin[a]) || std::isnan(n.boundsMax[a])) return false;
    return true;
}

// Structure: every primitive in exactly one leaf, children inside their parents, leaves around
// their primitives, indices in range, children after parents.
void checkStructure(const Bvh& bvh, const std::vector<Aabb>& primBounds) {
    std::vector<int> seen(primBounds.size(), 0);
    for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
        const BvhNode& n = bvh.nodes[i];
        INFO("node " << i);
        REQUIRE(finiteNode(n));
        if (n.isLeaf()) {
            REQUIRE(std::size_t(n.rightOrFirst) + n.count() <= bvh.primIndices.size());
            for (std::uint32_t k = 0; k < n.count(); ++k) {
                const std::uint32_t id = bvh.primIndices[n.rightOrFirst + k];
                REQUIRE(id < primBounds.size());
                ++seen[id];
                const Aabb& b = primBounds[id];
                REQUIRE(glm::all(glm::lessThanEqual(n.boundsMin, b.min)));
                REQUIRE(glm::all(glm::greaterThanEqual(n.boundsMax, b.max)));
            }
        } else {
            REQUIRE(n.axis() < 3);
            REQUIRE(i + 1 < bvh.nodes.size());
            REQUIRE(n.rightOrFirst > i + 1);
            REQUIRE(n.rightOrFirst < bvh.nodes.size());
            for (const BvhNode* c : {&bvh.nodes[i + 1], &bvh.nodes[n.rightOrFirst]}) {
                REQUIRE(glm::all(glm::lessThanEqual(n.boundsMin, c->boundsMin)));
                REQUIRE(glm::all(glm::greaterThanEqual(n.boundsMax, c->boundsMax)));
            }
        }
    }
    std::size_t valid = 0;
    for (std::size_t i = 0; i < primBounds.size(); ++i) {
        // What the build accepts: finite, non-empty boxes whose centroid sum does not overflow.
        const glm::vec3 sum = primBounds[i].min + primBounds[i].max;
        if (primBounds[i].valid() && std::isfinite(sum.x) && std::isfinite(sum.y) && std::isfinite(sum.z)) {
            ++valid;
            REQUIRE(seen[i] == 1);
        } else {
            REQUIRE(seen[i] == 0);
        }
    }
    REQUIRE(bvh.primIndices.size() == valid);
    REQUIRE(bvh.skipped == primBounds.size() - valid);
    REQUIRE(bvhStats(bvh).depth <= kBvhMaxDepth);
}

std::vector<Aabb> triangleBoxes(const TestMesh& m) {
    std::vector<Aabb> b(m.triangles.size());
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
        const glm::uvec3 t = m.triangles[i];
        if (t.x >= m.positions.size() || t.y >= m.positions.size() || t.z >= m.positions.size()) continue;
        bool finite = true;
        for (std::uint32_t k : {t.x, t.y, t.z})
            for (int a = 0; a < 3; ++a) finite = finite && std::isfinite(m.positions[k][a]);
        if (!finite) continue;
        b[i].grow(m.positions[t.x]);
        b[i].grow(m.positions[t.y]);
        b[i].grow(m.positions[t.z]);
    }
    return b;
}

// ---- Scene-level brute force ----

struct TestScene {
    std::vector<TestMesh> meshes;
    std::vector<std::vector<glm::vec3>> positions;
    SceneBvh bvh;
};

RayHit bruteForceScene(const TestScene& s, const Ray& ray) {
    RayHit best;
    for (std::size_t i = 0; i < s.bvh.instances.size(); ++i) {
        const TestMesh& m = s.meshes[s.bvh.instances[i].mesh];
        const Ray local = transformRay(glm::inverse(s.bvh.instances[i].objectToWorld), ray);
        const RayHit h = bruteForce(m, local, best.t);
        if (h.hit() && h.t < best.t) {
            best = h;
            best.instance = static_cast<std::uint32_t>(i);
        }
    }
    return best;
}

glm::mat4 randomTransform(std::mt19937& rng, float spread) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::uniform_real_distribution<float> s(0.3f, 2.0f);
    glm::mat4 m = glm::translate(glm::mat4(1.0f), spread * glm::vec3(u(rng), u(rng), u(rng)));
    m = glm::rotate(m, 3.14159f * u(rng), glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f)));
    return glm::scale(m, glm::vec3(s(rng), s(rng), s(rng)));  // non-uniform
}

TestScene makeScene(std::size_t instances, std::uint32_t seed) {
    TestScene s;
    s.meshes = {uvSphere(12, 24), torus(24, 12), randomSoup(300, seed)};
    for (const TestMesh& m : s.meshes) {
        s.positions.push_back(m.positions);
        s.bvh.blases.push_back(buildBlas(m.positions, m.triangles));
    }
    std::mt19937 rng(seed);
    for (std::size_t i = 0; i < instances; ++i)
        s.bvh.instances.push_back({static_cast<std::uint32_t>(i % s.meshes.size()), randomTransform(rng, 12.0f)});
    buildTlas(s.bvh);
    return s;
}

std::vector<Ray> sceneRays(std::size_t n, std::uint32_t seed, float spread) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Ray> rays(n);
    for (Ray& r : rays) {
        r.origin = spread * glm::vec3(u(rng), u(rng), u(rng));
        r.dir = glm::vec3(u(rng), u(rng), u(rng));
    }
    return rays;
}

Mismatches compareScene(const TestScene& s, const std::vector<Ray>& rays) {
    Mismatches mm;
    for (const Ray& ray : rays) {
        const RayHit bf = bruteForceScene(s, ray);
        const RayHit h = intersectScene(s.bvh, s.positions, ray);
        if (bf.hit()) ++mm.hits;
        bool ok = h.hit() == bf.hit();
        if (ok && bf.hit()) {
            ok = closeT(h.t, bf.t);
            if (ok && (h.instance != bf.instance || h.primitive != bf.primitive)) {
                // A tie: the BVH's triangle must be hit at the same t.
                const Ray local = transformRay(glm::inverse(s.bvh.instances[h.instance].objectToWorld), ray);
                ok = closeT(triangleT(s.meshes[s.bvh.instances[h.instance].mesh], h.primitive, local), bf.t);
            }
        }
        if (!ok) ++mm.closest;
        if (occludedScene(s.bvh, s.positions, ray) != bf.hit()) ++mm.any;
    }
    return mm;
}

}  // namespace

TEST_CASE("BvhNode is the 32-byte std430 layout shared with GLSL", "[bvh]") {
    STATIC_REQUIRE(sizeof(BvhNode) == 32);
    BvhNode n{};
    n.countAndAxis = (5u << 2) | 2u;
    CHECK(n.isLeaf());
    CHECK(n.count() == 5);
    n.countAndAxis = 2u;
    CHECK_FALSE(n.isLeaf());
    CHECK(n.axis() == 2);
}

TEST_CASE("BVH closest and any hit match brute force on random triangle soups", "[bvh]") {
    struct Setting { const char* name; BvhBuildOptions opt; };
    std::vector<Setting> settings;
    settings.push_back({"default", {}});
    BvhBuildOptions o;
    o.bins = 12;
    o.allAxes = false;
    settings.push_back({"12 bins longest axis", o});
    o = {};
    o.maxLeafSize = 1;
    o.threads = 1;
    settings.push_back({"leaf 1, single thread", o});
    o = {};
    o.sah = false;
    o.maxLeafSize = 4;
    settings.push_back({"median split", o});
    o = {};
    o.bins = 64;
    o.maxLeafSize = 16;
    settings.push_back({"64 bins, leaf 16", o});

    for (std::size_t n : {std::size_t(1), std::size_t(2), std::size_t(7), std::size_t(100), std::size_t(3000)}) {
        const TestMesh m = randomSoup(n, static_cast<std::uint32_t>(n) * 7u + 1u);
        const std::vector<Ray> rays = randomRays(m, n < 100 ? 500 : 2000, 42);
        for (const Setting& s : settings) {
            INFO(n << " triangles, " << s.name);
            const MeshBlas blas = buildBlas(m.positions, m.triangles, s.opt);
            checkStructure(blas.bvh, triangleBoxes(m));
            const Mismatches mm = compareBlas(m, blas, rays);
            CHECK(mm.hits > rays.size() / 10);
            CHECK(mm.closest == 0);
            CHECK(mm.any == 0);
        }
    }
}

TEST_CASE("BVH matches brute force on closed meshes with shared vertices", "[bvh]") {
    for (const TestMesh& m : {uvSphere(24, 48), torus(48, 24), uvSphere(3, 4)}) {
        const MeshBlas blas = buildBlas(m.positions, m.triangles);
        checkStructure(blas.bvh, triangleBoxes(m));
        const std::vector<Ray> rays = randomRays(m, 3000, 5);
        const Mismatches mm = compareBlas(m, blas, rays);
        INFO(m.triangles.size() << " triangles");
        CHECK(mm.hits > rays.size() / 4);
        CHECK(mm.closest == 0);
        CHECK(mm.any == 0);
    }
}

TEST_CASE("Parallel build of a large soup is correct and the same tree as single-threaded", "[bvh]") {
    const TestMesh m = randomSoup(120000, 99);
    BvhBuildOptions one;
    one.threads = 1;
    BvhBuildOptions many;
    many.threads = 4;  // more threads than this machine's cores: exercises the splicing
    const MeshBlas a = buildBlas(m.positions, m.triangles, one);
    const MeshBlas b = buildBlas(m.positions, m.triangles, many);
    checkStructure(b.bvh, triangleBoxes(m));
    // The build is deterministic whatever the thread count: same nodes, same order.
    REQUIRE(a.bvh.nodes.size() == b.bvh.nodes.size());
    CHECK(std::memcmp(a.bvh.nodes.data(), b.bvh.nodes.data(), a.bvh.nodes.size() * sizeof(BvhNode)) == 0);
    CHECK(a.bvh.primIndices == b.bvh.primIndices);
    CHECK(a.bvh.builtSahCost == Approx(sahCost(a.bvh)).epsilon(1e-4));
    const Mismatches mm = compareBlas(m, b, randomRays(m, 400, 8));
    CHECK(mm.closest == 0);
    CHECK(mm.any == 0);
}

TEST_CASE("Two-level BVH: many rotated, scaled instances match brute force", "[bvh]") {
    const TestScene s = makeScene(150, 17);
    const Mismatches mm = compareScene(s, sceneRays(1500, 3, 14.0f));
    CHECK(mm.hits > 200);
    CHECK(mm.closest == 0);
    CHECK(mm.any == 0);
}

TEST_CASE("TLAS refit after moving instances gives the same hits as a fresh build", "[bvh]") {
    TestScene s = makeScene(120, 23);
    const float cost0 = sahCost(s.bvh.tlas);
    std::mt19937 rng(77);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (Instance& inst : s.bvh.instances) {
        // Move, rotate and rescale every instance.
        inst.objectToWorld = glm::translate(glm::mat4(1.0f), 3.0f * glm::vec3(u(rng), u(rng), u(rng))) *
                             inst.objectToWorld *
                             glm::rotate(glm::mat4(1.0f), u(rng), glm::vec3(0.3f, 1.0f, 0.2f)) *
                             glm::scale(glm::mat4(1.0f), glm::vec3(1.0f + 0.5f * u(rng)));
    }
    refitTlas(s.bvh);
    TestScene fresh = s;
    buildTlas(fresh.bvh);
    const std::vector<Ray> rays = sceneRays(1500, 4, 14.0f);
    std::size_t differ = 0, hits = 0;
    for (const Ray& ray : rays) {
        const RayHit a = intersectScene(s.bvh, s.positions, ray);
        const RayHit b = intersectScene(fresh.bvh, fresh.positions, ray);
        if (b.hit()) ++hits;
        if (a.hit() != b.hit() || (a.hit() && (a.t != b.t))) ++differ;
        if (occludedScene(s.bvh, s.positions, ray) != b.hit()) ++differ;
    }
    CHECK(hits > 200);
    CHECK(differ == 0);
    const Mismatches mm = compareScene(s, rays);
    CHECK(mm.closest == 0);
    CHECK(mm.any == 0);
    // Every node of the refit tree still bounds its children.
    for (std::size_t i = 0; i < s.bvh.tlas.nodes.size(); ++i) REQUIRE(finiteNode(s.bvh.tlas.nodes[i]));
    CHECK(cost0 > 0.0f);
}

TEST_CASE("Refit cost growth flags a rebuild when instances scatter", "[bvh]") {
    TestScene s = makeScene(200, 31);
    CHECK_FALSE(refitTlas(s.bvh));  // nothing moved
    CHECK(sahCost(s.bvh.tlas) == Approx(s.bvh.tlas.builtSahCost).epsilon(1e-4));
    // Shuffle the placements: the tree's grouping no longer matches space.
    std::mt19937 rng(5);
    std::vector<glm::mat4> m;
    for (const Instance& i : s.bvh.instances) m.push_back(i.objectToWorld);
    std::shuffle(m.begin(), m.end(), rng);
    for (std::size_t i = 0; i < m.size(); ++i) s.bvh.instances[i].objectToWorld = m[i];
    CHECK(refitTlas(s.bvh));
    buildTlas(s.bvh);
    CHECK_FALSE(needsRebuild(s.bvh.tlas));
}

TEST_CASE("BLAS refit after deforming vertices gives the same hits as a fresh build", "[bvh]") {
    TestMesh m = torus(40, 20);
    MeshBlas blas = buildBlas(m.positions, m.triangles);
    for (glm::vec3& p : m.positions) p = glm::vec3(p.x * 1.3f, p.y + 0.2f * std::sin(3.0f * p.x), p.z * 0.8f);
    refitBlas(blas, m.positions);
    checkStructure(blas.bvh, triangleBoxes(m));
    const MeshBlas fresh = buildBlas(m.positions, m.triangles);
    std::size_t differ = 0;
    for (const Ray& ray : randomRays(m, 3000, 12)) {
        const RayHit a = intersectBlas(blas, m.positions, ray), b = intersectBlas(fresh, m.positions, ray);
        if (a.hit() != b.hit() || (a.hit() && a.t != b.t)) ++differ;
    }
    CHECK(differ == 0);
    const Mismatches mm = compareBlas(m, blas, randomRays(m, 1000, 13));
    CHECK(mm.closest == 0);
    CHECK(mm.any == 0);
}

TEST_CASE("Watertight: rays from inside a closed mesh aimed at its vertices and edges never escape", "[bvh]") {
    struct Case { const char* name; TestMesh mesh; glm::mat4 toWorld; };
    std::vector<Case> cases;
    cases.push_back({"sphere", uvSphere(16, 32), glm::mat4(1.0f)});
    cases.push_back({"coarse sphere", uvSphere(4, 5), glm::mat4(1.0f)});
    cases.push_back({"torus", torus(32, 16), glm::mat4(1.0f)});
    cases.push_back({"rotated, scaled sphere instance",
                     uvSphere(16, 32),
                     glm::rotate(glm::translate(glm::mat4(1.0f), {3.0f, -1.0f, 2.0f}), 0.7f, glm::vec3(1.0f, 2.0f, 0.5f)) *
                         glm::scale(glm::mat4(1.0f), {2.0f, 0.5f, 1.3f})});
    for (const Case& c : cases) {
        const TestMesh& m = c.mesh;
        SceneBvh scene;
        scene.blases.push_back(buildBlas(m.positions, m.triangles));
        scene.instances.push_back({0u, c.toWorld});
        buildTlas(scene);
        const std::vector<std::vector<glm::vec3>> pos{m.positions};
        const bool isTorus = std::string(c.name) == "torus";
        std::mt19937 rng(1234);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
        std::uniform_int_distribution<std::size_t> pickTri(0, m.triangles.size() - 1);
        std::size_t misses = 0, rays = 0;
        for (int i = 0; i < 25000; ++i) {
            // An origin inside: near the centre of the sphere, or on the torus's core circle.
            glm::vec3 o;
            if (isTorus) {
                const float a = 3.14159f * u(rng);
                o = glm::vec3(std::cos(a), 0.0f, std::sin(a)) + 0.1f * glm::vec3(u(rng), u(rng), u(rng));
            } else {
                o = 0.3f * glm::vec3(u(rng), u(rng), u(rng));
            }
            const glm::uvec3 t = m.triangles[pickTri(rng)];
            const glm::vec3 v0 = m.positions[t.x], v1 = m.positions[t.y], v2 = m.positions[t.z];
            // Exactly at a vertex, and at points of the three edges (computed in float: on the
            // edge to within rounding, which is what tests the watertight test).
            const float s = u01(rng);
            for (const glm::vec3& target : {v0, v1 + s * (v2 - v1), v0 + s * (v1 - v0), v2 + s * (v0 - v2)}) {
                // Directions in object space, mapped to the world with the instance transform.
                const glm::vec3 wo = glm::vec3(c.toWorld * glm::vec4(o, 1.0f));
                const glm::vec3 wt = glm::vec3(c.toWorld * glm::vec4(target, 1.0f));
                const Ray ray{wo, wt - wo};
                ++rays;
                if (!intersectScene(scene, pos, ray).hit()) ++misses;
                if (!occludedScene(scene, pos, ray)) ++misses;
            }
        }
        INFO(c.name << ": " << rays << " rays");
        CHECK(rays == 100000);
        CHECK(misses == 0);
    }
}

TEST_CASE("Broken input never puts NaN into the BVH", "[bvh]") {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    TestMesh m = randomSoup(500, 3);
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back({nan, 0.0f, 0.0f});
    m.positions.push_back({inf, 1.0f, 0.0f});
    m.positions.push_back({0.0f, -inf, 0.0f});
    m.positions.push_back({3e38f, 3e38f, 3e38f});
    m.positions.push_back({2e38f, 3e38f, 3e38f});
    m.positions.push_back({0.5f, 0.5f, 0.5f});
    m.triangles.push_back({base, 0, 1});            // NaN vertex
    m.triangles.push_back({base + 1, 2, 3});        // inf vertex
    m.triangles.push_back({base + 2, base + 1, 4}); // -inf and inf
    m.triangles.push_back({base + 3, base + 4, base + 3});  // centroid sum overflows (and repeated index)
    m.triangles.push_back({base + 5, base + 5, base + 5});  // a point
    m.triangles.push_back({0, 0, 1});               // a line
    m.triangles.push_back({0, 1, 100000});          // index out of range
    for (int i = 0; i < 50; ++i) m.triangles.push_back({7, 8, 9});  // 50 identical triangles
    const MeshBlas blas = buildBlas(m.positions, m.triangles);
    const std::vector<Aabb> boxes = triangleBoxes(m);
    checkStructure(blas.bvh, boxes);
    CHECK(blas.bvh.skipped == 5);  // NaN, inf, -inf, overflow, out of range
    for (const BvhNode& n : blas.bvh.nodes) REQUIRE(finiteNode(n));
    for (const Ray& ray : randomRays(randomSoup(500, 3), 500, 9)) {
        const RayHit h = intersectBlas(blas, m.positions, ray);
        if (h.hit()) REQUIRE(std::isfinite(h.t));
    }

    // Nothing valid at all, and nothing at all.
    const std::vector<glm::vec3> bad{{nan, nan, nan}};
    const std::vector<glm::uvec3> tri{{0, 0, 0}};
    const MeshBlas empty = buildBlas(bad, tri);
    CHECK(empty.bvh.empty());
    CHECK(empty.bvh.skipped == 1);
    CHECK_FALSE(intersectBlas(empty, bad, Ray{{0, 0, 0}, {1, 0, 0}}).hit());
    CHECK(buildBvh({}).empty());

    // A TLAS with broken transforms leaves those instances out.
    SceneBvh scene;
    scene.blases.push_back(buildBlas(m.positions, m.triangles));
    REQUIRE(scene.blases[0].bvh.nodes[0].bounds().valid());
    glm::mat4 nanM(1.0f);
    nanM[3][0] = nan;
    scene.instances = {{0u, glm::mat4(1.0f)}, {0u, nanM}, {0u, glm::mat4(0.0f)}, {7u, glm::mat4(1.0f)}};
    buildTlas(scene);
    CHECK(scene.tlas.primIndices.size() == 1);
    for (const BvhNode& n : scene.tlas.nodes) REQUIRE(finiteNode(n));
}

TEST_CASE("Refit with vertices turned NaN keeps the bounds NaN-free", "[bvh]") {
    TestMesh m = uvSphere(8, 16);
    MeshBlas blas = buildBlas(m.positions, m.triangles);
    m.positions[5] = glm::vec3(std::numeric_limits<float>::quiet_NaN());
    refitBlas(blas, m.positions);
    for (const BvhNode& n : blas.bvh.nodes) REQUIRE(finiteNode(n));
    const RayHit h = intersectBlas(blas, m.positions, Ray{{0, 0, 0}, {0.3f, 0.2f, 1.0f}});
    CHECK(h.hit());
}

TEST_CASE("Binned SAH beats a median split in SAH cost", "[bvh]") {
    for (const TestMesh& m : {uvSphere(64, 128), torus(96, 48), randomSoup(20000, 11)}) {
        BvhBuildOptions median;
        median.sah = false;
        median.maxLeafSize = 4;
        const float sah = sahCost(buildBlas(m.positions, m.triangles).bvh);
        const float med = sahCost(buildBlas(m.positions, m.triangles, median).bvh);
        INFO(m.triangles.size() << " triangles: SAH " << sah << ", median " << med);
        CHECK(sah < med);
    }
}

// The binary trees the wide collapses are tested on: the default build, leaves of one triangle
// (every small subtree merged), leaves as long as allowed (longer than kWideLeafMaxCount get
// split into nodes) and a median split.
namespace {
struct WideSetting { const char* name; BvhBuildOptions opt; };
std::vector<WideSetting> wideSettings() {
    std::vector<WideSetting> settings;
    settings.push_back({"default", {}});
    BvhBuildOptions o;
    o.maxLeafSize = 1;
    settings.push_back({"leaf 1", o});
    o = {};
    o.bins = 64;
    o.maxLeafSize = 16;
    o.traversalCost = 4.0f;  // leaves as long as allowed
    settings.push_back({"leaf 16", o});
    o = {};
    o.sah = false;
    o.maxLeafSize = 4;
    settings.push_back({"median split", o});
    return settings;
}

// The 4-wide form is checked on random soups of 1, 3, 40 and 3000 triangles, each built with
// every setting above: check(n, setting, the triangles' boxes, the binary build).
template <typename Check>
void forEachWideCase(std::uint32_t seedScale, std::uint32_t seedOffset, Check&& check) {
    const std::vector<WideSetting> settings = wideSettings();
    for (std::size_t n : {std::size_t(1), std::size_t(3), std::size_t(40), std::size_t(3000)}) {
        const TestMesh m = randomSoup(n, static_cast<std::uint32_t>(n) * seedScale + seedOffset);
        const std::vector<Aabb> boxes = triangleBoxes(m);
        for (const WideSetting& s : settings) {
            INFO(n << " triangles, " << s.name);
            check(n, s, boxes, buildBlas(m.positions, m.triangles, s.opt));
        }
    }
}

// A wide node's leaf reference: counts its triangles in seen and checks that each
// lies inside the box the walk meets it in (lo, hi). Returns the leaf's triangle count.
std::uint32_t checkWideLeaf(std::uint32_t ref, glm::vec3 lo, glm::vec3 hi, const MeshBlas& blas,
                            const std::vector<Aabb>& boxes, std::vector<int>& seen) {
    const std::uint32_t first = ref & kWideLeafMaxFirst, count = (ref >> kLeafCountShift) & kWideLeafMaxCount;
    REQUIRE(count >= 1);
    REQUIRE(first + count <= seen.size());
    for (std::uint32_t t = first; t < first + count; ++t) {
        ++seen[t];
        const Aabb tb = boxes[blas.triangleIds[t]];
        CHECK(glm::all(glm::lessThanEqual(lo, tb.min)));
        CHECK(glm::all(glm::greaterThanEqual(hi, tb.max)));
    }
    return count;
}
}  // namespace

TEST_CASE("collapseBvh4: the 4-wide form holds every leaf exactly once, inside its ancestors' boxes", "[bvh]") {
    // The GPU walks this form (geometry/walk_wide4.glsl); its traversal is checked against the CPU BVH
    // in tests/gpu/test_geometry.cpp. Leaves longer than kWideLeafMaxCount (leaf 16 here) become
    // nodes of shorter leaves.
    forEachWideCase(3u, 5u, [](std::size_t n, const WideSetting& s, const std::vector<Aabb>& boxes, const MeshBlas& blas) {
        std::vector<WideBvhNode> wide(5);  // appended after 5 others: indices are absolute
        const std::uint32_t base = 5;
        REQUIRE(collapseBvh4(blas.bvh, base, wide));
        REQUIRE(wide.size() > 5);
        std::vector<int> seen(blas.triangles.size(), 0);
        std::size_t reached = 0, leaves = 0, mergedLeaves = 0;
        // Walk from the root with each child's box; every box must contain what is below it.
        struct Item { std::uint32_t ref; glm::vec3 lo, hi; };
        std::vector<Item> todo{{base, glm::vec3(-1e30f), glm::vec3(1e30f)}};
        while (!todo.empty()) {
            const Item it = todo.back();
            todo.pop_back();
            REQUIRE(it.ref >= base);
            REQUIRE(it.ref - base < wide.size() - 5);
            const WideBvhNode& w = wide[it.ref];
            ++reached;
            int children = 0;
            for (int k = 0; k < 4; ++k) {
                const glm::vec3 lo(w.minX[k], w.minY[k], w.minZ[k]), hi(w.maxX[k], w.maxY[k], w.maxZ[k]);
                if (w.child[k] == kWideEmpty) {
                    CHECK(lo.x > hi.x);  // an inverted box: never entered
                    continue;
                }
                ++children;
                CHECK(glm::all(glm::lessThanEqual(it.lo, lo)));
                CHECK(glm::all(glm::greaterThanEqual(it.hi, hi)));
                if ((w.child[k] & kWideLeaf) != 0) {
                    const std::uint32_t count = checkWideLeaf(w.child[k], lo, hi, blas, boxes, seen);
                    ++leaves;
                    // Binary leaves of one triangle: a longer leaf is a merged subtree.
                    if (s.opt.maxLeafSize == 1) CHECK(count <= kWideMergeMax);
                    mergedLeaves += count == kWideMergeMax;
                } else {
                    todo.push_back({w.child[k], lo, hi});
                }
            }
            CHECK(children >= 1);
        }
        CHECK(reached == wide.size() - 5);  // no node unreached
        // Small subtrees were merged into leaves (most pairs of sibling leaves are).
        if (s.opt.maxLeafSize == 1 && n > 100) CHECK(mergedLeaves * 4 > leaves);
        for (std::size_t t = 0; t < seen.size(); ++t) REQUIRE(seen[t] == 1);
        // Fewer steps: about a third of the binary tree's interior nodes (2 to 4 children each).
        const std::size_t interior = (blas.bvh.nodes.size() - 1) / 2;
        if (n > 100 && s.opt.maxLeafSize <= kWideLeafMaxCount) CHECK(wide.size() - 5 <= interior / 2 + 1);
    });
}

TEST_CASE("quantizeWideNode: each decoded child box contains the child's box, within a grid step, and empty children are inverted", "[bvh]") {
    // What the GPU's 4-wide traversal reads (GpuWideBvhNode): boxes as bytes on a per-axis grid.
    // A decoded box must contain the child's (else a ray could miss a triangle it hits), and
    // should be at most one grid step larger per side (else the quantisation wastes steps).
    auto check = [](const WideBvhNode& w) {
        const gpu::GpuWideBvhNode q = quantizeWideNode(w);
        for (int k = 0; k < 4; ++k) {
            CHECK(q.child[k] == w.child[k]);
            glm::vec3 lo, hi;
            decodeWideBox(q, k, lo, hi);
            const glm::vec3 clo(w.minX[k], w.minY[k], w.minZ[k]), chi(w.maxX[k], w.maxY[k], w.maxZ[k]);
            if (w.child[k] == kWideEmpty) {
                CHECK(lo.x > hi.x);
                CHECK(lo.y > hi.y);
                CHECK(lo.z > hi.z);
                continue;
            }
            for (int a = 0; a < 3; ++a) {
                INFO("child " << k << " axis " << a << ": [" << clo[a] << ", " << chi[a] << "] decoded [" << lo[a] << ", "
                              << hi[a] << "]");
                REQUIRE(lo[a] <= clo[a]);
                REQUIRE(hi[a] >= chi[a]);
                const float step = decodeWideBound(q, a, 1) - decodeWideBound(q, a, 0);
                const float slack = step + 2.0f * std::nextafter(std::abs(clo[a]) + std::abs(chi[a]), INFINITY) * 0x1p-24f;
                CHECK(clo[a] - lo[a] <= slack);
                CHECK(hi[a] - chi[a] <= slack);
            }
        }
    };
    // The nodes of real trees (random soups, as collapseBvh4's test builds them).
    for (std::size_t n : {std::size_t(3), std::size_t(40), std::size_t(3000)}) {
        const TestMesh m = randomSoup(n, static_cast<std::uint32_t>(n) * 7u + 1u);
        const MeshBlas blas = buildBlas(m.positions, m.triangles);
        std::vector<WideBvhNode> wide;
        REQUIRE(collapseBvh4(blas.bvh, 0, wide));
        for (const WideBvhNode& w : wide) check(w);
    }
    // Hand-made ones: far from the origin, flat, a single point, negative, tiny, huge, empty slots.
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const float offsets[] = {0.0f, -3.5f, 1e6f, -7.25e7f, 1e-30f, 3e30f};
    const float sizes[] = {0.0f, 1e-7f, 1e-3f, 1.0f, 1e4f, 1e30f};
    for (float offset : offsets) {
        for (float size : sizes) {
            for (int trial = 0; trial < 20; ++trial) {
                WideBvhNode w{};
                for (int k = 0; k < 4; ++k) {
                    const bool empty = trial % 5 == 0 ? k >= 2 : (trial % 7 == 3 && k == 1);
                    w.child[k] = empty ? kWideEmpty : kWideLeaf | (1u << kLeafCountShift) | std::uint32_t(k);
                    float* mins[3] = {w.minX, w.minY, w.minZ};
                    float* maxs[3] = {w.maxX, w.maxY, w.maxZ};
                    for (int a = 0; a < 3; ++a) {
                        if (empty) {
                            mins[a][k] = INFINITY;
                            maxs[a][k] = -INFINITY;
                            continue;
                        }
                        float x0 = offset + size * unit(rng), x1 = offset + size * unit(rng);
                        if (trial % 4 == 1) x1 = x0;  // flat
                        mins[a][k] = std::min(x0, x1);
                        maxs[a][k] = std::max(x0, x1);
                    }
                }
                INFO("offset " << offset << ", size " << size << ", trial " << trial);
                check(w);
            }
        }
    }
}

TEST_CASE("a mesh's 4-wide tree made at 0 and placed at a base equal those made at the base", "[bvh]") {
    // The mesh cache makes the 4-wide form once per import, at base 0; a scene's layout places it
    // with appendWideBvh. Long leaves (split into nodes of shorter leaves) and a leaf root included.
    BvhBuildOptions longLeaves;
    longLeaves.maxLeafSize = 64;
    longLeaves.traversalCost = 40.0f;
    for (std::size_t n : {std::size_t(1), std::size_t(57), std::size_t(2000)}) {
        for (const BvhBuildOptions& opt : {BvhBuildOptions{}, longLeaves}) {
            const TestMesh m = randomSoup(n, static_cast<std::uint32_t>(n) + 91u);
            const MeshBlas blas = buildBlas(m.positions, m.triangles, opt);
            const std::uint32_t base = 12345;
            std::vector<WideBvhNode> w0, wb;
            REQUIRE(collapseBvh4(blas.bvh, 0, w0));
            REQUIRE(collapseBvh4(blas.bvh, base, wb));
            std::vector<gpu::GpuWideBvhNode> q0, qb, wplaced(2);
            for (const WideBvhNode& w : w0) q0.push_back(quantizeWideNode(w));
            for (const WideBvhNode& w : wb) qb.push_back(quantizeWideNode(w));
            appendWideBvh(q0, base, wplaced);
            REQUIRE(wplaced.size() == qb.size() + 2);
            int differ = 0;
            for (std::size_t i = 0; i < qb.size(); ++i)
                differ += std::memcmp(&wplaced[i + 2], &qb[i], sizeof(gpu::GpuWideBvhNode)) != 0;
            CHECK(differ == 0);
        }
    }
}
