// Binned SAH BVH build, refit and SAH cost (see bvh.h).
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

}  // namespace caustic
