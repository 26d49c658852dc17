// caustic-walk-sim: what a BVH change would do to llvmpipe's mesh walk, estimated on the CPU before
// any shader is written (a benchmark aid, never a test; docs/performance.md, session 16).
//
// llvmpipe runs 8 invocations as the lanes of one SIMD register, and a loop runs until its last
// lane is done; an iteration of the 4-wide walk (shaders/geometry/bvh.glsl, traceInstanceTree with
// the register stack) is a node step or a leaf, and when lanes differ it pays for both. So the
// cost of a group of 8 rays is modelled as the sum over its lock-step iterations of 1 when any
// lane steps through a node plus 0.1 + 0.35 x (the most triangles a lane tests) when any lane is
// at a leaf (session 14's profile: a node step's loop ~1,600 instructions, a triangle ~550).
//
// The rays: a mesh (any file the renderer imports) in its own space, three sets of 4000
// groups of 8: "camera" (from a common far point towards random points of the mesh's box, a
// group's rays from one point), "diffuse" (closest hit, from random points on random triangles,
// cosine-distributed about either side's normal) and "shadow" (the same rays, any hit). The walk
// is the shader's: the GPU's quantised 4-wide nodes (collapseBvh4, quantizeWideNode), nearest
// child first, far children pushed farthest first, no culling of popped entries (the GPU keeps no
// entry distances), the watertight triangle test.
//
//   caustic-walk-sim MESH [--builder binned|sweep|sbvh] [--alpha A] [--cull] [--postpone]
//
// --builder: the renderer's binned SAH build (default); an exact sweep SAH over every split; a
// spatial-split BVH (Stich, Friedrich and Dietrich 2009, "Spatial Splits in Bounding Volume
// Hierarchies"): triangles clipped at binned planes where the best object split's children overlap
// by more than alpha x the root's area (--alpha, default 1e-5). Both of the latter are measuring
// prototypes here, not builders the renderer has.
// --cull: popped entries starting beyond the closest hit are skipped (what entry distances on the
// stack would buy). --postpone: Aila and Laine's (2009) speculative while-while walk: lanes at a
// leaf keep one postponed and walk on until every lane holds one, then all test their leaves.
#include "renderer/bvh.h"
#include "renderer/mesh_import.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

using namespace caustic;

namespace {

struct SimMesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
};

// The file through the renderer's own import (renderer/mesh_import.h: any format Assimp reads,
// validated as the renderer's meshes are), every mesh of it in one list in the file's root space.
bool loadMesh(const char* path, SimMesh& mesh) {
    const MeshImportResult imported = importMeshFile(path);
    if (!imported.ok()) {
        std::fprintf(stderr, "caustic-walk-sim: %s\n", imported.error.c_str());
        return false;
    }
    for (const caustic::Mesh& m : imported.meshes) {
        const auto base = static_cast<std::uint32_t>(mesh.positions.size());
        mesh.positions.insert(mesh.positions.end(), m.positions.begin(), m.positions.end());
        for (const glm::uvec3& t : m.triangles) mesh.triangles.push_back(t + glm::uvec3(base));
    }
    if (mesh.triangles.empty()) {
        std::fprintf(stderr, "caustic-walk-sim: %s: no triangles\n", path);
        return false;
    }
    return true;
}

// ---- Two measuring prototypes of other builders ----------------------------------------------------

struct Ref {
    std::uint32_t id;
    Aabb box;
};

