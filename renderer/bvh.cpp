// Binned SAH BVH build, refit, SAH cost, and the CPU reference traversal (see bvh.h).
//
// Build choices, measured with app/bvh_bench.cpp on this project's 2-core machine (a displaced
// sphere of 1.05M triangles; SAH cost with traversal cost 0.125; see the numbers in the report
// of the geometry issue and re-run the bench to refresh them):
//   - bins: 16 on all three axes. 12 bins on the longest axis only (the baseline) gave a
//     tree with a higher SAH cost; three axes lower it further for about 1.5x the binning time;
//     32 bins buy little over 16 and cost more time.
//   - leaves: SAH-chosen up to maxLeafSize = 8 (a leaf is made when its cost, one test per
//     primitive, is no more than the best split's); with traversal cost 0.125 the SAH rarely
//     wants leaves of more than 2-3 triangles anyway.
//   - the primitives are partitioned in place as 32-byte records (box + id), not through an index
//     array, so every pass over a node's range streams memory.
//   - subtrees of more than kParallelMinPrims primitives are built on a new thread (up to twice
//     the core count alive at once, so a thread that finishes early does not leave a core idle
//     while its sibling works); each thread writes its own node array, spliced in afterwards.
#include "renderer/bvh.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>
#include <utility>

namespace caustic {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
// Subtrees at least this big are worth a thread (creating one costs ~20 us; building 16K
// primitives takes ~3 ms).
constexpr std::size_t kParallelMinPrims = 16 * 1024;
constexpr int kMaxBins = 64;

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The primitive record the build partitions in place: its box and id, 32 bytes.
struct BuildPrim {
    glm::vec3 min;
    std::uint32_t id;
    glm::vec3 max;
    std::uint32_t pad;
    // Twice the centroid: the factor cancels in every use (binning is relative to the bounds of
    // the same quantity).
    glm::vec3 centroid2() const { return min + max; }
};
static_assert(sizeof(BuildPrim) == 32);

// Plain (no default initialisers): a node only initialises the bins it uses, which matters for
// the many small nodes near the leaves.
struct Bin {
    glm::vec3 min, max;
    std::uint32_t count;
};

struct Split {
    int axis = -1;
    int bin = 0;          // left side = bins [0, bin)
    float cost = kInf;
};

class Builder {
public:
    Builder(std::vector<BuildPrim>& prims, const BvhBuildOptions& opt)
        : m_prims(prims), m_opt(opt), m_bins(std::clamp(opt.bins, 2, kMaxBins)) {
        int hw = opt.threads > 0 ? opt.threads : static_cast<int>(std::thread::hardware_concurrency());
        m_spareThreads = hw > 1 ? 2 * hw - 1 : 0;
    }

