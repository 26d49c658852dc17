#version 450 core
#extension GL_ARB_shader_ballot : require
#extension GL_ARB_gpu_shader_int64 : require
// The wavefront's shade kernel (integrator/wavefront.glsl says how the two kernels share a path
// step): one invocation per live slot of list u_listIn (u_start: every slot of the dispatch's
// tiles, whose first samples start here). It finishes the slot's path step with what the walk
// found, adds a finished sample to the film and starts the pixel's next one (frame.dispatch.x
// samples a dispatch, as path.comp), then tests the path's new rays against the top level's
// primitives and instance boxes, queues those that enter a box for the walk kernel and the slot
// for the next pass (list u_listOut).
#include "film.glsl"
#include "wavefront.glsl"

layout(local_size_x = WAVEFRONT_GROUP_SIZE) in;

uniform uint u_start;     // 1: the dispatch's first pass (slots 0 .. u_slots - 1)
uniform uint u_slots;
uniform uint u_listIn;    // 0 or 1: the list of live slots read (not with u_start)
uniform uint u_listOut;   // the other: the list written

void main() {
    uint index = gl_GlobalInvocationID.x;
    bool start = u_start != 0u;
    if (index >= (start ? u_slots : wavefrontListCount(u_listIn))) return;
    uint slot = start ? index : wavefrontListEntry(u_listIn, index);
    // The slot's pixel, as path.comp's work group of its tile would have it (see there).
    uint tile = frame.dispatch.z + slot / 64u;
    uvec2 cropSize = uvec2(imageSize(accumImage));
    uint tilesX = (cropSize.x + 7u) / 8u;
    uvec2 local = uvec2(tile % tilesX, tile / tilesX) * 8u + uvec2(slot % 8u, (slot / 8u) % 8u);
    if (start && (tile >= frame.dispatch.w || local.x >= cropSize.x || local.y >= cropSize.y ||
                  frame.dispatch.x == 0u))
        return;
    uvec2 pixel = local + frame.options.yz;
    uint pixelIndex = pixel.y * frame.image.x + pixel.x;

    PathState st;
    Sampler smp;
    if (start) {
        st = pathBegin(sampleCameraRay(pixel, pixelIndex, 0u, smp));
    } else {
        wavefrontLoad(slot, st, smp);
        TraceHit th = wavefrontLoadHit(slot);
        if (pathResolve(st, smp, th.ref != 0xffffffffu, th, wavefrontLoadOccluded(slot))) {
            ivec2 ip = ivec2(local);
            PixelSums px = loadPixelSums(ip);
            addSample(px, st.L, st.aov);
            storePixelSums(ip, px);
            uint s = smp.index - frame.image.z + 1u;
            if (s >= frame.dispatch.x) return;  // the pixel's samples are done
            st = pathBegin(sampleCameraRay(pixel, pixelIndex, s, smp));
        }
    }

    // The step's rays against the top level; those that enter an instance's box go to the walk.
    uint rays = pathStepRays(st);
    TraceHit h;
    uint candidates = 0u;
    if (!st.ended) traceBakedTopLevel(st.ray.o, st.ray.d, FLT_MAX, h, candidates);
    else h.ref = 0xffffffffu;
    bool occluded = false;
    uint shadowCandidates = 0u;
    if (st.shadowPending) {
        TraceHit hs;
        occluded = traceBakedTopLevel(st.shadowRay.o, st.shadowRay.d, st.shadowTMax, hs, shadowCandidates);
        if (occluded) shadowCandidates = 0u;
    }
    wavefrontStore(slot, st, smp);
    wavefrontStoreHit(slot, h);
    wavefrontStoreOccluded(slot, occluded);
    wavefrontAppend(WAVEFRONT_WALK_LIST, 2u * slot, candidates != 0u);
    wavefrontAppend(WAVEFRONT_WALK_LIST, 2u * slot + 1u, shadowCandidates != 0u);
    wavefrontAppend(u_listOut, slot, true);
    // The rays traced for this step (countRays, once per subgroup).
    uint total;
    subgroupPrefixSum(rays, total);
    if (subgroupLeader()) countRays(total);
}
