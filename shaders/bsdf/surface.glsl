// The layered surface material ("type": "surface"): a physically based subset of OpenPBR Surface
// 1.1 (Andersson, Kutz, Portsmouth et al., Academy Software Foundation 2024). From the top:
//   sheen  (colour x weight Sh, roughness r): the Charlie lobe of layer_lobes.glsl;
//   coat   (weight wc, colour Cc, GGX alpha ac, ior nc): a dielectric GGX reflection lobe; what
//          passes it is tinted by Cc (once, not per path length: a simple absorbing coat);
//   base   a mix by metalness M of
//          metal:      GGX (alpha as) with the F82-tint Fresnel, F0 = base colour C, tint S;
//          dielectric: a GGX reflection lobe (alpha as, ior ns, weight ws, tinted by S) over a
//                      Lambertian diffuse of albedo C.
// Layers are combined by energy-conserving albedo scaling (Kulla and Conty 2017, "Revisiting
// Physically Based Shading at Imageworks", SIGGRAPH course; OpenPBR's "albedo scaling"), with w E
// the top lobe's directional albedo times its weight (E tabulated on the GPU from layer_lobes.glsl
// by surface_albedo.comp), in two forms:
//   specular over diffuse (reciprocal):  spec + diffuse (1 - w E(wo)) (1 - w E(wi)) / (1 - w E_avg)
//     with E_avg = 2 int E mu dmu: symmetric in wo and wi, and over the Lambertian base it conserves
//     energy exactly, the base reflecting (1 - w E(wo)) (1 - w E_avg) / (1 - w E_avg);
//   coat and sheen over what lies below:  top + below (1 - w E(wo))
//     which reflects exactly w E(wo) + (1 - w E(wo)) A_below(wo) for every wo: never more than 1,
//     and 1 when the stack below conserves energy. Not reciprocal (the factor depends on wo only,
//     as Turquin's compensation in conductor.glsl). The symmetric form above was tried for these
//     layers and rejected: over a glossy stack it overshoots (a white sheen over a smooth coat
//     reflected 1.019 at normal incidence, because the coat sends light to where the sheen's E is
//     small), and its bounded variants lose 5 to 18 % (docs/materials.md).
// The metal lobe is single scattering (it loses what GGX loses at high roughness, as a conductor
// without energy_compensation).
// Transmission and subsurface are parts of their own, chosen per hit by the integrator
// (integrator/surface_parts.glsl); this model is the rest, reflection only.
// Simplifications against OpenPBR, by design: no thin film or anisotropy; the base is Lambert, not EON; the coat does not darken or refract the base's
// lobes (the specular layer's IOR stays relative to air under the coat); the coat colour is one
// multiplication. Roughness parameters in the file are OpenPBR's perceptual ones (alpha = r^2,
// done by the scene compiler, the sheen's r likewise); the GpuMaterial holds alphas and r.
// Sampling: three strategies, chosen by the lobes' estimated albedos at wo: cosine-weighted (the
// diffuse base and the sheen), visible normals of alpha as (specular and metal), visible normals of
// alpha ac (coat); the pdf is the mixture of the three, so eval, pdf and sample agree.
// GpuMaterial: albedo.rgb = C, albedo.w = M; params = (as, ns, ws, wc); eta.rgb = S, eta.w = ac;
//   k.rgb = Cc, k.w = nc; sheen.rgb = Sh, sheen.w = r; textures: albedo -> C, roughness (R) ->
//   the specular roughness (perceptual, squared here), with MAT_FLAG_METAL_TEXTURE its G channel
//   -> M (glTF metallic-roughness textures, baked by renderer/gpu_materials.cpp).
// Reflection only: the frame is turned towards the viewer (two-sided).
#ifndef BSDF_SURFACE_GLSL
#define BSDF_SURFACE_GLSL
#include "common.glsl"
#include "layer_lobes.glsl"
#include "../lib/sampling.glsl"

