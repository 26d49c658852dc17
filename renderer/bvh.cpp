// Binned SAH BVH build, refit, SAH cost, and the CPU reference traversal (see bvh.h).
//
// Build choices, measured with app/bvh_bench.cpp on this project's shared 2-core machine (a
// displaced sphere of 1.05M triangles, SAH cost with traversal cost 0.125; timings are noisy
// there, SAH costs are exact):
//   - bins: 16 on all three axes: SAH cost 11.80, against 12.02 for the baseline (12 bins,
//     longest axis only), 11.82 for 12 bins on three axes and 11.78 for 32 bins; three axes cost
//     about 1.3x the binning time of one, 32 bins buy nothing measurable over 16.
//   - nodes of at most kSmallNode primitives use the exact sweep SAH (cheaper than binning them);
//     small nodes bin with as many bins as primitives.
//   - leaves: SAH-chosen up to maxLeafSize = 8; with traversal cost 0.125 the SAH makes leaves of
//     1.07 triangles on average (leaf <= 1 gives 11.84, a median split with leaves of 4 gives 24.3).
//   - the primitives are partitioned in place as 32-byte SIMD records (the ids in a parallel
//     array), not through an index array, so every pass over a node's range streams memory.
//   - subtrees of more than kParallelMinPrims primitives on both sides are built on a new thread
//     (up to twice the core count alive at once, so a thread that finishes early does not leave
//     a core idle while its sibling works); each writes its nodes straight into the final array
//     at its worst-case offset and compact() closes the gaps, so no node is copied twice.
//     1.05M triangles: ~550 ms on one thread, ~310-360 ms on two (2.9-3.4 M triangles/s) when
//     the machine is otherwise idle.
//   - kBvhRebuildFactor = 1.5: in the bench's TLAS of 1600 instances moved apart by growing
//     amounts, a refit tree at 1.2x the fresh SAH cost traced 16% slower than a rebuilt one and
//     at 1.54x 36% slower, while a TLAS rebuild of 1600 instances takes ~1 ms. 1.5 is the issue's
//     suggestion and keeps refits for small edits (gizmo drags); a renderer that rebuilds the TLAS
//     every change anyway loses nothing.
#include "renderer/bvh.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>
#include <utility>