// The bounds of triangle v clipped to `box` (Sutherland-Hodgman against its six planes).
Aabb clippedBounds(const glm::vec3* v, const Aabb& box) {
    glm::vec3 poly[9], next[9];
    int n = 3;
    for (int i = 0; i < 3; ++i) poly[i] = v[i];
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            const float plane = side ? box.max[axis] : box.min[axis];
            auto inside = [&](const glm::vec3& p) { return side ? p[axis] <= plane : p[axis] >= plane; };
            int m = 0;
            for (int i = 0; i < n; ++i) {
                const glm::vec3 p = poly[i], q = poly[(i + 1) % n];
                if (inside(p)) next[m++] = p;
                if (inside(p) != inside(q)) {
                    glm::vec3 r = p + (plane - p[axis]) / (q[axis] - p[axis]) * (q - p);
                    r[axis] = plane;
                    next[m++] = r;
                }
            }
            n = m;
            std::copy(next, next + n, poly);
            if (n == 0) return {};
        }
    }
    Aabb r;
    for (int i = 0; i < n; ++i) r.grow(poly[i]);
    r.min = glm::max(r.min, box.min);
    r.max = glm::min(r.max, box.max);
    return r;
}

// A recursive top-down build: the exact sweep SAH over object splits on all three axes and, with
// spatial splits on, binned spatial splits (32 bins) where the object split's children overlap.
class PrototypeBuilder {
public:
    PrototypeBuilder(const SimMesh& mesh, bool spatial, float alpha) : m_mesh(mesh), m_spatial(spatial), m_alpha(alpha) {}

    MeshBlas build() {
        std::vector<Ref> refs;
        Aabb root;
        for (std::uint32_t i = 0; i < m_mesh.triangles.size(); ++i) {
            Aabb b;
            for (int k = 0; k < 3; ++k) b.grow(m_mesh.positions[m_mesh.triangles[i][k]]);
            refs.push_back({i, b});
            root.grow(b);
        }
        m_rootArea = root.halfArea();
        node(refs, 1);
        MeshBlas blas;
        blas.bvh.nodes = m_nodes;
        blas.bvh.primIndices = m_prims;
        blas.triangleIds = m_prims;
        for (std::uint32_t id : m_prims) blas.triangles.push_back(m_mesh.triangles[id]);
        blas.bvh.builtSahCost = sahCost(blas.bvh);
        return blas;
    }
    int spatialSplits() const { return m_spatialSplits; }

private:
    static constexpr float kTraversalCost = 0.125f;  // the renderer's
    static constexpr int kBins = 32;

    void triangle(std::uint32_t id, glm::vec3* v) const {
        for (int k = 0; k < 3; ++k) v[k] = m_mesh.positions[m_mesh.triangles[id][k]];
    }

