// Two-level BVH traversal (renderer/bvh.h builds the trees): a loop walks the top level over
// analytic primitives and mesh instances and, on reaching an instance, a loop nested in it walks
// the instance's own BVH in object space (the ray is transformed, t keeps its meaning). One
// explicit stack holds the nodes still to visit (the far child of each node whose children both
// hit; children are visited nearer first; a popped node's children are slab-tested against the
// closest hit so far); an instance's entries sit above the top level's. Closest hit and any hit (shadow rays, early exit) are the
// same routine with a flag. A triangle hit counts only where its material's alpha mask keeps it
// (alpha_mask.glsl; compiled out for scenes without masks).
//   Boxes: the slab test picking the near/far plane by the direction's sign, with the far
//   distance scaled by 1 + 2 gamma_3 (Ize 2013, "Robust BVH Ray Traversal", JCGT 2(2)); an
//   inverted (empty) box is never entered.
//   A mesh's tree is walked in one of two forms, one file each (renderer/integrator_config.h
//   chooses): the binary nodes with a memory stack (geometry/walk_binary.glsl, NVIDIA's) or the
//   4-wide nodes with a register stack (geometry/walk_wide4.glsl, llvmpipe's).
//   Triangles: Woop, Benthin and Wald 2013, "Watertight Ray/Triangle Intersection", JCGT 2(1),
//   with float edge functions kept monotone (`precise`: never of the wrong sign) and those that
//   are exactly 0 redone in double (as the CPU reference does).
#ifndef GEOMETRY_BVH_GLSL
#define GEOMETRY_BVH_GLSL
#include "../lib/math.glsl"
#include "../scene/buffers.glsl"
#include "alpha_mask.glsl"

// The most a traversal holds: the top level's pending siblings (fewer than kBvhMaxDepth = 32) and
// the instance tree's (fewer than 32). A push that would overflow is dropped (the node is not
// visited) rather than written out of bounds. (76 entries: what NVIDIA is measured with.)
// The 4-wide walk pushes up to three siblings per step: 31 top-level entries and 3 per level of
// an instance's tree (no deeper than its binary tree, 32) need 127. Only programs that can meet a
// mesh get the larger stack: on llvmpipe 128 entries make scenes without meshes that walk the top
// level 10-20 % slower than 76 (docs/performance.md).
#if defined(CAUSTIC_WIDE_BVH) && defined(CAUSTIC_FETCH_TEXELS)
const int BVH_STACK_SIZE = HAS_MESHES ? 128 : 76;
#else
const int BVH_STACK_SIZE = 76;
#endif

struct TraceHit {
    float t;
    uint ref;      // the top-level entry: a primitive index, or TLAS_REF_INSTANCE | instance
    uint triangle; // for instances: the index into triangles[]
    vec2 bary;     // for triangles: (b1, b2)
};

vec3 safeInverse(vec3 d) {
    // A zero component would give inf * 0 = NaN in the slab test; a tiny one gives a huge slope.
    vec3 s = vec3(d.x < 0.0 ? -1.0 : 1.0, d.y < 0.0 ? -1.0 : 1.0, d.z < 0.0 ? -1.0 : 1.0);
    return 1.0 / mix(d, s * 1e-30, lessThan(abs(d), vec3(1e-30)));
}

bool slabTest(GpuBvhNode n, vec3 o, vec3 invD, float tMax, out float tEnter) {
    vec3 nearB = vec3(invD.x < 0.0 ? n.boundsMax.x : n.boundsMin.x, invD.y < 0.0 ? n.boundsMax.y : n.boundsMin.y,
                      invD.z < 0.0 ? n.boundsMax.z : n.boundsMin.z);
    vec3 farB = vec3(invD.x < 0.0 ? n.boundsMin.x : n.boundsMax.x, invD.y < 0.0 ? n.boundsMin.y : n.boundsMax.y,
                     invD.z < 0.0 ? n.boundsMin.z : n.boundsMax.z);
    vec3 t0 = (nearB - o) * invD, t1 = (farB - o) * invD;
    float tn = max(max(t0.x, t0.y), max(t0.z, 0.0));
    float tf = min(min(t1.x, t1.y), t1.z) * 1.0000004;
    tEnter = tn;
    return tn <= min(tf, tMax);
}

