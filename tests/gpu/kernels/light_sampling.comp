#version 450 core
// Test kernel: draws light samples from a fixed shading point with the integrator's own
// sampleLight / lightPdf, and checks each sample against the scene: the direction must reach the
// light at the sampled distance, and lightPdf must reproduce the sampling pdf.
// results[i] = (1/pdf or 0, |lightPdf/pdf - 1|, 1 if the ray hits the light at dist, 1 if valid).
#include "lights/lights.glsl"
#include "geometry/intersect.glsl"
#include "lib/rng.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
uniform uint u_light;
uniform vec3 u_point;

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint rng = rngInit(i, 0u, 12345u);
    LightSample s = sampleLight(u_light, u_point, rngNext2(rng));
    if (!(s.pdf > 0.0)) { results[i] = vec4(0.0); return; }
    GpuLight l = lights[u_light];
    float pdfMismatch = 0.0;
    float hitsLight = 1.0;
    if (l.info.x == LIGHT_RECT || l.info.x == LIGHT_SPHERE) {
        vec3 q = u_point + s.dist * s.wi;
        vec3 nl = l.info.x == LIGHT_RECT ? normalize(cross(l.p1.xyz, l.p2.xyz)) : normalize(q - l.p0.xyz);
        pdfMismatch = abs(lightPdf(u_light, u_point, s.wi, q, nl) / s.pdf - 1.0);
        Ray r;
        r.o = u_point;
        r.d = s.wi;
        Hit h;
        bool hit = sceneIntersect(r, FLT_MAX, h);
        hitsLight = (hit && h.light == u_light + 1u && abs(h.t - s.dist) <= 1e-3 * s.dist) ? 1.0 : 0.0;
    } else if (l.info.x == LIGHT_ENV) {
        pdfMismatch = abs(lightPdf(u_light, u_point, s.wi, vec3(0.0), vec3(0.0)) / s.pdf - 1.0);
    }
    results[i] = vec4(1.0 / s.pdf, pdfMismatch, hitsLight, 1.0);
}
