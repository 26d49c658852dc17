// Unidirectional path tracing with next event estimation and multiple importance sampling.
//
// At every vertex: emission is added once, either because nothing else could have sampled it
// (the camera ray, a delta bounce, the BSDF-only strategy) or with the MIS weight of the BSDF
// strategy against the light strategy; then one light is chosen (lights/light_select.glsl: by
// the light tree's importance at the vertex, by power, or uniformly), sampled and traced with a
// shadow ray, weighted by the power heuristic against the BSDF pdf; then the BSDF is sampled for
// the continuation ray, whose hit supplies the BSDF strategy's emission term. A bounce therefore
// costs one continuation ray and one shadow ray. Vertices whose material is purely specular skip
// next event estimation (no light sample can have a non-zero BSDF value there).
//
// Media (CAUSTIC_MEDIA; integrator/medium.glsl): the path carries the interiors it is in (a stack,
// nested by priority); each segment it traces through a medium that scatters may end at a medium
// vertex (pathMediumVertex: next event estimation with the shadow ray's transmittance, then
// phase-function sampling), and otherwise multiplies the throughput by the segment's transmittance
// over its probability; refraction into or out of an object, and crossing a MAT_VOLUME boundary or
// a false interface, change the stack; a true interface's IOR is relative to the medium beyond it.
//
// Glass splitting (frame.options.x & OPTION_GLASS_SPLIT; docs/design.md derives it): at a smooth
// dielectric vertex the lobe not taken, when it leaves the medium, is traced too, by a probe ray
// that only adds the emission it sees (with the lobe's weight, not over its probability); the
// taken lobe's next emission term is scaled by its probability when the other choice would have
// probed it, so each lobe's direct emission is counted once in expectation. The probe waits its
// turn in the loop (`probing`, `pending`), so the loop keeps one closest-hit call site.
//
// Depth: `bounces` counts the scattering events on the path so far. frame.counts.z (max depth)
// caps it: 0 shows only emitters seen directly, 1 adds direct lighting, and so on. A subsurface
// walk's reflections off its boundary are vertices with random numbers of their own (bounceSlot
// of `bounces`) but outside the depth budget (`freeVertices`; pathDepth).
// Russian roulette (frame.sampling.z, RR_*; docs/design.md says how the default was chosen) acts
// on the throughput times eta^2 accumulated over refractions (Veach 1997 sec. 5.2: radiance
// scales by 1/eta^2 across an interface, which says nothing about how much the path will still
// carry), after the continuation ray is set up.
// Random numbers come from the sampler (lib/sampler.glsl) by dimension slot, one table per bounce.
//
// AOVs (the denoiser's guides, Open Image Denoise's documented convention): at the first vertex
// whose material is not purely specular (bsdfIsDelta), the path records the material's
// reflectance there (textured albedo for the diffuse models, tint * F(normal incidence) for rough
// conductors, the tint for rough glass) and the world shading normal turned towards the viewer.
// Delta vertices (mirror, smooth glass and metal) are passed through, so through a glass sphere
// the AOVs show what lies behind it. A path that escapes, ends or is absorbed before such a
// vertex records zeros.
#ifndef INTEGRATOR_PATH_GLSL
#define INTEGRATOR_PATH_GLSL
#include "../lib/sampler.glsl"
#include "../geometry/intersect.glsl"
#include "../bsdf/bsdf.glsl"
#include "../bsdf/material.glsl"
#include "../lights/lights.glsl"
#include "../lights/light_select.glsl"
#include "medium.glsl"
#include "surface_parts.glsl"

struct PathAov {
    vec3 albedo;
    vec3 normal;
};

// Reflectance of a non-delta material for the albedo AOV (values in [0, 1]).
vec3 aovAlbedo(GpuMaterial m) {
    if (m.info.x == MAT_ROUGH_CONDUCTOR) return m.albedo.rgb * conductorFresnel(m, 1.0);
    return m.albedo.rgb;  // diffuse models: albedo; rough dielectric: tint
}

