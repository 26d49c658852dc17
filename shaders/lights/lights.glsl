// Light sampling for next event estimation, and the pdfs that multiple importance sampling needs
// when a BSDF-sampled ray hits an emitter.
//
// Conventions (docs/scene-format.md): area lights and the environment are given in radiance
// (W sr^-1 m^-2), point and spot lights in intensity (W sr^-1). All pdfs returned here are per
// unit solid angle at the shading point and do NOT include the probability of choosing the light
// (that is light_select.glsl's lightSelectPmf).
//
// Sidedness: area lights (rect, sphere, mesh) emit from both faces when LIGHT_FLAG_TWO_SIDED is
// set (rect lights with two_sided, emissive materials), else from their front only (rect lights,
// objects with their own "emission"); the primitive or instance then carries
// PRIM_FLAG_ONE_SIDED_EMITTER, so a BSDF-sampled ray that hits the back sees no emission, and the
// light sampler returns pdf 0 for points behind the emitter, so both strategies agree.
// rect:   uniform point on the parallelogram; p_area = 1/A, p_omega = r^2 / (|cos theta_l| A).
//         The front is cross(edge u, edge v).
// sphere: outside: uniform direction in the cone that subtends the sphere,
//         cos theta_max = sqrt(1 - R^2/d^2), p_omega = 1 / (2 pi (1 - cos theta_max))
//         (PBRT 4th ed. sec. 6.2.4): every point of that cap faces the shading point, so sidedness
//         does not matter there; inside: uniform point on the surface, converted to solid angle,
//         or nothing when one-sided (its front is the outside).
// point:  a delta light, L_i = I / r^2.
// spot:   a point light times smoothstep(cos outer, cos inner, cos theta) (PBRT 4th ed. 12.2.2),
//         or with LIGHT_FLAG_LINEAR_ANGLE times clamp((outer - theta) / (outer - inner), 0, 1)
//         (Mitsuba 3's spot); docs/scene-format.md.
// mesh:   an emissive mesh instance: a triangle chosen in proportion to its world area (emitting
//         triangles only), a uniform point on it; p_omega = r^2 / (|cos theta_l| A_emitting); the
//         radiance is that triangle's material's. The front is the side of the object-space
//         cross(p1 - p0, p2 - p0) (counter-clockwise winding seen from the front). A point an
//         alpha mask cuts out gives no sample (rays pass through it, so nothing is lost: the
//         estimate stays that of the area that is there, with the same pdf both strategies use).
// Emission textures (LIGHT_FLAG_EMISSION_TEXTURE): rect, sphere and mesh lights multiply the
// radiance by the material's emission texture at the sampled point (bsdf/material.glsl,
// emissionTexel; rect: its (alpha, beta), sphere: primitiveSurface's angles, mesh: the vertex
// UVs), exactly what a ray that hits the point sees; the sampling density stays uniform in area
// (the texture is not importance-sampled), so the pdfs, and MIS, are unchanged.
// env:    a map is importance-sampled by its luminance table (environment.glsl); the constant
//         colour and the smooth sky use uniform directions on the sphere, p_omega = 1/(4 pi).
#ifndef LIGHTS_LIGHTS_GLSL
#define LIGHTS_LIGHTS_GLSL
#include "../lib/sampling.glsl"
#include "../scene/buffers.glsl"
#include "environment.glsl"
#include "../geometry/surface.glsl"
#include "../geometry/alpha_mask.glsl"
#include "../bsdf/material.glsl"

struct LightSample {
    vec3 wi;       // unit direction from the shading point towards the light
    float dist;    // distance to the sampled point (FLT_MAX for the environment)
    vec3 nl;       // unit surface normal at the sampled point (area lights), else 0
    vec3 Li;       // incident radiance (or intensity / r^2 for delta lights)
    float pdf;     // solid-angle pdf (1 for delta lights), 0 if the sample is invalid
    bool isDelta;
};

// Solid-angle pdf of sampling direction wi from `p` towards point `q` on an area light with unit
// normal `nl`, given the area pdf 1/area.
float areaToSolidAngle(float pdfArea, vec3 p, vec3 q, vec3 nl) {
    vec3 d = q - p;
    float dist2 = dot(d, d);
    float cosL = abs(dot(nl, d)) * inversesqrt(dist2);
    return cosL > 0.0 ? pdfArea * dist2 / cosL : 0.0;
}

