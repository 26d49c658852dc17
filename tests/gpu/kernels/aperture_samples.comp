#version 450 core
// Test kernel: the aperture image's sampler (integrator/aperture.glsl). inputs[i].xy = u;
// results[i] = (the point in [-1, 1]^2, its transmission, 0).
#include "integrator/camera.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
layout(std430, binding = 12) readonly buffer Inputs { vec4 inputs[]; };
uniform uint u_count;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    vec2 p = sampleApertureImage(inputs[i].xy);
    results[i] = vec4(p, apertureTransmission(p), 0.0);
}
