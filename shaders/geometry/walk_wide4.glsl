// A mesh's own BVH in its 4-wide form (renderer/bvh.h, collapseBvh4 and quantizeWideNode;
// GpuWideBvhNode in shared/layout.h), walked with the newest pending entries held in variables:
// llvmpipe's walk (renderer/integrator_config.h chooses it; it reads the nodes through buffer
// textures, so it needs CAUSTIC_FETCH_TEXELS). Half as many steps as the binary tree's, each
// testing four boxes at once; docs/performance.md, "What bounds speed on llvmpipe", has the figures.
// Included by geometry/bvh.glsl, which declares what it uses (slabTests, traceLeafTriangles,
// g_bvhStack, WALK_STATS_*).
#ifndef GEOMETRY_WALK_WIDE4_GLSL
#define GEOMETRY_WALK_WIDE4_GLSL

// One step through a 4-wide node (GpuWideBvhNode): its four children's boxes slab-tested at once
// (the same test as slabTest, by coordinate over vec4s), the nearest child hit becomes `ref`; the
// others hit, farthest first, are the last `nFar` of (far.x, far.y, far.z), for the caller to push
// in that order. False when none is hit.
bool wideDescend(inout uint ref, vec3 o, vec3 invD, float tMax, out uvec3 far, out int nFar) {
    // The node's four texels (GpuWideBvhNode), its boxes decoded from bytes: bound = origin +
    // q * scale, exact product, so the decoded box is the one renderer/bvh_wide.cpp checked contains
    // the child's.
    uint t0 = GPU_ROW_COUNT(GPU_WIDE_BVH_NODE_ROWS) * ref;
    uvec4 head = FETCH_U4(wideNodeTexels, t0), qXY = FETCH_U4(wideNodeTexels, t0 + 1u);
    uvec2 qZ = FETCH_U4(wideNodeTexels, t0 + 2u).xy;
    uvec4 child = FETCH_U4(wideNodeTexels, t0 + 3u);
    vec3 origin = uintBitsToFloat(head.xyz);
    vec3 scale = uintBitsToFloat(((uvec3(head.w) >> uvec3(0u, 8u, 16u)) & 0xffu) << 23u);
#define WIDE_BYTES(w) vec4((uvec4(w) >> uvec4(0u, 8u, 16u, 24u)) & 0xffu)
    vec4 minX = origin.x + WIDE_BYTES(qXY.x) * scale.x, maxX = origin.x + WIDE_BYTES(qXY.y) * scale.x;
    vec4 minY = origin.y + WIDE_BYTES(qXY.z) * scale.y, maxY = origin.y + WIDE_BYTES(qXY.w) * scale.y;
    vec4 minZ = origin.z + WIDE_BYTES(qZ.x) * scale.z, maxZ = origin.z + WIDE_BYTES(qZ.y) * scale.z;
#undef WIDE_BYTES
    vec4 tn;
    bvec4 h = slabTests(minX, maxX, minY, maxY, minZ, maxZ, o, invD, tMax, tn);
    // Entry distances of the children hit (+inf for the others), sorted with their references by
    // a 5-comparator network: (0 1) (2 3) (0 2) (1 3) (1 2).
    vec4 key = mix(vec4(uintBitsToFloat(0x7f800000u)), tn, h);
    uvec4 c = child;
#define WIDE_SORT2(i, j) \
    if (key[j] < key[i]) { float tk = key[i]; key[i] = key[j]; key[j] = tk; uint tc = c[i]; c[i] = c[j]; c[j] = tc; }
    WIDE_SORT2(0, 1) WIDE_SORT2(2, 3) WIDE_SORT2(0, 2) WIDE_SORT2(1, 3) WIDE_SORT2(1, 2)
#undef WIDE_SORT2
    far = c.wzy;
    nFar = (isinf(key.y) ? 0 : 1) + (isinf(key.z) ? 0 : 1) + (isinf(key.w) ? 0 : 1);
    if (isinf(key.x)) return false;
    ref = c.x;
    return true;
}

// The register stack (CAUSTIC_REGISTER_STACK = K, at least 1): the walk's K newest pending
// entries in its variables s[0..K-1] (s[0] the newest, `held` of them), the older ones on the
// memory stack above `base`, which holds entries only while s is full. On llvmpipe every push and
// pop of the memory stack is a per-lane store or load, a variable is a register. Macros over the
// walk's own variables: the same code as a function taking the stack `inout` is 0.65-0.76x as fast
// on llvmpipe (docs/performance.md, "Ideas tried and not kept").
#ifndef CAUSTIC_REGISTER_STACK
#define CAUSTIC_REGISTER_STACK 2
#endif
#define REGISTER_STACK_DECLARE()                                                                \
    const int K = CAUSTIC_REGISTER_STACK;                                                       \
    uint s[K];                                                                                  \
    for (int i = 0; i < K; ++i) s[i] = 0u;                                                      \
    int held = 0;
#define REGISTER_STACK_PUSH(value)                                                              \
    {                                                                                           \
        if (held == K) {                                                                        \
            if (sp < BVH_STACK_SIZE) g_bvhStack[sp++] = s[K - 1];                               \
        } else {                                                                                \
            ++held;                                                                             \
        }                                                                                       \
        for (int i = K - 1; i > 0; --i) s[i] = s[i - 1];                                        \
        s[0] = (value);                                                                         \
    }
// The newest entry into `dest`, or out of the walk's loop when there is none.
#define REGISTER_STACK_POP(dest)                                                                \
    if (held == 0) break;                                                                       \
    dest = s[0];                                                                                \
    for (int i = 0; i < K - 1; ++i) s[i] = s[i + 1];                                            \
    if (sp > base) {                                                                            \
        s[K - 1] = g_bvhStack[--sp];                                                            \
    } else {                                                                                    \
        --held;                                                                                 \
    }

// The instance's tree below its root, whose box the ray (o, d in object space) is known to hit;
// entries beyond the register stack go on the memory stack above `base`, which it leaves as it
// found it. One loop: a node's step or a leaf's triangles per iteration.
bool traceInstanceTree(GpuInstance inst, uint instance, vec3 o, vec3 d, vec3 invD, bool anyHit, int base,
                       inout TraceHit hit) {
    WALK_STATS_TREE()
    WatertightRay wr = makeWatertightRay(o, d);
    uint firstTriangle = inst.firstTriangle;
    int sp = base;
    bool found = false;
    uint ref = inst.wideRoot;
    uvec3 far;
    int nFar;
    REGISTER_STACK_DECLARE()
    while (true) {
        WALK_STATS_STEP()
        if ((ref & WIDE_CHILD_LEAF) == 0u) {
            bool descends = wideDescend(ref, o, invD, hit.t, far, nFar);
            if (nFar >= 3) REGISTER_STACK_PUSH(far.x)
            if (nFar >= 2) REGISTER_STACK_PUSH(far.y)
            if (nFar >= 1) REGISTER_STACK_PUSH(far.z)
            if (descends) continue;
        } else if (traceLeafTriangles(wr, inst, instance, firstTriangle, LEAF_FIRST(ref), LEAF_COUNT(ref),
                                      anyHit, hit)) {
            found = true;
            if (anyHit) return true;
        }
        REGISTER_STACK_POP(ref)
    }
    return found;
}

#endif