    void build(std::vector<BvhNode>& out, std::uint32_t begin, std::uint32_t end, const Aabb& bounds,
               const Aabb& centroids, int depth) {
        const std::uint32_t count = end - begin;
        const std::size_t nodeIndex = out.size();
        out.push_back({bounds.min, 0u, bounds.max, 0u});

        auto makeLeaf = [&] {
            out[nodeIndex].rightOrFirst = begin;
            out[nodeIndex].countAndAxis = count << 2;
        };
        if (count == 1 || depth >= kBvhMaxDepth) return makeLeaf();

        Split split;
        if (m_opt.sah) split = findSahSplit(begin, end, bounds, centroids);
        // A leaf when it is small enough and the SAH prefers it (a leaf costs one test per
        // primitive), or when no split separates the centroids (all equal), or without SAH.
        if (count <= m_opt.maxLeafSize &&
            (!m_opt.sah || split.axis < 0 || static_cast<float>(count) <= split.cost))
            return makeLeaf();

        std::uint32_t mid = begin;
        Aabb lb, lc, rb, rc;
        int axis = 0;
        if (split.axis >= 0) {
            axis = split.axis;
            mid = partitionByBin(begin, end, centroids, split, &lb, &lc, &rb, &rc);
        }
        if (split.axis < 0 || mid == begin || mid == end) {
            // Median split: no SAH split (all centroids equal, or SAH disabled) or a degenerate
            // partition. Order by centroid along the longest centroid axis and cut in half.
            glm::vec3 ext = centroids.max - centroids.min;
            axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
            mid = begin + count / 2;
            std::nth_element(m_prims.begin() + begin, m_prims.begin() + mid, m_prims.begin() + end,
                             [axis](const BuildPrim& a, const BuildPrim& b) {
                                 return a.centroid2()[axis] < b.centroid2()[axis];
                             });
            lb = lc = rb = rc = Aabb{};
            for (std::uint32_t i = begin; i < mid; ++i) growPrim(m_prims[i], &lb, &lc);
            for (std::uint32_t i = mid; i < end; ++i) growPrim(m_prims[i], &rb, &rc);
        }
        out[nodeIndex].countAndAxis = static_cast<std::uint32_t>(axis);

        const std::uint32_t rightCount = end - mid;
        if (rightCount >= kParallelMinPrims && (mid - begin) >= kParallelMinPrims &&
            takeThread()) {
            std::vector<BvhNode> rightNodes;
            rightNodes.reserve(2 * static_cast<std::size_t>(rightCount));
            std::thread worker([&] {
                build(rightNodes, mid, end, rb, rc, depth + 1);
                m_spareThreads.fetch_add(1, std::memory_order_relaxed);
            });
            build(out, begin, mid, lb, lc, depth + 1);
            worker.join();
            const auto offset = static_cast<std::uint32_t>(out.size());
            out[nodeIndex].rightOrFirst = offset;
            for (BvhNode& n : rightNodes)
                if (!n.isLeaf()) n.rightOrFirst += offset;
            out.insert(out.end(), rightNodes.begin(), rightNodes.end());
        } else {
            build(out, begin, mid, lb, lc, depth + 1);
            out[nodeIndex].rightOrFirst = static_cast<std::uint32_t>(out.size());
            build(out, mid, end, rb, rc, depth + 1);
        }
    }

private:
    static void growPrim(const BuildPrim& p, Aabb* b, Aabb* c) {
        b->min = glm::min(b->min, p.min);
        b->max = glm::max(b->max, p.max);
        c->grow(p.centroid2());
    }

    bool takeThread() {
        int n = m_spareThreads.load(std::memory_order_relaxed);
        while (n > 0)
            if (m_spareThreads.compare_exchange_weak(n, n - 1, std::memory_order_relaxed)) return true;
        return false;
    }

    // Per-axis mapping from a centroid to a bin; scale = 0 marks an axis whose centroids do not
    // spread (nothing to split there).
    struct Binning {
        glm::vec3 origin, scale;
        int bins;
        int binOf(const glm::vec3& c2, int axis) const {
            int b = static_cast<int>((c2[axis] - origin[axis]) * scale[axis]);
            return std::clamp(b, 0, bins - 1);
        }
    };

    Binning makeBinning(const Aabb& centroids) const {
        Binning bn{centroids.min, glm::vec3(0.0f), m_bins};
        glm::vec3 ext = centroids.max - centroids.min;
        for (int a = 0; a < 3; ++a) {
            // An extent so small that bins/extent overflows is no extent.
            float s = static_cast<float>(m_bins) / ext[a];
            bn.scale[a] = ext[a] > 0.0f && std::isfinite(s) ? s * (1.0f - 1e-6f) : 0.0f;
        }
        if (!m_opt.allAxes) {
            int longest = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
            for (int a = 0; a < 3; ++a)
                if (a != longest) bn.scale[a] = 0.0f;
        }
        return bn;
    }

