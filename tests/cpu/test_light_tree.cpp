// The light tree's build (renderer/light_tree.h): every light is in exactly one leaf, its trail
// leads there, a node's intensity is the sum of its children's and its box and cone hold theirs,
// and the depth stays within the 32 levels a trail can encode, even for adversarial layouts.
#include "renderer/light_tree.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

using namespace caustic;

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

float angleBetween(glm::vec3 a, glm::vec3 b) { return std::acos(std::clamp(glm::dot(a, b), -1.0f, 1.0f)); }

// Checks the subtree at `node` and returns the lights below it.
std::vector<std::uint32_t> checkNode(const LightTree& t, const std::vector<LightBounds>& lights, std::uint32_t node,
                                     int depth, std::uint32_t trail) {
    REQUIRE(node < t.nodes.size());
    REQUIRE(depth < 32);
    const gpu::GpuLightNode& n = t.nodes[node];
    if (n.info.x & LIGHT_TREE_LEAF) {
        const std::uint32_t light = n.info.x & ~LIGHT_TREE_LEAF;
        REQUIRE(light < lights.size());
        CHECK(t.trails[light] == trail);
        CHECK(n.boundsMin.w == Approx(lights[light].intensity));
        return {light};
    }
    const std::uint32_t left = node + 1, right = n.info.x;
    REQUIRE(right > left);
    std::vector<std::uint32_t> below = checkNode(t, lights, left, depth + 1, trail);
    const std::vector<std::uint32_t> r = checkNode(t, lights, right, depth + 1, trail | (1u << depth));
    below.insert(below.end(), r.begin(), r.end());
    const float sum = t.nodes[left].boundsMin.w + t.nodes[right].boundsMin.w;
    CHECK(n.boundsMin.w == Approx(sum).epsilon(1e-5));
    const float thetaO = std::acos(std::clamp(n.boundsMax.w, -1.0f, 1.0f));
    const float thetaE = std::acos(std::clamp(n.axis.w, -1.0f, 1.0f));
    for (std::uint32_t l : below) {
        const LightBounds& b = lights[l];
        for (int c = 0; c < 3; ++c) {
            CHECK(n.boundsMin[c] <= b.boundsMin[c]);
            CHECK(n.boundsMax[c] >= b.boundsMax[c]);
        }
        // The node's cone holds every light's normal cone, and its theta_e is the largest.
        if (n.boundsMax.w > -1.0f)
            CHECK(angleBetween(glm::vec3(n.axis), b.axis) + std::acos(std::clamp(b.cosThetaO, -1.0f, 1.0f)) <= thetaO + 1e-3f);
        CHECK(std::acos(std::clamp(b.cosThetaE, -1.0f, 1.0f)) <= thetaE + 1e-4f);
    }
    return below;
}

void checkTree(const std::vector<LightBounds>& lights, const std::vector<std::uint32_t>& members) {
    const LightTree t = buildLightTree(lights, members);
    REQUIRE(t.nodes.size() == 2 * members.size() - 1);
    CHECK(t.depth < 32);
    std::vector<std::uint32_t> found = checkNode(t, lights, 0, 0, 0u);
    std::sort(found.begin(), found.end());
    std::vector<std::uint32_t> want = members;
    std::sort(want.begin(), want.end());
    CHECK(found == want);
}

}  // namespace

TEST_CASE("light tree: every light in one leaf, sums, boxes and cones hold their children", "[light_tree]") {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<LightBounds> lights;
    for (int i = 0; i < 500; ++i) {
        LightBounds b;
        const glm::vec3 c(10 * u(rng), 10 * u(rng), 10 * u(rng));
        const float r = 0.1f + 0.5f * (u(rng) + 1.0f);
        b.boundsMin = c - r;
        b.boundsMax = c + r;
        b.intensity = 1.0f + 100.0f * (u(rng) + 1.0f);
        if (i % 3 == 0) {  // one-sided emitters of random orientation
            b.axis = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
            b.cosThetaO = 1.0f;
        } else if (i % 3 == 1) {  // spots
            b.axis = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
            b.cosThetaO = std::cos(0.3f);
            b.cosThetaE = std::cos(0.2f);
        }
        lights.push_back(b);
    }
    std::vector<std::uint32_t> members;
    for (std::uint32_t i = 0; i < lights.size(); ++i)
        if (i != 17) members.push_back(i);  // one light (an environment, say) left out
    checkTree(lights, members);
    const LightTree t = buildLightTree(lights, members);
    CHECK(t.trails[17] == 0u);
    // A single light is a leaf at the root; none is an empty tree.
    CHECK(buildLightTree(lights, {5}).nodes.size() == 1);
    CHECK(buildLightTree(lights, {}).nodes.empty());
}

TEST_CASE("light tree: degenerate and adversarial layouts stay within 32 levels", "[light_tree]") {
    std::vector<LightBounds> lights;
    SECTION("coincident point lights") {
        for (int i = 0; i < 1000; ++i) {
            LightBounds b;
            b.intensity = 1.0f;
            lights.push_back(b);
        }
    }
    SECTION("exponentially spaced along a line, exponentially bright") {
        for (int i = 0; i < 3000; ++i) {
            LightBounds b;
            b.boundsMin = b.boundsMax = glm::vec3(std::pow(1.01f, float(i)), 0.0f, 0.0f);
            b.intensity = std::pow(1.02f, float(i % 700));
            lights.push_back(b);
        }
    }
    SECTION("lights of zero intensity beside bright ones") {
        for (int i = 0; i < 300; ++i) {
            LightBounds b;
            b.boundsMin = b.boundsMax = glm::vec3(float(i), float(i % 7), 0.0f);
            b.intensity = i % 2 ? 0.0f : 5.0f;
            lights.push_back(b);
        }
    }
    std::vector<std::uint32_t> members(lights.size());
    for (std::uint32_t i = 0; i < members.size(); ++i) members[i] = i;
    checkTree(lights, members);
}

TEST_CASE("light tree: the orientation measure and the union of cones", "[light_tree]") {
    // M_Omega of a one-sided Lambertian emitter (theta_o = 0, theta_e = pi/2) is pi, the
    // cosine-weighted hemisphere; of a point light (theta_o = pi) 4 pi, the whole sphere.
    CHECK(orientationMeasure(1.0f, 0.0f) == Approx(kPi).epsilon(1e-5));
    CHECK(orientationMeasure(-1.0f, 0.0f) == Approx(4.0f * kPi).epsilon(1e-5));
    LightBounds a, b;
    a.axis = glm::vec3(0, 0, 1);
    a.cosThetaO = 1.0f;
    b.axis = glm::vec3(1, 0, 0);
    b.cosThetaO = 1.0f;
    const LightBounds u = unionBounds(a, b);  // two normals 90 degrees apart: a cone of 45 degrees between them
    CHECK(u.cosThetaO == Approx(std::cos(kPi / 4)).margin(1e-5));
    CHECK(glm::dot(u.axis, glm::normalize(glm::vec3(1, 0, 1))) == Approx(1.0f).margin(1e-5));
    b.axis = glm::vec3(0, 0, -1);  // opposite normals: the whole sphere
    CHECK(unionBounds(a, b).cosThetaO == -1.0f);
    b.axis = glm::vec3(0, 0, 1);
    b.cosThetaO = std::cos(0.5f);  // nested cones: the wider
    CHECK(unionBounds(a, b).cosThetaO == Approx(std::cos(0.5f)));
}