// slabTest's arithmetic for several boxes at once, by coordinate (the 4-wide and the pair nodes'
// children): their entry distances (tn) and which of them the ray hits below tMax.
#define SLAB_TESTS_BODY(T)                                                                          \
    T nx = invD.x < 0.0 ? maxX : minX, fx = invD.x < 0.0 ? minX : maxX;                             \
    T ny = invD.y < 0.0 ? maxY : minY, fy = invD.y < 0.0 ? minY : maxY;                             \
    T nz = invD.z < 0.0 ? maxZ : minZ, fz = invD.z < 0.0 ? minZ : maxZ;                             \
    tn = max(max((nx - o.x) * invD.x, (ny - o.y) * invD.y), max((nz - o.z) * invD.z, T(0.0)));     \
    T tf = min(min((fx - o.x) * invD.x, (fy - o.y) * invD.y), (fz - o.z) * invD.z) * 1.0000004;   \
    return lessThanEqual(tn, min(tf, T(tMax)));
bvec2 slabTests(vec2 minX, vec2 maxX, vec2 minY, vec2 maxY, vec2 minZ, vec2 maxZ, vec3 o, vec3 invD, float tMax,
                out vec2 tn) {
    SLAB_TESTS_BODY(vec2)
}
bvec4 slabTests(vec4 minX, vec4 maxX, vec4 minY, vec4 maxY, vec4 minZ, vec4 maxZ, vec3 o, vec3 invD, float tMax,
                out vec4 tn) {
    SLAB_TESTS_BODY(vec4)
}
#undef SLAB_TESTS_BODY

struct WatertightRay { vec3 o; int kx, ky, kz; vec3 s; };

WatertightRay makeWatertightRay(vec3 o, vec3 d) {
    WatertightRay r;
    r.o = o;
    vec3 ad = abs(d);
    r.kz = ad.x >= ad.y && ad.x >= ad.z ? 0 : (ad.y >= ad.z ? 1 : 2);
    r.kx = r.kz == 2 ? 0 : r.kz + 1;
    r.ky = r.kx == 2 ? 0 : r.kx + 1;
    if (d[r.kz] < 0.0) { int tmp = r.kx; r.kx = r.ky; r.ky = tmp; }
    r.s = vec3(d[r.kx] / d[r.kz], d[r.ky] / d[r.kz], 1.0 / d[r.kz]);
    return r;
}

// a * b - c * d, each product rounded on its own: rounding is monotone, so a b > c d gives
// fl(a b) >= fl(c d), and the result is never of the wrong sign (it may be 0 where the exact value
// is not, which the triangle test redoes in double). `precise` forbids the compiler to contract it
// into fma(a, b, -fl(c d)), which can have the wrong sign: a ray through one of two triangles
// near their shared edge could then miss both. renderer/bvh_reference.cpp computes the same on the CPU.
float edgeFunction(float a, float b, float c, float d) {
    precise float ab = a * b;
    precise float cd = c * d;
    precise float r = ab - cd;
    return r;
}

