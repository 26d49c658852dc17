// The wavefront integrator (llvmpipe, scenes with a baked top level and meshes): the megakernel's
// path step (integrator/path.glsl) cut at its trace, into two kernels over queues (after Laine,
// Karras and Aila 2013, "Megakernels Considered Harmful: Wavefront Path Tracing on GPUs"):
//   wavefront_shade.comp, one invocation per live path slot: finishes the step its rays' walk
//     ended (pathResolve: the shadow ray's radiance, the hit's shading, the next rays), adds a
//     finished sample to the film and starts the pixel's next one, tests the new rays against the
//     baked top level's primitives and instance root boxes (traceBakedTopLevel), and queues for
//     the walk kernel only the rays that enter an instance's box before their nearest primitive;
//   wavefront_walk.comp, one invocation per queued ray: walks the instances' trees
//     (traceBakedInstances) and keeps a nearer hit.
// Why (docs/performance.md, session 11): llvmpipe runs 8 invocations as SIMD lanes and runs every
// loop until its last lane is done, so in the megakernel a pass cost every lane the whole step,
// and the tree walk ran with about 2 of 8 lanes busy (the others had no mesh to walk or waited).
// Here every lane of a walk holds a ray that meets a mesh, and the shading kernel has no walk.
//
// A slot is one pixel of the dispatch's tiles (slot = 64 * tile index + pixel in the 8x8 tile,
// as path.comp's work groups), carrying its pixel's samples one after another in the order
// path.comp's regenerating loop does: each sample has the same random numbers and is summed
// into the same film in the same order, so the image is the megakernel's bit for bit.
//
// Memory: the path state (PathState and Sampler, WAVEFRONT_STATE_TEXELS texels of 4 words) and
// the walk's results (WAVEFRONT_HIT_TEXELS) in buffer images; the two lists of live slots (one
// read, one written: a kernel's output is the next's input) and the walk queue in one r32ui
// buffer image; their counts and indirect dispatch sizes in a storage buffer. On llvmpipe an
// image load or store is a gather or scatter of the 8 lanes, where a storage-buffer access is a
// loop over the lanes (session 10's measurement).
#ifndef INTEGRATOR_WAVEFRONT_GLSL
#define INTEGRATOR_WAVEFRONT_GLSL
// (The kernels enable GL_ARB_shader_ballot and GL_ARB_gpu_shader_int64, after #version.)
#include "path.glsl"

layout(rgba32ui, binding = BINDING_WAVEFRONT_STATE_IMAGE) uniform uimageBuffer wavefrontState;
layout(rgba32ui, binding = BINDING_WAVEFRONT_HITS_IMAGE) uniform uimageBuffer wavefrontHits;
layout(r32ui, binding = BINDING_WAVEFRONT_LISTS_IMAGE) uniform uimageBuffer wavefrontLists;
// Per list l (0 and 1: slot lists, WAVEFRONT_WALK_LIST: the walk queue): words 4l..4l+2 are the
// indirect dispatch (work groups, 1, 1) that runs it, word 4l+3 its entry count.
layout(std430, binding = BINDING_WAVEFRONT_COUNTS) buffer WavefrontCounts { uint wavefrontCounts[]; };

// Where each list starts in wavefrontLists (in entries).
uniform uint u_listBase[3];

// Subgroups (GL_ARB_shader_ballot: on llvmpipe the 8 lanes of a 256-bit vector). On llvmpipe an
// atomic is a loop over the 8 lanes, each an atomic instruction on a word that both of its
// threads update; the kernels add a subgroup's shares in one atomic of an elected lane instead.

// The exclusive prefix sum of the running lanes' n (each below 8) in lane order, and their total.
uint subgroupPrefixSum(uint n, out uint total) {
    uint below = 0u;
    total = 0u;
    for (uint bit = 0u; bit < 3u; ++bit) {
        uvec2 m = unpackUint2x32(ballotARB(((n >> bit) & 1u) != 0u));
        uvec2 lt = m & unpackUint2x32(gl_SubGroupLtMaskARB);
        below += uint(bitCount(lt.x) + bitCount(lt.y)) << bit;
        total += uint(bitCount(m.x) + bitCount(m.y)) << bit;
    }
    return below;
}

// The first running lane of the subgroup, which makes the subgroup's atomic.
bool subgroupLeader() { return gl_SubGroupInvocationARB == readFirstInvocationARB(gl_SubGroupInvocationARB); }

