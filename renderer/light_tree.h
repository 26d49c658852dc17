// The light tree: a binary tree over a scene's lights (all but the environment) that next event
// estimation walks to choose a light by its estimated contribution at the shading point (Conty
// Estevez and Kulla 2018, "Importance Sampling of Many Lights with Adaptive Tree Splitting"; the
// traversal and the importance are in shaders/lights/light_select.glsl).
//
// Each light is described by its bounds: a box holding it, a cone of emitted directions (every
// surface normal within theta_o of `axis`, emission up to theta_e beyond a normal), and its
// intensity: the luminance of the most radiant intensity it sends towards one point (W sr^-1):
// L A for a rect (each face) and a flat emissive mesh (per face, summed over triangles), L pi R^2
// for a sphere, I for point and spot lights. Its importance at a point is then in units of
// irradiance, comparable with an environment's.
// A node holds the union of its children's bounds and the sum of their intensities. The build is
// top-down, splitting by the surface area orientation heuristic (the paper's eq. 2, with its
// orientation measure M_Omega, eq. 1, and the regularisation of long boxes) over 12 bins on each
// axis. A light's path from the root is a bit per level (1: right), so trees are at most 32
// deep: below depth 32 - ceil(log2 n) a node is split at its median, which bounds the depth.
#pragma once

#include "shaders/shared/layout.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace caustic {

struct LightBounds {
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};
    glm::vec3 axis{0.0f, 0.0f, 1.0f};  // unit
    float cosThetaO = -1.0f;           // -1: normals in every direction
    float cosThetaE = 0.0f;            // emission up to 90 degrees from a normal
    float intensity = 0.0f;            // luminance, W sr^-1
};

// The bounds of a union of lights (Conty Estevez and Kulla 2018, algorithm 1 for the cones).
LightBounds unionBounds(const LightBounds& a, const LightBounds& b);

// The paper's orientation measure M_Omega of a cone (eq. 1): the integral over the cone's
// emitted directions of the cosine-weighted solid angle.
float orientationMeasure(float cosThetaO, float cosThetaE);

struct LightTree {
    std::vector<gpu::GpuLightNode> nodes;  // depth first; the root at 0, a left child next to its parent
    std::vector<std::uint32_t> trails;     // per input light: its path (bit d: right child at depth d)
    int depth = 0;                         // the deepest leaf's depth (the root's is 0)
};

// Builds the tree over lights[i] for every i in `members` (light indices the GPU uses: a leaf
// stores lights index i); trails has lights.size() entries (0 for non-members). Empty members:
// no nodes.
LightTree buildLightTree(const std::vector<LightBounds>& lights, const std::vector<std::uint32_t>& members);

}  // namespace caustic