// Whether Russian roulette ends the path here (after `bounces` + 1 scattering events, with the
// eta^2-corrected throughput rrBeta); else *q is the survival probability to divide by.
bool russianRouletteEnds(uint bounces, float rrBeta, float u, out float q) {
    uint rule = frame.sampling.z;
    q = 1.0;
    uint depth = bounces + 1u;
    if (rule == RR_ORIGINAL) {
        if (depth >= 3u) q = clamp(rrBeta, 0.05, 1.0);
    } else if (rule == RR_MITSUBA) {
        if (depth >= 5u) q = min(rrBeta, 0.95);
    } else if (rule == RR_PBRT) {
        if (depth >= 2u && rrBeta < 1.0) q = rrBeta;
    }
    return q < 1.0 && u >= q;
}

// The radiance a surface emits towards wo: its material's emission from both faces, unless the
// primitive is a one-sided emitter seen from behind.
// With an emission texture the radiance is the material's at the hit's texture coordinates
// (materialEmission: the value light sampling sees at the same point).
vec3 emittedTowards(Hit hit, GpuMaterial mat, vec3 wo) {
    bool frontFacing = dot(hit.ng, wo) > 0.0;
    if (!frontFacing && (hit.flags & PRIM_FLAG_ONE_SIDED_EMITTER) != 0u) return vec3(0.0);
    if (CAUSTIC_EMISSION_TEXTURES != 0u && mat.textures.w != 0u && maxComponent(mat.emission.rgb) > 0.0)
        return materialEmission(mat, hitSurface(hit).uv);
    return mat.emission.rgb;
}

// What a glass-splitting probe ray sees: the emission of the surface it hits, or the environment's
// radiance when it escapes. No MIS weight: the probe leaves a delta vertex, where no light sample
// could have found the same path.
vec3 probeEmission(bool found, Hit hit, vec3 d) {
    if (!found) return HAS_ANY_ENVIRONMENT && frame.envInfo.x != ENV_NONE ? environmentRadiance(d) : vec3(0.0);
    return emittedTowards(hit, loadMaterial(hit.material), -d);
}

// A path in flight: everything one bounce hands the next (pathStep). pathBegin starts one at a
// camera ray; pathRadiance runs one to its end. path.comp's regenerating loop (CAUSTIC_REGENERATE)
// steps each invocation's paths one bounce at a time and starts the pixel's next sample in a lane
// whose path has ended, so that no SIMD lane idles while its neighbours' paths go on.
struct PathState {
    Ray ray;
    vec3 L;
    vec3 beta;
    bool countEmitted;    // camera ray or after a delta bounce or BSDF-only: weight 1
    float prevBsdfPdf;
    vec3 prevP;
    vec3 prevN;           // the previous vertex's shading normal, for the light selection pmf
    bool prevTwoSided;    // whether it transmits (both hemispheres receive light)
    float etaScale;       // product of eta'^2 over the refractions so far
    float pathLength;     // for the texture ray cone (bsdf/material.glsl)
    // Glass splitting (see the header): whether the ray traced next is a probe, the weight of
    // what it sees, the continuation ray waiting behind it (none when the path ends after the
    // probe), and the factor (the chosen lobe's probability) that scales the continuation's next
    // emission term.
    bool probing;
    bool pendingEnds;
    vec3 probeBeta;
    Ray pending;
    float emitScale;
    uint bounces;
    uint freeVertices;    // vertices of subsurface walks among `bounces` (MEDIA_RANDOM_WALK; pathDepth)
    bool aovDone;
    PathAov aov;
    // CAUSTIC_PAIRED_TRACE: the shadow ray of the last vertex waits for the next step, which
    // traces it with the continuation ray in one walk (geometry/bvh.glsl, traceScenePair); what it
    // adds if unoccluded; and whether the path has ended with only that shadow ray left to trace.
    bool shadowPending;
    bool ended;
    Ray shadowRay;
    float shadowTMax;
    vec3 shadowL;
    // Media (CAUSTIC_MEDIA): the interiors the path is in (integrator/medium.glsl; its medium is
    // stackTop's), and how many segments it has traced through media (the free-flight samples'
    // slots).
    uvec4 stack;
    uint segments;
};

