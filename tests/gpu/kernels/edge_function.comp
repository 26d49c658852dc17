#version 450 core
// Test kernel for the triangle test's edge functions (geometry/bvh.glsl, edgeFunction):
// results[i].x = a b - c d for inputs[i] = (a, b, c, d).
#include "geometry/intersect.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
layout(std430, binding = 12) readonly buffer Inputs { vec4 inputs[]; };
uniform uint u_count;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    vec4 q = inputs[i];
    results[i] = vec4(edgeFunction(q.x, q.y, q.z, q.w), 0.0, 0.0, 0.0);
}
