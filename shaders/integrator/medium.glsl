// Participating media: homogeneous media with an absorption coefficient sigma_a and a scattering
// coefficient sigma_s per RGB channel (per scene unit) and a Henyey-Greenstein phase function.
//
// Where media are. A medium is named by an entry: 0 is the scene's (the environment's fog,
// GpuFrame::mediumA/S; vacuum when both are zero), m > 0 the interior of the object whose material
// is m - 1. A material with MAT_FLAG_MEDIUM holds its interior's coefficients (shared/layout.h);
// any other interior is vacuum. The surfaces that bound an interior are those of dielectrics with a
// reflection lobe (smooth and rough glass) and of MAT_VOLUME (an index-matched boundary: no surface
// at all, rays and shadow rays cross it unchanged).
//
// Nesting (Schmidt and Budge 2002, "Simple Nested Dielectrics in Ray Traced Images"): a path
// carries the interiors it is in, a stack of up to four entries in the order entered
// (PathState::stack). A ray that crosses a bounding surface against its normal enters that
// interior (pushed), along it leaves it (removed). Where interiors overlap, the one of the highest
// priority (GpuMaterial::info.w; the latest entered among equals) is what is there: its medium
// scatters, and a dielectric surface inside it is a false interface (interfaceIsFalse), crossed
// like a volume's. At a true interface the dielectric's IOR is taken relative to the medium beyond
// it (outsideIor: the next dielectric on the stack, volumes skipped, else 1), so a glass of water
// is modelled as a glass and a slightly larger volume of water of lower priority, and the glass
// and water meet at eta = 1.33 / 1.5 without an interface surface of their own. The camera starts
// outside every object (docs/materials.md, "Media").
//
// Free flight (mediumSampleDistance): the distance to the next scattering event is sampled from
// one channel's exponential, the channel chosen with probability proportional to the path's
// throughput in it, and the throughput is weighted by the one-sample balance heuristic over the
// channels: the pdf divided by is sum_c p_c sigma_t,c T_c(t), the mixture of the three strategies
// (the "spectral MIS" of Mitsuba 3's volpath; Miller, Georgiev and Jarosz 2019, "A Null-Scattering
// Path Integral Formulation of Light Transport", sec. 6). A channel's weight is then at most
// sigma_s,c / (p_c sigma_t,c) times its throughput, so a chromatic medium makes no fireflies, and a
// grey one gives exactly the albedo sigma_s / sigma_t at every scattering event. A medium that
// only absorbs draws no random number: the segment's transmittance goes into the throughput.
//
// Medium vertices (integrator/path.glsl, pathMediumVertex) do next event estimation with the
// transmittance along the shadow ray (shadowTransmittance: through MAT_VOLUME boundaries, zero
// at any other surface), combined with phase-function sampling by the power heuristic on the
// directional pdfs (both strategies estimate the transmittance without bias, so the weights need
// not include it; Mitsuba 3's volpath does the same).
#ifndef INTEGRATOR_MEDIUM_GLSL
#define INTEGRATOR_MEDIUM_GLSL
#include "../lib/math.glsl"
#include "../lib/sampler.glsl"
#include "../geometry/intersect.glsl"
#include "../bsdf/material.glsl"

struct Medium {
    vec3 sigmaA;
    vec3 sigmaS;
    float g;
    bool walk;  // a subsurface interior (MAT_FLAG_RANDOM_WALK): walked without light sampling (path.glsl)
};

// The medium of entry m (see the header).
Medium mediumAt(uint m) {
    Medium md;
    if (m == 0u) {
        md.sigmaA = frame.mediumA.rgb;
        md.sigmaS = frame.mediumS.rgb;
        md.g = frame.mediumA.w;
        md.walk = false;
        return md;
    }
    GpuMaterial mat = loadMaterial(m - 1u);
    bool has = (mat.info.y & MAT_FLAG_MEDIUM) != 0u;
    md.sigmaA = has ? mat.k.rgb : vec3(0.0);
    md.sigmaS = has ? mat.eta.rgb : vec3(0.0);
    md.g = has ? mat.eta.w : 0.0;
    md.walk = HAS_MEDIA(MEDIA_RANDOM_WALK) && (mat.info.y & MAT_FLAG_RANDOM_WALK) != 0u;
    return md;
}

