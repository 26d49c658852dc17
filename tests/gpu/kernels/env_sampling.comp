#version 450 core
// Test kernel for the environment light.
//   u_mode 0: results[i] = (direction sampled by sampleLight for the environment, its pdf)
//   u_mode 1: results[i].x = lightPdf of the environment for the direction through the centre of
//             cell i of the sampling table (row-major, (s width) x (s height) cells, s =
//             frame.envInfo.w cells per texel and axis), .y = sin(theta) there.
#include "lights/lights.glsl"
#include "lib/rng.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
uniform uint u_mode;
uniform uint u_light;
uniform uint u_count;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    if (u_mode == 0u) {
        uint rng = rngInit(i, 0u, 777u);
        LightSample s = sampleLight(u_light, vec3(0.0), rngNext2(rng));
        results[i] = vec4(s.wi, s.pdf);
    } else {
        uint w = frame.envInfo.y * frame.envInfo.w, h = frame.envInfo.z * frame.envInfo.w;
        vec2 uv = vec2((float(i % w) + 0.5) / float(w), (float(i / w) + 0.5) / float(h));
        vec3 d = envUvToDirection(uv);
        results[i] = vec4(lightPdf(u_light, vec3(0.0), d, vec3(0.0), vec3(0.0)), sin(PI * uv.y), 0.0, 0.0);
    }
}
