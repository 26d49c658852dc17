#version 450 core
// Test kernel for the media (integrator/medium.glsl, the integrator's own file):
//   u_mode 0 (phase sampling): invocation i samples hgSample(+z, u_g) from random numbers of
//     stream i: results[2i] = (wi, pdf), results[2i+1] = (hgPhase(wi.z, u_g), 0, 0, 0).
//   u_mode 1 (phase integral): invocation i integrates hgPhase(cos theta, u_g) sin theta over cell i
//     of u_rows theta bins on [0, pi] by u_cols phi bins on [0, 2 pi), midpoint rule on u_sub x
//     u_sub points: results[i].x.
//   u_mode 2 (free flight): invocation i runs mediumSampleDistance for the medium (u_sigmaA,
//     u_sigmaS), a segment of length u_tMax and throughput u_beta, with the independent sampler
//     of pixel i: results[2i] = (weight, 1 if it scattered else 0), results[2i+1] = (t, 0, 0, 0).
#include "integrator/medium.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
uniform uint u_mode;
uniform uint u_count;
uniform uint u_seed;
uniform uint u_rows;
uniform uint u_cols;
uniform uint u_sub;
uniform float u_g;
uniform vec3 u_sigmaA;
uniform vec3 u_sigmaS;
uniform vec3 u_beta;
uniform float u_tMax;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    if (u_mode == 0u) {
        uint rng = rngInit(i, 0u, u_seed);
        float pdf;
        vec3 wi = hgSample(vec3(0.0, 0.0, 1.0), u_g, rngNext2(rng), pdf);
        results[2u * i] = vec4(wi, pdf);
        results[2u * i + 1u] = vec4(hgPhase(wi.z, u_g), 0.0, 0.0, 0.0);
    } else if (u_mode == 1u) {
        uint row = i / u_cols;
        float dtheta = PI / float(u_rows), dphi = 2.0 * PI / float(u_cols);
        float sum = 0.0;
        for (uint a = 0u; a < u_sub; ++a) {
            float theta = (float(row) + (float(a) + 0.5) / float(u_sub)) * dtheta;
            sum += hgPhase(cos(theta), u_g) * sin(theta) * float(u_sub);  // constant in phi
        }
        results[i] = vec4(sum * dtheta * dphi / float(u_sub * u_sub), 0.0, 0.0, 0.0);
    } else {
        Sampler smp = samplerStart(SAMPLER_INDEPENDENT, i, 0u, u_seed);
        Medium md;
        md.sigmaA = u_sigmaA;
        md.sigmaS = u_sigmaS;
        md.g = 0.0;
        float t;
        vec3 weight;
        bool scattered = mediumSampleDistance(md, u_tMax, u_beta, smp, 0u, t, weight);
        results[2u * i] = vec4(weight, scattered ? 1.0 : 0.0);
        results[2u * i + 1u] = vec4(t, 0.0, 0.0, 0.0);
    }
}
