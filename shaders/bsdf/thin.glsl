// Thin-walled sheets (OpenPBR's geometry_thin_walled): a surface with no inside, whose transmitted
// light leaves from the other side of the same point. Two models, both symmetric in the sheet's
// two faces (a viewer below the sheet sees the same sheet mirrored: wo.z < 0 flips both
// directions) and both BSDF_TRANSMITS (the frame keeps the front normal).
//
// Thin dielectric (MAT_THIN_DIELECTRIC): a sheet of index eta whose two interfaces are parallel.
//   A light ray meeting the sheet at cos theta is reflected by the first interface with Fresnel
//   F, and what enters bounces between the two interfaces: summing the series (no absorption
//   inside), the sheet reflects R = F + (1 - F)^2 F / (1 - F^2) = 2F / (1 + F) and transmits
//   1 - R, leaving parallel to the incident ray (the refraction in and out cancels). The
//   transmitted light is tinted once by `tint` (albedo.rgb, OpenPBR's transmission_color).
//   Smooth (alpha below 1e-3): two delta lobes, reflection with probability R, straight-through
//   (wi = -wo) with 1 - R.
//   Rough: each microfacet of the GGX distribution (alpha = params.x) is such a sheet: a visible
//   normal wm is drawn from wo, R(wo.wm) reflects about it, 1 - R passes to the mirror image of
//   the reflected direction through the sheet's plane (for wm = z this is -wo). So the
//   transmission lobe is the reflection lobe mirrored, weighted by 1 - R instead of R:
//     f(wo, wi) = D(wm) G2(wo, wr) [R(wo.wm) if wi.z > 0, else tint (1 - R(wo.wm))] / (4 wo.z |wi.z|)
//   with wr = wi mirrored to the upper side (wr = (wi.x, wi.y, |wi.z|)) and wm = normalize(wo + wr);
//   the pdf is ggxReflectionPdf(wo, wr) times R or 1 - R. Single scattering: what GGX loses at high
//   roughness is lost (as the rough dielectric).
// Diffuse transmission (MAT_DIFFUSE_TRANSMISSION): a Lambertian sheet, albedo.rgb / pi towards
//   wo's side and eta.rgb / pi through it, under a GGX specular layer (below); sampling picks the
//   specular lobe or a side by their estimated albedos, then a visible normal or a cosine-weighted
//   direction.
#ifndef BSDF_THIN_GLSL
#define BSDF_THIN_GLSL
#include "common.glsl"
#include "fresnel.glsl"
#include "microfacet.glsl"
#include "layer_lobes.glsl"
#include "surface.glsl"
#include "../lib/sampling.glsl"

// The sheet's reflectance at cos theta (see the header).
float thinReflectance(float cosTheta, float eta) {
    float F = fresnelDielectric(abs(cosTheta), eta);
    return 2.0 * F / (1.0 + F);
}

bool thinIsSmooth(GpuMaterial m) { return m.params.x < 1e-3; }

vec3 thinDielectricEval(GpuMaterial m, vec3 wo, vec3 wi) {
    if (thinIsSmooth(m) || wo.z == 0.0 || wi.z == 0.0) return vec3(0.0);
    if (wo.z < 0.0) {
        wo.z = -wo.z;
        wi.z = -wi.z;
    }
    bool through = wi.z < 0.0;
    vec3 wr = vec3(wi.xy, abs(wi.z));
    vec3 wm = wo + wr;
    if (dot(wm, wm) == 0.0) return vec3(0.0);
    wm = normalize(wm);
    float alpha = max(m.params.x, GGX_MIN_ALPHA);
    float R = thinReflectance(dot(wo, wm), m.params.y);
    float f = ggxD(wm, alpha) * ggxG(wo, wr, alpha) / (4.0 * wo.z * wr.z);
    return through ? m.albedo.rgb * (f * (1.0 - R)) : vec3(f * R);
}

float thinDielectricPdf(GpuMaterial m, vec3 wo, vec3 wi) {
    if (thinIsSmooth(m) || wo.z == 0.0 || wi.z == 0.0) return 0.0;
    if (wo.z < 0.0) {
        wo.z = -wo.z;
        wi.z = -wi.z;
    }
    vec3 wr = vec3(wi.xy, abs(wi.z));
    vec3 wm = wo + wr;
    if (dot(wm, wm) == 0.0) return 0.0;
    wm = normalize(wm);
    float alpha = max(m.params.x, GGX_MIN_ALPHA);
    float R = thinReflectance(dot(wo, wm), m.params.y);
    return ggxReflectionPdf(wo, wr, alpha) * (wi.z > 0.0 ? R : 1.0 - R);
}

// uLobe: reflection or transmission; u: the visible normal (rough).
BsdfSample thinDielectricSample(GpuMaterial m, vec3 wo, float uLobe, vec2 u) {
    if (wo.z == 0.0) return bsdfInvalidSample();
    float side = wo.z < 0.0 ? -1.0 : 1.0;
    vec3 w = vec3(wo.xy, abs(wo.z));
    BsdfSample s;
    if (thinIsSmooth(m)) {
        float R = thinReflectance(w.z, m.params.y);
        bool through = uLobe >= R;
        s.wi = through ? -wo : reflectLocal(wo);
        s.pdf = through ? 1.0 - R : R;
        s.f = (through ? m.albedo.rgb * (1.0 - R) : vec3(R)) / abs(s.wi.z);
        s.flags = BSDF_FLAG_DELTA;
        return s;
    }
    float alpha = max(m.params.x, GGX_MIN_ALPHA);
    vec3 wm = ggxSampleVisibleNormal(w, alpha, u);
    vec3 wr = reflectAbout(w, wm);
    if (wr.z <= 0.0) return bsdfInvalidSample();
    float R = thinReflectance(dot(w, wm), m.params.y);
    vec3 wi = uLobe < R ? wr : vec3(wr.xy, -wr.z);
    s.wi = vec3(wi.xy, side * wi.z);
    s.f = thinDielectricEval(m, wo, s.wi);
    s.pdf = thinDielectricPdf(m, wo, s.wi);
    s.flags = 0u;
    return s;
}