PathState pathBegin(Ray ray) {
    PathState st;
    st.ray = ray;
    st.L = vec3(0.0);
    st.beta = vec3(1.0);
    st.countEmitted = true;
    st.prevBsdfPdf = 0.0;
    st.prevP = ray.o;
    st.prevN = vec3(0.0);
    st.prevTwoSided = false;
    st.etaScale = 1.0;
    st.pathLength = 0.0;
    st.probing = false;
    st.pendingEnds = false;
    st.probeBeta = vec3(0.0);
    st.pending = ray;
    st.emitScale = 1.0;
    st.bounces = 0u;
    st.freeVertices = 0u;
    st.aovDone = false;
    st.aov.albedo = vec3(0.0);
    st.aov.normal = vec3(0.0);
    st.shadowPending = false;
    st.ended = false;
    st.shadowRay = ray;
    st.shadowTMax = 0.0;
    st.shadowL = vec3(0.0);
    st.stack = uvec4(0u);
    st.segments = 0u;
    return st;
}

// The scattering events that count towards max_depth: `bounces` less the subsurface walks' free
// vertices.
uint pathDepth(PathState st) { return HAS_MEDIA(MEDIA_RANDOM_WALK) ? st.bounces - st.freeVertices : st.bounces; }

// The end of a path after its last vertex's shading: true, unless its shadow ray still waits for
// the next step (CAUSTIC_PAIRED_TRACE), which then only traces it.
bool pathEndsAfterShading(inout PathState st) {
    if (!st.shadowPending) return true;
    st.ended = true;
    return false;
}

// What an unoccluded light sample adds: the path's throughput times f cos / pdf, with the power
// heuristic's weight against BSDF sampling (1 for delta lights or without MIS).
vec3 lightSampleRadiance(vec3 beta, vec3 f, float cosWi, LightSample ls, float pmf, float pdfBsdf, bool misOn) {
    float pl = pmf * ls.pdf;
    float w = (ls.isDelta || !misOn) ? 1.0 : powerHeuristic(pl, pdfBsdf);
    return beta * f * abs(cosWi) * ls.Li * (w / pl);
}

// The most segments a path traces through media (boundaries crossed and scattering events); a path
// that reaches it ends (a guard against a ray caught between boundaries; docs/materials.md).
#define MEDIUM_MAX_PATH_SEGMENTS 1024u