bool intersectTriangle(WatertightRay r, vec3 v0, vec3 v1, vec3 v2, float tMax, out float t, out vec2 bary) {
    vec3 a = v0 - r.o, b = v1 - r.o, c = v2 - r.o;
    float ax = a[r.kx] - r.s.x * a[r.kz], ay = a[r.ky] - r.s.y * a[r.kz];
    float bx = b[r.kx] - r.s.x * b[r.kz], by = b[r.ky] - r.s.y * b[r.kz];
    float cx = c[r.kx] - r.s.x * c[r.kz], cy = c[r.ky] - r.s.y * c[r.kz];
    float u = edgeFunction(cx, by, cy, bx);
    float v = edgeFunction(ax, cy, ay, cx);
    float w = edgeFunction(bx, ay, by, ax);
    // A float edge function that is 0 may be a rounding artefact (never one of the wrong sign):
    // redone in double (exact products), as in Woop et al. (Not by fma two-products: GLSL's fma
    // need not round once, and llvmpipe's does not.)
    if (u == 0.0 || v == 0.0 || w == 0.0) {
        double ud = double(cx) * double(by) - double(cy) * double(bx);
        double vd = double(ax) * double(cy) - double(ay) * double(cx);
        double wd = double(bx) * double(ay) - double(by) * double(ax);
        if ((ud < 0.0 || vd < 0.0 || wd < 0.0) && (ud > 0.0 || vd > 0.0 || wd > 0.0)) return false;
        u = float(ud);
        v = float(vd);
        w = float(wd);
    }
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
    float det = u + v + w;
    if (!(det != 0.0)) return false;
    float tScaled = u * r.s.z * a[r.kz] + v * r.s.z * b[r.kz] + w * r.s.z * c[r.kz];
    float invDet = 1.0 / det;
    t = tScaled * invDet;
    if (!(t > 0.0 && t < tMax)) return false;
    bary = vec2(v * invDet, w * invDet);
    return true;
}

// intersectPrimitive (analytic shapes) comes from intersect.glsl, which includes this file after
// declaring it.
bool intersectPrimitiveT(uint index, vec3 o, vec3 d, float tMax, out float t);

// The traversal stack lives at file scope, not in traceScene: the integrator calls traceScene from
// three places (the continuation ray, and two kinds of shadow ray), and NVIDIA's compiler inlines
// each call with its own copy of a local array, so a function-local stack was three stacks (3.3 KB
// of local memory per invocation); one shared array made the integrator 3x faster on an H100.
// Its size matters as much: entries are node indices only (4 bytes), not (node, entry distance)
// pairs; halving the stack's bytes doubled the speed again, more than culling popped nodes that
// start beyond the closest hit ever saved (docs/performance.md, "The integrator profile (H100)").
uint g_bvhStack[BVH_STACK_SIZE];

// The walks' statistics (CAUSTIC_WALK_STATS: a benchmark aid, never on by default; the entry
// shader enables GL_ARB_shader_ballot and defines CAUSTIC_BALLOT): per invocation, the
// iterations of the mesh walks' loops it took part in, those in which it was its SIMD group's
// lowest active lane (so that summed over the group they count the group's iterations), and the
// instance trees it began to walk; integrator/film.glsl, countWalkStats, adds them up. Counts, not
// times: a change to the walk's schedule shows in them whatever the machine's load.
#if defined(CAUSTIC_WALK_STATS) && defined(CAUSTIC_BALLOT)
#define BVH_WALK_STATS
uint g_walkGroupSteps = 0u, g_walkLaneSteps = 0u, g_walkTrees = 0u;
#define WALK_STATS_STEP()                                                                         \
    {                                                                                             \
        ++g_walkLaneSteps;                                                                        \
        uvec2 ballot = unpackUint2x32(ballotARB(true));                                           \
        uint lowest = ballot.x != 0u ? uint(findLSB(ballot.x)) : 32u + uint(findLSB(ballot.y));   \
        if (gl_SubGroupInvocationARB == lowest) ++g_walkGroupSteps;                               \
    }
#define WALK_STATS_TREE() ++g_walkTrees;
#else
#define WALK_STATS_STEP()
#define WALK_STATS_TREE()
#endif

