// Baked geometry (CAUSTIC_BAKED_PRIMITIVES, CAUSTIC_BAKED_TOP_LEVEL: renderer_programs.cpp,
// bakedPrimitiveTests and bakedInstanceTests): the record tests of a few analytic primitives and
// mesh instances as constants of the scene's program, and the walk of two rays through a baked
// top level. Included by geometry/bvh.glsl before traceScene, which expands them.
#ifndef GEOMETRY_TRACE_BAKED_GLSL
#define GEOMETRY_TRACE_BAKED_GLSL

#if defined(CAUSTIC_BAKED_PRIMITIVES) || defined(CAUSTIC_BAKED_TOP_LEVEL)
// Baked geometry (renderer_programs.cpp, bakedPrimitiveTests): the renderer's define expands to one of these
// per primitive or instance, each record's words as literals, inside traceScene or traceScenePair
// (they use its bakedRay, rayO, rayD, anyHit, hit and found). The tests are the loop's and the walk's own.
#define BAKED_PRIMITIVE(kind, ra, rb, rc, index) BAKED_PRIMITIVE_TEST(kind, ra, rb, rc, index)
#define BAKED_PRIMITIVE_TEST(kind, ra, rb, rc, index) {                                         \
            GpuPrimitive rec;                                                                 \
            rec.a = uintBitsToFloat(ra);                                                      \
            rec.b = uintBitsToFloat(rb);                                                      \
            rec.c = uintBitsToFloat(rc);                                                      \
            rec.info = uvec4(kind, 0u, 0u, 0u);                                               \
            float t;                                                                          \
            if ((kind) == PRIM_SPHERE ? intersectSphere(rec, bakedRay, hit.t, t)              \
                                      : intersectQuadPlane(rec, bakedRay, hit.t, t)) {        \
                hit.t = t;                                                                    \
                hit.ref = index;                                                              \
                found = true;                                                                 \
                if (anyHit) return true;                                                      \
            }                                                                                 \
        }
// A baked instance (CAUSTIC_BAKED_TOP_LEVEL), expanded by traceScenePair with these meanings in
// turn: BAKED_INSTANCE_SCAN tests a ray against the instance's root box (its last two rows, object
// space) and makes it a candidate (bit index + shift); PAIR_PICK finds the nearest candidate;
// BAKED_INSTANCE_SELECT makes `inst` that candidate's record.
#define BAKED_INSTANCE_SCAN(index, w0, w1, w2, o0, o1, o2, i1, i2, i3, bmin, bmax) {             \
            vec3 bo = vec3(dot(uintBitsToFloat(w0), vec4(rayO, 1.0)), dot(uintBitsToFloat(w1), vec4(rayO, 1.0)), \
                           dot(uintBitsToFloat(w2), vec4(rayO, 1.0)));                        \
            vec3 bd = vec3(dot(uintBitsToFloat(w0).xyz, rayD), dot(uintBitsToFloat(w1).xyz, rayD), \
                           dot(uintBitsToFloat(w2).xyz, rayD));                               \
            GpuBvhNode root;                                                                  \
            root.boundsMin = uintBitsToFloat(bmin).xyz;                                       \
            root.boundsMax = uintBitsToFloat(bmax).xyz;                                       \
            float te;                                                                         \
            if (slabTest(root, bo, safeInverse(bd), hit.t, te)) {                             \
                candidates |= 1u << ((index) + shift);                                        \
                enter[(index) + shift] = te;                                                  \
            }                                                                                 \
        }
#define BAKED_INSTANCE_SELECT(index, w0, w1, w2, o0, o1, o2, i1, i2, i3, bmin, bmax)            \
        if (pick == (index)) {                                                                \
            inst.worldToObject0 = uintBitsToFloat(w0);                                        \
            inst.worldToObject1 = uintBitsToFloat(w1);                                        \
            inst.worldToObject2 = uintBitsToFloat(w2);                                        \
            inst.objectToWorld0 = uintBitsToFloat(o0);                                        \
            inst.objectToWorld1 = uintBitsToFloat(o1);                                        \
            inst.objectToWorld2 = uintBitsToFloat(o2);                                        \
            inst.rootNode = i1.x;                                                             \
            inst.firstTriangle = i1.y;                                                        \
            inst.material = i1.z;                                                             \
            inst.light = i1.w;                                                                \
            inst.firstVertex = i2.x;                                                          \
            inst.triangleCount = i2.y;                                                        \
            inst.fileMaterials = i2.z;                                                        \
            inst.flags = i2.w;                                                                \
            inst.wideRoot = i3.x;                                                             \
            inst.unused0 = i3.y;                                                              \
            inst.unused1 = i3.z;                                                              \
            inst.unused2 = i3.w;                                                              \
        }
#endif

