// The single lobes the layered surface material (surface.glsl) is built from, with no table and
// no scene buffer in reach, so that the kernel that tabulates their directional albedos
// (surface_albedo.comp) runs exactly this code:
//   - dielectricReflection: the GGX reflection lobe of a dielectric interface (a specular layer or
//     a clear coat), D G2 F(wo.wm, eta) / (4 cos wo cos wi), F the unpolarised dielectric Fresnel
//     of fresnel.glsl, D and G2 (height-correlated) of microfacet.glsl;
//   - fresnelF82Tint: the metal Fresnel of OpenPBR Surface 1.1 (sec. "Metal"), the "F82-tint"
//     model of Kutz, Hasan and Edmondson 2021 ("Novel aspects of the Adobe Standard Material"):
//     Schlick's F0 + (1 - F0)(1 - mu)^5 minus a mu (1 - mu)^6, with a chosen so that F at
//     mu_bar = 1/7 (82 degrees) is the tint times Schlick's value there;
//   - sheen: the "Charlie" microfiber distribution of Estevez and Kulla 2017 ("Production Friendly
//     Microfacet Sheen BRDF", Sony Pictures Imageworks), D(wm) = (2 + 1/r) sin(theta_m)^(1/r) /
//     (2 pi), with that paper's own Smith-style shadowing G = 1 / (1 + Lambda(wo) + Lambda(wi)),
//     Lambda fitted as exp(L(cos)) below cos 0.5 and exp(2 L(0.5) - L(1 - cos)) above, L(x) =
//     a / (1 + b x^c) + d x + e with (a..e) interpolated between their r = 0 and r = 1 fits by
//     (1 - r)^2 (the paper's table; the glTF extension KHR_materials_sheen reprints it):
//     f = D G / (4 cos wo cos wi). Reciprocal. Not the visibility of Neubelt and Pettineo 2013,
//     which the extension also allows: with it the lobe reflects up to 1.57 at grazing angles for
//     small r (measured by surface_albedo.comp), which albedo scaling cannot take. Simpler than the
//     LTC fit of Zeltner, Burley and Chiang 2022. r is clamped to [0.07, 1] (below, the
//     distribution is too peaked at grazing angles for float precision).
#ifndef BSDF_LAYER_LOBES_GLSL
#define BSDF_LAYER_LOBES_GLSL
#include "fresnel.glsl"
#include "microfacet.glsl"

const float SHEEN_MIN_ROUGHNESS = 0.07;

// f without the cosine; wo, wi in the upper hemisphere (0 otherwise).
float dielectricReflection(vec3 wo, vec3 wi, float alpha, float eta) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    vec3 wm = wo + wi;
    if (dot(wm, wm) == 0.0) return 0.0;
    wm = normalize(wm);
    return ggxD(wm, alpha) * ggxG(wo, wi, alpha) * fresnelDielectric(dot(wo, wm), eta) / (4.0 * wo.z * wi.z);
}

// The pdf of wi when wm is drawn from the visible normals of wo and wo is reflected about it.
float ggxReflectionPdf(vec3 wo, vec3 wi, float alpha) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    vec3 wm = wo + wi;
    if (dot(wm, wm) == 0.0) return 0.0;
    wm = normalize(wm);
    return ggxVisibleD(wo, wm, alpha) / (4.0 * abs(dot(wo, wm)));
}

vec3 fresnelF82Tint(float mu, vec3 f0, vec3 tint) {
    const float muBar = 1.0 / 7.0;
    mu = clamp(mu, 0.0, 1.0);
    const float b = muBar * pow(1.0 - muBar, 6.0);
    vec3 schlickBar = f0 + (1.0 - f0) * pow(1.0 - muBar, 5.0);
    vec3 a = schlickBar * (1.0 - tint) / b;
    vec3 schlick = f0 + (1.0 - f0) * pow(1.0 - mu, 5.0);
    return clamp(schlick - a * mu * pow(1.0 - mu, 6.0), 0.0, 1.0);
}

float sheenD(vec3 wm, float r) {
    float invR = 1.0 / r;
    float sin2 = max(0.0, 1.0 - wm.z * wm.z);
    return (2.0 + invR) * pow(sin2, 0.5 * invR) / (2.0 * PI);
}

float sheenL(float x, float r) {
    float t = (1.0 - r) * (1.0 - r);
    float a = mix(21.5473, 25.3245, t), b = mix(3.82987, 3.32435, t), c = mix(0.19823, 0.16801, t);
    float d = mix(-1.97760, -1.27393, t), e = mix(-4.32054, -4.85967, t);
    return a / (1.0 + b * pow(x, c)) + d * x + e;
}

float sheenLambda(float cosTheta, float r) {
    float x = abs(cosTheta);
    return x < 0.5 ? exp(sheenL(x, r)) : exp(2.0 * sheenL(0.5, r) - sheenL(1.0 - x, r));
}

// f without the cosine (white sheen); wo, wi in the upper hemisphere.
float sheenEval(vec3 wo, vec3 wi, float r) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    r = clamp(r, SHEEN_MIN_ROUGHNESS, 1.0);
    vec3 wm = wo + wi;
    if (dot(wm, wm) == 0.0) return 0.0;
    wm = normalize(wm);
    float g = 1.0 / (1.0 + sheenLambda(wo.z, r) + sheenLambda(wi.z, r));
    return sheenD(wm, r) * g / (4.0 * wo.z * wi.z);
}

// The tables' coordinates: the ior axis is x = (ior - 1) / (ior + 1) over ior [1, 3], i.e. [0, 0.5].
float surfaceIorCoordinate(float eta) { return clamp((eta - 1.0) / (eta + 1.0), 0.0, 0.5) * 2.0; }
float surfaceIorFromCoordinate(float t) {
    float x = 0.5 * t;
    return (1.0 + x) / (1.0 - x);
}

#endif