// One interior node's step: tests both children against the ray; the nearer one hit becomes
// `node` and its record `n` (fetched here for its box, so the walk does not fetch it again: a
// third of the binary walk's fetches; neutral on llvmpipe), the farther one (when both
// are hit) goes on the stack. False when neither is hit. Used by the top level's walk and the
// binary mesh walk (geometry/walk_binary.glsl).
bool bvhDescend(inout GpuBvhNode n, inout uint node, vec3 o, vec3 invD, float tMax, inout int sp) {
    uint l = node + 1u, r = n.rightOrFirst;
    GpuBvhNode nl = loadBvhNode(l), nr = loadBvhNode(r);
    float tl, tr;
    bool hl = slabTest(nl, o, invD, tMax, tl);
    bool hr = slabTest(nr, o, invD, tMax, tr);
    if (hl && hr) {
        bool leftFirst = tl <= tr;
        if (sp < BVH_STACK_SIZE) g_bvhStack[sp++] = leftFirst ? r : l;
        node = leftFirst ? l : r;
        n = leftFirst ? nl : nr;
        return true;
    }
    if (hl || hr) {
        node = hl ? l : r;
        n = hl ? nl : nr;
        return true;
    }
    return false;
}

// A leaf's word in the wide nodes and the pair records (shared/layout.h): its first triangle and
// its count.
#define LEAF_FIRST(word) ((word) & LEAF_MAX_FIRST)
#define LEAF_COUNT(word) (((word) >> LEAF_COUNT_SHIFT) & LEAF_MAX_COUNT)

// A leaf's triangles, [first, first + count) of the instance's (from firstTriangle): a hit
// nearer than hit.t replaces it. The one place where a triangle hit is accepted, for both forms of
// the instance's traversal. True when a hit was found.
bool traceLeafTriangles(WatertightRay wr, GpuInstance inst, uint instance, uint firstTriangle, uint first, uint count,
                        bool anyHit, inout TraceHit hit) {
    bool found = false;
    for (uint k = first; k < first + count; ++k) {
        GpuTriangle tri = loadTriangle(firstTriangle + k);
        float t;
        vec2 b;
        // The one place a triangle hit is accepted (both traversals), and the alpha cut-outs'
        // any-hit test (geometry/alpha_mask.glsl; compiled out for scenes without masks).
        if (intersectTriangle(wr, tri.p0.xyz, tri.p1.xyz, tri.p2.xyz, hit.t, t, b) && alphaMaskKeeps(inst, tri, b)) {
            hit.t = t;
            hit.ref = TLAS_REF_INSTANCE | instance;
            hit.triangle = firstTriangle + k;
            hit.bary = b;
            found = true;
            if (anyHit) return true;
        }
    }
    return found;
}

// The mesh walk: one file per form of the meshes' trees, chosen by the integrator's
// configuration (renderer/integrator_config.h). Each defines traceInstanceTree.
#if defined(CAUSTIC_WIDE_BVH) && defined(CAUSTIC_FETCH_TEXELS)
#include "walk_wide4.glsl"
#else
#include "walk_binary.glsl"
#endif

// The ray in the instance's object space (t keeps its meaning: d is not renormalised).
void rayToObject(GpuInstance inst, vec3 rayO, vec3 rayD, out vec3 o, out vec3 d) {
    o = vec3(dot(inst.worldToObject0, vec4(rayO, 1.0)), dot(inst.worldToObject1, vec4(rayO, 1.0)),
             dot(inst.worldToObject2, vec4(rayO, 1.0)));
    d = vec3(dot(inst.worldToObject0.xyz, rayD), dot(inst.worldToObject1.xyz, rayD), dot(inst.worldToObject2.xyz, rayD));
}

// The instance's root box, then its tree.
bool traceInstanceRecord(GpuInstance inst, uint instance, vec3 rayO, vec3 rayD, bool anyHit, int base, inout TraceHit hit) {
    vec3 o, d;
    rayToObject(inst, rayO, rayD, o, d);
    vec3 invD = safeInverse(d);
    float tEnter;
    if (!slabTest(loadBvhNode(inst.rootNode), o, invD, hit.t, tEnter)) return false;
    return traceInstanceTree(inst, instance, o, d, invD, anyHit, base, hit);
}