// Bilinear in the BSDF tables: `base` the first entry, `stride` the distance between rows, x and
// y the coordinates in [0, 1] over N entries each.
float surfaceTable2(int base, int stride, float x, float y) {
    const int N = GGX_ALBEDO_TABLE_SIZE;
    vec2 p = clamp(vec2(x, y), 0.0, 1.0) * float(N - 1);
    ivec2 i0 = min(ivec2(p), ivec2(N - 2));
    vec2 t = p - vec2(i0);
    int b = base + i0.y * stride + i0.x;
    return mix(mix(bsdfTable(b), bsdfTable(b + 1), t.x), mix(bsdfTable(b + stride), bsdfTable(b + stride + 1), t.x), t.y);
}

// The dielectric reflection lobe's directional albedo E(mu, alpha, eta) and its average.
void surfaceIorSlices(float eta, out int s0, out float t) {
    float x = surfaceIorCoordinate(eta) * float(SURFACE_TABLE_IOR - 1);
    s0 = min(int(x), SURFACE_TABLE_IOR - 2);
    t = x - float(s0);
}

float dielectricAlbedo(float mu, float alpha, float eta) {
    const int N = GGX_ALBEDO_TABLE_SIZE;
    int s0;
    float t;
    surfaceIorSlices(eta, s0, t);
    float a = surfaceTable2(BSDF_TABLE_DIELECTRIC + s0 * N * N, N, mu, alpha);
    float b = surfaceTable2(BSDF_TABLE_DIELECTRIC + (s0 + 1) * N * N, N, mu, alpha);
    return mix(a, b, t);
}

float dielectricAlbedoAverage(float alpha, float eta) {
    const int N = GGX_ALBEDO_TABLE_SIZE;
    int s0;
    float t;
    surfaceIorSlices(eta, s0, t);
    // Rows of the average table are ior slices, alpha runs along them.
    float p = clamp(alpha, 0.0, 1.0) * float(N - 1);
    int i0 = min(int(p), N - 2);
    float tx = p - float(i0);
    int b0 = BSDF_TABLE_DIELECTRIC_AVG + s0 * N + i0, b1 = b0 + N;
    return mix(mix(bsdfTable(b0), bsdfTable(b0 + 1), tx), mix(bsdfTable(b1), bsdfTable(b1 + 1), tx), t);
}

float sheenAlbedo(float mu, float r) { return surfaceTable2(BSDF_TABLE_SHEEN, GGX_ALBEDO_TABLE_SIZE, mu, r); }

float surfaceMean(vec3 c) { return (c.r + c.g + c.b) / 3.0; }

// What depends on wo only: the layers' albedos at wo (times their weights), their averages and
// the three sampling strategies' probabilities.
struct SurfaceAtWo {
    float alphaS, alphaC, sheenR;
    float sheenW, eSheenO;             // sheenW = max(Sh): the sheen's weight in the scaling
    float eCoatO;                      // wc E_coat(wo)
    float eSpecO, specNorm;            // ws E_spec(wo), 1 - ws E_spec_avg
    float pCos, pSpec, pCoat;
};

SurfaceAtWo surfaceAtWo(GpuMaterial m, vec3 wo) {
    SurfaceAtWo s;
    float mu = wo.z;
    s.alphaS = max(m.params.x, GGX_MIN_ALPHA);
    s.alphaC = max(m.eta.w, GGX_MIN_ALPHA);
    s.sheenR = m.sheen.w;
    s.sheenW = maxComponent(m.sheen.rgb);
    s.eSheenO = s.sheenW > 0.0 ? s.sheenW * sheenAlbedo(mu, s.sheenR) : 0.0;
    float wc = m.params.w, ws = m.params.z;
    s.eCoatO = wc > 0.0 ? wc * dielectricAlbedo(mu, s.alphaC, m.k.w) : 0.0;
    s.eSpecO = ws > 0.0 ? ws * dielectricAlbedo(mu, s.alphaS, m.params.y) : 0.0;
    s.specNorm = ws > 0.0 ? max(1.0 - ws * dielectricAlbedoAverage(s.alphaS, m.params.y), 1e-4) : 1.0;
    // Estimated albedos of what each strategy samples.
    float metal = m.albedo.w;
    float underSheen = 1.0 - s.eSheenO;
    float underCoat = underSheen * (1.0 - s.eCoatO) * surfaceMean(m.k.rgb);
    float cosW = s.eSheenO + underCoat * (1.0 - metal) * (1.0 - s.eSpecO) * surfaceMean(m.albedo.rgb);
    float specW = underCoat * (metal * surfaceMean(m.albedo.rgb) + (1.0 - metal) * s.eSpecO * surfaceMean(m.eta.rgb));
    float coatW = underSheen * s.eCoatO;
    float total = cosW + specW + coatW;
    if (!(total > 0.0)) {
        cosW = 1.0;
        total = 1.0;
    }
    s.pCos = cosW / total;
    s.pSpec = specW / total;
    s.pCoat = coatW / total;
    return s;
}