    void node(std::vector<Ref>& refs, int depth) {
        Aabb bounds;
        for (const Ref& r : refs) bounds.grow(r.box);
        const auto index = static_cast<std::uint32_t>(m_nodes.size());
        m_nodes.push_back({bounds.min, 0u, bounds.max, 0u});
        const auto n = static_cast<std::uint32_t>(refs.size());
        auto leaf = [&] {
            m_nodes[index].rightOrFirst = static_cast<std::uint32_t>(m_prims.size());
            m_nodes[index].countAndAxis = n << 2;
            for (const Ref& r : refs) m_prims.push_back(r.id);
        };
        if (n == 1 || depth >= kBvhMaxDepth) return leaf();
        const float parentArea = bounds.halfArea();

        float objectCost = INFINITY;
        int objectAxis = 0;
        std::uint32_t objectLeft = 1;
        Aabb objectL, objectR;
        std::vector<float> rightCost(n);
        std::vector<Aabb> rightBox(n);
        for (int a = 0; a < 3; ++a) {
            std::sort(refs.begin(), refs.end(), [a](const Ref& x, const Ref& y) { return x.box.center()[a] < y.box.center()[a]; });
            Aabb acc;
            for (std::uint32_t i = n - 1; i > 0; --i) {
                acc.grow(refs[i].box);
                rightCost[i] = acc.halfArea() * static_cast<float>(n - i);
                rightBox[i] = acc;
            }
            acc = Aabb{};
            for (std::uint32_t i = 1; i < n; ++i) {
                acc.grow(refs[i - 1].box);
                const float c = kTraversalCost + (acc.halfArea() * static_cast<float>(i) + rightCost[i]) / parentArea;
                if (c < objectCost) {
                    objectCost = c;
                    objectAxis = a;
                    objectLeft = i;
                    objectL = acc;
                    objectR = rightBox[i];
                }
            }
        }

        float spatialCost = INFINITY;
        int spatialAxis = -1;
        float spatialPlane = 0.0f;
        Aabb overlap{glm::max(objectL.min, objectR.min), glm::min(objectL.max, objectR.max)};
        if (m_spatial && !overlap.empty() && overlap.halfArea() > m_alpha * m_rootArea) {
            for (int a = 0; a < 3; ++a) {
                const float lo = bounds.min[a], extent = bounds.max[a] - lo;
                if (!(extent > 0.0f)) continue;
                Aabb bins[kBins];
                int enter[kBins] = {}, exit[kBins] = {};
                auto binOf = [&](float x) { return std::clamp(static_cast<int>((x - lo) / extent * kBins), 0, kBins - 1); };
                for (const Ref& r : refs) {
                    glm::vec3 v[3];
                    triangle(r.id, v);
                    const int b0 = binOf(r.box.min[a]), b1 = binOf(r.box.max[a]);
                    ++enter[b0];
                    ++exit[b1];
                    for (int b = b0; b <= b1; ++b) {
                        if (b0 == b1) {
                            bins[b].grow(r.box);
                            continue;
                        }
                        Aabb slab = r.box;
                        slab.min[a] = std::max(slab.min[a], lo + extent * static_cast<float>(b) / kBins);
                        slab.max[a] = std::min(slab.max[a], lo + extent * static_cast<float>(b + 1) / kBins);
                        const Aabb c = clippedBounds(v, slab);
                        if (!c.empty()) bins[b].grow(c);
                    }
                }
                float right[kBins];
                int rightCount[kBins];
                Aabb acc;
                int count = 0;
                for (int i = kBins - 1; i > 0; --i) {
                    acc.grow(bins[i]);
                    count += exit[i];
                    right[i] = acc.halfArea() * static_cast<float>(count);
                    rightCount[i] = count;
                }
                acc = Aabb{};
                count = 0;
                for (int i = 1; i < kBins; ++i) {
                    acc.grow(bins[i - 1]);
                    count += enter[i - 1];
                    if (count == 0 || rightCount[i] == 0) continue;
                    const float c = kTraversalCost + (acc.halfArea() * static_cast<float>(count) + right[i]) / parentArea;
                    if (c < spatialCost) {
                        spatialCost = c;
                        spatialAxis = a;
                        spatialPlane = lo + extent * static_cast<float>(i) / kBins;
                    }
                }
            }
        }
        if (n <= 8 && static_cast<float>(n) <= std::min(objectCost, spatialCost)) return leaf();

        std::vector<Ref> left, right;
        if (spatialAxis >= 0 && spatialCost < objectCost) {
            for (const Ref& r : refs) {
                if (r.box.max[spatialAxis] <= spatialPlane) {
                    left.push_back(r);
                } else if (r.box.min[spatialAxis] >= spatialPlane) {
                    right.push_back(r);
                } else {
                    glm::vec3 v[3];
                    triangle(r.id, v);
                    Aabb lb = r.box, rb = r.box;
                    lb.max[spatialAxis] = spatialPlane;
                    rb.min[spatialAxis] = spatialPlane;
                    const Aabb cl = clippedBounds(v, lb), cr = clippedBounds(v, rb);
                    if (!cl.empty()) left.push_back({r.id, cl});
                    if (!cr.empty()) right.push_back({r.id, cr});
                }
            }
            if (left.empty() || right.empty()) {
                left.clear();
                right.clear();
                spatialAxis = -1;
            } else {
                ++m_spatialSplits;
            }
        }
        if (left.empty()) {
            spatialAxis = -1;
            std::sort(refs.begin(), refs.end(),
                      [objectAxis](const Ref& x, const Ref& y) { return x.box.center()[objectAxis] < y.box.center()[objectAxis]; });
            left.assign(refs.begin(), refs.begin() + objectLeft);
            right.assign(refs.begin() + objectLeft, refs.end());
        }
        std::vector<Ref>().swap(refs);
        m_nodes[index].countAndAxis = static_cast<std::uint32_t>(spatialAxis >= 0 ? spatialAxis : objectAxis);
        node(left, depth + 1);
        m_nodes[index].rightOrFirst = static_cast<std::uint32_t>(m_nodes.size());
        node(right, depth + 1);
    }

