// The 4-wide BVH: the binary tree collapsed to four children a node, and quantised as the GPU
// reads it (see bvh.h).
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
    WideCollapse c{bvh.nodes, base - static_cast<std::uint32_t>(start), out, kWideMergeMax};
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

void appendWideBvh(std::span<const gpu::GpuWideBvhNode> nodes, std::uint32_t base, std::vector<gpu::GpuWideBvhNode>& out) {
    const std::size_t start = out.size();
    out.insert(out.end(), nodes.begin(), nodes.end());
    for (std::size_t i = start; i < out.size(); ++i)
        for (int k = 0; k < 4; ++k)
            if ((out[i].child[k] & kWideLeaf) == 0u) out[i].child[k] += base;  // (kWideEmpty has the leaf bit)
}

}  // namespace caustic
