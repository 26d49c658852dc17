#version 450 core
// Test kernel for the BSDF models: includes the same bsdf/bsdf.glsl as the integrator and calls
// its wrapper on the material u_material of the materials buffer (a test buffer bound there).
//   u_mode 0 (sample): invocation i draws a sample for u_wo from random numbers of stream i:
//     results[3i]   = (wi, pdf), results[3i+1] = (f |cos wi| / pdf, flags),
//     results[3i+2] = (bsdfEval(wo, wi), bsdfPdf(wo, wi)) at the sampled wi.
//   u_mode 1 (pdf integral): invocation i integrates bsdfPdf(u_wo, .) over cell i of a grid of
//     u_rows theta bins on [0, pi] (row 0 around +z) by u_cols phi bins on [0, 2 pi), with the
//     midpoint rule on u_sub x u_sub points of pdf sin(theta): results[i].x. Bins in theta rather
//     than cos(theta) keep narrow lobes around the poles (low roughness, normal incidence)
//     resolved by the integration.
//   u_mode 2 (reciprocity): a random pair (a, b) of upper-hemisphere directions per invocation:
//     results[2i] = (bsdfEval(a, b), 0), results[2i+1] = (bsdfEval(b, a), 0).
#include "bsdf/bsdf.glsl"
#include "lib/rng.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
uniform uint u_mode;
uniform uint u_count;
uniform uint u_material;
uniform vec3 u_wo;
uniform uint u_rows;
uniform uint u_cols;
uniform uint u_sub;
uniform uint u_seed;

vec3 dirFromThetaPhi(float theta, float phi) {
    float r = sin(theta);
    return vec3(r * cos(phi), r * sin(phi), cos(theta));
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    GpuMaterial m = materials[u_material];
    if (u_mode == 0u) {
        uint rng = rngInit(i, 0u, u_seed);
        vec2 u = rngNext2(rng);
        BsdfSample s = bsdfSample(m, u_wo, vec3(u, rngNext(rng)));
        vec3 weight = s.pdf > 0.0 ? s.f * abs(s.wi.z) / s.pdf : vec3(0.0);
        results[3u * i] = vec4(s.wi, s.pdf);
        results[3u * i + 1u] = vec4(weight, float(s.flags));
        results[3u * i + 2u] = vec4(bsdfEval(m, u_wo, s.wi), bsdfPdf(m, u_wo, s.wi));
    } else if (u_mode == 1u) {
        uint row = i / u_cols, col = i % u_cols;
        float dtheta = PI / float(u_rows), dphi = 2.0 * PI / float(u_cols);
        float theta0 = float(row) * dtheta;
        float phi0 = float(col) * dphi;
        float sum = 0.0;
        for (uint a = 0u; a < u_sub; ++a)
            for (uint b = 0u; b < u_sub; ++b) {
                float theta = theta0 + (float(a) + 0.5) / float(u_sub) * dtheta;
                float phi = phi0 + (float(b) + 0.5) / float(u_sub) * dphi;
                sum += bsdfPdf(m, u_wo, dirFromThetaPhi(theta, phi)) * sin(theta);
            }
        results[i] = vec4(sum * dtheta * dphi / float(u_sub * u_sub), 0.0, 0.0, 0.0);
    } else {
        uint rng = rngInit(i, 1u, u_seed);
        vec3 a = sampleUniformSphere(rngNext2(rng));
        vec3 b = sampleUniformSphere(rngNext2(rng));
        a.z = abs(a.z);
        b.z = abs(b.z);
        results[2u * i] = vec4(bsdfEval(m, a, b), 0.0);
        results[2u * i + 1u] = vec4(bsdfEval(m, b, a), 0.0);
    }
}