LightSample sampleLight(uint index, vec3 p, vec2 u) {
    GpuLight l = loadLight(index);
    LightSample s;
    s.isDelta = false;
    s.pdf = 0.0;
    s.Li = vec3(0.0);
    s.dist = 0.0;
    s.nl = vec3(0.0);
    s.wi = vec3(0.0, 0.0, 1.0);
    uint type = l.info.x;
    // Each type is guarded by HAS_LIGHT (scene/features.glsl): a scene-specialised program keeps
    // only the types its scene has.
    if (HAS_LIGHT(LIGHT_RECT) && type == LIGHT_RECT) {
        vec3 q = l.p0.xyz + u.x * l.p1.xyz + u.y * l.p2.xyz;
        vec3 n = normalizeScaled(cross(l.p1.xyz, l.p2.xyz));
        vec3 d = q - p;
        float dist2 = dot(d, d);
        if (dist2 <= 0.0) return s;
        s.dist = sqrt(dist2);
        s.wi = d / s.dist;
        float cosL = -dot(n, s.wi);
        if (cosL <= 0.0 && (l.info.y & LIGHT_FLAG_TWO_SIDED) == 0u) return s;
        cosL = abs(cosL);
        if (cosL <= 0.0) return s;
        s.pdf = dist2 / (cosL * l.p1.w);
        s.nl = n;
        s.Li = l.color.rgb;
        // u is the point's (alpha, beta) on the quad: its texture coordinates (geometry/surface.glsl).
        if (CAUSTIC_EMISSION_TEXTURES != 0u && (l.info.y & LIGHT_FLAG_EMISSION_TEXTURE) != 0u)
            s.Li *= emissionTexel(loadMaterial(loadPrimitive(l.info.z).info.y), u);
    } else if (HAS_LIGHT(LIGHT_SPHERE) && type == LIGHT_SPHERE) {
        vec3 c = l.p0.xyz;
        float radius = l.p0.w;
        vec3 toC = c - p;
        float d2 = dot(toC, toC);
        if (d2 > radius * radius * 1.00001) {
            float d = sqrt(d2);
            vec3 axis = toC / d;
            float sin2Max = radius * radius / d2;
            float cosMax = safeSqrt(1.0 - sin2Max);
            // For tiny cones, 1 - cosMax cancels; use the series 1 - cos = sin^2/2 + sin^4/8.
            float oneMinusCos = sin2Max < 1e-3 ? 0.5 * sin2Max + 0.125 * sin2Max * sin2Max : 1.0 - cosMax;
            vec3 local = sampleUniformCone(u, 1.0 - oneMinusCos);
            Frame f = frameFromNormal(axis);
            s.wi = normalize(toWorld(f, local));
            // Distance to the near side of the sphere along wi.
            float b = dot(toC, s.wi);
            float h2 = max(d2 - b * b, 0.0);
            s.dist = b - safeSqrt(radius * radius - h2);
            s.nl = normalize(p + s.dist * s.wi - c);
            s.pdf = 1.0 / (2.0 * PI * oneMinusCos);
        } else {
            if ((l.info.y & LIGHT_FLAG_TWO_SIDED) == 0u) return s;  // inside a one-sided sphere
            vec3 n = sampleUniformSphere(u);
            vec3 q = c + radius * n;
            vec3 d = q - p;
            float dist2 = dot(d, d);
            if (dist2 <= 0.0) return s;
            s.dist = sqrt(dist2);
            s.wi = d / s.dist;
            s.pdf = areaToSolidAngle(1.0 / (4.0 * PI * radius * radius), p, q, n);
            s.nl = n;
        }
        s.Li = l.color.rgb;
        if (CAUSTIC_EMISSION_TEXTURES != 0u && (l.info.y & LIGHT_FLAG_EMISSION_TEXTURE) != 0u) {
            GpuPrimitive prim = loadPrimitive(l.info.z);
            s.Li *= emissionTexel(loadMaterial(prim.info.y), primitiveSurface(prim, p + s.dist * s.wi).uv);
        }
    } else if ((HAS_LIGHT(LIGHT_POINT) || HAS_LIGHT(LIGHT_SPOT)) && (type == LIGHT_POINT || type == LIGHT_SPOT)) {
        vec3 d = l.p0.xyz - p;
        float dist2 = dot(d, d);
        if (dist2 <= 0.0) return s;
        s.dist = sqrt(dist2);
        s.wi = d / s.dist;
        s.isDelta = true;
        s.pdf = 1.0;
        float falloff = 1.0;
        if (HAS_LIGHT(LIGHT_SPOT) && type == LIGHT_SPOT) {
            float cosTheta = dot(-s.wi, l.p1.xyz);
            if ((l.info.y & LIGHT_FLAG_LINEAR_ANGLE) == 0u) {
                falloff = smoothstep(l.p1.w, l.p2.w, cosTheta);
            } else {
                // The angle from its sine and cosine (atan2 is accurate at every angle; acos near
                // cos = 1 loses the angle's low bits, and llvmpipe's acos was ~6e-5 rad off at 35
                // degrees).
                float theta = atan(length(cross(-s.wi, l.p1.xyz)), cosTheta);
                falloff = theta <= l.p2.y ? 1.0 : clamp((l.p2.x - theta) / max(l.p2.x - l.p2.y, 1e-7), 0.0, 1.0);
            }
        }
        s.Li = l.color.rgb * falloff / dist2;
    } else if (HAS_LIGHT(LIGHT_MESH) && type == LIGHT_MESH) {
        // A triangle by area (binary search of the instance's CDF), then a uniform point in it
        // (PBRT 4th ed. eq. A.12, the square-root parametrisation), reusing u.x's remainder.
        GpuInstance inst = loadInstance(l.info.z);
        uint offset = l.info.w, count = inst.triangleCount;
        uint lo = 0u, hi = count - 1u;
        while (lo < hi) {
            uint mid = (lo + hi) >> 1;
            if (u.x < meshLightCdf(offset + mid)) hi = mid; else lo = mid + 1u;
        }
        float c0 = lo > 0u ? meshLightCdf(offset + lo - 1u) : 0.0, c1 = meshLightCdf(offset + lo);
        float ux = c1 > c0 ? clamp((u.x - c0) / (c1 - c0), 0.0, 1.0) : 0.5;
        GpuTriangle tri = loadTriangle(inst.firstTriangle + lo);
        float su = sqrt(ux);
        vec2 b = vec2(su * (1.0 - u.y), su * u.y);  // weights of p1 and p2
        vec3 qo = (1.0 - b.x - b.y) * tri.p0.xyz + b.x * tri.p1.xyz + b.y * tri.p2.xyz;
        vec3 q = vec3(dot(inst.objectToWorld0, vec4(qo, 1.0)), dot(inst.objectToWorld1, vec4(qo, 1.0)),
                      dot(inst.objectToWorld2, vec4(qo, 1.0)));
        vec3 n = normalize(instanceNormalToWorld(inst, cross(tri.p1.xyz - tri.p0.xyz, tri.p2.xyz - tri.p0.xyz)));
        vec3 d = q - p;
        float dist2 = dot(d, d);
        if (dist2 <= 0.0) return s;
        if (dot(n, d) >= 0.0 && (l.info.y & LIGHT_FLAG_TWO_SIDED) == 0u) return s;  // its back faces p
        s.dist = sqrt(dist2);
        s.wi = d / s.dist;
        s.nl = n;
        // A point an alpha mask cuts out is not there (a ray through it passes): no sample.
        if (!alphaMaskKeeps(inst, tri, b)) return s;
        s.pdf = areaToSolidAngle(1.0 / l.p0.x, p, q, n);
        GpuMaterial em = loadMaterial(triangleMaterial(inst, tri));
        s.Li = CAUSTIC_EMISSION_TEXTURES != 0u && (l.info.y & LIGHT_FLAG_EMISSION_TEXTURE) != 0u
                   ? materialEmission(em, triangleUv(tri, b)) : em.emission.rgb;
    } else if (HAS_LIGHT(LIGHT_ENV) && type == LIGHT_ENV) {
        if (HAS_ENVIRONMENT(ENV_MAP) && frame.envInfo.x == ENV_MAP) {
            s.wi = sampleEnvironmentMap(u, s.pdf);
        } else {
            s.wi = sampleUniformSphere(u);
            s.pdf = uniformSpherePdf();
        }
        s.dist = FLT_MAX;
        s.Li = environmentRadiance(s.wi);
    }
    return s;
}