// A medium vertex at distance t along st.ray in medium md (integrator/medium.glsl): the AOVs if
// none were recorded (the medium's single-scattering albedo, a zero normal), next event estimation
// (the phase function for f, no cosine; the shadow ray's transmittance), then the continuation by
// phase-function sampling, whose weight f / pdf is 1, and Russian roulette. True when the path has
// ended.
// betaIn and tMax: the throughput the distance t was sampled with and the segment's length (for the
// MIS weight against equiangular sampling, equiangularDirect).
bool pathMediumVertex(inout PathState st, inout Sampler smp, Medium md, float t, vec3 betaIn, float tMax) {
    uint bounces = st.bounces;
    bool useLights = frame.counts.w != STRATEGY_BSDF_ONLY && frame.counts.y > 0u;
    bool misOn = frame.counts.w == STRATEGY_MIS;
    vec3 p = st.ray.o + t * st.ray.d;
    vec3 d = normalize(st.ray.d);
    st.pathLength += t;
    if (!st.aovDone) {
        st.aovDone = true;
        vec3 sigmaT = md.sigmaA + md.sigmaS;
        st.aov.albedo = md.sigmaS / max(sigmaT, vec3(1e-30));
        st.aov.normal = vec3(0.0);
    }
    // A subsurface interior (md.walk): the walk goes on outside the depth budget, with neither light
    // sampling (a light is outside the object, past a refracting boundary no shadow ray passes) nor
    // Russian roulette (the single-scattering albedo keeps the throughput bounded; the walk ends at
    // MEDIUM_MAX_PATH_SEGMENTS). What it meets when it leaves counts with weight 1.
    if (md.walk) {
        if (st.segments > MEDIUM_MAX_PATH_SEGMENTS) return true;
        float pdfWalk;
        st.ray.o = p;
        st.ray.d = hgSample(d, md.g, sample2D(smp, walkSlot(st.segments)), pdfWalk);
        st.countEmitted = true;
        st.emitScale = 1.0;
        return false;
    }
    uint depth = pathDepth(st);
    if (depth >= frame.counts.z) return true;
    uint li;
    float pmf;
    if (useLights && selectLight(sample1D(smp, bounceSlot(bounces, SLOT_LIGHT_SELECT)), p, vec3(0.0), true, li, pmf)) {
        LightSample ls = sampleLight(li, p, sample2D(smp, bounceSlot(bounces, SLOT_LIGHT)));
        if (ls.pdf > 0.0 && maxComponent(ls.Li) > 0.0) {
            float ph = hgPhase(dot(d, ls.wi), md.g);
            Ray shadow;
            float shadowTMax = FLT_MAX;
            if (ls.dist >= FLT_MAX) {
                shadow.o = p;
                shadow.d = ls.wi;
            } else {
                shadow = segmentRay(p, vec3(0.0), p + ls.dist * ls.wi, ls.nl);
                shadowTMax = 1.0;
            }
            vec3 tr = shadowTransmittance(shadow, shadowTMax, st.stack);
            // A point or spot light: the equiangular strategy could have found it here too.
            uint n = deltaLightCount();
            if (ls.isDelta && n > 0u)
                tr *= powerHeuristic(pmf * freeFlightPdf(md, betaIn, t),
                                     equiangularPdf(st.ray.o, d, tMax, loadLight(li).p0.xyz, t) / float(n));
            if (maxComponent(tr) > 0.0) st.L += tr * lightSampleRadiance(st.beta, vec3(ph), 1.0, ls, pmf, ph, misOn);
        }
    }
    float pdf;
    vec3 wi = hgSample(d, md.g, sample2D(smp, bounceSlot(bounces, SLOT_BSDF_DIR)), pdf);
    st.countEmitted = false;
    st.emitScale = 1.0;
    st.prevBsdfPdf = pdf;
    st.prevP = p;
    st.prevN = vec3(0.0);
    st.prevTwoSided = true;
    st.ray.o = p;
    st.ray.d = wi;
    float q;
    if (russianRouletteEnds(depth, maxComponent(st.beta) * st.etaScale, sample1D(smp, bounceSlot(bounces, SLOT_RR)), q))
        return true;
    st.beta /= q;
    st.bounces = bounces + 1u;
    return false;
}

// Direct light from one point or spot light (chosen uniformly) at a distance along the segment
// (ray, [0, tMax)) sampled equiangularly towards it (integrator/medium.glsl), weighted by the
// power heuristic against free-flight sampling with next event estimation choosing the same light
// (pathMediumVertex weighs that one the other way). beta: the throughput entering the segment.
vec3 equiangularDirect(vec3 beta, Ray ray, float tMax, Medium md, uvec4 stack, inout Sampler smp, uint slot) {
    uint n = deltaLightCount();
    if (n == 0u) return vec3(0.0);
    vec2 u = sample2D(smp, slot);
    uint li = deltaLight(min(uint(u.x * float(n)), n - 1u));
    vec3 c = loadLight(li).p0.xyz;
    float t, pdfEq;
    if (!equiangularSample(ray.o, ray.d, tMax, c, u.y, t, pdfEq)) return vec3(0.0);
    vec3 x = ray.o + t * ray.d;
    LightSample ls = sampleLight(li, x, vec2(0.5));
    if (!(ls.pdf > 0.0) || maxComponent(ls.Li) <= 0.0) return vec3(0.0);
    float pChoose = 1.0 / float(n);
    float w = powerHeuristic(pChoose * pdfEq, lightSelectPmf(li, x, vec3(0.0), true) * freeFlightPdf(md, beta, t));
    vec3 tr = shadowTransmittance(segmentRay(x, vec3(0.0), c, vec3(0.0)), 1.0, stack);
    vec3 sigmaT = md.sigmaA + md.sigmaS;
    return beta * md.sigmaS * exp(-sigmaT * t) * tr * ls.Li * hgPhase(dot(ray.d, ls.wi), md.g) * (w / (pChoose * pdfEq));
}