bool mediumScatters(Medium md) { return HAS_MEDIA(MEDIA_SCATTERING) && maxComponent(md.sigmaS) > 0.0; }

// exp(-sigma_t d); d may be FLT_MAX (an infinite segment: 0 where sigma_t > 0, 1 where it is 0).
vec3 mediumTransmittance(Medium md, float d) { return exp(-(md.sigmaA + md.sigmaS) * d); }

// Whether the surfaces of material `mat` bound an interior (see the header).
bool boundsInterior(GpuMaterial mat) {
    uint type = mat.info.x;
    if (HAS_MEDIA(MEDIA_BOUNDARIES) && type == MAT_VOLUME) return true;
    return (type == MAT_DIELECTRIC || type == MAT_ROUGH_DIELECTRIC) && (mat.info.y & MAT_FLAG_NO_REFLECTION) == 0u;
}

// The stack of interiors (see the header): entries in the order entered, 0 for an empty slot.
int mediumPriority(uint entry) { return int(loadMaterial(entry - 1u).info.w); }

// The entry whose interior is where the path is: the highest priority, the latest among equals; 0
// (the scene's medium) for an empty stack. `skipVolumes`: the highest that is not MAT_VOLUME (whose
// IOR is that of what surrounds it).
uint stackTopOf(uvec4 s, bool skipVolumes) {
    uint top = 0u;
    int best = -1;
    for (int i = 0; i < 4; ++i) {
        uint e = s[i];
        if (e == 0u) break;
        GpuMaterial m = loadMaterial(e - 1u);
        if (skipVolumes && m.info.x == MAT_VOLUME) continue;
        int p = int(m.info.w);
        if (p >= best) {
            best = p;
            top = e;
        }
    }
    return top;
}
uint stackTop(uvec4 s) { return stackTopOf(s, false); }

uvec4 stackPush(uvec4 s, uint e) {
    if (s.w != 0u) s = uvec4(s.yzw, 0u);  // full: the oldest entry goes (docs/materials.md)
    if (s.x == 0u) s.x = e;
    else if (s.y == 0u) s.y = e;
    else if (s.z == 0u) s.z = e;
    else s.w = e;
    return s;
}

// The stack without the latest occurrence of e (unchanged when e is not in it).
uvec4 stackRemove(uvec4 s, uint e) {
    if (s.w == e) return uvec4(s.xyz, 0u);
    if (s.z == e) return uvec4(s.xy, s.w, 0u);
    if (s.y == e) return uvec4(s.x, s.zw, 0u);
    if (s.x == e) return uvec4(s.yzw, 0u);
    return s;
}

// The stack after a ray of direction d crosses a bounding surface of material index `material`
// (front normal ng): entering against the normal, leaving along it.
uvec4 stackCross(uvec4 s, uint material, vec3 ng, vec3 d) {
    return dot(ng, d) < 0.0 ? stackPush(s, material + 1u) : stackRemove(s, material + 1u);
}

// Whether a dielectric's surface that a ray with stack s meets is a false interface: entering an
// interior that one already around outranks, or leaving one that another holds the space of.
bool interfaceIsFalse(uvec4 s, uint material, vec3 ng, vec3 d) {
    uint e = material + 1u;
    uint top = stackTop(s);
    if (dot(ng, d) < 0.0) return top != 0u && mediumPriority(top) > mediumPriority(e);
    return top != e && stackRemove(s, e) != s;
}

// The IOR beyond a true interface of material index `material` for a ray with stack s: the
// dielectric whose interior surrounds it there (volumes skipped), else 1 (the scene's medium).
float outsideIor(uvec4 s, uint material) {
    uint e = stackTopOf(stackRemove(s, material + 1u), true);
    return e == 0u ? 1.0 : loadMaterial(e - 1u).params.y;
}

// The sampler slot of the k-th free-flight sample of a path: a range of its own, above every
// bounce's (lib/sampler.glsl hashes slots, so any unused number is a fresh dimension), because a
// bounce may run through several segments (one per boundary crossed).
uint mediumSlot(uint k) { return 0x00100000u + k; }
// The direction sampled at the k-th segment's scattering event of a subsurface walk (path.glsl), and
// a bounce's choice of a surface's part (integrator/surface_parts.glsl): ranges of their own.
uint walkSlot(uint k) { return 0x00200000u + k; }
uint partSlot(uint bounce) { return 0x00300000u + bounce; }