vec3 surfaceEvalAt(GpuMaterial m, SurfaceAtWo s, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    float metal = m.albedo.w, ws = m.params.z, wc = m.params.w;
    vec3 wm = normalize(wo + wi);
    // Base: metal + (specular + scaled diffuse).
    float dg = ggxD(wm, s.alphaS) * ggxG(wo, wi, s.alphaS) / (4.0 * wo.z * wi.z);
    vec3 base = metal * fresnelF82Tint(dot(wo, wm), m.albedo.rgb, m.eta.rgb) * dg;
    if (metal < 1.0) {
        vec3 spec = ws * m.eta.rgb * (dg * fresnelDielectric(dot(wo, wm), m.params.y));
        float eSpecI = ws > 0.0 ? ws * dielectricAlbedo(wi.z, s.alphaS, m.params.y) : 0.0;
        vec3 diffuse = m.albedo.rgb * (INV_PI * (1.0 - s.eSpecO) * (1.0 - eSpecI) / s.specNorm);
        base += (1.0 - metal) * (spec + diffuse);
    }
    // Coat over the base, sheen over everything (the wo-only scaling, see the header).
    vec3 f = base * m.k.rgb;
    if (wc > 0.0) f = wc * dielectricReflection(wo, wi, s.alphaC, m.k.w) + f * (1.0 - s.eCoatO);
    if (s.sheenW > 0.0) f = m.sheen.rgb * sheenEval(wo, wi, s.sheenR) + f * (1.0 - s.eSheenO);
    return f;
}

float surfacePdfAt(SurfaceAtWo s, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    float pdf = s.pCos * wi.z * INV_PI;
    if (s.pSpec > 0.0) pdf += s.pSpec * ggxReflectionPdf(wo, wi, s.alphaS);
    if (s.pCoat > 0.0) pdf += s.pCoat * ggxReflectionPdf(wo, wi, s.alphaC);
    return pdf;
}

vec3 surfaceEval(GpuMaterial m, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    return surfaceEvalAt(m, surfaceAtWo(m, wo), wo, wi);
}

float surfacePdf(GpuMaterial m, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    return surfacePdfAt(surfaceAtWo(m, wo), wo, wi);
}

// u.xy: the direction, u.z: the strategy.
BsdfSample surfaceSample(GpuMaterial m, vec3 wo, vec3 u) {
    if (wo.z <= 0.0) return bsdfInvalidSample();
    SurfaceAtWo s = surfaceAtWo(m, wo);
    BsdfSample r;
    if (u.z < s.pCos) {
        r.wi = sampleCosineHemisphere(u.xy);
    } else {
        float alpha = u.z < s.pCos + s.pSpec ? s.alphaS : s.alphaC;
        r.wi = reflectAbout(wo, ggxSampleVisibleNormal(wo, alpha, u.xy));
    }
    if (r.wi.z <= 0.0) return bsdfInvalidSample();
    r.f = surfaceEvalAt(m, s, wo, r.wi);
    r.pdf = surfacePdfAt(s, wo, r.wi);
    r.flags = 0u;
    return r;
}

#endif
