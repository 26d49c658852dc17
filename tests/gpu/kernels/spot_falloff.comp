#version 450 core
// Test kernel: the integrator's own spot light sample (sampleLight) at given shading points.
// In: results[i].xyz, a point. Out: results[i] = (Li.rgb, dist).
#include "lights/lights.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
uniform uint u_light;

void main() {
    uint i = gl_GlobalInvocationID.x;
    LightSample s = sampleLight(u_light, results[i].xyz, vec2(0.5));
    results[i] = vec4(s.Li, s.dist);
}
