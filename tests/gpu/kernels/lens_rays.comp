#version 450 core
// Test kernel: the shader's lens-system camera rays (integrator/lens_camera.glsl) in the lens's
// frame. inputs[2i] = (film x, film y in mm, pupil sample u, v), inputs[2i + 1].x = channel.
//   results[2i]     = (ray origin in mm, weight; 0 where the lens blocks the ray)
//   results[2i + 1] = (ray direction, 1 where it passes)
#include "integrator/camera.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
layout(std430, binding = 12) readonly buffer Inputs { vec4 inputs[]; };
uniform uint u_count;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    vec4 a = inputs[2u * i];
    uint channel = uint(inputs[2u * i + 1u].x);
    vec3 o, d;
    float w;
    bool passes = lensRayFromFilm(a.xy, a.zw, channel, o, d, w);
    results[2u * i] = vec4(o, w);
    results[2u * i + 1u] = vec4(d, passes ? 1.0 : 0.0);
}
