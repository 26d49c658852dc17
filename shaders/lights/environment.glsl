// The environment: what a ray that leaves the scene sees, and what the environment light emits.
// One lookup serves both, so escaped rays and light samples always agree.
//   constant: a uniform radiance.
//   sky:      a gradient from the horizon radiance (at and below the horizon) to the zenith
//             radiance straight up, blended with sqrt(max(y, 0)) so that the bright horizon band is
//             wider than a linear blend would make it. +y is up.
//   map:      an equirectangular HDR image, bilinearly filtered. Direction <-> (u, v) in [0,1]^2:
//             theta = pi v from +y (v = 0 is the top row), phi = 2 pi (u - 1/2) measured from -z
//             towards +x, so the image centre is straight ahead of the default camera (-z):
//             d = (sin theta sin phi, cos theta, -sin theta cos phi). `rotation` turns the map
//             about +y. Importance sampling picks a cell of the two-level CDF built on the CPU
//             (W x H cells: frame.envInfo.w per texel and axis; pdf_uv = p_row p_col W H), a
//             uniform point in it, and converts: pdf_omega = pdf_uv / (2 pi^2 sin theta)
//             (PBRT 4th ed. eq. 12.10).
#ifndef LIGHTS_ENVIRONMENT_GLSL
#define LIGHTS_ENVIRONMENT_GLSL
#include "../lib/math.glsl"
#include "../scene/buffers.glsl"

// World direction -> the map's (u, v), after undoing the rotation about +y.
vec2 envDirectionToUv(vec3 dir) {
    float c = frame.envMap.x, s = frame.envMap.y;
    vec3 d = vec3(c * dir.x - s * dir.z, dir.y, s * dir.x + c * dir.z);  // R_y(-rotation) dir
    float theta = acos(clamp(d.y, -1.0, 1.0));
    float phi = atan(d.x, -d.z);
    return vec2(phi * (0.5 * INV_PI) + 0.5, theta * INV_PI);
}

vec3 envUvToDirection(vec2 uv) {
    float theta = PI * uv.y, phi = 2.0 * PI * (uv.x - 0.5);
    float sinTheta = sin(theta);
    vec3 d = vec3(sinTheta * sin(phi), cos(theta), -sinTheta * cos(phi));
    float c = frame.envMap.x, s = frame.envMap.y;
    return vec3(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);  // R_y(rotation) d
}

vec3 environmentRadiance(vec3 dir) {
    uint type = frame.envInfo.x;
    if (HAS_ENVIRONMENT(ENV_CONSTANT) && type == ENV_CONSTANT) return frame.envRadiance.rgb;
    if (HAS_ENVIRONMENT(ENV_SKY) && type == ENV_SKY) {
        float t = sqrt(clamp(dir.y, 0.0, 1.0));
        return mix(frame.envHorizon.rgb, frame.envZenith.rgb, t);
    }
    if (HAS_ENVIRONMENT(ENV_MAP) && type == ENV_MAP) return frame.envMap.z * textureLod(envMapTexture, envDirectionToUv(dir), 0.0).rgb;
    return vec3(0.0);
}

// Index i with cdf[offset + i] <= u < cdf[offset + i + 1], for a CDF of n + 1 entries: the
// largest i < n with cdf[offset + i] <= u. The guide table at `guide` (2^guideLog2 + 1 entries,
// renderer/gpu_scene.h) bounds it to [guide[k], guide[k + 1]] for the bucket k of u (u 2^guideLog2
// is exact), and a binary search finds it there: the same index as a search over the whole CDF,
// in a step or two instead of log2 n (each a storage-buffer load, a loop over the lanes on
// llvmpipe).
uint envFindInterval(bool marginal, uint offset, uint guide, uint guideLog2, float u) {
    uint buckets = 1u << guideLog2;
    uint k = min(uint(u * float(buckets)), buckets - 1u);
    uint lo = uint(sceneTable(guide + k)), hi = uint(sceneTable(guide + k + 1u));
    while (lo < hi) {
        uint mid = (lo + hi + 1u) >> 1;
        float c = marginal ? envMarginalCdf(offset + mid) : envConditionalCdf(offset + mid);
        if (c <= u) lo = mid; else hi = mid - 1u;
    }
    return lo;
}

// Samples a direction from the map's luminance; returns the solid-angle pdf (0 if degenerate).
vec3 sampleEnvironmentMap(vec2 u, out float pdf) {
    uint w = frame.envInfo.y * frame.envInfo.w, h = frame.envInfo.z * frame.envInfo.w;
    uint j = envFindInterval(true, 0u, frame.envGuide.x, frame.envGuide.z, u.y);
    float r0 = envMarginalCdf(j), r1 = envMarginalCdf(j + 1u);
    uint rowOffset = j * (w + 1u);
    uint i = envFindInterval(false, rowOffset, frame.envGuide.y + j * ((1u << frame.envGuide.w) + 1u), frame.envGuide.w, u.x);
    float c0 = envConditionalCdf(rowOffset + i), c1 = envConditionalCdf(rowOffset + i + 1u);
    float pRow = r1 - r0, pCol = c1 - c0;
    // Continuous position inside the chosen texel (reusing the leftover of each random number).
    float dv = pRow > 0.0 ? clamp((u.y - r0) / pRow, 0.0, 1.0) : 0.5;
    float du = pCol > 0.0 ? clamp((u.x - c0) / pCol, 0.0, 1.0) : 0.5;
    vec2 uv = vec2((float(i) + du) / float(w), (float(j) + dv) / float(h));
    float sinTheta = sin(PI * uv.y);
    pdf = sinTheta > 0.0 ? pRow * pCol * float(w * h) / (2.0 * PI * PI * sinTheta) : 0.0;
    return envUvToDirection(uv);
}

float environmentMapPdf(vec3 dir) {
    uint w = frame.envInfo.y * frame.envInfo.w, h = frame.envInfo.z * frame.envInfo.w;
    vec2 uv = envDirectionToUv(dir);
    uint i = min(uint(uv.x * float(w)), w - 1u);
    uint j = min(uint(uv.y * float(h)), h - 1u);
    float pRow = envMarginalCdf(j + 1u) - envMarginalCdf(j);
    uint rowOffset = j * (w + 1u);
    float pCol = envConditionalCdf(rowOffset + i + 1u) - envConditionalCdf(rowOffset + i);
    float sinTheta = sin(PI * uv.y);
    return sinTheta > 0.0 ? pRow * pCol * float(w * h) / (2.0 * PI * PI * sinTheta) : 0.0;
}

#endif