// Appends `value` to list l where `want` holds (call it with every lane of the subgroup that is
// still running): the list's count grows by the subgroup's appends, its dispatch to as many work
// groups as cover the count.
void wavefrontAppend(uint l, uint value, bool want) {
    uint total;
    uint below = subgroupPrefixSum(want ? 1u : 0u, total);
    uint base = 0u;
    if (subgroupLeader() && total > 0u) {
        base = atomicAdd(wavefrontCounts[4u * l + 3u], total);
        atomicMax(wavefrontCounts[4u * l], (base + total + WAVEFRONT_GROUP_SIZE - 1u) / WAVEFRONT_GROUP_SIZE);
    }
    base = readFirstInvocationARB(base);
    if (want) imageStore(wavefrontLists, int(u_listBase[l] + base + below), uvec4(value));
}

uint wavefrontListCount(uint l) { return wavefrontCounts[4u * l + 3u]; }
uint wavefrontListEntry(uint l, uint i) { return imageLoad(wavefrontLists, int(u_listBase[l] + i)).x; }

// The state's texels (4 words each): 0 and 1 the continuation ray (o, emitScale; d, flags),
// 2 and 3 the shadow ray (o, its tMax; d, prevBsdfPdf), so that the walk kernel reads a ray in
// two texels; then the rest of PathState and the Sampler.
#define WF_F(v) floatBitsToUint(v)
void wavefrontStore(uint slot, PathState st, Sampler smp) {
    int b = int(slot * WAVEFRONT_STATE_TEXELS);
    uint flags = (st.countEmitted ? 1u : 0u) | (st.prevTwoSided ? 2u : 0u) | (st.probing ? 4u : 0u) |
                 (st.pendingEnds ? 8u : 0u) | (st.aovDone ? 16u : 0u) | (st.shadowPending ? 32u : 0u) |
                 (st.ended ? 64u : 0u) | (st.bounces << 8);
    imageStore(wavefrontState, b + 0, uvec4(WF_F(st.ray.o), WF_F(st.emitScale)));
    imageStore(wavefrontState, b + 1, uvec4(WF_F(st.ray.d), flags));
    imageStore(wavefrontState, b + 2, uvec4(WF_F(st.shadowRay.o), WF_F(st.shadowTMax)));
    imageStore(wavefrontState, b + 3, uvec4(WF_F(st.shadowRay.d), WF_F(st.prevBsdfPdf)));
    imageStore(wavefrontState, b + 4, uvec4(WF_F(st.L), WF_F(st.etaScale)));
    imageStore(wavefrontState, b + 5, uvec4(WF_F(st.beta), WF_F(st.pathLength)));
    imageStore(wavefrontState, b + 6, uvec4(WF_F(st.prevP), smp.index));
    imageStore(wavefrontState, b + 7, uvec4(WF_F(st.prevN), smp.pixelSeed));
    imageStore(wavefrontState, b + 8, uvec4(WF_F(st.shadowL), smp.rng));
    imageStore(wavefrontState, b + 9, uvec4(WF_F(st.aov.albedo), smp.type));
    imageStore(wavefrontState, b + 10, uvec4(WF_F(st.aov.normal), 0u));
    // Glass splitting's probe: only a scene with smooth glass has one.
    if (HAS_MATERIAL(MAT_DIELECTRIC)) {
        imageStore(wavefrontState, b + 11, uvec4(WF_F(st.probeBeta), 0u));
        imageStore(wavefrontState, b + 12, uvec4(WF_F(st.pending.o), 0u));
        imageStore(wavefrontState, b + 13, uvec4(WF_F(st.pending.d), 0u));
    }
}
#undef WF_F

