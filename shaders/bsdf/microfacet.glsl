// The Trowbridge-Reitz (GGX) microfacet distribution, isotropic, with roughness alpha.
//   D(wm) = alpha^2 / (pi ((wm.x^2 + wm.y^2) + alpha^2 wm.z^2)^2)   (Walter et al. 2007, eq. 33,
//     written without tan so that it stays accurate for small alpha)
//   Lambda(w) = (sqrt(1 + alpha^2 tan^2(theta)) - 1) / 2          (Heitz 2014, eq. 72)
//   Shadowing-masking: the HEIGHT-CORRELATED Smith term G2 = 1 / (1 + Lambda(wo) + Lambda(wi))
//     (Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
//     JCGT 3(2), eq. 99). It is more accurate than the separable G1(wo) G1(wi), and it is what
//     pbrt-v4 uses. Mitsuba 3's rough conductor and rough dielectric use the separable form
//     (MicrofacetDistribution::G in its render/microfacet.h: smith_g1(wi) * smith_g1(wo)), so
//     they are slightly darker at grazing angles; at normal incidence of wo the two coincide
//     (Lambda(wo) = 0). The white-furnace numbers in docs/materials.md are for this term.
//   Sampling: the distribution of visible normals D_wo(wm) = G1(wo) max(0, wo.wm) D(wm) / |wo.z|
//     (Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4)), drawn with the
//     spherical-cap method of Dupuy & Benyoub 2023, "Sampling Visible GGX Normals with Spherical
//     Caps", HPG (listing 3). wo may lie below the surface (inside a dielectric): it is flipped to
//     the upper side first, so the sampled wm always has wm.z > 0.
#ifndef BSDF_MICROFACET_GLSL
#define BSDF_MICROFACET_GLSL
#include "../lib/math.glsl"

// The smallest alpha the rough models evaluate (textures may ask for less); below about 1e-3
// the scene compiler switches to the smooth (delta) models instead.
const float GGX_MIN_ALPHA = 1e-3;

float ggxD(vec3 wm, float alpha) {
    if (wm.z <= 0.0) return 0.0;
    float a2 = alpha * alpha;
    float t = wm.x * wm.x + wm.y * wm.y + a2 * wm.z * wm.z;
    return a2 / (PI * t * t);
}

float ggxLambda(vec3 w, float alpha) {
    float cos2 = w.z * w.z;
    if (cos2 <= 0.0) return 1e30;
    float sin2 = max(0.0, w.x * w.x + w.y * w.y);
    // (sqrt(1 + a^2 tan^2) - 1) / 2 = (sqrt(cos^2 + a^2 sin^2) / |cos| - 1) / 2
    return 0.5 * (sqrt(cos2 + alpha * alpha * sin2) / abs(w.z) - 1.0);
}

float ggxG1(vec3 w, float alpha) { return 1.0 / (1.0 + ggxLambda(w, alpha)); }

// Height-correlated masking-shadowing (see the header).
float ggxG(vec3 wo, vec3 wi, float alpha) { return 1.0 / (1.0 + ggxLambda(wo, alpha) + ggxLambda(wi, alpha)); }

// The density of visible normals seen from w (either side; Heitz 2018 eq. 1 with |.|).
float ggxVisibleD(vec3 w, vec3 wm, float alpha) {
    if (w.z == 0.0) return 0.0;
    return ggxG1(w, alpha) / abs(w.z) * ggxD(wm, alpha) * abs(dot(w, wm));
}

// A visible normal for the view direction w (Dupuy & Benyoub 2023).
vec3 ggxSampleVisibleNormal(vec3 w, float alpha, vec2 u) {
    // Stretch the view so that the distribution becomes the hemisphere configuration.
    vec3 wh = normalize(vec3(alpha * w.x, alpha * w.y, w.z));
    if (wh.z < 0.0) wh = -wh;
    // Uniform point on the spherical cap z >= -wh.z, then the half vector to wh.
    float phi = 2.0 * PI * u.x;
    float z = (1.0 - u.y) * (1.0 + wh.z) - wh.z;
    float sinTheta = safeSqrt(1.0 - z * z);
    vec3 c = vec3(sinTheta * cos(phi), sinTheta * sin(phi), z);
    vec3 h = c + wh;
    // Unstretch (h.z >= 0 by construction; the floor only guards the measure-zero h = 0).
    return normalize(vec3(alpha * h.x, alpha * h.y, max(h.z, 1e-9)));
}

#endif