// The probability of sampling each channel's free flight for a path of throughput beta.
vec3 channelPmf(vec3 beta) {
    float sum = beta.r + beta.g + beta.b;
    return sum > 0.0 ? beta / sum : vec3(1.0 / 3.0);
}

// The density of free-flight sampling's distance t (before the segment's end) for throughput beta.
float freeFlightPdf(Medium md, vec3 beta, float t) {
    vec3 sigmaT = md.sigmaA + md.sigmaS;
    return dot(channelPmf(beta), sigmaT * exp(-sigmaT * t));
}

// Free-flight sampling over a segment of length tMax (FLT_MAX: unbounded) of the medium md (see
// the header). True when the path scatters at t < tMax; else t = tMax. `weight` multiplies the
// throughput either way. A medium that does not scatter draws nothing.
bool mediumSampleDistance(Medium md, float tMax, vec3 beta, inout Sampler smp, uint slot, out float t, out vec3 weight) {
    vec3 sigmaT = md.sigmaA + md.sigmaS;
    t = tMax;
    if (!mediumScatters(md)) {
        weight = exp(-sigmaT * tMax);
        return false;
    }
    vec2 u = sample2D(smp, slot);
    vec3 pc = channelPmf(beta);
    float sc = u.x < pc.r ? sigmaT.r : (u.x < pc.r + pc.g ? sigmaT.g : sigmaT.b);
    float ts = sc > 0.0 ? -log(1.0 - u.y) / sc : FLT_MAX;
    if (ts < tMax) {
        t = ts;
        vec3 tr = exp(-sigmaT * ts);
        float pdf = dot(pc, sigmaT * tr);
        weight = pdf > 0.0 ? md.sigmaS * tr / pdf : vec3(0.0);
        return true;
    }
    vec3 tr = exp(-sigmaT * tMax);
    float pass = dot(pc, tr);
    weight = pass > 0.0 ? tr / pass : vec3(0.0);
    return false;
}

// The Henyey-Greenstein phase function of the cosine between the directions of travel before and
// after scattering (g > 0: forward scattering), per steradian; it integrates to 1 over the sphere.
float hgPhase(float cosTheta, float g) {
    float denom = 1.0 + g * g - 2.0 * g * cosTheta;
    return INV_4PI * (1.0 - g * g) / (denom * sqrt(max(denom, 1e-12)));
}

// A direction after scattering from direction of travel d, distributed as hgPhase (its pdf in
// *pdf): the cosine by inverting the CDF of the cosine, (1 + g^2 - ((1 - g^2) / (1 - g + 2 g u))^2)
// / (2 g), uniform in the azimuth.
vec3 hgSample(vec3 d, float g, vec2 u, out float pdf) {
    float cosTheta;
    if (abs(g) < 1e-3) {
        cosTheta = 2.0 * u.x - 1.0;
    } else {
        float s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
        cosTheta = clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
    }
    float sinTheta = safeSqrt(1.0 - cosTheta * cosTheta);
    float phi = 2.0 * PI * u.y;
    pdf = hgPhase(cosTheta, g);
    return toWorld(frameFromNormal(d), vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta));
}

// Equiangular sampling (Kulla and Fajardo 2012, "Importance Sampling Techniques for Path Tracing in
// Participating Media"): a distance along the segment o + t d, t in [0, tMax), with density
// proportional to 1 / (distance to the point c)^2, the inverse-square falloff of a point light at c:
// with delta = dot(c - o, d) and D the distance from c to the line, t = delta + D tan(theta),
// theta uniform between atan(-delta / D) and atan((tMax - delta) / D), and
//   pdf(t) = D / ((theta_b - theta_a) (D^2 + (t - delta)^2)).
// Free flight alone puts medium vertices near a point or spot light too rarely for the 1 / r^2 they
// receive (fireflies, an estimator of unbounded variance); the integrator adds an equiangular
// sample towards one of them per segment and weighs the two by MIS (path.glsl).
// The segment's geometry for a light at c: delta, D and the angle range [thetaA, thetaB]; false
// when the light lies on the segment's line (never sampled there, so its pdf is 0).
bool equiangularRange(vec3 o, vec3 d, float tMax, vec3 c, out float delta, out float D, out float thetaA,
                      out float thetaB) {
    delta = dot(c - o, d);
    D = length(c - (o + delta * d));
    thetaA = atan(-delta / D);
    thetaB = atan((min(tMax, 1e30) - delta) / D);
    return D > 1e-6 * max(1.0, abs(delta));
}