    const SimMesh& m_mesh;
    bool m_spatial;
    float m_alpha;
    float m_rootArea = 0.0f;
    int m_spatialSplits = 0;
    std::vector<BvhNode> m_nodes;
    std::vector<std::uint32_t> m_prims;
};

// ---- The walk, lane by lane ---------------------------------------------------------------------

struct Tree {
    std::vector<gpu::GpuWideBvhNode> nodes;
    const MeshBlas* blas;
    const SimMesh* mesh;
};

struct Lane {
    const Tree* tree;
    Ray ray;
    bool anyHit;
    glm::vec3 invDir;
    WatertightRay wray{Ray{}};
    float tMax = INFINITY;
    std::vector<std::pair<std::uint32_t, float>> stack;  // reference, entry distance
    std::uint32_t current = 0;  // the root
    bool walking = true;        // `current` is a reference still to visit
    bool done = false;
    std::uint32_t postponed = 0;
    bool hasPostponed = false;

    Lane(const Tree* t, const Ray& r, bool any) : tree(t), ray(r), anyHit(any), invDir(1.0f / r.dir), wray(r) {}

    static bool isLeaf(std::uint32_t ref) { return (ref & kWideLeaf) != 0u; }

    void pop(bool cull) {
        while (!stack.empty()) {
            const auto [ref, t] = stack.back();
            stack.pop_back();
            if (cull && t > tMax) continue;
            current = ref;
            walking = true;
            return;
        }
        walking = false;
    }

    // A node step at `current`: the nearest child hit next, the others pushed farthest first.
    void step(bool cull) {
        const gpu::GpuWideBvhNode& n = tree->nodes[current];
        float key[4];
        int order[4] = {0, 1, 2, 3};
        for (int k = 0; k < 4; ++k) {
            glm::vec3 lo, hi;
            decodeWideBox(n, k, lo, hi);
            const glm::vec3 t0 = (lo - ray.origin) * invDir, t1 = (hi - ray.origin) * invDir;
            const glm::vec3 tn = glm::min(t0, t1), tf = glm::max(t0, t1);
            const float enter = std::max({0.0f, tn.x, tn.y, tn.z});
            const float leave = std::min({tMax, tf.x * 1.0000004f, tf.y * 1.0000004f, tf.z * 1.0000004f});
            key[k] = n.child[k] != kWideEmpty && lo.x <= hi.x && enter <= leave ? enter : INFINITY;
        }
        std::sort(order, order + 4, [&](int a, int b) { return key[a] < key[b]; });
        for (int k = 3; k >= 1; --k)
            if (key[order[k]] != INFINITY) stack.push_back({n.child[order[k]], key[order[k]]});
        if (key[order[0]] != INFINITY) {
            current = n.child[order[0]];
        } else {
            pop(cull);
        }
    }

    // A leaf's triangles; returns how many were tested.
    int test(std::uint32_t ref) {
        const std::uint32_t first = ref & kWideLeafMaxFirst, count = (ref >> 27) & 15u;
        bool hit = false;
        for (std::uint32_t k = first; k < first + count; ++k) {
            const glm::uvec3 tri = tree->blas->triangles[k];
            const auto& p = tree->mesh->positions;
            float t, u, v;
            if (intersectTriangle(wray, p[tri.x], p[tri.y], p[tri.z], tMax, &t, &u, &v)) {
                tMax = t;
                hit = true;
            }
        }
        if (hit && anyHit) {
            done = true;
            walking = false;
        }
        return static_cast<int>(count);
    }
};

struct Cost {
    double cost = 0.0, iterations = 0.0, laneIterations = 0.0, triangles = 0.0;
};

