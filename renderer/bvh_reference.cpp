// The CPU reference traversal: closest-hit and any-hit queries on a mesh BVH and on the two-level
// scene, with the watertight triangle test the GPU walks use (see bvh.h).
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

}  // namespace

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