#if defined(CAUSTIC_BAKED_TOP_LEVEL) && HAS_MESHES
// Two rays in one walk of a baked top level (at most 16 instances; renderer_programs.cpp): a path step's
// continuation and shadow rays (integrator/path.glsl, CAUSTIC_PAIRED_TRACE), or traceScene's one
// ray as either. Ray 0 is traced for its closest hit below tMax0 (the return value, and hit0), ray
// 1 (a shadow ray) for any hit below tMax1 (occluded1); either may be absent (want0, want1). Each
// ray's primitives are tested, the instances whose root box it meets become candidates (bit k for
// ray 0, bit 16 + k for ray 1), and one loop walks every candidate, nearest entry first, through
// one copy of the tree walk. Where the two rays were walked one after the other, each paid a pass
// of the walk's loops on llvmpipe even when none of its lanes met a mesh, and a lane walking its
// shadow ray waited for the lanes walking their continuation rays; here lanes walk either in the
// same pass. Each ray meets its own candidates in its own nearest-first order, so ray 0's hit is
// what walking it alone finds.
#define PAIR_PICK(index, w0, w1, w2, o0, o1, o2, i1, i2, i3, bmin, bmax)                        \
        if ((candidates & (1u << (index))) != 0u && enter[index] < pickT) {                  \
            pickT = enter[index];                                                             \
            pick = index;                                                                     \
        }                                                                                     \
        if ((candidates & (1u << (index + 16u))) != 0u && enter[index + 16u] < pickT) {      \
            pickT = enter[index + 16u];                                                       \
            pick = index + 16u;                                                               \
        }
bool traceScenePair(bool want0, vec3 o0, vec3 d0, float tMax0, bool want1, vec3 o1, vec3 d1, float tMax1,
                    out TraceHit hit0, out bool occluded1) {
    bool found0;
    TraceHit h0, h1;
    h0.t = tMax0;
    h1.t = tMax1;
    h0.ref = h1.ref = 0xffffffffu;
    h0.triangle = h1.triangle = 0u;
    h0.bary = h1.bary = vec2(0.0);
    found0 = false;
    occluded1 = false;
    uint candidates = 0u;
    float enter[32];
    // Each ray's primitives and root boxes: the single ray's tests (BAKED_PRIMITIVE,
    // BAKED_INSTANCE_SCAN); `anyHit` false for both, so that the primitive test's early return
    // is compiled out (a primitive that occludes the shadow ray just ends as a hit).
    const bool anyHit = false;
#undef BAKED_PRIMITIVE
#define BAKED_PRIMITIVE BAKED_PRIMITIVE_TEST
#define BAKED_INSTANCE BAKED_INSTANCE_SCAN
    if (want0) {
        vec3 rayO = o0, rayD = d0;
        Ray bakedRay;
        bakedRay.o = rayO;
        bakedRay.d = rayD;
        TraceHit hit = h0;
        bool found = false;
        const uint shift = 0u;
        CAUSTIC_BAKED_TOP_LEVEL
        h0 = hit;
        found0 = found;
    }
    if (want1) {
        vec3 rayO = o1, rayD = d1;
        Ray bakedRay;
        bakedRay.o = rayO;
        bakedRay.d = rayD;
        TraceHit hit = h1;
        bool found = false;
        const uint shift = 16u;
        CAUSTIC_BAKED_TOP_LEVEL
        occluded1 = found;
        if (found) candidates &= 0xffffu;  // occluded by a primitive: no mesh needs walking
    }
#undef BAKED_PRIMITIVE
#undef BAKED_INSTANCE
#define BAKED_PRIMITIVE(kind, ra, rb, rc, index)
    while (candidates != 0u) {
        float pickT = uintBitsToFloat(0x7f800000u);
        uint pick = 0u;
#define BAKED_INSTANCE PAIR_PICK
        CAUSTIC_BAKED_TOP_LEVEL
#undef BAKED_INSTANCE
        candidates &= ~(1u << pick);
        bool shadow = pick >= 16u;
        uint k = pick & 15u;
        TraceHit th = shadow ? h1 : h0;
        // The rest of this ray's candidates start no nearer (the root box test's own rule).
        if (!(pickT <= th.t)) {
            candidates &= shadow ? 0xffffu : 0xffff0000u;
            continue;
        }
        GpuInstance inst;
        pick = k;
#define BAKED_INSTANCE BAKED_INSTANCE_SELECT
        CAUSTIC_BAKED_TOP_LEVEL
#undef BAKED_INSTANCE
        vec3 o, d;
        rayToObject(inst, shadow ? o1 : o0, shadow ? d1 : d0, o, d);
        bool met = traceInstanceTree(inst, k, o, d, safeInverse(d), shadow, 0, th);
        if (shadow) {
            h1 = th;
            if (met) {
                occluded1 = true;
                candidates &= 0xffffu;
            }
        } else {
            h0 = th;
            found0 = found0 || met;
        }
    }
#undef BAKED_PRIMITIVE
    hit0 = h0;
    return found0;
}
#endif

#endif