// The diffuse transmitter under its specular layer (the surface's: weight ws = k.x, GGX alpha
// params.x, ior params.y), combined as the surface combines specular and diffuse (surface.glsl,
// albedo scaling): f = ws F D G / (4 cos cos) on wo's side, plus on either side
//   C / pi (1 - ws E(wo)) (1 - ws E(wi)) / (1 - ws E_avg),  C = albedo.rgb (wo's side) or eta.rgb (through)
// which gives each side exactly (1 - ws E(wo)) times its colour.
struct ThinDiffuseAtWo {
    float alpha, ws, eO, norm, pSpec, pReflect;
};

ThinDiffuseAtWo thinDiffuseAtWo(GpuMaterial m, float mu) {
    ThinDiffuseAtWo t;
    t.alpha = max(m.params.x, GGX_MIN_ALPHA);
    t.ws = m.k.x;
    t.eO = t.ws > 0.0 ? t.ws * dielectricAlbedo(mu, t.alpha, m.params.y) : 0.0;
    t.norm = t.ws > 0.0 ? max(1.0 - t.ws * dielectricAlbedoAverage(t.alpha, m.params.y), 1e-4) : 1.0;
    float r = surfaceMean(m.albedo.rgb), tr = surfaceMean(m.eta.rgb);
    float diffuse = (1.0 - t.eO) * (r + tr);
    t.pSpec = t.eO + diffuse > 0.0 ? t.eO / (t.eO + diffuse) : 0.0;
    t.pReflect = r + tr > 0.0 ? r / (r + tr) : 0.5;
    return t;
}

vec3 diffuseTransmissionEvalAt(GpuMaterial m, ThinDiffuseAtWo t, vec3 wo, vec3 wi) {
    bool through = wi.z < 0.0;
    vec3 w = vec3(wi.xy, abs(wi.z));
    float eI = t.ws > 0.0 ? t.ws * dielectricAlbedo(w.z, t.alpha, m.params.y) : 0.0;
    vec3 f = (through ? m.eta.rgb : m.albedo.rgb) * (INV_PI * (1.0 - t.eO) * (1.0 - eI) / t.norm);
    if (!through && t.ws > 0.0) f += vec3(t.ws * dielectricReflection(wo, wi, t.alpha, m.params.y));
    return f;
}

float diffuseTransmissionPdfAt(ThinDiffuseAtWo t, vec3 wo, vec3 wi) {
    float pdf = (1.0 - t.pSpec) * (wi.z > 0.0 ? t.pReflect : 1.0 - t.pReflect) * cosineHemispherePdf(abs(wi.z));
    if (wi.z > 0.0 && t.pSpec > 0.0) pdf += t.pSpec * ggxReflectionPdf(wo, wi, t.alpha);
    return pdf;
}

vec3 diffuseTransmissionEval(GpuMaterial m, vec3 wo, vec3 wi) {
    if (wo.z == 0.0 || wi.z == 0.0) return vec3(0.0);
    if (wo.z < 0.0) {
        wo.z = -wo.z;
        wi.z = -wi.z;
    }
    return diffuseTransmissionEvalAt(m, thinDiffuseAtWo(m, wo.z), wo, wi);
}

float diffuseTransmissionPdf(GpuMaterial m, vec3 wo, vec3 wi) {
    if (wo.z == 0.0 || wi.z == 0.0) return 0.0;
    if (wo.z < 0.0) {
        wo.z = -wo.z;
        wi.z = -wi.z;
    }
    return diffuseTransmissionPdfAt(thinDiffuseAtWo(m, wo.z), wo, wi);
}

// u.xy: the direction; u.z: the specular lobe or the diffuse side.
BsdfSample diffuseTransmissionSample(GpuMaterial m, vec3 wo, vec3 u) {
    if (wo.z == 0.0) return bsdfInvalidSample();
    float side = wo.z < 0.0 ? -1.0 : 1.0;
    vec3 w = vec3(wo.xy, abs(wo.z));
    ThinDiffuseAtWo t = thinDiffuseAtWo(m, w.z);
    vec3 wi;
    if (u.z < t.pSpec) {
        wi = reflectAbout(w, ggxSampleVisibleNormal(w, t.alpha, u.xy));
        if (wi.z <= 0.0) return bsdfInvalidSample();
    } else {
        wi = sampleCosineHemisphere(u.xy);
        if ((u.z - t.pSpec) >= (1.0 - t.pSpec) * t.pReflect) wi.z = -wi.z;
    }
    BsdfSample s;
    s.f = diffuseTransmissionEvalAt(m, t, w, wi);
    s.pdf = diffuseTransmissionPdfAt(t, w, wi);
    s.wi = vec3(wi.xy, side * wi.z);
    s.flags = 0u;
    return s;
}

#endif