// What a path step does with what its trace found (found, hit: st.ray's closest hit): the
// emission seen, then at a surface next event estimation and the continuation ray. True when the
// path has ended (st.L and st.aov are then its results).
bool pathShade(inout PathState st, inout Sampler smp, bool found, Hit hit) {
    uint strategy = frame.counts.w;
    uint maxDepth = frame.counts.z;
    bool useLights = strategy != STRATEGY_BSDF_ONLY && frame.counts.y > 0u;
    bool misOn = strategy == STRATEGY_MIS;
    // Texture level of detail: a ray cone of the camera's pixel angle, its width grown along the
    // whole path length (bsdf/material.glsl).
    float pixelSpread = 2.0 * length(frame.camUp.xyz) / float(frame.image.y);
    bool split = (frame.options.x & OPTION_GLASS_SPLIT) != 0u && frame.counts.y > 0u;
    uint bounces = st.bounces, depth = pathDepth(st);

    if (st.probing) {
        st.L += st.probeBeta * probeEmission(found, hit, st.ray.d);
        st.probing = false;
        if (st.pendingEnds) return true;
        st.ray = st.pending;
        return false;
    }
    // Media: the segment just traced ran through the path's medium. It may scatter before its end
    // (a medium vertex), else its transmittance over the probability of passing goes into the
    // throughput before anything at its end uses it. A MAT_VOLUME boundary or a false interface at
    // its end is crossed: the stack changes and the same ray goes on, no scattering event.
    if (CAUSTIC_MEDIA != 0u) {
        Medium md = mediumAt(stackTop(st.stack));
        float tMax = found ? hit.t : FLT_MAX;
        float t;
        vec3 weight, betaIn = st.beta;
        bool scatters = mediumSampleDistance(md, tMax, st.beta, smp, mediumSlot(st.segments), t, weight);
        // Point and spot lights: an equiangular sample along the segment (the scattering event it
        // stands for is this bounce's, so only below the maximum depth).
        if (useLights && mediumScatters(md) && !md.walk && depth < maxDepth)
            st.L += equiangularDirect(betaIn, st.ray, tMax, md, st.stack, smp, equiangularSlot(st.segments));
        st.segments += 1u;
        st.beta *= weight;
        if (maxComponent(st.beta) <= 0.0) return true;
        if (scatters) return pathMediumVertex(st, smp, md, t, betaIn, tMax);
        GpuMaterial boundary;
        if (found) boundary = loadMaterial(hit.material);
        if (found && ((HAS_MEDIA(MEDIA_BOUNDARIES) && boundary.info.x == MAT_VOLUME) ||
                      (boundsInterior(boundary) && interfaceIsFalse(st.stack, hit.material, hit.ng, st.ray.d)))) {
            if (st.segments > MEDIUM_MAX_PATH_SEGMENTS) return true;
            st.stack = stackCross(st.stack, hit.material, hit.ng, st.ray.d);
            st.pathLength += hit.t;
            st.ray.o = offsetRayOrigin(hit.p, hit.ng, st.ray.d);
            return false;
        }
    }
    if (!found) {
        uint envIndex = frame.dispatch.y;
        if (HAS_ANY_ENVIRONMENT && frame.envInfo.x != ENV_NONE) {
            vec3 Le = environmentRadiance(st.ray.d);
            if (st.countEmitted || !useLights) {
                st.L += st.beta * Le * st.emitScale;
            } else if (misOn && envIndex > 0u) {
                float pl = lightSelectPmf(envIndex - 1u, st.prevP, st.prevN, st.prevTwoSided) *
                           lightPdf(envIndex - 1u, st.prevP, st.ray.d, vec3(0.0), vec3(0.0));
                st.L += st.beta * Le * powerHeuristic(st.prevBsdfPdf, pl);
            }
        }
        return true;
    }

    GpuMaterial mat = loadMaterial(hit.material);
    vec3 wo = -st.ray.d;
    // A true interface of nested interiors: the IOR relative to the medium beyond it.
    if (CAUSTIC_MEDIA != 0u && boundsInterior(mat)) mat.params.y /= outsideIor(st.stack, hit.material);

    // Emission.
    vec3 Le = emittedTowards(hit, mat, wo);
    if (maxComponent(Le) > 0.0) {
        if (st.countEmitted || !useLights) {
            st.L += st.beta * Le * st.emitScale;
        } else if (misOn && hit.light > 0u) {
            uint li = hit.light - 1u;
            float pl = lightSelectPmf(li, st.prevP, st.prevN, st.prevTwoSided) * lightPdf(li, st.prevP, st.ray.d, hit.p, hit.ng);
            st.L += st.beta * Le * powerHeuristic(st.prevBsdfPdf, pl);
        }
    }

    // Textures, then the shading frame. Reflection-only models are two-sided: the normal is
    // turned towards the viewer. Transmissive models keep the front (unflipped) normal, so
    // that wo.z < 0 tells them the viewer is inside. A shading normal (normal map) that puts
    // the viewer below the surface falls back to the geometric normal.
    st.pathLength += hit.t;
    float cosHit = abs(dot(hit.ng, wo));
    float coneWidth = pixelSpread * st.pathLength / max(cosHit, 0.1);
    vec3 ns = hit.ns;
    if (CAUSTIC_TEXTURES != 0u && any(notEqual(mat.textures.xyz, uvec3(0u)))) {
        SurfacePoint sp = hitSurface(hit);
        vec3 normalTexel;
        mat = materialAtSurface(mat, sp, coneWidth, normalTexel);
        ns = shadingNormalAt(mat, sp, hit.ns, normalTexel);
    }
    // A surface with a transmission or subsurface part: the part or the rest, chosen here
    // (integrator/surface_parts.glsl); from here on the hit's material is the one chosen.
    uint matIndex = hit.material;
    SurfacePartVertex pv;
    pv.isPart = false;
    if (surfaceHasParts(mat)) {
        st.beta *= surfaceChoosePart(mat, matIndex, wo, hit.ng, ns, st.stack, sample1D(smp, partSlot(bounces)), pv);
        if (boundsInterior(mat)) mat.params.y /= outsideIor(st.stack, matIndex);
    }
    bool keepFront = bsdfHasTransmission(mat);
    float side = dot(hit.ng, wo) < 0.0 && !keepFront ? -1.0 : 1.0;
    vec3 n = side * ns;
    if (dot(n, wo) * dot(side * hit.ng, wo) <= 0.0) n = side * hit.ng;
    if (!st.aovDone && !bsdfIsDelta(mat)) {
        st.aovDone = true;
        st.aov.albedo = aovAlbedo(mat);
        st.aov.normal = dot(n, wo) < 0.0 ? -n : n;  // n: the shading normal, or ng where it fails
    }
    if (depth >= maxDepth) return true;
    Frame f = frameFromNormal(n);
    vec3 woL = toLocal(f, wo);
    float ngWo = dot(hit.ng, wo);

    // Next event estimation.
    uint li;
    float pmf;
    if (useLights && !bsdfIsDelta(mat) &&
        selectLight(sample1D(smp, bounceSlot(bounces, SLOT_LIGHT_SELECT)), hit.p, n, keepFront, li, pmf)) {
        LightSample ls = sampleLight(li, hit.p, sample2D(smp, bounceSlot(bounces, SLOT_LIGHT)));
        if (ls.pdf > 0.0 && maxComponent(ls.Li) > 0.0) {
            vec3 wiL = toLocal(f, ls.wi);
            float pdfBsdf;
            vec3 fv = bsdfEvalPdf(mat, woL, wiL, pdfBsdf);
            if (pv.isPart) fv *= surfacePartFactor(pv, hit.ng, wo, ls.wi, ns);
            // Reflection and transmission as the geometry sees them must agree with the
            // shading frame's (a shading normal must not leak light through the surface).
            if ((woL.z * wiL.z > 0.0) != (ngWo * dot(hit.ng, ls.wi) > 0.0)) fv = vec3(0.0);
            if (maxComponent(fv) > 0.0) {
                // One call site for both kinds of shadow ray: each call inlines the whole
                // traversal, and code size costs speed on the GPU (docs/performance.md).
                Ray shadow;
                float shadowTMax = FLT_MAX;
                if (ls.dist >= FLT_MAX) {
                    shadow.o = offsetRayOrigin(hit.p, hit.ng, ls.wi);
                    shadow.d = ls.wi;
                } else {
                    shadow = segmentRay(hit.p, hit.ng, hit.p + ls.dist * ls.wi, ls.nl);
                    shadowTMax = 1.0;
                }
#ifdef CAUSTIC_PAIRED_TRACE
                st.shadowPending = true;
                st.shadowRay = shadow;
                st.shadowTMax = shadowTMax;
                st.shadowL = lightSampleRadiance(st.beta, fv, wiL.z, ls, pmf, pdfBsdf, misOn);
#else
                if (CAUSTIC_MEDIA != 0u) {
                    // The shadow ray leaves into the interiors on its side of the surface.
                    uvec4 shadowStack = st.stack;
                    if ((dot(hit.ng, ls.wi) > 0.0) != (ngWo > 0.0) && boundsInterior(mat))
                        shadowStack = stackCross(st.stack, matIndex, hit.ng, ls.wi);
                    vec3 tr = shadowTransmittance(shadow, shadowTMax, shadowStack);
                    if (maxComponent(tr) > 0.0)
                        st.L += tr * lightSampleRadiance(st.beta, fv, wiL.z, ls, pmf, pdfBsdf, misOn);
                } else if (!sceneOccluded(shadow, shadowTMax)) {
                    // (computed after the trace: nothing more lives across it, which NVIDIA's
                    // register count rewards)
                    st.L += lightSampleRadiance(st.beta, fv, wiL.z, ls, pmf, pdfBsdf, misOn);
                }
#endif
            }
        }
    }

    // Continuation ray by BSDF sampling.
    vec2 uDir = sample2D(smp, bounceSlot(bounces, SLOT_BSDF_DIR));
    BsdfSample bs = bsdfSample(mat, woL, vec3(uDir, sample1D(smp, bounceSlot(bounces, SLOT_BSDF_LOBE))));
    if (bs.pdf <= 0.0) return pathEndsAfterShading(st);
    vec3 wiW = toWorld(f, bs.wi);
    if (pv.isPart) bs.f *= surfacePartFactor(pv, hit.ng, wo, wiW, ns);
    // Reflection or transmission as the geometry sees it must agree with the shading frame's.
    bool ends = (woL.z * bs.wi.z > 0.0) != (ngWo * dot(hit.ng, wiW) > 0.0);

    // Glass splitting: the lobe not taken is traced next, for the emission it sees alone. Only
    // lobes that leave the medium are probed (wi.z > 0: the dielectric's frame keeps the outward
    // normal): a probe that stays inside a closed glass object would see that object again.
    // A lobe that is probed when not taken has its emission scaled by its probability when
    // taken, so that in expectation its emission is counted once (docs/design.md). The probe
    // is traced even when the continuation is refused or ended by Russian roulette.
    st.emitScale = 1.0;
    vec3 probeDir = vec3(0.0);
    // With nested interiors, only where leaving this object leaves every interior (the probe sees
    // what lies beyond with nothing on the way).
    // A surface's part is not split (its light leaving passes the surface's layers).
    if (CAUSTIC_MEDIA != 0u) split = split && !pv.isPart && stackRemove(st.stack, matIndex + 1u) == uvec4(0u);
    if (HAS_MATERIAL(MAT_DIELECTRIC) && split && mat.info.x == MAT_DIELECTRIC) {
        if (bs.wi.z > 0.0) st.emitScale = bs.pdf;
        BsdfSample other = smoothDielectricOtherLobe(mat, woL, bs);
        probeDir = toWorld(f, other.wi);
        if (other.pdf > 0.0 && other.wi.z > 0.0 &&
            (woL.z * other.wi.z > 0.0) == (ngWo * dot(hit.ng, probeDir) > 0.0)) {
            st.probing = true;
            st.probeBeta = st.beta * other.f * abs(other.wi.z);  // the lobe's weight, not over its pdf
        }
    }

    if (!ends) {
        st.beta *= bs.f * abs(bs.wi.z) / bs.pdf;
        st.countEmitted = (bs.flags & BSDF_FLAG_DELTA) != 0u;
        st.prevBsdfPdf = bs.pdf;
        st.prevP = hit.p;
        st.prevN = n;
        st.prevTwoSided = keepFront;
        if (woL.z * bs.wi.z < 0.0 && !bsdfIsThin(mat)) {  // refraction: eta' is the ratio of the side entered to the side left
            float eta = mat.params.y;
            st.etaScale *= woL.z > 0.0 ? eta * eta : 1.0 / (eta * eta);
            if (CAUSTIC_MEDIA != 0u && boundsInterior(mat)) st.stack = stackCross(st.stack, matIndex, hit.ng, wiW);
        }
        st.ray.o = offsetRayOrigin(hit.p, hit.ng, wiW);
        st.ray.d = wiW;
        float q;
        ends = russianRouletteEnds(depth, maxComponent(st.beta) * st.etaScale, sample1D(smp, bounceSlot(bounces, SLOT_RR)), q);
        if (!ends) {
            st.beta /= q;
            ends = maxComponent(st.beta) <= 0.0;
        }
    }
    if (st.probing) {  // the probe goes first; the continuation waits (or ends after it)
        st.pending = st.ray;
        st.pendingEnds = ends;
        st.ray.o = offsetRayOrigin(hit.p, hit.ng, probeDir);
        st.ray.d = probeDir;
    } else if (ends) {
        return pathEndsAfterShading(st);
    }
    // A subsurface walk's reflection off its boundary from inside is part of the walk: outside the
    // depth budget too (a vertex of its own for the random numbers).
    bool walkReflection = HAS_MEDIA(MEDIA_RANDOM_WALK) && (mat.info.y & MAT_FLAG_RANDOM_WALK) != 0u &&
                          ngWo < 0.0 && dot(hit.ng, wiW) < 0.0;
    if (walkReflection) {
        if (st.segments > MEDIUM_MAX_PATH_SEGMENTS) return pathEndsAfterShading(st);
        st.freeVertices += 1u;
    }
    st.bounces = bounces + 1u;
    return false;
}

