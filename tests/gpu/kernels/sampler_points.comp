#version 450 core
// Test kernel for the integrator's sampler (lib/sampler.glsl): results[i] for i in [0, u_count)
// is (sample2D, sample1D) of sample index u_first + i of pixel u_pixel in dimension slot u_slot.
// With u_perPixel != 0 the invocations walk pixels instead: pixel u_pixel + i, sample u_first.
#include "lib/sampler.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
uniform uint u_count;
uniform uint u_pixel;
uniform uint u_first;
uniform uint u_slot;
uniform uint u_seed;
uniform uint u_type;
uniform uint u_perPixel;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    uint pixel = u_perPixel != 0u ? u_pixel + i : u_pixel;
    uint index = u_perPixel != 0u ? u_first : u_first + i;
    Sampler s = samplerStart(u_type, pixel, index, u_seed);
    vec2 a = sample2D(s, u_slot);
    float b = sample1D(s, u_slot);
    results[i] = vec4(a, b, 0.0);
}