    Split findSahSplit(std::uint32_t begin, std::uint32_t end, const Aabb& bounds,
                       const Aabb& centroids) const {
        Split best;
        const Binning bn = makeBinning(centroids);
        if (bn.scale.x == 0.0f && bn.scale.y == 0.0f && bn.scale.z == 0.0f) return best;

        Bin bins[3][kMaxBins];
        for (int a = 0; a < 3; ++a)
            for (int i = 0; i < m_bins; ++i) bins[a][i] = {glm::vec3(kInf), glm::vec3(-kInf), 0u};
        for (std::uint32_t i = begin; i < end; ++i) {
            const BuildPrim& p = m_prims[i];
            const glm::vec3 c2 = p.centroid2();
            for (int a = 0; a < 3; ++a) {
                if (bn.scale[a] == 0.0f) continue;
                Bin& b = bins[a][bn.binOf(c2, a)];
                b.min = glm::min(b.min, p.min);
                b.max = glm::max(b.max, p.max);
                ++b.count;
            }
        }

        const float parentArea = bounds.halfArea();
        const float invParent = parentArea > 0.0f ? 1.0f / parentArea : 0.0f;
        for (int a = 0; a < 3; ++a) {
            if (bn.scale[a] == 0.0f) continue;
            // Sweep from the right: rightArea[i] * rightCount[i] for bins [i, bins).
            float rightCost[kMaxBins];
            Aabb acc;
            std::uint32_t n = 0;
            for (int i = m_bins - 1; i > 0; --i) {
                acc.grow(Aabb{bins[a][i].min, bins[a][i].max});
                n += bins[a][i].count;
                rightCost[i] = n > 0 ? acc.halfArea() * static_cast<float>(n) : 0.0f;
            }
            acc = Aabb{};
            n = 0;
            std::uint32_t total = end - begin;
            for (int i = 1; i < m_bins; ++i) {
                acc.grow(Aabb{bins[a][i - 1].min, bins[a][i - 1].max});
                n += bins[a][i - 1].count;
                if (n == 0 || n == total) continue;
                float cost;
                if (invParent > 0.0f) {
                    cost = m_opt.traversalCost +
                           (acc.halfArea() * static_cast<float>(n) + rightCost[i]) * invParent;
                } else {
                    // A parent without area (all boxes on one line): no area ratios to weigh
                    // by, so prefer balanced counts; still cheaper than a leaf of them all.
                    const float fl = static_cast<float>(n), fr = static_cast<float>(total - n);
                    cost = m_opt.traversalCost + (fl * fl + fr * fr) / static_cast<float>(total);
                }
                if (cost < best.cost) best = {a, i, cost};
            }
        }
        return best;
    }

    std::uint32_t partitionByBin(std::uint32_t begin, std::uint32_t end, const Aabb& centroids,
                                 const Split& split, Aabb* lb, Aabb* lc, Aabb* rb, Aabb* rc) {
        const Binning bn = makeBinning(centroids);
        std::uint32_t i = begin, j = end;
        while (i < j) {
            if (bn.binOf(m_prims[i].centroid2(), split.axis) < split.bin) {
                growPrim(m_prims[i], lb, lc);
                ++i;
            } else {
                --j;
                std::swap(m_prims[i], m_prims[j]);
                growPrim(m_prims[j], rb, rc);
            }
        }
        return i;
    }

    std::vector<BuildPrim>& m_prims;
    const BvhBuildOptions& m_opt;
    const int m_bins;
    std::atomic<int> m_spareThreads{0};
};

// Ray constants for box tests.
struct BoxRay {
    glm::vec3 origin, invDir;
    int negX, negY, negZ;
    explicit BoxRay(const Ray& r) : origin(r.origin), invDir(1.0f / r.dir) {
        negX = invDir.x < 0.0f;
        negY = invDir.y < 0.0f;
        negZ = invDir.z < 0.0f;
    }
};

// Robust slab test (Ize 2013, "Robust BVH Ray Traversal", JCGT 2(2)): the far distance is
// enlarged by 1 + 2 gamma(3) so rounding never culls a box the ray touches, which keeps the
// watertight triangle test watertight through the hierarchy. Slabs are picked by the sign of the
// direction, not by min/max of the two distances, so an inverted (empty) box is never entered;
// a NaN (origin on a slab plane of an axis the ray is parallel to) leaves the interval as is.
// Returns the entry distance, or +inf for a miss.
inline float hitBox(const BoxRay& r, const glm::vec3& bmin, const glm::vec3& bmax, float tMax) {
    constexpr float kRobust = 1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);
    const float nx = ((r.negX ? bmax.x : bmin.x) - r.origin.x) * r.invDir.x;
    const float fx = ((r.negX ? bmin.x : bmax.x) - r.origin.x) * r.invDir.x;
    const float ny = ((r.negY ? bmax.y : bmin.y) - r.origin.y) * r.invDir.y;
    const float fy = ((r.negY ? bmin.y : bmax.y) - r.origin.y) * r.invDir.y;
    const float nz = ((r.negZ ? bmax.z : bmin.z) - r.origin.z) * r.invDir.z;
    const float fz = ((r.negZ ? bmin.z : bmax.z) - r.origin.z) * r.invDir.z;
    float tNear = 0.0f, tFar = tMax;
    if (nx > tNear) tNear = nx;
    if (ny > tNear) tNear = ny;
    if (nz > tNear) tNear = nz;
    if (fx * kRobust < tFar) tFar = fx * kRobust;
    if (fy * kRobust < tFar) tFar = fy * kRobust;
    if (fz * kRobust < tFar) tFar = fz * kRobust;
    return tNear <= tFar ? tNear : kInf;
}