#ifdef CAUSTIC_PAIRED_TRACE
// A path step after the walk of its two rays (CAUSTIC_PAIRED_TRACE): found and th are the
// continuation ray's closest hit, occluded whether the last vertex's shadow ray met anything. The
// shadow ray's radiance is added first, as it was at its vertex; a path that had ended with only
// its shadow ray left ends here. (The seam where a wavefront would cut the step: a shade kernel
// would call this with what a walk kernel found; docs/performance.md, "Ideas tried and not kept".)
bool pathResolve(inout PathState st, inout Sampler smp, bool found, TraceHit th, bool occluded) {
    if (st.shadowPending && !occluded) st.L += st.shadowL;
    st.shadowPending = false;
    if (st.ended) return true;
    Hit hit;
    if (found) hit = hitAttributes(st.ray, th);
    return pathShade(st, smp, found, hit);
}

// How many rays a path step traces for st: the continuation ray unless the path has ended, and
// the last vertex's shadow ray when it waits.
uint pathStepRays(PathState st) { return (st.ended ? 0u : 1u) + (st.shadowPending ? 1u : 0u); }
#endif

// One trip through the path loop: traces st.ray (with CAUSTIC_PAIRED_TRACE also the last vertex's
// shadow ray, in one walk) and handles what it finds. True when the path has ended (st.L and
// st.aov are then its results).
bool pathStep(inout PathState st, inout Sampler smp) {
#ifdef CAUSTIC_PAIRED_TRACE
    TraceHit th;
    bool occluded;
    bool found = traceScenePair(!st.ended, st.ray.o, st.ray.d, FLT_MAX, st.shadowPending, st.shadowRay.o,
                                st.shadowRay.d, st.shadowTMax, th, occluded);
    g_rayCount += pathStepRays(st);
    return pathResolve(st, smp, found, th, occluded);
#else
    Hit hit;
    bool found = sceneIntersect(st.ray, FLT_MAX, hit);  // the integrator's one closest-hit call
    return pathShade(st, smp, found, hit);
#endif
}

vec3 pathRadiance(Ray ray, inout Sampler smp, out PathAov aov) {
    PathState st = pathBegin(ray);
    while (!pathStep(st, smp)) {}
    aov = st.aov;
    return st.L;
}

#endif
