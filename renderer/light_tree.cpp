#include "renderer/light_tree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace caustic {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

float safeAcos(float c) { return std::acos(std::clamp(c, -1.0f, 1.0f)); }

glm::vec3 centroid(const LightBounds& b) { return 0.5f * (b.boundsMin + b.boundsMax); }

// A surface-area measure that stays positive for flat and degenerate boxes (colinear or
// coincident lights), so the heuristic still prefers the smaller children there.
float boxMeasure(const LightBounds& b) {
    const glm::vec3 e = glm::max(b.boundsMax - b.boundsMin, glm::vec3(0.0f));
    const float s = e.x + e.y + e.z;
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x) + 1e-4f * s * s;
}

float splitCost(const LightBounds& b) {
    return b.intensity * orientationMeasure(b.cosThetaO, b.cosThetaE) * boxMeasure(b);
}

struct Builder {
    const std::vector<LightBounds>& lights;
    LightTree& tree;

    LightBounds boundsOf(const std::uint32_t* first, std::size_t n) const {
        LightBounds b = lights[first[0]];
        for (std::size_t i = 1; i < n; ++i) b = unionBounds(b, lights[first[i]]);
        return b;
    }

    // Builds the subtree over [first, first + n) at `depth` along `trail`; returns its node index.
    std::uint32_t build(std::uint32_t* first, std::size_t n, int depth, std::uint32_t trail) {
        const auto index = static_cast<std::uint32_t>(tree.nodes.size());
        tree.nodes.emplace_back();
        const LightBounds b = boundsOf(first, n);
        gpu::GpuLightNode node{};
        node.boundsMin = glm::vec4(b.boundsMin, b.intensity);
        node.boundsMax = glm::vec4(b.boundsMax, b.cosThetaO);
        node.axis = glm::vec4(b.axis, b.cosThetaE);
        tree.depth = std::max(tree.depth, depth);
        if (n == 1) {
            node.info = glm::uvec4(LIGHT_TREE_LEAF | first[0], 0, 0, 0);
            tree.trails[first[0]] = trail;
            tree.nodes[index] = node;
            return index;
        }
        const std::size_t mid = split(first, n, b, depth);
        build(first, mid, depth + 1, trail);
        const std::uint32_t right = build(first + mid, n - mid, depth + 1, trail | (1u << depth));
        node.info = glm::uvec4(right, 0, 0, 0);
        tree.nodes[index] = node;
        return index;
    }

    // Reorders [first, first + n) and returns the size of the left part (1 <= mid < n).
    std::size_t split(std::uint32_t* first, std::size_t n, const LightBounds& b, int depth) const {
        glm::vec3 cmin(std::numeric_limits<float>::max()), cmax(-std::numeric_limits<float>::max());
        for (std::size_t i = 0; i < n; ++i) {
            cmin = glm::min(cmin, centroid(lights[first[i]]));
            cmax = glm::max(cmax, centroid(lights[first[i]]));
        }
        const glm::vec3 extent = cmax - cmin;
        int widest = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
        auto median = [&](int axis) {
            std::nth_element(first, first + n / 2, first + n, [&](std::uint32_t a, std::uint32_t c) {
                return centroid(lights[a])[axis] < centroid(lights[c])[axis];
            });
            return n / 2;
        };
        // Depth bound: ceil(log2 n) more levels must fit under 32.
        int levels = 0;
        while ((std::size_t(1) << levels) < n) ++levels;
        if (depth + levels >= 31) return median(widest);

        constexpr int kBins = 12;
        const glm::vec3 boxExtent = b.boundsMax - b.boundsMin;
        const float maxBoxExtent = std::max({boxExtent.x, boxExtent.y, boxExtent.z});
        float bestCost = std::numeric_limits<float>::infinity();
        int bestAxis = -1, bestSplit = 0;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(extent[axis] > 0.0f)) continue;
            std::array<LightBounds, kBins> bins{};
            std::array<bool, kBins> used{};
            auto binOf = [&](std::uint32_t l) {
                const float t = (centroid(lights[l])[axis] - cmin[axis]) / extent[axis];
                return std::clamp(static_cast<int>(t * kBins), 0, kBins - 1);
            };
            for (std::size_t i = 0; i < n; ++i) {
                const int k = binOf(first[i]);
                bins[k] = used[k] ? unionBounds(bins[k], lights[first[i]]) : lights[first[i]];
                used[k] = true;
            }
            // Regularisation: splitting a long box across its short axis is penalised.
            const float kr = boxExtent[axis] > 0.0f ? maxBoxExtent / boxExtent[axis] : 1.0f;
            for (int s = 1; s < kBins; ++s) {
                LightBounds left{}, right{};
                bool hasLeft = false, hasRight = false;
                for (int k = 0; k < s; ++k)
                    if (used[k]) { left = hasLeft ? unionBounds(left, bins[k]) : bins[k]; hasLeft = true; }
                for (int k = s; k < kBins; ++k)
                    if (used[k]) { right = hasRight ? unionBounds(right, bins[k]) : bins[k]; hasRight = true; }
                if (!hasLeft || !hasRight) continue;
                const float cost = kr * (splitCost(left) + splitCost(right));
                if (cost < bestCost) {
                    bestCost = cost;
                    bestAxis = axis;
                    bestSplit = s;
                }
            }
        }
        if (bestAxis < 0) return median(widest);  // every centroid in one place
        const int axis = bestAxis;
        std::uint32_t* m = std::partition(first, first + n, [&](std::uint32_t l) {
            const float t = (centroid(lights[l])[axis] - cmin[axis]) / extent[axis];
            return std::clamp(static_cast<int>(t * kBins), 0, kBins - 1) < bestSplit;
        });
        const std::size_t mid = static_cast<std::size_t>(m - first);
        if (mid == 0 || mid == n) return median(widest);
        return mid;
    }
};

}  // namespace

