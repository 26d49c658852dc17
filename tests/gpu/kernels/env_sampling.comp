#version 450 core
// Test kernel for the environment light.
//   u_mode 0: results[i] = (direction sampled by sampleLight for the environment, its pdf)
//   u_mode 1: results[i].x = lightPdf of the environment for the direction through the centre of
//             cell i of the sampling table (row-major, (s width) x (s height) cells, s =
//             frame.envInfo.w cells per texel and axis), .y = sin(theta) there.
//   u_mode 2: results[i] holds (u, row, table) on entry (table 0: the row CDF, 1: the column CDF
//             of `row`); on exit .x = envFindInterval's index (the guided search), .y = the index
//             of a binary search over the whole CDF (the reference, written here).
#include "lights/lights.glsl"
#include "lib/rng.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
uniform uint u_mode;
uniform uint u_light;
uniform uint u_count;

uint wholeSearch(bool marginal, uint offset, uint n, float u) {
    uint lo = 0u, hi = n - 1u;
    while (lo < hi) {
        uint mid = (lo + hi + 1u) >> 1;
        float c = marginal ? envMarginalCdf(offset + mid) : envConditionalCdf(offset + mid);
        if (c <= u) lo = mid; else hi = mid - 1u;
    }
    return lo;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    if (u_mode == 2u) {
        uint w = frame.envInfo.y * frame.envInfo.w, h = frame.envInfo.z * frame.envInfo.w;
        float u = results[i].x;
        uint row = uint(results[i].y);
        bool marginal = results[i].z == 0.0;
        uint guided = marginal ? envFindInterval(true, 0u, frame.envGuide.x, frame.envGuide.z, u)
                               : envFindInterval(false, row * (w + 1u), frame.envGuide.y + row * ((1u << frame.envGuide.w) + 1u),
                                                 frame.envGuide.w, u);
        uint whole = marginal ? wholeSearch(true, 0u, h, u) : wholeSearch(false, row * (w + 1u), w, u);
        results[i] = vec4(float(guided), float(whole), 0.0, 0.0);
        return;
    }
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