// Generic stack traversal of one BVH. leaf(first, count, tMax&) tests a leaf's primitives,
// lowering tMax on a hit, and returns true to stop (any-hit). Near child first.
template <class LeafFn>
bool traverse(const std::vector<BvhNode>& nodes, const BoxRay& br, float& tMax, LeafFn&& leaf) {
    if (nodes.empty()) return false;
    if (hitBox(br, nodes[0].boundsMin, nodes[0].boundsMax, tMax) == kInf) return false;
    struct Entry { std::uint32_t node; float t; };
    Entry stack[kBvhMaxDepth + 1];
    int sp = 0;
    std::uint32_t idx = 0;
    for (;;) {
        const BvhNode& n = nodes[idx];
        if (n.isLeaf()) {
            if (leaf(n.rightOrFirst, n.count(), tMax)) return true;
        } else {
            const std::uint32_t l = idx + 1, r = n.rightOrFirst;
            float tl = hitBox(br, nodes[l].boundsMin, nodes[l].boundsMax, tMax);
            float tr = hitBox(br, nodes[r].boundsMin, nodes[r].boundsMax, tMax);
            if (tl != kInf && tr != kInf) {
                if (tr < tl) {
                    stack[sp++] = {l, tl};
                    idx = r;
                } else {
                    stack[sp++] = {r, tr};
                    idx = l;
                }
                continue;
            }
            if (tl != kInf) { idx = l; continue; }
            if (tr != kInf) { idx = r; continue; }
        }
        // Pop the next entry still nearer than the closest hit.
        for (;;) {
            if (sp == 0) return false;
            const Entry e = stack[--sp];
            if (e.t <= tMax) { idx = e.node; break; }
        }
    }
}

Aabb triangleBounds(std::span<const glm::vec3> pos, const glm::uvec3& t) {
    const std::size_t n = pos.size();
    if (t.x >= n || t.y >= n || t.z >= n) return {};
    Aabb b;
    b.grow(pos[t.x]);
    b.grow(pos[t.y]);
    b.grow(pos[t.z]);
    return b;
}

// Bottom-up bounds from per-slot (reordered position) primitive bounds.
template <class SlotBounds>
void refitNodes(std::vector<BvhNode>& nodes, SlotBounds&& slotBounds) {
    for (std::size_t i = nodes.size(); i-- > 0;) {
        BvhNode& n = nodes[i];
        Aabb b;
        if (n.isLeaf()) {
            for (std::uint32_t k = 0; k < n.count(); ++k) {
                Aabb pb = slotBounds(n.rightOrFirst + k);
                if (pb.valid()) b.grow(pb);
            }
        } else {
            b.grow(nodes[i + 1].bounds());
            b.grow(nodes[n.rightOrFirst].bounds());
        }
        n.boundsMin = b.min;
        n.boundsMax = b.max;
    }
}

struct InstanceRay {
    BoxRay box;
    WatertightRay tri;
    explicit InstanceRay(const Ray& r) : box(r), tri(r) {}
};

