// Bounding volume hierarchies: a generic binned-SAH BVH over axis-aligned boxes, used twice,
// once per mesh over its triangles (the bottom level, BLAS) and once over the instances' world
// bounds (the top level, TLAS). Plus refit, the SAH cost that tells when a refit tree has degraded
// enough to rebuild, and a CPU traversal of both levels (closest hit and any hit) with the
// watertight ray/triangle test of Woop, Benthin and Wald 2013 ("Watertight Ray/Triangle
// Intersection", JCGT 2(1)). The CPU traversal is the reference the GLSL traversal is tested
// against, so it keeps to what a shader can do: a fixed stack, integer node indices, float maths.
//
// Layout (BvhNode): flattened depth first. An interior node's left child is the next node; only
// the right child's index is stored. A leaf's primitives are a contiguous range of the reordered
// primitive list. Children always come after their parent, so one reverse pass over the nodes is
// a bottom-up pass (refit).
//
// Build (see bvh_build.cpp for the measurements behind the choices): binned SAH over centroid
// bounds on all three axes with 16 bins, traversal cost 0.125 relative to one primitive test;
// leaves are made where the SAH says a leaf is cheaper than the best split (up to maxLeafSize
// primitives); a median split on the longest centroid axis when the binned split degenerates.
// Large subtrees are built on worker threads.
//
// Invalid input is handled, not trusted: a primitive whose bounds are not finite (NaN, inf) or are
// empty is left out of the tree (counted in Bvh::skipped), so no node bound is ever NaN.
#pragma once

#include "shaders/shared/layout.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

namespace caustic {

// An axis-aligned box. Empty (min > max) by default.
struct Aabb {
    glm::vec3 min{std::numeric_limits<float>::infinity()};
    glm::vec3 max{-std::numeric_limits<float>::infinity()};

    void grow(const glm::vec3& p) { min = glm::min(min, p); max = glm::max(max, p); }
    void grow(const Aabb& b) { min = glm::min(min, b.min); max = glm::max(max, b.max); }
    bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
    // Finite and not empty: the only boxes a BVH accepts.
    bool valid() const;
    // Half the surface area (the SAH only uses ratios); 0 for an empty box.
    float halfArea() const;
    glm::vec3 center() const { return 0.5f * (min + max); }
};

// One node, 32 bytes: two 16-byte rows, mirrored in GLSL as
//   struct BvhNode { vec3 boundsMin; uint rightOrFirst; vec3 boundsMax; uint countAndAxis; };
// (std430: a vec3 followed by a scalar packs into 16 bytes).
//   count = countAndAxis >> 2, axis = countAndAxis & 3.
//   count > 0: leaf; its primitives are [rightOrFirst, rightOrFirst + count) of the reordered list.
//   count = 0: interior; left child = this index + 1, right child = rightOrFirst; axis is the
//              split axis (0, 1, 2): for a ray with d[axis] < 0 visit the right child first.
struct BvhNode {
    glm::vec3 boundsMin;
    std::uint32_t rightOrFirst;
    glm::vec3 boundsMax;
    std::uint32_t countAndAxis;

    bool isLeaf() const { return (countAndAxis >> 2) != 0; }
    std::uint32_t count() const { return countAndAxis >> 2; }
    std::uint32_t axis() const { return countAndAxis & 3u; }
    Aabb bounds() const { return {boundsMin, boundsMax}; }
};
static_assert(sizeof(BvhNode) == 32, "BvhNode mirrors a std430 struct of two 16-byte rows");
static_assert(offsetof(BvhNode, rightOrFirst) == 12 && offsetof(BvhNode, boundsMax) == 16 &&
              offsetof(BvhNode, countAndAxis) == 28, "BvhNode field offsets are shared with GLSL");

inline constexpr std::uint32_t kBvhMaxLeafCount = (1u << 30) - 1u;  // what countAndAxis can hold
// The deepest tree the build makes: the traversal's fixed stack (CPU and GLSL) needs this many
// entries per level. Deeper subtrees (only possible with pathological input: a binned SAH build of
// a million-triangle mesh is 30 deep) are made into larger leaves. 32, not more: the GPU stack's
// size (shaders/geometry/bvh.glsl, BVH_STACK_SIZE) follows from it, and on NVIDIA the integrator's
// speed follows from the stack's size (docs/performance.md, "The integrator profile (H100)").
inline constexpr int kBvhMaxDepth = 32;

struct BvhBuildOptions {
    int bins = 16;                 // SAH bins per axis (>= 2)
    bool allAxes = true;           // bin all three axes; false: only the longest centroid axis
    float traversalCost = 0.125f;  // cost of visiting a node, relative to one primitive test
    std::uint32_t maxLeafSize = 8; // SAH may make leaves up to this size; larger always split
    bool sah = true;               // false: median split on the longest axis (for comparison)
    int threads = 0;               // 0: std::thread::hardware_concurrency(); 1: single-threaded
};

struct Bvh {
    std::vector<BvhNode> nodes;            // empty when there are no valid primitives
    std::vector<std::uint32_t> primIndices;// reordered list: leaf ranges index into this
    std::size_t skipped = 0;               // primitives left out for non-finite or empty bounds
    float builtSahCost = 0.0f;             // sahCost() right after the build (see needsRebuild)

