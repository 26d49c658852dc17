#version 450 core
// The directional albedo E(mu, alpha) of the F = 1 GGX lobe with the height-correlated Smith term,
// computed from this very microfacet code (microfacet.glsl) for the multiple-scattering
// compensation of rough conductors (conductor.glsl), once per renderer: E is the mean of the
// visible-normal sample weight G2(wo, wi) / G1(wo) over a stratified 64 x 64 grid of the
// sampler's two numbers, wi the mirror direction of wo about the sampled normal (zero below the
// horizon). Entry (i, j) is mu = i / (N - 1) and alpha = j / (N - 1), both at least 1e-3.
#include "../shared/layout.h"
#include "microfacet.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = BINDING_BSDF_TABLES) writeonly buffer GgxAlbedoOut { float table[]; };

const int N = GGX_ALBEDO_TABLE_SIZE;
const int S = 64;

void main() {
    const ivec2 id = ivec2(gl_GlobalInvocationID.xy);
    if (id.x >= N || id.y >= N) return;
    const float alpha = max(float(id.y) / float(N - 1), 1e-3);
    const float mu = max(float(id.x) / float(N - 1), 1e-3);
    const vec3 wo = vec3(sqrt(1.0 - mu * mu), 0.0, mu);
    const float g1 = ggxG1(wo, alpha);
    float sum = 0.0;
    for (int a = 0; a < S; ++a) {
        float row = 0.0;
        for (int b = 0; b < S; ++b) {
            const vec2 u = (vec2(a, b) + 0.5) / float(S);
            const vec3 wm = ggxSampleVisibleNormal(wo, alpha, u);
            const vec3 wi = reflect(-wo, wm);
            if (wi.z > 0.0) row += ggxG(wo, wi, alpha) / g1;
        }
        sum += row;
    }
    table[id.y * N + id.x] = sum / float(S * S);
}