float equiangularDensity(float D, float thetaA, float thetaB, float x) { return D / ((thetaB - thetaA) * (D * D + x * x)); }

float equiangularPdf(vec3 o, vec3 d, float tMax, vec3 c, float t) {
    float delta, D, thetaA, thetaB;
    if (!equiangularRange(o, d, tMax, c, delta, D, thetaA, thetaB)) return 0.0;
    return equiangularDensity(D, thetaA, thetaB, t - delta);
}

// A distance by equiangular sampling (above); false where the light lies on the segment's line.
bool equiangularSample(vec3 o, vec3 d, float tMax, vec3 c, float u, out float t, out float pdf) {
    float delta, D, thetaA, thetaB;
    pdf = 0.0;
    t = 0.0;
    if (!equiangularRange(o, d, tMax, c, delta, D, thetaA, thetaB)) return false;
    t = delta + D * tan(mix(thetaA, thetaB, u));
    if (!(t >= 0.0 && t < tMax)) return false;
    pdf = equiangularDensity(D, thetaA, thetaB, t - delta);
    return pdf > 0.0;
}

// The number of point and spot lights (GpuFrame::options.w), the lights equiangular sampling
// aims at, each chosen with probability 1 / that.
uint deltaLightCount() { return HAS_LIGHT(LIGHT_POINT) || HAS_LIGHT(LIGHT_SPOT) ? frame.options.w : 0u; }

// The k-th point or spot light in the light list.
uint deltaLight(uint k) {
    uint n = frame.counts.y;
    for (uint i = 0u; i < n; ++i) {
        uint type = loadLight(i).info.x;
        if (type == LIGHT_POINT || type == LIGHT_SPOT) {
            if (k == 0u) return i;
            --k;
        }
    }
    return 0u;
}

// The equiangular sampler's slot for the path's k-th segment (a range of its own, as mediumSlot).
uint equiangularSlot(uint k) { return 0x00200000u + k; }

// The most boundaries a shadow ray crosses; beyond them it counts as blocked (docs/materials.md).
#define MEDIUM_MAX_SHADOW_CROSSINGS 16

// The transmittance of shadow ray r over t in (0, tMax) that starts with the stack of interiors
// `stack`: 0 when it meets a surface other than a MAT_VOLUME boundary or a false interface, else
// the product of exp(-sigma_t d) over the pieces between the boundaries it crosses (the medium
// changing at each).
vec3 shadowTransmittance(Ray r, float tMax, uvec4 stack) {
    float scale = length(r.d);
    if (!HAS_MEDIA(MEDIA_BOUNDARIES | MEDIA_NESTED)) {
        if (sceneOccluded(r, tMax)) return vec3(0.0);
        return mediumTransmittance(mediumAt(stackTop(stack)), tMax < FLT_MAX ? tMax * scale : FLT_MAX);
    }
    vec3 tr = vec3(1.0);
    bool segment = tMax < FLT_MAX;  // a segment ray: it ends at `target` (t = 1 of r.d unnormalised)
    vec3 target = r.o + r.d * (segment ? tMax : 0.0);
    for (int i = 0; i <= MEDIUM_MAX_SHADOW_CROSSINGS; ++i) {
        Hit h;
        bool found = sceneIntersect(r, tMax, h);
        float len = found ? h.t * scale : (segment ? tMax * scale : FLT_MAX);
        tr *= mediumTransmittance(mediumAt(stackTop(stack)), len);
        if (!found) return tr;
        GpuMaterial m = loadMaterial(h.material);
        bool crossed = (HAS_MEDIA(MEDIA_BOUNDARIES) && m.info.x == MAT_VOLUME) ||
                       (boundsInterior(m) && interfaceIsFalse(stack, h.material, h.ng, r.d));
        if (!crossed || maxComponent(tr) <= 0.0) return vec3(0.0);
        stack = stackCross(stack, h.material, h.ng, r.d);
        r.o = offsetRayOrigin(h.p, h.ng, r.d);
        if (segment) {
            r.d = target - r.o;
            scale = length(r.d);
            if (dot(r.d, target - h.p) <= 0.0) return tr;  // the boundary lies at the target
        }
    }
    return vec3(0.0);
}

#endif
