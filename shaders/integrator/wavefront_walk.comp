#version 450 core
#extension GL_ARB_shader_ballot : require
#extension GL_ARB_gpu_shader_int64 : require
// The wavefront's walk kernel (integrator/wavefront.glsl): one invocation per queued ray (entry
// 2 * slot + kind: the continuation ray, or the shadow ray), every one of which enters some
// instance's root box before its nearest primitive hit. Walks those instances' trees
// (traceBakedInstances, nearest first) and overwrites the slot's result with a nearer hit: the
// continuation ray's closest hit, or the shadow ray's occlusion.
#include "wavefront.glsl"

layout(local_size_x = WAVEFRONT_GROUP_SIZE) in;

void main() {
    uint index = gl_GlobalInvocationID.x;
    if (index >= wavefrontListCount(WAVEFRONT_WALK_LIST)) return;
    uint entry = wavefrontListEntry(WAVEFRONT_WALK_LIST, index);
    uint slot = entry >> 1;
    bool shadow = (entry & 1u) != 0u;
    vec3 o, d;
    float shadowTMax;
    wavefrontLoadRay(entry, o, d, shadowTMax);
    TraceHit h;
    if (shadow) {
        h.t = shadowTMax;
        h.ref = 0xffffffffu;
        h.triangle = 0u;
        h.bary = vec2(0.0);
    } else {
        h = wavefrontLoadHit(slot);
    }
    if (!traceBakedInstances(o, d, shadow, h)) return;
    if (shadow) wavefrontStoreOccluded(slot, true);
    else wavefrontStoreHit(slot, h);
}