bool traceInstance(uint instance, vec3 rayO, vec3 rayD, bool anyHit, int base, inout TraceHit hit) {
    return traceInstanceRecord(loadInstance(instance), instance, rayO, rayD, anyHit, base, hit);
}

// Baked geometry: the tests of a scene's primitives and instances as constants of its program,
// and the paired walk of a baked top level (renderer_programs.cpp makes the defines).
#include "trace_baked.glsl"

bool traceScene(vec3 rayO, vec3 rayD, float tMax, bool anyHit, out TraceHit hit) {
    hit.t = tMax;
    hit.ref = 0xffffffffu;
    hit.triangle = 0u;
    hit.bary = vec2(0.0);
    if (frame.geometry.x == 0u) return false;
    // A few analytic primitives and no meshes (a Cornell box is 18 quads): testing them all beats
    // walking a tree, by about 1.5x on llvmpipe (docs/performance.md).
    // (CAUSTIC_TRAVERSAL: a scene-specialised program keeps only the one its scene uses.)
    if (CAUSTIC_TRAVERSAL == 1u ||
        (CAUSTIC_TRAVERSAL == 0u && frame.geometry.y == 0u && frame.counts.x <= BVH_BRUTE_FORCE_MAX)) {
        bool found = false;
#ifdef CAUSTIC_BAKED_PRIMITIVES
        // The primitives as constants of the program (renderer_programs.cpp, bakedPrimitiveTests): the
        // same tests as the loop below, on immediates instead of fetched records.
        Ray bakedRay;
        bakedRay.o = rayO;
        bakedRay.d = rayD;
        CAUSTIC_BAKED_PRIMITIVES
        return found;
#endif
        for (uint i = 0u; i < frame.counts.x; ++i) {
            float t;
            if (intersectPrimitiveT(i, rayO, rayD, hit.t, t)) {
                hit.t = t;
                hit.ref = i;
                found = true;
                if (anyHit) return true;
            }
        }
        return found;
    }
#if defined(CAUSTIC_BAKED_TOP_LEVEL) && HAS_MESHES
    {
        // The top level's entries as constants of the program (renderer_programs.cpp, bakedPrimitiveTests):
        // the one ray as either ray of traceScenePair.
        bool occluded;
        bool found = traceScenePair(!anyHit, rayO, rayD, tMax, anyHit, rayO, rayD, tMax, hit, occluded);
        return anyHit ? occluded : found;
    }
#endif
    // The top level, over analytic primitives and mesh instances.
    vec3 invD = safeInverse(rayD);
    float tEnter;
    uint node = 0u;
    GpuBvhNode n = loadBvhNode(node);
    if (!slabTest(n, rayO, invD, hit.t, tEnter)) return false;
    int sp = 0;
    bool found = false;
    while (true) {
        uint count = n.countAndAxis >> 2;
        if (count == 0u) {
            if (bvhDescend(n, node, rayO, invD, hit.t, sp)) continue;
        } else {
            for (uint k = n.rightOrFirst; k < n.rightOrFirst + count; ++k) {
                uint ref = loadTlasRef(k);
                if (HAS_MESHES && (ref & TLAS_REF_INSTANCE) != 0u) {
                    if (traceInstance(ref & ~TLAS_REF_INSTANCE, rayO, rayD, anyHit, sp, hit)) {
                        found = true;
                        if (anyHit) return true;
                    }
                    continue;
                }
                float t;
                if (intersectPrimitiveT(ref, rayO, rayD, hit.t, t)) {
                    hit.t = t;
                    hit.ref = ref;
                    found = true;
                    if (anyHit) return true;
                }
            }
        }
        if (sp == 0) break;
        node = g_bvhStack[--sp];
        n = loadBvhNode(node);
    }
    return found;
}

#endif