template <bool kAnyHit>
bool traverseBlas(const MeshBlas& blas, std::span<const glm::vec3> pos, const Ray& ray, float& tMax,
                  RayHit* hit) {
    InstanceRay ir(ray);
    return traverse(blas.bvh.nodes, ir.box, tMax,
                    [&](std::uint32_t first, std::uint32_t count, float& tm) {
        const std::size_t n = pos.size();
        for (std::uint32_t k = first; k < first + count; ++k) {
            const glm::uvec3 tri = blas.triangles[k];
            if (tri.x >= n || tri.y >= n || tri.z >= n) continue;  // vertices changed size
            float t, u, v;
            if (intersectTriangle(ir.tri, pos[tri.x], pos[tri.y], pos[tri.z], tm, &t, &u, &v)) {
                tm = t;
                if constexpr (kAnyHit) return true;
                hit->t = t;
                hit->u = u;
                hit->v = v;
                hit->primitive = blas.triangleIds[k];
            }
        }
        return false;
    });
}

template <bool kAnyHit>
bool traverseScene(const SceneBvh& scene, MeshPositions positions, const Ray& ray, float& tMax,
                   RayHit* hit) {
    BoxRay br(ray);
    return traverse(scene.tlas.nodes, br, tMax,
                    [&](std::uint32_t first, std::uint32_t count, float& tm) {
        for (std::uint32_t k = first; k < first + count; ++k) {
            const std::uint32_t id = scene.tlas.primIndices[k];
            const Instance& inst = scene.instances[id];
            if (inst.mesh >= scene.blases.size() || inst.mesh >= positions.size()) continue;
            const Ray local = transformRay(scene.worldToObject[id], ray);
            RayHit h;
            const bool any = traverseBlas<kAnyHit>(scene.blases[inst.mesh], positions[inst.mesh], local, tm, &h);
            if constexpr (kAnyHit) {
                if (any) return true;
            } else if (h.hit()) {
                *hit = h;
                hit->instance = id;
            }
        }
        return false;
    });
}

bool affineFinite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

}  // namespace

bool Aabb::valid() const { return finite3(min) && finite3(max) && !empty(); }