float orientationMeasure(float cosThetaO, float cosThetaE) {
    const float thetaO = safeAcos(cosThetaO), thetaE = safeAcos(cosThetaE);
    const float thetaW = std::min(thetaO + thetaE, kPi);
    const float sinO = std::sin(thetaO);
    return 2.0f * kPi * (1.0f - cosThetaO) +
           0.5f * kPi * (2.0f * thetaW * sinO - std::cos(thetaO - 2.0f * thetaW) - 2.0f * thetaO * sinO + cosThetaO);
}

LightBounds unionBounds(const LightBounds& a, const LightBounds& b) {
    LightBounds u;
    u.boundsMin = glm::min(a.boundsMin, b.boundsMin);
    u.boundsMax = glm::max(a.boundsMax, b.boundsMax);
    u.intensity = a.intensity + b.intensity;
    u.cosThetaE = std::min(a.cosThetaE, b.cosThetaE);  // the larger theta_e
    // The cones: the smallest cone (of the paper's construction) holding both.
    const LightBounds* wide = &a;
    const LightBounds* narrow = &b;
    float tWide = safeAcos(a.cosThetaO), tNarrow = safeAcos(b.cosThetaO);
    if (tNarrow > tWide) {
        std::swap(wide, narrow);
        std::swap(tWide, tNarrow);
    }
    const float tD = safeAcos(glm::dot(wide->axis, narrow->axis));
    if (std::min(tD + tNarrow, kPi) <= tWide) {
        u.axis = wide->axis;
        u.cosThetaO = wide->cosThetaO;
        return u;
    }
    const float tO = 0.5f * (tWide + tD + tNarrow);
    const glm::vec3 k = glm::cross(wide->axis, narrow->axis);
    const float kl = glm::length(k);
    if (tO >= kPi || kl < 1e-6f) {
        u.axis = wide->axis;
        u.cosThetaO = -1.0f;
        return u;
    }
    // Turn the wide cone's axis towards the narrow one's by tO - tWide (Rodrigues, k is normal
    // to the axis).
    const float tR = tO - tWide;
    const glm::vec3 kn = k / kl;
    u.axis = glm::normalize(wide->axis * std::cos(tR) + glm::cross(kn, wide->axis) * std::sin(tR));
    u.cosThetaO = std::cos(tO);
    return u;
}

LightTree buildLightTree(const std::vector<LightBounds>& lights, const std::vector<std::uint32_t>& members) {
    LightTree tree;
    tree.trails.assign(lights.size(), 0u);
    if (members.empty()) return tree;
    std::vector<std::uint32_t> order = members;
    tree.nodes.reserve(2 * order.size() - 1);
    Builder b{lights, tree};
    b.build(order.data(), order.size(), 0, 0u);
    return tree;
}

}  // namespace caustic