    bool empty() const { return nodes.empty(); }
};

// A 4-wide BVH for the GPU's 4-wide walk (shaders/geometry/walk_wide4.glsl; the GPU reads it
// quantised, quantizeWideNode below): collapsed from a binary tree, each node holds its up to
// four children's boxes by coordinate and their references. Why: llvmpipe executes a traversal
// step's whole loop body for 8 rays at once, so a step costs the same whatever it does; fewer,
// wider steps test more boxes per step (docs/performance.md).
struct WideBvhNode {
    float minX[4], maxX[4], minY[4], maxY[4], minZ[4], maxZ[4];
    std::uint32_t child[4];  // kWideEmpty, kWideLeaf | count << kLeafCountShift | first, or a node's index
    std::uint32_t pad[4];
};
// (The words' layout is shaders/shared/layout.h's, which the shaders decode.)
inline constexpr std::uint32_t kWideEmpty = WIDE_CHILD_EMPTY;
inline constexpr std::uint32_t kWideLeaf = WIDE_CHILD_LEAF;
inline constexpr std::uint32_t kLeafCountShift = LEAF_COUNT_SHIFT;  // a leaf's count << this | first
// A leaf's word (a wide node's child): primitives [first, first + count), count in
// [1, LEAF_MAX_COUNT], first <= LEAF_MAX_FIRST (the callers check).
inline constexpr std::uint32_t leafWord(std::uint32_t first, std::uint32_t count) {
    return LEAF_BIT | count << LEAF_COUNT_SHIFT | first;
}
inline constexpr std::uint32_t kWideLeafMaxCount = WIDE_LEAF_MAX_COUNT;
inline constexpr std::uint32_t kWideLeafMaxFirst = WIDE_LEAF_MAX_FIRST;
// Subtrees of at most this many primitives become one leaf of the 4-wide tree. The binary tree's
// SAH (traversal cost 0.125) makes leaves of ~1 triangle, right for a GPU's cheap box tests; on
// llvmpipe each leaf costs a pass of the traversal's outer loop for all 8 lanes, and leaves of
// two make the knot scene 1.05x faster per CPU second than leaves of one (3 and 4 about as much,
// 6 less; docs/performance.md).
inline constexpr std::uint32_t kWideMergeMax = 2u;

// Appends the 4-wide form of `bvh` to `out`, its root first; child node indices are absolute
// (base + the node's position among those appended). Each node takes the children of a binary
// node and, while it has fewer than four, replaces the child of largest surface area that is an
// interior node by that node's two children; an interior node whose subtree holds at most
// kWideMergeMax primitives becomes one leaf. Binary leaves of more than kWideLeafMaxCount
// primitives become nodes of shorter leaves (the same box). An empty tree appends nothing. False
// when a leaf's first primitive is beyond kWideLeafMaxFirst (nothing appended then).
bool collapseBvh4(const Bvh& bvh, std::uint32_t base, std::vector<WideBvhNode>& out);

// Appends `nodes` (quantised 4-wide nodes of a tree collapsed at base 0) to `out` as if collapsed at
// `base` (child node references moved by base).
void appendWideBvh(std::span<const gpu::GpuWideBvhNode> nodes, std::uint32_t base, std::vector<gpu::GpuWideBvhNode>& out);

// A 4-wide node as the GPU reads it (gpu::GpuWideBvhNode, whose layout shaders/shared/layout.h
// gives: 64 bytes, four texels instead of eight), its children's boxes quantised to 8 bits on a
// grid over their union (after Ylitie, Karras and Laine 2017, "Efficient Incoherent Ray Traversal
// on GPUs Through Compressed Wide BVHs"): per axis an origin and a power-of-two scale s, each
// child's bounds as bytes q with bound = origin + q * s (q * s is exact, so the one rounding is
// the addition's, the same on every device). The bytes are chosen so that the decoded box contains
// the child's box (lo rounded down, hi up; checked in float as decodeWideBound computes it), so a
// ray that hits a child's box hits its decoded box; an empty child decodes to an inverted box (lo >
// hi on every axis).
gpu::GpuWideBvhNode quantizeWideNode(const WideBvhNode& node);
// The bound the GPU decodes from byte q of axis a (origin + q * s, in float).
float decodeWideBound(const gpu::GpuWideBvhNode& node, int axis, std::uint32_t q);
// Child k's decoded box.
void decodeWideBox(const gpu::GpuWideBvhNode& node, int k, glm::vec3& lo, glm::vec3& hi);

// Builds over primBounds (one box per primitive, indexed by primitive id).
Bvh buildBvh(std::span<const Aabb> primBounds, const BvhBuildOptions& options = {});

// Recomputes every node's bounds bottom-up for the same topology from new primitive bounds
// (indexed by primitive id, as for the build). A primitive whose new bounds are invalid
// contributes nothing (its leaf may become empty: an inverted box that no ray enters).
void refitBvh(Bvh& bvh, std::span<const Aabb> primBounds);

// The SAH cost of the tree: sum over interior nodes of traversalCost * A(node) / A(root) plus sum
// over leaves of count * A(leaf) / A(root) (MacDonald and Booth 1990), A = surface area.
float sahCost(const Bvh& bvh, float traversalCost = 0.125f);

// Refit keeps the topology, so moving things apart grows overlapping boxes and the cost. The
// renderer refits while the cost stays under kBvhRebuildFactor times the cost measured after the
// last build and rebuilds beyond it: see bvh_build.cpp for the measurement behind 1.5.
inline constexpr float kBvhRebuildFactor = 1.5f;
bool needsRebuild(const Bvh& bvh, float traversalCost = 0.125f);

// Maximum depth (root = 1) and leaf statistics, for tests and the benchmark.
struct BvhStats {
    int depth = 0;
    std::size_t leaves = 0, interior = 0, maxLeafCount = 0;
    double meanLeafCount = 0.0;
};
BvhStats bvhStats(const Bvh& bvh);

// ---- Two levels -------------------------------------------------------------------------------

// One mesh's bottom-level BVH. `triangles` is the mesh's triangle list reordered so that a leaf's
// range indexes it directly (no indirection on the GPU); triangleIds maps back to the original
// triangle index (bvh.primIndices holds the same). Degenerate triangles stay in (a zero-area
// triangle is never hit); triangles with non-finite vertices or out-of-range indices are left out.
struct MeshBlas {
    Bvh bvh;
    std::vector<glm::uvec3> triangles;
    std::vector<std::uint32_t> triangleIds;
};

MeshBlas buildBlas(std::span<const glm::vec3> positions, std::span<const glm::uvec3> triangles,
                   const BvhBuildOptions& options = {});
// The vertices moved (same triangles): refit the bounds. Check needsRebuild(blas.bvh) after.
void refitBlas(MeshBlas& blas, std::span<const glm::vec3> positions);

struct Instance {
    std::uint32_t mesh = 0;                // index into the BLAS list
    glm::mat4 objectToWorld{1.0f};         // affine
};

// The world bounds of each instance: the BLAS root box's eight corners transformed. An instance
// with a non-finite or singular transform, or an out-of-range or empty mesh, gets an empty box
// and is left out of the TLAS.
std::vector<Aabb> instanceWorldBounds(std::span<const MeshBlas> blases,
                                      std::span<const Instance> instances);

// The whole two-level structure the renderer keeps: BLASes, instances, their inverse transforms
// and the TLAS over instance world bounds.
struct SceneBvh {
    std::vector<MeshBlas> blases;
    std::vector<Instance> instances;
    std::vector<glm::mat4> worldToObject;  // one per instance (inverse of objectToWorld)
    Bvh tlas;
};

// (Re)builds the TLAS (and worldToObject) from sceneBvh.blases and sceneBvh.instances.
void buildTlas(SceneBvh& scene, const BvhBuildOptions& options = {});
// The instances' transforms changed (same instances, same meshes): recompute worldToObject and
// refit the TLAS. Returns needsRebuild(scene.tlas): true means call buildTlas instead next time.
bool refitTlas(SceneBvh& scene);

// ---- CPU traversal ------------------------------------------------------------------------------

struct Ray {
    glm::vec3 origin;
    glm::vec3 dir;  // need not be unit length; t is in units of dir
};

struct RayHit {
    float t = std::numeric_limits<float>::infinity();
    std::uint32_t instance = ~0u;
    std::uint32_t primitive = ~0u;   // the original triangle index in the instance's mesh
    float u = 0.0f, v = 0.0f;        // barycentrics: p = (1-u-v) v0 + u v1 + v v2
    bool hit() const { return primitive != ~0u; }
};

// Per-ray constants of the watertight test (Woop et al. 2013, section 3): the dominant axis kz
// of the direction, the other two kx, ky (swapped to keep the winding when d[kz] < 0) and the
// shear that maps the ray to the +z axis.
struct WatertightRay {
    glm::vec3 origin;
    int kx, ky, kz;
    float sx, sy, sz;
    explicit WatertightRay(const Ray& ray);
};

// The watertight ray/triangle test: a hit with t in (0, tMax) sets *t, *u, *v. Edges shared by
// two triangles are never missed by both (no ray escapes through a closed mesh); a ray exactly on
// an edge may hit both. Float edge functions (edgeFunction), never of the wrong sign; a double
// precision redo when one is exactly 0 (section 3).
bool intersectTriangle(const WatertightRay& ray, const glm::vec3& v0, const glm::vec3& v1,
                       const glm::vec3& v2, float tMax, float* t, float* u, float* v);

// An edge function, a * b - c * d with each product rounded on its own (never contracted into an
// fma): rounding is monotone, so the result is never of the wrong sign, only sometimes 0 where
// the exact value is not. The GLSL traversal computes the same (geometry/bvh.glsl, `precise`: an
// fma contraction, fl(a b - fl(c d)), can have the wrong sign and let a ray through an edge miss
// both triangles).
float edgeFunction(float a, float b, float c, float d);

// Closest hit with t in (0, tMax) over one BLAS (instance left as ~0u) or the whole scene.
RayHit intersectBlas(const MeshBlas& blas, std::span<const glm::vec3> positions, const Ray& ray,
                     float tMax = std::numeric_limits<float>::infinity());
// Any hit with t in (0, tMax): early exit.
bool occludedBlas(const MeshBlas& blas, std::span<const glm::vec3> positions, const Ray& ray,
                  float tMax = std::numeric_limits<float>::infinity());

// Positions of every mesh, indexed like SceneBvh::blases (the BLAS does not own its vertices:
// the renderer's mesh does).
using MeshPositions = std::span<const std::vector<glm::vec3>>;
RayHit intersectScene(const SceneBvh& scene, MeshPositions positions, const Ray& ray,
                      float tMax = std::numeric_limits<float>::infinity());
bool occludedScene(const SceneBvh& scene, MeshPositions positions, const Ray& ray,
                   float tMax = std::numeric_limits<float>::infinity());
// The closest hit that `keep` accepts: asked of every triangle hit nearer than the closest one
// kept so far (as the GPU traversal asks geometry/alpha_mask.glsl), with the instance, the
// triangle's slot in its BLAS's reordered `triangles` and the barycentrics; a hit it refuses is
// passed through, and what lies behind is found by the same walk.
using HitFilter = std::function<bool(std::uint32_t instance, std::uint32_t slot, float u, float v)>;
RayHit intersectScene(const SceneBvh& scene, MeshPositions positions, const Ray& ray, float tMax,
                      const HitFilter& keep);

// The object-space ray of an instance: origin and direction through worldToObject (the direction
// is not normalised, so t is the same in both spaces). Shared by the traversal and the tests'
// brute force so that both see bit-identical rays.
Ray transformRay(const glm::mat4& worldToObject, const Ray& ray);

}  // namespace caustic