float Aabb::halfArea() const {
    if (empty()) return 0.0f;
    glm::vec3 e = max - min;
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

Bvh buildBvh(std::span<const Aabb> primBounds, const BvhBuildOptions& options) {
    Bvh bvh;
    std::vector<BuildPrim> prims;
    prims.reserve(primBounds.size());
    Aabb bounds, centroids;
    for (std::size_t i = 0; i < primBounds.size(); ++i) {
        const Aabb& b = primBounds[i];
        // A finite box can still have a centroid sum that overflows (|coordinates| near FLT_MAX).
        if (!b.valid() || !finite3(b.min + b.max)) {
            ++bvh.skipped;
            continue;
        }
        prims.push_back({b.min, static_cast<std::uint32_t>(i), b.max, 0u});
        bounds.grow(b);
        centroids.grow(b.min + b.max);
    }
    if (prims.empty()) return bvh;

    BvhBuildOptions opt = options;
    opt.maxLeafSize = std::clamp<std::uint32_t>(opt.maxLeafSize, 1u, kBvhMaxLeafCount);
    Builder builder(prims, opt);
    bvh.nodes.reserve(prims.size() * 2);
    builder.build(bvh.nodes, 0, static_cast<std::uint32_t>(prims.size()), bounds, centroids, 1);
    bvh.nodes.shrink_to_fit();
    bvh.primIndices.resize(prims.size());
    for (std::size_t i = 0; i < prims.size(); ++i) bvh.primIndices[i] = prims[i].id;
    bvh.builtSahCost = sahCost(bvh, opt.traversalCost);
    return bvh;
}

void refitBvh(Bvh& bvh, std::span<const Aabb> primBounds) {
    refitNodes(bvh.nodes, [&](std::uint32_t slot) {
        std::uint32_t id = bvh.primIndices[slot];
        return id < primBounds.size() ? primBounds[id] : Aabb{};
    });
}

float sahCost(const Bvh& bvh, float traversalCost) {
    if (bvh.nodes.empty()) return 0.0f;
    const float rootArea = bvh.nodes[0].bounds().halfArea();
    double cost = 0.0;
    for (const BvhNode& n : bvh.nodes) {
        double a = n.bounds().halfArea();
        cost += n.isLeaf() ? a * n.count() : a * traversalCost;
    }
    // A flat or point root (all primitives on a line or a point) has no area to divide by: the
    // cost is then the unweighted sum, which still orders trees.
    return static_cast<float>(rootArea > 0.0f ? cost / rootArea : cost);
}

bool needsRebuild(const Bvh& bvh, float traversalCost) {
    if (bvh.nodes.empty()) return false;
    return sahCost(bvh, traversalCost) > kBvhRebuildFactor * bvh.builtSahCost;
}

BvhStats bvhStats(const Bvh& bvh) {
    BvhStats s;
    if (bvh.nodes.empty()) return s;
    struct Item { std::uint32_t node; int depth; };
    std::vector<Item> stack{{0u, 1}};
    std::size_t prims = 0;
    while (!stack.empty()) {
        Item it = stack.back();
        stack.pop_back();
        const BvhNode& n = bvh.nodes[it.node];
        s.depth = std::max(s.depth, it.depth);
        if (n.isLeaf()) {
            ++s.leaves;
            prims += n.count();
            s.maxLeafCount = std::max<std::size_t>(s.maxLeafCount, n.count());
        } else {
            ++s.interior;
            stack.push_back({it.node + 1, it.depth + 1});
            stack.push_back({n.rightOrFirst, it.depth + 1});
        }
    }
    s.meanLeafCount = s.leaves ? static_cast<double>(prims) / static_cast<double>(s.leaves) : 0.0;
    return s;
}

MeshBlas buildBlas(std::span<const glm::vec3> positions, std::span<const glm::uvec3> triangles,
                   const BvhBuildOptions& options) {
    std::vector<Aabb> bounds(triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i) bounds[i] = triangleBounds(positions, triangles[i]);
    MeshBlas blas;
    blas.bvh = buildBvh(bounds, options);
    blas.triangleIds = blas.bvh.primIndices;
    blas.triangles.resize(blas.triangleIds.size());
    for (std::size_t i = 0; i < blas.triangleIds.size(); ++i)
        blas.triangles[i] = triangles[blas.triangleIds[i]];
    return blas;
}

void refitBlas(MeshBlas& blas, std::span<const glm::vec3> positions) {
    refitNodes(blas.bvh.nodes, [&](std::uint32_t slot) { return triangleBounds(positions, blas.triangles[slot]); });
}

std::vector<Aabb> instanceWorldBounds(std::span<const MeshBlas> blases, std::span<const Instance> instances) {
    std::vector<Aabb> out(instances.size());
    for (std::size_t i = 0; i < instances.size(); ++i) {
        const Instance& inst = instances[i];
        if (inst.mesh >= blases.size() || blases[inst.mesh].bvh.empty()) continue;
        const glm::mat4& m = inst.objectToWorld;
        if (!affineFinite(m) || glm::determinant(glm::mat3(m)) == 0.0f) continue;
        const Aabb ob = blases[inst.mesh].bvh.nodes[0].bounds();
        Aabb wb;
        for (int c = 0; c < 8; ++c) {
            glm::vec3 p{(c & 1) ? ob.max.x : ob.min.x, (c & 2) ? ob.max.y : ob.min.y,
                        (c & 4) ? ob.max.z : ob.min.z};
            wb.grow(glm::vec3(m * glm::vec4(p, 1.0f)));
        }
        // Pad by a few ulps of the coordinates' magnitude: the world-space box test and the
        // object-space triangle test round differently, and a ray that hits a triangle lying on
        // the object box's face must not miss the world box.
        glm::vec3 pad = (glm::abs(wb.min) + glm::abs(wb.max)) * 0x1p-20f + glm::vec3(1e-30f);
        wb.min -= pad;
        wb.max += pad;
        if (wb.valid()) out[i] = wb;
    }
    return out;
}

void buildTlas(SceneBvh& scene, const BvhBuildOptions& options) {
    scene.worldToObject.resize(scene.instances.size());
    for (std::size_t i = 0; i < scene.instances.size(); ++i)
        scene.worldToObject[i] = glm::inverse(scene.instances[i].objectToWorld);
    std::vector<Aabb> bounds = instanceWorldBounds(scene.blases, scene.instances);
    scene.tlas = buildBvh(bounds, options);
}

bool refitTlas(SceneBvh& scene) {
    scene.worldToObject.resize(scene.instances.size());
    for (std::size_t i = 0; i < scene.instances.size(); ++i)
        scene.worldToObject[i] = glm::inverse(scene.instances[i].objectToWorld);
    std::vector<Aabb> bounds = instanceWorldBounds(scene.blases, scene.instances);
    refitBvh(scene.tlas, bounds);
    return needsRebuild(scene.tlas);
}

WatertightRay::WatertightRay(const Ray& ray) : origin(ray.origin) {
    const glm::vec3 ad = glm::abs(ray.dir);
    kz = ad.x >= ad.y && ad.x >= ad.z ? 0 : (ad.y >= ad.z ? 1 : 2);
    kx = kz == 2 ? 0 : kz + 1;
    ky = kx == 2 ? 0 : kx + 1;
    if (ray.dir[kz] < 0.0f) std::swap(kx, ky);
    sx = ray.dir[kx] / ray.dir[kz];
    sy = ray.dir[ky] / ray.dir[kz];
    sz = 1.0f / ray.dir[kz];
}

// Woop, Benthin and Wald 2013, figure 2 (without backface culling).
bool intersectTriangle(const WatertightRay& r, const glm::vec3& v0, const glm::vec3& v1,
                       const glm::vec3& v2, float tMax, float* tOut, float* uOut, float* vOut) {
    const glm::vec3 a = v0 - r.origin, b = v1 - r.origin, c = v2 - r.origin;
    const float ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
    const float bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
    const float cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
    float u = cx * by - cy * bx;
    float v = ax * cy - ay * cx;
    float w = bx * ay - by * ax;
    if (u == 0.0f || v == 0.0f || w == 0.0f) {
        // An edge function that is exactly 0 may be a rounding artefact: redo the three in double
        // (a product of two floats is exact in double, so the signs are exact), which decides
        // the side consistently for both triangles that share the edge. The side test is made on
        // the doubles: a tiny value may round to 0 as a float.
        const double ud = static_cast<double>(cx) * by - static_cast<double>(cy) * bx;
        const double vd = static_cast<double>(ax) * cy - static_cast<double>(ay) * cx;
        const double wd = static_cast<double>(bx) * ay - static_cast<double>(by) * ax;
        if ((ud < 0.0 || vd < 0.0 || wd < 0.0) && (ud > 0.0 || vd > 0.0 || wd > 0.0)) return false;
        u = static_cast<float>(ud);
        v = static_cast<float>(vd);
        w = static_cast<float>(wd);
    }
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
    const float det = u + v + w;
    if (!(det != 0.0f)) return false;  // also rejects NaN
    const float az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
    const float tScaled = u * az + v * bz + w * cz;
    const float invDet = 1.0f / det;
    const float t = tScaled * invDet;
    if (!(t > 0.0f && t < tMax)) return false;  // NaN fails here too
    *tOut = t;
    *uOut = v * invDet;
    *vOut = w * invDet;
    return true;
}

Ray transformRay(const glm::mat4& worldToObject, const Ray& ray) {
    return {glm::vec3(worldToObject * glm::vec4(ray.origin, 1.0f)),
            glm::vec3(worldToObject * glm::vec4(ray.dir, 0.0f))};
}

RayHit intersectBlas(const MeshBlas& blas, std::span<const glm::vec3> positions, const Ray& ray, float tMax) {
    RayHit hit;
    traverseBlas<false>(blas, positions, ray, tMax, &hit);
    return hit;
}

bool occludedBlas(const MeshBlas& blas, std::span<const glm::vec3> positions, const Ray& ray, float tMax) {
    return traverseBlas<true>(blas, positions, ray, tMax, nullptr);
}

RayHit intersectScene(const SceneBvh& scene, MeshPositions positions, const Ray& ray, float tMax) {
    RayHit hit;
    traverseScene<false>(scene, positions, ray, tMax, &hit);
    return hit;
}

bool occludedScene(const SceneBvh& scene, MeshPositions positions, const Ray& ray, float tMax) {
    return traverseScene<true>(scene, positions, ray, tMax, nullptr);
}

}  // namespace caustic