void wavefrontLoad(uint slot, out PathState st, out Sampler smp) {
    int b = int(slot * WAVEFRONT_STATE_TEXELS);
    uvec4 t0 = imageLoad(wavefrontState, b + 0), t1 = imageLoad(wavefrontState, b + 1);
    uvec4 t2 = imageLoad(wavefrontState, b + 2), t3 = imageLoad(wavefrontState, b + 3);
    uvec4 t4 = imageLoad(wavefrontState, b + 4), t5 = imageLoad(wavefrontState, b + 5);
    uvec4 t6 = imageLoad(wavefrontState, b + 6), t7 = imageLoad(wavefrontState, b + 7);
    uvec4 t8 = imageLoad(wavefrontState, b + 8), t9 = imageLoad(wavefrontState, b + 9);
    uvec4 t10 = imageLoad(wavefrontState, b + 10);
    st.ray.o = uintBitsToFloat(t0.xyz);
    st.emitScale = uintBitsToFloat(t0.w);
    st.ray.d = uintBitsToFloat(t1.xyz);
    uint flags = t1.w;
    st.countEmitted = (flags & 1u) != 0u;
    st.prevTwoSided = (flags & 2u) != 0u;
    st.probing = (flags & 4u) != 0u;
    st.pendingEnds = (flags & 8u) != 0u;
    st.aovDone = (flags & 16u) != 0u;
    st.shadowPending = (flags & 32u) != 0u;
    st.ended = (flags & 64u) != 0u;
    st.bounces = flags >> 8;
    st.shadowRay.o = uintBitsToFloat(t2.xyz);
    st.shadowTMax = uintBitsToFloat(t2.w);
    st.shadowRay.d = uintBitsToFloat(t3.xyz);
    st.prevBsdfPdf = uintBitsToFloat(t3.w);
    st.L = uintBitsToFloat(t4.xyz);
    st.etaScale = uintBitsToFloat(t4.w);
    st.beta = uintBitsToFloat(t5.xyz);
    st.pathLength = uintBitsToFloat(t5.w);
    st.prevP = uintBitsToFloat(t6.xyz);
    smp.index = t6.w;
    st.prevN = uintBitsToFloat(t7.xyz);
    smp.pixelSeed = t7.w;
    st.shadowL = uintBitsToFloat(t8.xyz);
    smp.rng = t8.w;
    st.aov.albedo = uintBitsToFloat(t9.xyz);
    smp.type = t9.w;
    st.aov.normal = uintBitsToFloat(t10.xyz);
    st.probeBeta = vec3(0.0);
    st.pending = st.ray;
    if (HAS_MATERIAL(MAT_DIELECTRIC)) {
        st.probeBeta = uintBitsToFloat(imageLoad(wavefrontState, b + 11).xyz);
        st.pending.o = uintBitsToFloat(imageLoad(wavefrontState, b + 12).xyz);
        st.pending.d = uintBitsToFloat(imageLoad(wavefrontState, b + 13).xyz);
    }
}

// A queued ray (entry = 2 * slot + kind; kind 0 the continuation ray, 1 the shadow ray) as the
// walk kernel reads it; for a shadow ray w is its tMax.
void wavefrontLoadRay(uint entry, out vec3 o, out vec3 d, out float w) {
    int b = int((entry >> 1) * WAVEFRONT_STATE_TEXELS + 2u * (entry & 1u));
    uvec4 t0 = imageLoad(wavefrontState, b);
    o = uintBitsToFloat(t0.xyz);
    w = uintBitsToFloat(t0.w);
    d = uintBitsToFloat(imageLoad(wavefrontState, b + 1).xyz);
}

// The walk's results per slot: texel 0 the continuation ray's nearest hit (t, ref, triangle; ref
// ~0u for none), texel 1 its barycentrics, texel 2 whether the shadow ray is occluded. The shade
// kernel writes what the top level found; the walk kernel overwrites what it finds nearer.
void wavefrontStoreHit(uint slot, TraceHit h) {
    int b = int(slot * WAVEFRONT_HIT_TEXELS);
    imageStore(wavefrontHits, b, uvec4(floatBitsToUint(h.t), h.ref, h.triangle, 0u));
    imageStore(wavefrontHits, b + 1, uvec4(floatBitsToUint(h.bary), 0u, 0u));
}

TraceHit wavefrontLoadHit(uint slot) {
    int b = int(slot * WAVEFRONT_HIT_TEXELS);
    uvec4 h0 = imageLoad(wavefrontHits, b);
    TraceHit h;
    h.t = uintBitsToFloat(h0.x);
    h.ref = h0.y;
    h.triangle = h0.z;
    h.bary = uintBitsToFloat(imageLoad(wavefrontHits, b + 1).xy);
    return h;
}

void wavefrontStoreOccluded(uint slot, bool occluded) {
    imageStore(wavefrontHits, int(slot * WAVEFRONT_HIT_TEXELS + 2u), uvec4(occluded ? 1u : 0u));
}

bool wavefrontLoadOccluded(uint slot) {
    return imageLoad(wavefrontHits, int(slot * WAVEFRONT_HIT_TEXELS + 2u)).x != 0u;
}

#endif
