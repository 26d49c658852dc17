#version 450 core
// Test kernel: the integrator's own camera rays (integrator/camera.glsl), traced through the
// scene. inputs[i] = (pixel x, pixel y, lens sample u, v); the pixel filter's sample is (0.5, 0.5),
// the pixel's centre under the box filter.
//   results[2i]     = (ray origin, t of the closest hit or -1)
//   results[2i + 1] = (ray direction, 0)
#include "integrator/camera.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
layout(std430, binding = 12) readonly buffer Inputs { vec4 inputs[]; };
uniform uint u_count;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    vec4 in_ = inputs[i];
    Ray r = cameraRay(uvec2(in_.xy), vec2(0.5), in_.zw);
    Hit hit;
    bool found = sceneIntersect(r, FLT_MAX, hit);
    results[2u * i] = vec4(r.o, found ? hit.t : -1.0);
    results[2u * i + 1u] = vec4(r.d, 0.0);
}