namespace caustic {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
// Subtrees at least this big are worth a thread (creating one costs ~20 us; building 16K
// primitives takes ~3 ms).
constexpr std::size_t kParallelMinPrims = 16 * 1024;
constexpr int kMaxBins = 64;
// Nodes of at most this many primitives get the exact sweep SAH instead of binning.
constexpr std::uint32_t kSmallNode = 12;

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Four floats / ints in one SIMD register through the GCC/Clang vector extensions (SSE on x86-64,
// NEON on ARM, scalar code elsewhere); lane 3 is unused (0). The build's inner loops grow boxes
// with two min/max instructions instead of six.
typedef float F4 __attribute__((vector_size(16)));
typedef std::int32_t I4 __attribute__((vector_size(16)));

inline F4 vmin(F4 a, F4 b) { return a < b ? a : b; }
inline F4 vmax(F4 a, F4 b) { return a > b ? a : b; }
inline F4 toF4(const glm::vec3& v) { return F4{v.x, v.y, v.z, 0.0f}; }
inline glm::vec3 toVec3(F4 v) { return {v[0], v[1], v[2]}; }

struct VBox {
    F4 min{kInf, kInf, kInf, 0.0f};
    F4 max{-kInf, -kInf, -kInf, 0.0f};
    void grow(F4 lo, F4 hi) { min = vmin(min, lo); max = vmax(max, hi); }
    void grow(F4 p) { grow(p, p); }
    float halfArea() const {
        if (!(min[0] <= max[0])) return 0.0f;  // empty
        F4 e = max - min;
        return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
    }
};

// The primitive record the build partitions in place (its id in a parallel array): 32 bytes.
struct BuildPrim {
    F4 min, max;
    // Twice the centroid: the factor cancels in every use (binning is relative to the bounds of
    // the same quantity).
    F4 centroid2() const { return min + max; }
};
static_assert(sizeof(BuildPrim) == 32);

struct Split {
    int axis = -1;
    int bin = 0;          // left side = bins [0, bin)
    float cost = kInf;
    VBox left, right;     // the primitive bounds of both sides (from the bins)
};

class Builder {
public:
    Builder(BvhNode* nodes, std::vector<BuildPrim>& prims, std::vector<std::uint32_t>& ids,
            const BvhBuildOptions& opt)
        : m_nodes(nodes), m_prims(prims), m_ids(ids), m_opt(opt), m_bins(std::clamp(opt.bins, 2, kMaxBins)) {
        int hw = opt.threads > 0 ? opt.threads : static_cast<int>(std::thread::hardware_concurrency());
        m_spareThreads = hw > 1 ? 2 * hw - 1 : 0;
    }

    // What a subtree build returns: the index after its last node, and the sum over its nodes
    // of the SAH terms (area x traversal cost, or area x count for a leaf) before the division
    // by the root area, so the build reports its own SAH cost without another pass.
    struct Result {
        std::uint32_t next;
        double cost;
    };

    // Builds the subtree of primitives [begin, end) with its root at m_nodes[nodeIndex], depth
    // first. A subtree of n primitives has at most 2n - 1 nodes; a subtree built on another
    // thread is placed at its parent's left subtree's worst-case end, which leaves a gap that
    // compact() removes afterwards.
    Result build(std::uint32_t nodeIndex, std::uint32_t begin, std::uint32_t end, const VBox& bounds,
                 const VBox& centroids, int depth) {
        const std::uint32_t count = end - begin;
        BvhNode& node = m_nodes[nodeIndex];
        node.boundsMin = toVec3(bounds.min);
        node.boundsMax = toVec3(bounds.max);
        const double area = bounds.halfArea();

        auto makeLeaf = [&]() -> Result {
            node.rightOrFirst = begin;
            node.countAndAxis = count << 2;
            return {nodeIndex + 1, area * count};
        };
        if (count == 1 || depth >= kBvhMaxDepth) return makeLeaf();

        std::uint32_t mid = begin;
        VBox lb, lc, rb, rc;
        int axis = 0;
        if (m_opt.sah && count <= kSmallNode) {
            // Few primitives: the exact SAH over every split position (sweep) is both better
            // and cheaper than binning.
            const SmallSplit ss = sweepSmall(begin, end, bounds);
            if (count <= m_opt.maxLeafSize && static_cast<float>(count) <= ss.cost) return makeLeaf();
            axis = ss.axis;
            mid = begin + ss.leftCount;
            for (std::uint32_t i = begin; i < mid; ++i) growPrim(m_prims[i], &lb, &lc);
            for (std::uint32_t i = mid; i < end; ++i) growPrim(m_prims[i], &rb, &rc);
        } else {
            Split split;
            if (m_opt.sah) split = findSahSplit(begin, end, bounds, centroids);
            // A leaf when it is small enough and the SAH prefers it (a leaf costs one test per
            // primitive), or when no split separates the centroids (all equal), or without SAH.
            if (count <= m_opt.maxLeafSize &&
                (!m_opt.sah || split.axis < 0 || static_cast<float>(count) <= split.cost))
                return makeLeaf();
            if (split.axis >= 0) {
                axis = split.axis;
                lb = split.left;
                rb = split.right;
                mid = partitionByBin(begin, end, centroids, split, &lc, &rc);
            }
            if (split.axis < 0 || mid == begin || mid == end) {
                // Median split: no SAH split (all centroids equal, or SAH disabled) or a
                // degenerate partition. Order by centroid along the longest centroid axis and
                // cut in half.
                const F4 ext = centroids.max - centroids.min;
                axis = ext[0] >= ext[1] && ext[0] >= ext[2] ? 0 : (ext[1] >= ext[2] ? 1 : 2);
                mid = begin + count / 2;
                medianPartition(begin, mid, end, axis);
                lb = lc = rb = rc = VBox{};
                for (std::uint32_t i = begin; i < mid; ++i) growPrim(m_prims[i], &lb, &lc);
                for (std::uint32_t i = mid; i < end; ++i) growPrim(m_prims[i], &rb, &rc);
            }
        }
        node.countAndAxis = static_cast<std::uint32_t>(axis);
        const double own = area * static_cast<double>(m_opt.traversalCost);

        const std::uint32_t leftCount = mid - begin, rightCount = end - mid;
        if (rightCount >= kParallelMinPrims && leftCount >= kParallelMinPrims && takeThread()) {
            const std::uint32_t rightIndex = nodeIndex + 1 + (2 * leftCount - 1);
            Result right{};
            std::thread worker([&] {
                right = build(rightIndex, mid, end, rb, rc, depth + 1);
                m_spareThreads.fetch_add(1, std::memory_order_relaxed);
            });
            const Result left = build(nodeIndex + 1, begin, mid, lb, lc, depth + 1);
            worker.join();
            node.rightOrFirst = rightIndex;
            if (left.next < rightIndex) {
                std::lock_guard<std::mutex> lock(m_gapMutex);
                m_gaps.push_back({left.next, rightIndex - left.next});
            }
            return {right.next, own + left.cost + right.cost};
        }
        const Result left = build(nodeIndex + 1, begin, mid, lb, lc, depth + 1);
        node.rightOrFirst = left.next;
        const Result right = build(left.next, mid, end, rb, rc, depth + 1);
        return {right.next, own + left.cost + right.cost};
    }

    // Removes the gaps left by parallel subtrees: nodes move down by the total size of the gaps
    // before them, and right-child indices are remapped the same way. Returns the node count.
    std::uint32_t compact(std::uint32_t end) {
        std::sort(m_gaps.begin(), m_gaps.end(), [](const Gap& a, const Gap& b) { return a.start < b.start; });
        auto remap = [&](std::uint32_t old) {
            std::uint32_t shift = 0;
            for (const Gap& g : m_gaps) {
                if (g.start >= old) break;
                shift += g.size;
            }
            return old - shift;
        };
        std::uint32_t dst = 0, src = 0;
        std::size_t gi = 0;
        while (src < end) {
            const std::uint32_t segEnd = gi < m_gaps.size() ? m_gaps[gi].start : end;
            for (; src < segEnd; ++src, ++dst) {
                BvhNode n = m_nodes[src];
                if (!n.isLeaf() && !m_gaps.empty()) n.rightOrFirst = remap(n.rightOrFirst);
                m_nodes[dst] = n;
            }
            if (gi < m_gaps.size()) src += m_gaps[gi++].size;
        }
        return dst;
    }

private:
    static void growPrim(const BuildPrim& p, VBox* b, VBox* c) {
        b->grow(p.min, p.max);
        c->grow(p.centroid2());
    }

    bool takeThread() {
        int n = m_spareThreads.load(std::memory_order_relaxed);
        while (n > 0)
            if (m_spareThreads.compare_exchange_weak(n, n - 1, std::memory_order_relaxed)) return true;
        return false;
    }

    struct SmallSplit {
        int axis = 0;
        std::uint32_t leftCount = 1;
        float cost = kInf;
    };

    // Exact SAH for a node of at most kSmallNode primitives: sort along each axis by centroid
    // (insertion sort), sweep every split position, then leave [begin, end) in the best axis's
    // order so that the split is at begin + leftCount.
    SmallSplit sweepSmall(std::uint32_t begin, std::uint32_t end, const VBox& bounds) {
        const std::uint32_t n = end - begin;
        const float parentArea = bounds.halfArea();
        const float invParent = parentArea > 0.0f ? 1.0f / parentArea : 0.0f;
        std::uint8_t order[3][kSmallNode];
        SmallSplit best;
        for (int a = 0; a < 3; ++a) {
            std::uint8_t* o = order[a];
            for (std::uint32_t i = 0; i < n; ++i) {
                const float key = m_prims[begin + i].centroid2()[a];
                std::uint32_t k = i;
                while (k > 0 && m_prims[begin + o[k - 1]].centroid2()[a] > key) {
                    o[k] = o[k - 1];
                    --k;
                }
                o[k] = static_cast<std::uint8_t>(i);
            }
            float rightCost[kSmallNode];
            VBox acc;
            for (std::uint32_t i = n - 1; i > 0; --i) {
                const BuildPrim& p = m_prims[begin + o[i]];
                acc.grow(p.min, p.max);
                rightCost[i] = acc.halfArea() * static_cast<float>(n - i);
            }
            acc = VBox{};
            for (std::uint32_t i = 1; i < n; ++i) {
                const BuildPrim& p = m_prims[begin + o[i - 1]];
                acc.grow(p.min, p.max);
                const float fl = static_cast<float>(i), fr = static_cast<float>(n - i);
                const float cost = invParent > 0.0f
                    ? m_opt.traversalCost + (acc.halfArea() * fl + rightCost[i]) * invParent
                    : m_opt.traversalCost + (fl * fl + fr * fr) / static_cast<float>(n);
                if (cost < best.cost) best = {a, i, cost};
            }
        }
        BuildPrim prims[kSmallNode];
        std::uint32_t ids[kSmallNode];
        for (std::uint32_t i = 0; i < n; ++i) {
            prims[i] = m_prims[begin + order[best.axis][i]];
            ids[i] = m_ids[begin + order[best.axis][i]];
        }
        std::copy(prims, prims + n, m_prims.begin() + begin);
        std::copy(ids, ids + n, m_ids.begin() + begin);
        return best;
    }

    // Per-axis mapping from a centroid to a bin; scale = 0 marks an axis whose centroids do not
    // spread (everything lands in bin 0: nothing to split there).
    struct Binning {
        F4 origin, scale;
        int bins;
        bool any;
        I4 binOf(F4 c2) const {
            const I4 b = __builtin_convertvector((c2 - origin) * scale, I4);
            const I4 zero{0, 0, 0, 0}, last{bins - 1, bins - 1, bins - 1, bins - 1};
            const I4 lo = b < zero ? zero : b;
            return lo > last ? last : lo;
        }
    };

    // Small nodes use fewer bins (as many as primitives): the per-node cost of clearing and
    // sweeping 3 x 16 bins would otherwise dominate the build near the leaves, and with few
    // primitives more bins than primitives add few distinct candidate splits.
    Binning makeBinning(const VBox& centroids, std::uint32_t count) const {
        const int bins = static_cast<int>(
            std::min<std::uint32_t>(static_cast<std::uint32_t>(m_bins), std::max(count, 2u)));
        Binning bn{centroids.min, F4{0.0f, 0.0f, 0.0f, 0.0f}, bins, false};
        bn.origin[3] = 0.0f;
        const F4 ext = centroids.max - centroids.min;
        const int longest = ext[0] >= ext[1] && ext[0] >= ext[2] ? 0 : (ext[1] >= ext[2] ? 1 : 2);
        for (int a = 0; a < 3; ++a) {
            if (!m_opt.allAxes && a != longest) continue;
            // An extent so small that bins/extent overflows is no extent. The factor just below
            // 1 keeps the largest centroid inside the last bin.
            const float s = static_cast<float>(bins) / ext[a];
            if (ext[a] > 0.0f && std::isfinite(s)) {
                bn.scale[a] = s * (1.0f - 1e-6f);
                bn.any = true;
            }
        }
        return bn;
    }

    Split findSahSplit(std::uint32_t begin, std::uint32_t end, const VBox& bounds,
                       const VBox& centroids) const {
        Split best;
        const Binning bn = makeBinning(centroids, end - begin);
        if (!bn.any) return best;
        const int nb = bn.bins;

        // Only the nb bins in use are cleared (a node near the leaves has few primitives and
        // clearing all 3 x kMaxBins would dominate its cost).
        struct Bin { F4 min, max; };  // no initialisers, unlike VBox
        Bin bins[3][kMaxBins];
        std::uint32_t counts[3][kMaxBins];
        for (int a = 0; a < 3; ++a)
            for (int i = 0; i < nb; ++i) {
                bins[a][i] = {F4{kInf, kInf, kInf, 0.0f}, F4{-kInf, -kInf, -kInf, 0.0f}};
                counts[a][i] = 0;
            }
        for (std::uint32_t i = begin; i < end; ++i) {
            const BuildPrim& p = m_prims[i];
            const I4 b = bn.binOf(p.centroid2());
            for (int a = 0; a < 3; ++a) {
                Bin& bin = bins[a][b[a]];
                bin.min = vmin(bin.min, p.min);
                bin.max = vmax(bin.max, p.max);
            }
            ++counts[0][b[0]];
            ++counts[1][b[1]];
            ++counts[2][b[2]];
        }

        const float parentArea = bounds.halfArea();
        const float invParent = parentArea > 0.0f ? 1.0f / parentArea : 0.0f;
        const std::uint32_t total = end - begin;
        for (int a = 0; a < 3; ++a) {
            if (bn.scale[a] == 0.0f) continue;
            // Sweep from the right: rightArea * rightCount for bins [i, nb).
            float rightCost[kMaxBins];
            Bin rightBox[kMaxBins];
            VBox acc;
            std::uint32_t n = 0;
            for (int i = nb - 1; i > 0; --i) {
                acc.grow(bins[a][i].min, bins[a][i].max);
                n += counts[a][i];
                rightCost[i] = n > 0 ? acc.halfArea() * static_cast<float>(n) : 0.0f;
                rightBox[i] = {acc.min, acc.max};
            }
            acc = VBox{};
            n = 0;
            for (int i = 1; i < nb; ++i) {
                acc.grow(bins[a][i - 1].min, bins[a][i - 1].max);
                n += counts[a][i - 1];
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
                if (cost < best.cost) best = {a, i, cost, acc, VBox{rightBox[i].min, rightBox[i].max}};
            }
        }
        return best;
    }

    // Hoare partition by the split's bin (each primitive classified once, only misplaced pairs
    // swapped), growing the two sides' centroid bounds on the way.
    std::uint32_t partitionByBin(std::uint32_t begin, std::uint32_t end, const VBox& centroids,
                                 const Split& split, VBox* lc, VBox* rc) {
        const Binning bn = makeBinning(centroids, end - begin);
        const int a = split.axis;
        const float origin = bn.origin[a], scale = bn.scale[a];
        const int last = bn.bins - 1;
        auto isLeft = [&](const BuildPrim& p, F4* c2) {
            *c2 = p.centroid2();
            const int b = std::clamp(static_cast<int>(((*c2)[a] - origin) * scale), 0, last);
            return b < split.bin;
        };
        std::uint32_t i = begin, j = end;
        F4 c2;
        for (;;) {
            while (i < j && isLeft(m_prims[i], &c2)) {
                lc->grow(c2);
                ++i;
            }
            while (i < j && !isLeft(m_prims[j - 1], &c2)) {
                rc->grow(c2);
                --j;
            }
            if (i >= j) break;
            // m_prims[i] belongs right, m_prims[j - 1] left.
            --j;
            std::swap(m_prims[i], m_prims[j]);
            std::swap(m_ids[i], m_ids[j]);
            lc->grow(m_prims[i].centroid2());
            rc->grow(m_prims[j].centroid2());
            ++i;
        }
        return i;
    }

    // Reorders [begin, end) so that [begin, mid) holds the smaller centroids along axis (the
    // rare fallback path: clarity over speed).
    void medianPartition(std::uint32_t begin, std::uint32_t mid, std::uint32_t end, int axis) {
        std::vector<std::pair<float, std::uint32_t>> keys(end - begin);
        for (std::uint32_t i = begin; i < end; ++i) keys[i - begin] = {m_prims[i].centroid2()[axis], i};
        std::nth_element(keys.begin(), keys.begin() + (mid - begin), keys.end());
        std::vector<BuildPrim> prims(end - begin);
        std::vector<std::uint32_t> ids(end - begin);
        for (std::size_t k = 0; k < keys.size(); ++k) {
            prims[k] = m_prims[keys[k].second];
            ids[k] = m_ids[keys[k].second];
        }
        std::copy(prims.begin(), prims.end(), m_prims.begin() + begin);
        std::copy(ids.begin(), ids.end(), m_ids.begin() + begin);
    }

    struct Gap {
        std::uint32_t start, size;
    };
    BvhNode* m_nodes;
    std::vector<BuildPrim>& m_prims;
    std::vector<std::uint32_t>& m_ids;
    std::mutex m_gapMutex;
    std::vector<Gap> m_gaps;
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

// Empty for a triangle with an out-of-range index or a non-finite vertex (such a triangle is
// left out of the tree, or contributes nothing to a refit).
Aabb triangleBounds(std::span<const glm::vec3> pos, const glm::uvec3& t) {
    const std::size_t n = pos.size();
    if (t.x >= n || t.y >= n || t.z >= n) return {};
    if (!finite3(pos[t.x]) || !finite3(pos[t.y]) || !finite3(pos[t.z])) return {};
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

// keep: null, or the any-hit filter (intersectScene with a HitFilter) with this BLAS's instance.
template <bool kAnyHit>
bool traverseBlas(const MeshBlas& blas, std::span<const glm::vec3> pos, const Ray& ray, float& tMax,
                  RayHit* hit, const HitFilter* keep = nullptr, std::uint32_t instance = 0) {
    InstanceRay ir(ray);
    return traverse(blas.bvh.nodes, ir.box, tMax,
                    [&](std::uint32_t first, std::uint32_t count, float& tm) {
        const std::size_t n = pos.size();
        for (std::uint32_t k = first; k < first + count; ++k) {
            const glm::uvec3 tri = blas.triangles[k];
            if (tri.x >= n || tri.y >= n || tri.z >= n) continue;  // vertices changed size
            float t, u, v;
            if (intersectTriangle(ir.tri, pos[tri.x], pos[tri.y], pos[tri.z], tm, &t, &u, &v) &&
                (!keep || (*keep)(instance, k, u, v))) {
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
                   RayHit* hit, const HitFilter* keep = nullptr) {
    BoxRay br(ray);
    return traverse(scene.tlas.nodes, br, tMax,
                    [&](std::uint32_t first, std::uint32_t count, float& tm) {
        for (std::uint32_t k = first; k < first + count; ++k) {
            const std::uint32_t id = scene.tlas.primIndices[k];
            const Instance& inst = scene.instances[id];
            if (inst.mesh >= scene.blases.size() || inst.mesh >= positions.size()) continue;
            const Ray local = transformRay(scene.worldToObject[id], ray);
            RayHit h;
            const bool any = traverseBlas<kAnyHit>(scene.blases[inst.mesh], positions[inst.mesh], local, tm, &h, keep, id);
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
    std::vector<std::uint32_t> ids;
    prims.reserve(primBounds.size());
    ids.reserve(primBounds.size());
    VBox bounds, centroids;
    for (std::size_t i = 0; i < primBounds.size(); ++i) {
        const Aabb& b = primBounds[i];
        // A finite box can still have a centroid sum that overflows (|coordinates| near FLT_MAX).
        if (!b.valid() || !finite3(b.min + b.max)) {
            ++bvh.skipped;
            continue;
        }
        const BuildPrim p{toF4(b.min), toF4(b.max)};
        prims.push_back(p);
        ids.push_back(static_cast<std::uint32_t>(i));
        bounds.grow(p.min, p.max);
        centroids.grow(p.centroid2());
    }
    if (prims.empty()) return bvh;

    BvhBuildOptions opt = options;
    opt.maxLeafSize = std::clamp<std::uint32_t>(opt.maxLeafSize, 1u, kBvhMaxLeafCount);
    // resize() value-initialises (zeroes) the nodes; a default-initialising allocator would save
    // that pass but make the public type unusual, and the pages are touched by the build anyway.
    bvh.nodes.resize(2 * prims.size() - 1);
    Builder builder(bvh.nodes.data(), prims, ids, opt);
    const auto built = builder.build(0, 0, static_cast<std::uint32_t>(prims.size()), bounds, centroids, 1);
    bvh.nodes.resize(builder.compact(built.next));
    bvh.primIndices = std::move(ids);
    const double rootArea = bounds.halfArea();
    bvh.builtSahCost = static_cast<float>(rootArea > 0.0 ? built.cost / rootArea : built.cost);
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

float edgeFunction(float a, float b, float c, float d) {
    // volatile: each product rounded on its own even where the compiler would contract a * b - c d
    // into an fma (GCC does with -ffp-contract=fast, its default, on targets with FMA).
    volatile float ab = a * b;
    volatile float cd = c * d;
    return ab - cd;
}

// Woop, Benthin and Wald 2013, figure 2 (without backface culling).
bool intersectTriangle(const WatertightRay& r, const glm::vec3& v0, const glm::vec3& v1,
                       const glm::vec3& v2, float tMax, float* tOut, float* uOut, float* vOut) {
    const glm::vec3 a = v0 - r.origin, b = v1 - r.origin, c = v2 - r.origin;
    const float ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
    const float bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
    const float cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
    // Float edge functions, never of the wrong sign (edgeFunction), as on the GPU.
    float u = edgeFunction(cx, by, cy, bx);
    float v = edgeFunction(ax, cy, ay, cx);
    float w = edgeFunction(bx, ay, by, ax);
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

namespace {

// Whether binary node b is an interior node whose subtree holds at most mergeMax primitives,
// as one range [first, first + count) (the builder partitions in place, so a subtree's leaves
// are consecutive; checked all the same): the wide trees make it one leaf.
bool smallSubtree(const std::vector<BvhNode>& nodes, std::uint32_t mergeMax, std::uint32_t b, std::uint32_t& first,
                  std::uint32_t& count) {
    if (nodes[b].isLeaf()) return false;
    std::uint32_t l = b, r = b;
    while (!nodes[l].isLeaf()) l = l + 1;
    while (!nodes[r].isLeaf()) r = nodes[r].rightOrFirst;
    first = nodes[l].rightOrFirst;
    const std::uint32_t end = nodes[r].rightOrFirst + nodes[r].count();
    if (end <= first || end - first > mergeMax) return false;
    count = end - first;
    std::uint32_t sum = 0, stack[64], sp = 0;
    stack[sp++] = b;
    while (sp > 0) {
        const std::uint32_t i = stack[--sp];
        const BvhNode& n = nodes[i];
        if (n.isLeaf()) {
            if (n.rightOrFirst < first || n.rightOrFirst + n.count() > end) return false;
            sum += n.count();
        } else {
            if (sp + 2 > 64) return false;
            stack[sp++] = i + 1;
            stack[sp++] = n.rightOrFirst;
        }
    }
    return sum == count;
}

// A wide tree's leaf of primitives [first, first + count) as its child word (WideBvhNode::child),
// for both collapses: the word where the leaf fits one; 0 where it is longer than
// kWideLeafMaxCount (the collapse splits it into up to `width` leaves of wideLeafPart primitives
// under a node with its box); kWideEmpty with ok false where its primitives lie beyond
// kWideLeafMaxFirst.
std::uint32_t wideLeafWord(std::uint32_t first, std::uint32_t count, bool& ok) {
    if (first > kWideLeafMaxFirst || count > kWideLeafMaxFirst - first + 1u) {
        ok = false;
        return kWideEmpty;
    }
    return count <= kWideLeafMaxCount ? leafWord(first, count) : 0u;
}
std::uint32_t wideLeafPart(std::uint32_t count, std::uint32_t width) { return std::max((count + width - 1u) / width, 1u); }

// The children of the wide node made for binary node b (b itself when it is a leaf at the root):
// while there are fewer than `width`, the interior child of largest surface area that is not a
// small subtree is replaced by its two children, in place (the order is the 4-wide nodes' slot
// order). Returns how many; used by the 4- and 8-wide collapses.
int wideChildren(const std::vector<BvhNode>& nodes, std::uint32_t mergeMax, std::uint32_t b, std::uint32_t* kids,
                 int width) {
    int n = 0;
    if (nodes[b].isLeaf()) {
        kids[n++] = b;
    } else {
        kids[n++] = b + 1;
        kids[n++] = nodes[b].rightOrFirst;
    }
    while (n < width) {
        int best = -1;
        float bestArea = -1.0f;
        for (int k = 0; k < n; ++k) {
            std::uint32_t f, c;
            if (nodes[kids[k]].isLeaf() || smallSubtree(nodes, mergeMax, kids[k], f, c)) continue;
            const float a = nodes[kids[k]].bounds().halfArea();
            if (a > bestArea) { bestArea = a; best = k; }
        }
        if (best < 0) break;
        const std::uint32_t opened = kids[best];
        for (int k = n; k > best + 1; --k) kids[k] = kids[k - 1];
        kids[best] = opened + 1;
        kids[best + 1] = nodes[opened].rightOrFirst;
        ++n;
    }
    return n;
}

// The wide trees' kWideMergeMax, or $CAUSTIC_WIDE_MERGE for measuring (docs/performance.md).
std::uint32_t wideMergeMax() {
    if (const char* env = std::getenv("CAUSTIC_WIDE_MERGE"); env && *env)
        return static_cast<std::uint32_t>(std::min(std::strtoul(env, nullptr, 10), 15ul));
    return kWideMergeMax;
}

struct WideCollapse {
    const std::vector<BvhNode>& nodes;
    std::uint32_t base;
    std::vector<WideBvhNode>& out;
    std::uint32_t mergeMax;
    bool ok = true;

    bool smallSubtree(std::uint32_t b, std::uint32_t& first, std::uint32_t& count) const {
        return caustic::smallSubtree(nodes, mergeMax, b, first, count);
    }

    static void setBox(WideBvhNode& w, int k, const glm::vec3& lo, const glm::vec3& hi) {
        w.minX[k] = lo.x; w.maxX[k] = hi.x;
        w.minY[k] = lo.y; w.maxY[k] = hi.y;
        w.minZ[k] = lo.z; w.maxZ[k] = hi.z;
    }

    static WideBvhNode emptyNode() {
        WideBvhNode w{};
        const float inf = std::numeric_limits<float>::infinity();
        for (int k = 0; k < 4; ++k) {
            setBox(w, k, glm::vec3(inf), glm::vec3(-inf));  // inverted: never entered
            w.child[k] = kWideEmpty;
        }
        return w;
    }

    // A leaf's reference; a long leaf becomes a node of shorter ones (its box for each).
    std::uint32_t leafRef(std::uint32_t first, std::uint32_t count, const glm::vec3& lo, const glm::vec3& hi) {
        if (const std::uint32_t word = wideLeafWord(first, count, ok); word != 0u) return word;
        const auto index = static_cast<std::uint32_t>(out.size());
        out.push_back(emptyNode());
        const std::uint32_t part = wideLeafPart(count, 4u);
        for (int k = 0; k < 4; ++k) {
            const std::uint32_t f = first + std::uint32_t(k) * part;
            if (f >= first + count) break;
            const std::uint32_t n = std::min(part, first + count - f);
            const std::uint32_t ref = leafRef(f, n, lo, hi);
            setBox(out[index], k, lo, hi);
            out[index].child[k] = ref;
        }
        return base + index;
    }

    // The wide node for binary node `b` (or, for a binary leaf at the root, a node holding it).
    std::uint32_t node(std::uint32_t b) {
        const auto index = static_cast<std::uint32_t>(out.size());
        out.push_back(emptyNode());
        std::uint32_t kids[4];
        const int n = wideChildren(nodes, mergeMax, b, kids, 4);
        for (int k = 0; k < n; ++k) {
            const BvhNode& c = nodes[kids[k]];
            std::uint32_t first = 0, count = 0;
            const std::uint32_t ref = c.isLeaf() ? leafRef(c.rightOrFirst, c.count(), c.boundsMin, c.boundsMax)
                                      : smallSubtree(kids[k], first, count) ? leafRef(first, count, c.boundsMin, c.boundsMax)
                                                                             : node(kids[k]);
            setBox(out[index], k, c.boundsMin, c.boundsMax);  // (out may have grown: index, not a reference)
            out[index].child[k] = ref;
        }
        return base + index;
    }
};

}  // namespace

bool collapseBvh4(const Bvh& bvh, std::uint32_t base, std::vector<WideBvhNode>& out) {
    if (bvh.nodes.empty()) return true;
    const std::size_t start = out.size();
    WideCollapse c{bvh.nodes, base - static_cast<std::uint32_t>(start), out, wideMergeMax()};
    c.node(0);
    if (!c.ok) out.resize(start);
    return c.ok;
}

namespace {

float scaleOf(std::uint32_t biasedExponent) { return std::bit_cast<float>(biasedExponent << 23); }

// The grid of the quantised boxes on one axis, from `lo` (the origin): the smallest biased exponent
// e in [1, 254] whose scale s = 2^(e - 127) makes the top value's bound lo + top * s (in float, as
// the shaders decode it) reach `hi` and lie above `lo` (so that an empty child, lo = top and hi = 0,
// decodes inverted even where the grid is a single point).
int gridExponent(float lo, float hi, std::uint32_t top) {
    auto reach = [&](int e) {
        const volatile float product = static_cast<float>(top) * scaleOf(static_cast<std::uint32_t>(e));
        return lo + product;
    };
    int e = 1;
    const float extent = hi - lo;
    if (extent > 0.0f && std::isfinite(extent)) e = std::clamp(std::ilogb(extent / static_cast<float>(top)) + 127, 1, 254);
    while (e < 254 && !(reach(e) >= hi && reach(e) > lo)) ++e;
    return e;
}

// Word w of a node's bytes: lo x, hi x, lo y, hi y (qXY), lo z, hi z (qZ.xy).
std::uint32_t& boundBytes(gpu::GpuWideBvhNode& node, int w) { return w < 4 ? node.qXY[w] : node.qZ[w - 4]; }
std::uint32_t boundBytes(const gpu::GpuWideBvhNode& node, int w) { return w < 4 ? node.qXY[w] : node.qZ[w - 4]; }

// A grid's bound: origin + q * s (s = 2^(exponent - 127)), in float as the shaders decode it. The
// product is exact (q < 2^8, s a power of two): fused or not, the sum is the one rounding.
float decodeGridBound(std::uint32_t originBits, std::uint32_t exponent, std::uint32_t q) {
    const volatile float product = static_cast<float>(q) * scaleOf(exponent);
    return std::bit_cast<float>(originBits) + product;
}

// A child's bytes on one axis of a wide node's grid (origin, exponent): the largest byte that
// decodes at or below its minimum and the smallest that decodes at or above its maximum.
void quantizeChildBounds(std::uint32_t originBits, std::uint32_t exponent, float lo, float hi, std::uint32_t& bl,
                         std::uint32_t& bh) {
    const float origin = std::bit_cast<float>(originBits), s = scaleOf(exponent);
    bl = static_cast<std::uint32_t>(std::clamp(std::floor((lo - origin) / s), 0.0f, 255.0f));
    while (bl > 0 && decodeGridBound(originBits, exponent, bl) > lo) --bl;
    while (bl < 255 && decodeGridBound(originBits, exponent, bl + 1) <= lo) ++bl;
    bh = static_cast<std::uint32_t>(std::clamp(std::ceil((hi - origin) / s), 0.0f, 255.0f));
    while (bh < 255 && decodeGridBound(originBits, exponent, bh) < hi) ++bh;
    while (bh > 0 && decodeGridBound(originBits, exponent, bh - 1) >= hi) --bh;
}

}  // namespace

float decodeWideBound(const gpu::GpuWideBvhNode& node, int axis, std::uint32_t q) {
    return decodeGridBound(node.head[axis], (node.head.w >> (8 * axis)) & 0xffu, q);
}

void decodeWideBox(const gpu::GpuWideBvhNode& node, int k, glm::vec3& lo, glm::vec3& hi) {
    for (int a = 0; a < 3; ++a) {
        lo[a] = decodeWideBound(node, a, (boundBytes(node, 2 * a) >> (8 * k)) & 0xffu);
        hi[a] = decodeWideBound(node, a, (boundBytes(node, 2 * a + 1) >> (8 * k)) & 0xffu);
    }
}

gpu::GpuWideBvhNode quantizeWideNode(const WideBvhNode& w) {
    gpu::GpuWideBvhNode out{};
    for (int k = 0; k < 4; ++k) out.child[k] = w.child[k];
    const float* mins[3] = {w.minX, w.minY, w.minZ};
    const float* maxs[3] = {w.maxX, w.maxY, w.maxZ};
    for (int a = 0; a < 3; ++a) {
        // The grid spans the union of the children that are there.
        float lo = std::numeric_limits<float>::infinity(), hi = -lo;
        for (int k = 0; k < 4; ++k) {
            if (w.child[k] == kWideEmpty || !(mins[a][k] <= maxs[a][k])) continue;
            lo = std::min(lo, mins[a][k]);
            hi = std::max(hi, maxs[a][k]);
        }
        if (!(lo <= hi)) lo = hi = 0.0f;  // no child (not made by collapseBvh4)
        out.head[a] = std::bit_cast<std::uint32_t>(lo);
        const int e = gridExponent(lo, hi, 255);
        out.head.w |= static_cast<std::uint32_t>(e) << (8 * a);
        std::uint32_t qlo = 0, qhi = 0;
        for (int k = 0; k < 4; ++k) {
            std::uint32_t bl = 255, bh = 0;  // empty: inverted
            if (w.child[k] != kWideEmpty && mins[a][k] <= maxs[a][k])
                quantizeChildBounds(out.head[a], static_cast<std::uint32_t>(e), mins[a][k], maxs[a][k], bl, bh);
            qlo |= bl << (8 * k);
            qhi |= bh << (8 * k);
        }
        boundBytes(out, 2 * a) = qlo;
        boundBytes(out, 2 * a + 1) = qhi;
    }
    return out;
}

float decodePairBound(const glm::uvec4& header, int axis, std::uint32_t q) {
    const float s = scaleOf((header.w >> (8 * axis)) & 0xffu);
    // Exact (q < 2^16, s a power of two): fused or not, the sum is the one rounding, as in the shader.
    const volatile float product = static_cast<float>(q) * s;
    return std::bit_cast<float>(header[axis]) + product;
}

void decodePairBox(const glm::uvec4& header, const glm::uvec4& r0, const glm::uvec4& r1, int k, glm::vec3& lo,
                   glm::vec3& hi) {
    const std::uint32_t words[6] = {r0.x, r0.y, r0.z, r0.w, r1.x, r1.y};
    for (int a = 0; a < 3; ++a) {
        lo[a] = decodePairBound(header, a, (words[2 * a] >> (16 * k)) & 0xffffu);
        hi[a] = decodePairBound(header, a, (words[2 * a + 1] >> (16 * k)) & 0xffffu);
    }
}

namespace {

// buildPairBvh's state: the binary tree, where its records go, and the grid.
struct PairBuild {
    const std::vector<BvhNode>& nodes;
    std::vector<glm::uvec4>& out;
    std::size_t start;   // out[start] is the header, at texel index base
    std::uint32_t base;
    glm::uvec4 header{0u};
    bool ok = true;

    // A child as a record sees it: a subtree (node) or a range of leaf primitives, and its box.
    struct Child {
        Aabb box;
        bool leaf = false;
        std::uint32_t node = 0, first = 0, count = 0;
        bool empty = false;
    };

    Child childOf(std::uint32_t i) const {
        const BvhNode& n = nodes[i];
        Child c;
        c.box = n.bounds();
        c.leaf = n.isLeaf();
        c.node = i;
        c.first = n.rightOrFirst;
        c.count = n.count();
        return c;
    }

    // The 16-bit values that decode at or below lo and at or above hi.
    std::uint32_t quantLo(int a, float lo) const {
        const float s = scaleOf((header.w >> (8 * a)) & 0xffu), origin = std::bit_cast<float>(header[a]);
        auto q = static_cast<std::uint32_t>(std::clamp(std::floor((lo - origin) / s), 0.0f, 65535.0f));
        while (q > 0 && decodePairBound(header, a, q) > lo) --q;
        while (q < 65535 && decodePairBound(header, a, q + 1) <= lo) ++q;
        return q;
    }
    std::uint32_t quantHi(int a, float hi) const {
        const float s = scaleOf((header.w >> (8 * a)) & 0xffu), origin = std::bit_cast<float>(header[a]);
        auto q = static_cast<std::uint32_t>(std::clamp(std::ceil((hi - origin) / s), 0.0f, 65535.0f));
        while (q < 65535 && decodePairBound(header, a, q) < hi) ++q;
        while (q > 0 && decodePairBound(header, a, q - 1) >= hi) --q;
        return q;
    }

    // A record for two children (made depth first, its children's records after it); returns its
    // texel index.
    std::uint32_t record(const Child& c0, const Child& c1) {
        const std::size_t at = out.size();
        if (at - start + base > 0x7ffffffeu) ok = false;
        out.resize(at + 2, glm::uvec4(0u));
        const std::uint32_t l0 = link(c0), l1 = link(c1);
        std::uint32_t w[6] = {0, 0, 0, 0, 0, 0};
        const Child* cs[2] = {&c0, &c1};
        for (int k = 0; k < 2; ++k) {
            for (int a = 0; a < 3; ++a) {
                std::uint32_t lo = 65535, hi = 0;  // empty: inverted
                if (!cs[k]->empty) {
                    lo = quantLo(a, cs[k]->box.min[a]);
                    hi = quantHi(a, cs[k]->box.max[a]);
                }
                w[2 * a] |= lo << (16 * k);
                w[2 * a + 1] |= hi << (16 * k);
            }
        }
        out[at] = glm::uvec4(w[0], w[1], w[2], w[3]);
        out[at + 1] = glm::uvec4(w[4], w[5], l0, l1);
        return static_cast<std::uint32_t>(at - start) + base;
    }

    std::uint32_t link(const Child& c) {
        if (c.empty) return kPairEmpty;
        if (!c.leaf) return record(childOf(c.node + 1), childOf(nodes[c.node].rightOrFirst));
        if (c.count <= kPairLeafMaxCount) {
            if (c.first > kPairLeafMaxFirst) ok = false;
            return leafWord(c.first & kPairLeafMaxFirst, c.count);
        }
        // A longer leaf: two halves with its box (depth log2(count / 15)).
        Child a = c, b = c;
        a.count = c.count / 2;
        b.first = c.first + a.count;
        b.count = c.count - a.count;
        return record(a, b);
    }
};

}  // namespace

bool buildPairBvh(const Bvh& bvh, std::uint32_t base, std::vector<glm::uvec4>& out) {
    if (bvh.nodes.empty()) return true;
    PairBuild b{bvh.nodes, out, out.size(), base};
    // The grid: per axis from the root box's lower bound, 65535 steps reaching its upper bound.
    const Aabb root = bvh.nodes[0].bounds();
    for (int a = 0; a < 3; ++a) {
        const float lo = std::isfinite(root.min[a]) ? root.min[a] : 0.0f;
        const float hi = std::isfinite(root.max[a]) ? root.max[a] : lo;
        b.header[a] = std::bit_cast<std::uint32_t>(lo);
        b.header.w |= static_cast<std::uint32_t>(gridExponent(lo, hi, 65535)) << (8 * a);
    }
    out.push_back(b.header);
    PairBuild::Child rootChild = b.childOf(0), none;
    none.empty = true;
    if (rootChild.leaf) {
        b.record(rootChild, none);
    } else {
        b.record(b.childOf(1), b.childOf(bvh.nodes[0].rightOrFirst));
    }
    if (!b.ok) out.resize(b.start);
    return b.ok;
}

void appendPairBvh(std::span<const glm::uvec4> tree, std::uint32_t base, std::vector<glm::uvec4>& out) {
    const std::size_t start = out.size();
    out.insert(out.end(), tree.begin(), tree.end());
    // Texel 0 is the header; then records of two texels, the links in the second's z and w.
    for (std::size_t t = start + 2; t < out.size(); t += 2)
        for (int k = 2; k < 4; ++k)
            if ((out[t][k] & kPairLeaf) == 0u) out[t][k] += base;  // (kPairEmpty has the leaf bit)
}

void appendWideBvh(std::span<const gpu::GpuWideBvhNode> nodes, std::uint32_t base, std::vector<gpu::GpuWideBvhNode>& out) {
    const std::size_t start = out.size();
    out.insert(out.end(), nodes.begin(), nodes.end());
    for (std::size_t i = start; i < out.size(); ++i)
        for (int k = 0; k < 4; ++k)
            if ((out[i].child[k] & kWideLeaf) == 0u) out[i].child[k] += base;  // (kWideEmpty has the leaf bit)
}

namespace {

// The 8-wide collapse (buildWide8Bvh in bvh.h): WideCollapse's rule with eight children a node
// (`kids`: each node's children, node references as indices into it), then the slots (place).
// (The rule fills the upper nodes and leaves the lowest short: below a node of 8 children, each
// binary node with two leaves becomes a node of 2. A ray meets the upper nodes most; a pass that
// let a node take a child's children into its free slots changed no node of the knot's tree nor
// of random soups' (session 21), so there is none.)
struct Wide8Collapse {
    struct Child { glm::vec3 lo, hi; std::uint32_t ref; };
    const std::vector<BvhNode>& nodes;
    std::uint32_t mergeMax;
    std::vector<std::vector<Child>> kids;
    bool ok = true;

    // A leaf's reference; a long leaf becomes a node of shorter ones (its box for each).
    std::uint32_t leafRef(std::uint32_t first, std::uint32_t count, const glm::vec3& lo, const glm::vec3& hi) {
        if (const std::uint32_t word = wideLeafWord(first, count, ok); word != 0u) return word;
        const auto index = static_cast<std::uint32_t>(kids.size());
        kids.emplace_back();
        const std::uint32_t part = wideLeafPart(count, 8u);
        std::vector<Child> parts;
        for (std::uint32_t f = first; f < first + count; f += part)
            parts.push_back({lo, hi, leafRef(f, std::min(part, first + count - f), lo, hi)});
        kids[index] = std::move(parts);
        return index;
    }

    // The node for binary node `b` (or, for a binary leaf at the root, a node holding it).
    std::uint32_t node(std::uint32_t b) {
        const auto index = static_cast<std::uint32_t>(kids.size());
        kids.emplace_back();
        std::uint32_t bins[8];
        const int n = wideChildren(nodes, mergeMax, b, bins, 8);
        std::vector<Child> children;
        for (int k = 0; k < n; ++k) {
            const BvhNode& c = nodes[bins[k]];
            std::uint32_t first = 0, count = 0;
            const std::uint32_t ref = c.isLeaf() ? leafRef(c.rightOrFirst, c.count(), c.boundsMin, c.boundsMax)
                                      : smallSubtree(nodes, mergeMax, bins[k], first, count)
                                          ? leafRef(first, count, c.boundsMin, c.boundsMax)
                                          : node(bins[k]);
            children.push_back({c.boundsMin, c.boundsMax, ref});
        }
        kids[index] = std::move(children);
        return index;
    }

    // The slots: slot s is the one a ray of octant s (bit a set: direction negative on axis a)
    // visits first, and a ray of octant o visits slots in the order p ^ o, p = 0, 1, ... So slot s
    // should hold the child met first along the direction of octant s: the assignment of children
    // to slots that minimises the sum of dot(child centre - node centre, octant s's diagonal),
    // made greedily (cheapest pair first) where Ylitie et al. 2017 solve it exactly; an
    // approximate order costs only visits, never a hit.
    static std::array<Child, 8> place(const std::vector<Child>& children) {
        std::array<Child, 8> slots;
        for (Child& c : slots) c = {glm::vec3(0.0f), glm::vec3(0.0f), kWideEmpty};
        glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
        for (const Child& c : children) {
            lo = glm::min(lo, c.lo);
            hi = glm::max(hi, c.hi);
        }
        const glm::vec3 centre = 0.5f * (lo + hi);
        bool kidUsed[8] = {}, slotUsed[8] = {};
        for (std::size_t round = 0; round < children.size(); ++round) {
            float best = std::numeric_limits<float>::infinity();
            int bk = -1, bs = -1;
            for (std::size_t k = 0; k < children.size(); ++k) {
                if (kidUsed[k]) continue;
                const glm::vec3 d = 0.5f * (children[k].lo + children[k].hi) - centre;
                for (int slot = 0; slot < 8; ++slot) {
                    if (slotUsed[slot]) continue;
                    const glm::vec3 diagonal((slot & 1) ? -1.0f : 1.0f, (slot & 2) ? -1.0f : 1.0f, (slot & 4) ? -1.0f : 1.0f);
                    const float cost = glm::dot(d, diagonal);
                    if (bk < 0 || cost < best) { best = cost; bk = int(k); bs = slot; }
                }
            }
            kidUsed[bk] = slotUsed[bs] = true;
            slots[std::size_t(bs)] = children[std::size_t(bk)];
        }
        return slots;
    }
};

// Word w (0-5: lo x, hi x, lo y, hi y, lo z, hi z) of slots 4 h to 4 h + 3's bytes in a node's texels.
std::uint32_t& wide8Bytes(glm::uvec4* node, int w, int h) { return node[1 + w / 2][2 * (w % 2) + h]; }

}  // namespace

bool buildWide8Bvh(const Bvh& bvh, std::vector<glm::uvec4>& out) {
    out.clear();
    if (bvh.nodes.empty()) return true;
    Wide8Collapse c{bvh.nodes, wideMergeMax(), {}};
    c.node(0);
    if (!c.ok || c.kids.size() > kWide8MaxNodes) return false;  // (the texel indices fit 24 bits)
    out.assign(c.kids.size() * kWide8Texels, glm::uvec4(0u));
    for (std::size_t i = 0; i < c.kids.size(); ++i) {
        glm::uvec4* node = &out[i * kWide8Texels];
        const std::array<Wide8Collapse::Child, 8> kids = Wide8Collapse::place(c.kids[i]);
        for (int k = 0; k < 8; ++k) {
            const std::uint32_t ref = kids[k].ref;
            node[4 + k / 4][k % 4] = (ref & kWideLeaf) != 0u ? ref : ref * kWide8Texels;  // a node's first texel
        }
        for (int a = 0; a < 3; ++a) {
            // The grid spans the union of the children that are there.
            float lo = std::numeric_limits<float>::infinity(), hi = -lo;
            for (const auto& kid : kids) {
                if (kid.ref == kWideEmpty || !(kid.lo[a] <= kid.hi[a])) continue;
                lo = std::min(lo, kid.lo[a]);
                hi = std::max(hi, kid.hi[a]);
            }
            if (!(lo <= hi)) lo = hi = 0.0f;
            node[0][a] = std::bit_cast<std::uint32_t>(lo);
            const auto e = static_cast<std::uint32_t>(gridExponent(lo, hi, 255));
            node[0].w |= e << (8 * a);
            for (int k = 0; k < 8; ++k) {
                std::uint32_t bl = 255, bh = 0;  // empty: inverted
                if (kids[k].ref != kWideEmpty && kids[k].lo[a] <= kids[k].hi[a])
                    quantizeChildBounds(node[0][a], e, kids[k].lo[a], kids[k].hi[a], bl, bh);
                wide8Bytes(node, 2 * a, k / 4) |= bl << (8 * (k % 4));
                wide8Bytes(node, 2 * a + 1, k / 4) |= bh << (8 * (k % 4));
            }
        }
    }
    return true;
}

bool pairBvhRequested() {
    const char* env = std::getenv("CAUSTIC_PAIR_BVH");
    return env && *env && std::strcmp(env, "0") != 0;
}

int wideBvhRequest() {
    const char* env = std::getenv("CAUSTIC_WIDE_BVH");
    if (!env || !*env) return -1;
    if (std::strcmp(env, "0") == 0) return 0;
    return std::strcmp(env, "8") == 0 ? 8 : 4;
}

bool wide8BvhRequested() { return wideBvhRequest() == 8; }

bool appendWide8Bvh(std::span<const glm::uvec4> texels, std::uint32_t base, std::vector<glm::uvec4>& out) {
    if (base + texels.size() > std::size_t(kWide8MaxNodes) * kWide8Texels) return false;
    const std::size_t start = out.size();
    out.insert(out.end(), texels.begin(), texels.end());
    for (std::size_t i = start; i < out.size(); i += kWide8Texels)
        for (int k = 0; k < 8; ++k) {
            std::uint32_t& ref = out[i + 4 + k / 4][k % 4];
            if ((ref & kWideLeaf) == 0u) ref += base;  // (kWideEmpty has the leaf bit)
        }
    return true;
}

void decodeWide8Box(std::span<const glm::uvec4> node, int k, glm::vec3& lo, glm::vec3& hi) {
    for (int a = 0; a < 3; ++a) {
        const std::uint32_t e = (node[0].w >> (8 * a)) & 0xffu;
        const std::uint32_t wl = node[1 + a][k / 4], wh = node[1 + a][2 + k / 4];
        lo[a] = decodeGridBound(node[0][a], e, (wl >> (8 * (k % 4))) & 0xffu);
        hi[a] = decodeGridBound(node[0][a], e, (wh >> (8 * (k % 4))) & 0xffu);
    }
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

RayHit intersectScene(const SceneBvh& scene, MeshPositions positions, const Ray& ray, float tMax, const HitFilter& keep) {
    RayHit hit;
    traverseScene<false>(scene, positions, ray, tMax, &hit, keep ? &keep : nullptr);
    return hit;
}

}  // namespace caustic