// Solid-angle pdf that sampleLight(index, p, .) produces direction wi hitting the light at q
// (with unit geometric normal nl there). For the environment q and nl are unused.
float lightPdf(uint index, vec3 p, vec3 wi, vec3 q, vec3 nl) {
    GpuLight l = loadLight(index);
    uint type = l.info.x;
    if (HAS_LIGHT(LIGHT_RECT) && type == LIGHT_RECT) {
        if (dot(nl, wi) >= 0.0 && (l.info.y & LIGHT_FLAG_TWO_SIDED) == 0u) return 0.0;
        return areaToSolidAngle(1.0 / l.p1.w, p, q, nl);
    }
    if (HAS_LIGHT(LIGHT_SPHERE) && type == LIGHT_SPHERE) {
        vec3 toC = l.p0.xyz - p;
        float d2 = dot(toC, toC);
        float radius = l.p0.w;
        if (d2 > radius * radius * 1.00001) {
            float sin2Max = radius * radius / d2;
            float oneMinusCos = sin2Max < 1e-3 ? 0.5 * sin2Max + 0.125 * sin2Max * sin2Max : 1.0 - safeSqrt(1.0 - sin2Max);
            return 1.0 / (2.0 * PI * oneMinusCos);
        }
        if ((l.info.y & LIGHT_FLAG_TWO_SIDED) == 0u) return 0.0;
        return areaToSolidAngle(1.0 / (4.0 * PI * radius * radius), p, q, nl);
    }
    if (HAS_LIGHT(LIGHT_MESH) && type == LIGHT_MESH) {
        if (dot(nl, wi) >= 0.0 && (l.info.y & LIGHT_FLAG_TWO_SIDED) == 0u) return 0.0;
        return areaToSolidAngle(1.0 / l.p0.x, p, q, nl);
    }
    if (HAS_LIGHT(LIGHT_ENV) && type == LIGHT_ENV) return HAS_ENVIRONMENT(ENV_MAP) && frame.envInfo.x == ENV_MAP ? environmentMapPdf(wi) : uniformSpherePdf();
    return 0.0;  // delta lights cannot be hit
}

#endif
