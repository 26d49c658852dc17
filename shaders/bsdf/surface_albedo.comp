#version 450 core
// The directional albedos the layered surface material (surface.glsl) scales its layers by,
// computed from the lobes' own code (layer_lobes.glsl) once per renderer, after ggx_albedo.comp
// (renderer/bsdf_tables.cpp). Two passes over the same buffer (u_pass):
//   0: E(mu, alpha, ior) = int dielectricReflection cos dwi, the mean of the visible-normal
//      weight F(wo.wm) G2 / G1 over a stratified 32 x 32 grid (as ggx_albedo.comp), for
//      mu = i / (N - 1), alpha = j / (N - 1) (both at least 1e-3) and ior slice k (the coordinate
//      k / (I - 1) of surfaceIorFromCoordinate); and the sheen lobe's E(mu, r), r = j / (N - 1),
//      the mean of 2 pi f cos over a stratified 64 x 64 grid uniform in solid angle (z = I);
//   1: the cosine-weighted averages E_avg = 2 int_0^1 E(mu) mu dmu of the dielectric table's
//      piecewise linear interpolant in mu, integrated exactly segment by segment, so that the average the
//      shader reads is the average of what it interpolates (a white Lambertian base under the
//      layer then reflects exactly 1 - E(wo), see surface.glsl).
#include "../shared/layout.h"
#include "layer_lobes.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(std430, binding = BINDING_BSDF_TABLES) buffer SurfaceAlbedoOut { float table[]; };
uniform uint u_pass;

const int N = GGX_ALBEDO_TABLE_SIZE;
const int I = SURFACE_TABLE_IOR;

float dielectricEntry(float mu, float alpha, float eta) {
    const int S = 32;
    const vec3 wo = vec3(sqrt(1.0 - mu * mu), 0.0, mu);
    const float g1 = ggxG1(wo, alpha);
    float sum = 0.0;
    for (int a = 0; a < S; ++a)
        for (int b = 0; b < S; ++b) {
            const vec3 wm = ggxSampleVisibleNormal(wo, alpha, (vec2(a, b) + 0.5) / float(S));
            const vec3 wi = reflect(-wo, wm);
            if (wi.z > 0.0) sum += fresnelDielectric(dot(wo, wm), eta) * ggxG(wo, wi, alpha) / g1;
        }
    return sum / float(S * S);
}

// Uniform in solid angle (weight 2 pi f cos): the lobe peaks at grazing wi, where cosine-
// distributed points are too sparse.
float sheenEntry(float mu, float r) {
    const int S = 64;
    const vec3 wo = vec3(sqrt(1.0 - mu * mu), 0.0, mu);
    float sum = 0.0;
    for (int a = 0; a < S; ++a)
        for (int b = 0; b < S; ++b) {
            const vec2 u = (vec2(a, b) + 0.5) / float(S);
            const float z = u.x, s = sqrt(max(0.0, 1.0 - z * z)), phi = 2.0 * PI * u.y;
            const vec3 wi = vec3(s * cos(phi), s * sin(phi), z);
            sum += 2.0 * PI * sheenEval(wo, wi, r) * z;
        }
    return sum / float(S * S);
}

// 2 int E(mu) mu dmu of the linear interpolant of the N entries at `base` (stride 1 in mu).
float cosineAverage(int base) {
    float sum = 0.0;
    for (int i = 0; i + 1 < N; ++i) {
        const float a = float(i) / float(N - 1), b = float(i + 1) / float(N - 1);
        const float ea = table[base + i], eb = table[base + i + 1];
        sum += ea * (b * b - a * a) + (eb - ea) / (b - a) * (2.0 * (b * b * b - a * a * a) / 3.0 - a * (b * b - a * a));
    }
    return sum;
}

void main() {
    const ivec3 id = ivec3(gl_GlobalInvocationID);
    if (id.x >= N || id.y >= N || id.z > I) return;
    const float mu = max(float(id.x) / float(N - 1), 1e-3);
    const float alpha = max(float(id.y) / float(N - 1), 1e-3);
    if (u_pass == 0u) {
        if (id.z < I) {
            const float eta = surfaceIorFromCoordinate(float(id.z) / float(I - 1));
            table[BSDF_TABLE_DIELECTRIC + (id.z * N + id.y) * N + id.x] = dielectricEntry(mu, alpha, eta);
        } else {
            table[BSDF_TABLE_SHEEN + id.y * N + id.x] = sheenEntry(mu, float(id.y) / float(N - 1));
        }
    } else if (id.x == 0 && id.z < I) {
        table[BSDF_TABLE_DIELECTRIC_AVG + id.z * N + id.y] = cosineAverage(BSDF_TABLE_DIELECTRIC + (id.z * N + id.y) * N);
    }
}