void addIteration(Cost& c, bool anyStep, int mostTriangles, int activeLanes) {
    c.iterations += 1.0;
    c.laneIterations += activeLanes;
    c.cost += (anyStep ? 1.0 : 0.0) + (mostTriangles > 0 ? 0.1 + 0.35 * mostTriangles : 0.0);
}

// The shader's loop: per iteration each lane steps through a node or tests a leaf.
void walkGroup(std::vector<Lane> lanes, bool cull, Cost& c) {
    for (;;) {
        bool anyStep = false;
        int most = 0, active = 0;
        for (Lane& l : lanes) {
            if (l.done || !l.walking) continue;
            ++active;
            if (!Lane::isLeaf(l.current)) {
                anyStep = true;
                l.step(cull);
            } else {
                const int n = l.test(l.current);
                c.triangles += n;
                most = std::max(most, n);
                if (!l.done) l.pop(cull);
            }
        }
        if (active == 0) return;
        addIteration(c, anyStep, most, active);
    }
}

// Speculative while-while (Aila and Laine 2009): a lane at a leaf postpones it and walks on
// until it meets a second leaf; when every lane holds a postponed leaf (or is done), all test.
void walkGroupPostponing(std::vector<Lane> lanes, bool cull, Cost& c) {
    for (;;) {
        bool any = false, allReady = true;
        for (const Lane& l : lanes) {
            if (l.done) continue;
            if (l.walking || l.hasPostponed) any = true;
            if (!(l.hasPostponed || !l.walking)) allReady = false;
        }
        if (!any) return;
        if (!allReady) {
            bool anyStep = false;
            int active = 0;
            for (Lane& l : lanes) {
                if (l.done || !l.walking) continue;
                if (Lane::isLeaf(l.current)) {
                    if (!l.hasPostponed) {
                        l.postponed = l.current;
                        l.hasPostponed = true;
                        l.pop(cull);
                    }
                } else {
                    anyStep = true;
                    ++active;
                    l.step(cull);
                }
            }
            if (anyStep) {
                addIteration(c, true, 0, active);
                continue;
            }
        }
        int most = 0, active = 0;
        for (Lane& l : lanes) {
            if (l.done || !l.hasPostponed) continue;
            l.hasPostponed = false;
            ++active;
            const int n = l.test(l.postponed);
            c.triangles += n;
            most = std::max(most, n);
        }
        if (active > 0) addIteration(c, false, most, active);
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: caustic-walk-sim MESH [--builder binned|sweep|sbvh] [--alpha A] [--cull] [--postpone]\n");
        return 2;
    }
    std::string builder = "binned";
    float alpha = 1e-5f;
    bool cull = false, postpone = false;
    for (int i = 2; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--builder" && i + 1 < argc) {
            builder = argv[++i];
        } else if (a == "--alpha" && i + 1 < argc) {
            alpha = std::strtof(argv[++i], nullptr);
        } else if (a == "--cull") {
            cull = true;
        } else if (a == "--postpone") {
            postpone = true;
        } else {
            std::fprintf(stderr, "caustic-walk-sim: unknown option %s\n", a.c_str());
            return 2;
        }
    }
    if (builder != "binned" && builder != "sweep" && builder != "sbvh") {
        std::fprintf(stderr, "caustic-walk-sim: --builder is binned, sweep or sbvh, not %s\n", builder.c_str());
        return 2;
    }
    SimMesh mesh;
    if (!loadMesh(argv[1], mesh)) return 1;

    MeshBlas blas;
    int spatialSplits = 0;
    if (builder == "binned") {
        blas = buildBlas(mesh.positions, mesh.triangles);
    } else {
        PrototypeBuilder b(mesh, builder == "sbvh", alpha);
        blas = b.build();
        spatialSplits = b.spatialSplits();
    }
    std::vector<WideBvhNode> wide;
    if (!collapseBvh4(blas.bvh, 0, wide)) {
        std::fprintf(stderr, "caustic-walk-sim: the tree does not fit the 4-wide form\n");
        return 1;
    }
    Tree tree{{}, &blas, &mesh};
    for (const WideBvhNode& w : wide) tree.nodes.push_back(quantizeWideNode(w));
    const BvhStats stats = bvhStats(blas.bvh);
    std::printf("%s: %zu triangles, %zu references (%d spatial splits), SAH %.3f, depth %d, %zu 4-wide nodes\n",
                builder.c_str(), mesh.triangles.size(), blas.triangles.size(), spatialSplits, blas.bvh.builtSahCost,
                stats.depth, tree.nodes.size());

    std::mt19937 rng(1);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    const glm::vec3 lo = blas.bvh.nodes[0].boundsMin, hi = blas.bvh.nodes[0].boundsMax;
    const glm::vec3 centre = 0.5f * (lo + hi);
    const float size = glm::length(hi - lo);
    const char* names[3] = {"camera", "diffuse", "shadow"};
    constexpr int kGroups = 4000;
    double total = 0.0;
    for (int set = 0; set < 3; ++set) {
        Cost c;
        for (int g = 0; g < kGroups; ++g) {
            std::vector<Lane> lanes;
            const glm::vec3 eye = centre + 2.0f * size *
                glm::normalize(glm::vec3(uniform(rng) - 0.5f, uniform(rng) - 0.5f, uniform(rng) - 0.5f) + glm::vec3(1e-6f));
            for (int l = 0; l < 8; ++l) {
                Ray r;
                if (set == 0) {
                    r.origin = eye;
                    r.dir = glm::normalize(lo + (hi - lo) * glm::vec3(uniform(rng), uniform(rng), uniform(rng)) - eye);
                } else {
                    const auto pick = std::min<std::size_t>(mesh.triangles.size() - 1,
                                                            static_cast<std::size_t>(uniform(rng) * static_cast<float>(mesh.triangles.size())));
                    const glm::uvec3 t = mesh.triangles[pick];
                    const glm::vec3 p0 = mesh.positions[t.x], p1 = mesh.positions[t.y], p2 = mesh.positions[t.z];
                    float b1 = uniform(rng), b2 = uniform(rng);
                    if (b1 + b2 > 1.0f) {
                        b1 = 1.0f - b1;
                        b2 = 1.0f - b2;
                    }
                    glm::vec3 n = glm::cross(p1 - p0, p2 - p0);
                    n = glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0.0f, 0.0f, 1.0f);
                    if (uniform(rng) < 0.5f) n = -n;
                    const glm::vec3 tangent = glm::normalize(std::abs(n.x) > 0.5f ? glm::cross(n, glm::vec3(0, 1, 0))
                                                                                   : glm::cross(n, glm::vec3(1, 0, 0)));
                    const glm::vec3 bitangent = glm::cross(n, tangent);
                    const float phi = 6.2831853f * uniform(rng), r2 = uniform(rng), sr = std::sqrt(r2);
                    r.dir = glm::normalize(tangent * (sr * std::cos(phi)) + bitangent * (sr * std::sin(phi)) +
                                           n * std::sqrt(std::max(0.0f, 1.0f - r2)));
                    r.origin = p0 + b1 * (p1 - p0) + b2 * (p2 - p0) + n * (1e-4f * size);
                }
                lanes.emplace_back(&tree, r, set == 2);
            }
            if (postpone) {
                walkGroupPostponing(lanes, cull, c);
            } else {
                walkGroup(lanes, cull, c);
            }
        }
        std::printf("%-8s lock-step iterations %6.2f  lane occupancy %5.1f %%  triangles per ray %5.2f  cost %6.2f per group\n",
                    names[set], c.iterations / kGroups, 100.0 * c.laneIterations / (8.0 * c.iterations),
                    c.triangles / (8.0 * kGroups), c.cost / kGroups);
        total += c.cost / kGroups;
    }
    std::printf("total cost %.2f per group of each set\n", total);
    return 0;
}
