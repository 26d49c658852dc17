#version 450 core
// Test kernel: traces the rays in `rays` (origin.xyz + tMax in w, direction.xyz) through the
// integrator's own scene traversal.
//   results[i] = (t or -1, top-level ref as float bits, original triangle id as float bits,
//                 1 if any-hit reports an occluder before tMax)
#include "geometry/intersect.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
layout(std430, binding = 12) readonly buffer Rays { vec4 rays[]; };
uniform uint u_count;
uniform uint u_bruteForce;  // 1: test every analytic primitive instead (the reference)

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    vec4 o = rays[2u * i], d = rays[2u * i + 1u];
    TraceHit th;
    bool hit;
    if (u_bruteForce != 0u) {
        th.t = o.w;
        hit = false;
        for (uint k = 0u; k < frame.counts.x; ++k) {
            float t;
            if (intersectPrimitiveT(k, o.xyz, d.xyz, th.t, t)) { th.t = t; th.ref = k; hit = true; }
        }
    } else {
        hit = traceScene(o.xyz, d.xyz, o.w, false, th);
    }
    TraceHit any;
    bool occluded = traceScene(o.xyz, d.xyz, o.w, true, any);
    uint triangleId = hit && (th.ref & TLAS_REF_INSTANCE) != 0u ? loadTriangle(th.triangle).v.w : 0xffffffffu;
    results[i] = vec4(hit ? th.t : -1.0, uintBitsToFloat(th.ref), uintBitsToFloat(triangleId), occluded ? 1.0 : 0.0);
}
