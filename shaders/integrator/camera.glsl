// Camera rays: a pinhole or a thin lens, with an importance-sampled pixel filter (a lens system:
// integrator/lens_camera.glsl).
//
// Pinhole: the jittered position on the image plane at distance 1, with the half-extents
// tan(fov/2) folded into camRight / camUp on the CPU. Image row 0 is the top.
// Thin lens (PBRT 4th ed. sec. 5.2.3): the pinhole ray is extended to the plane of focus,
// t = focalDistance / (dir . forward); the origin moves to a point on the lens and the ray aims at
// that point of focus, so the plane of focus stays sharp and other depths blur into a circle of
// confusion of radius aperture * |z - focal| / z (measured on the plane of focus).
// The lens sample: Shirley-Chiu's concentric disk for a round aperture, a uniform point in a
// regular polygon of `blades` sides (rotated by blade rotation), or a point of the aperture image
// drawn in proportion to its transmission (integrator/aperture.glsl; the sample's weight stays
// 1). Anamorphic: its x is divided by the squeeze factor before scaling by the aperture, so the
// bokeh is an oval `squeeze` times taller than wide.
// Pixel filters are importance-sampled (sample weights stay 1): box uniform over the pixel; tent
// of radius 1 by inverting its CDF; Gaussian sigma 0.5 by Box-Muller, truncated at 1.5 pixels.
#ifndef INTEGRATOR_CAMERA_GLSL
#define INTEGRATOR_CAMERA_GLSL
#include "../geometry/intersect.glsl"
#include "../lib/sampling.glsl"
#include "../scene/features.glsl"
#include "aperture.glsl"
#include "lens_camera.glsl"

// Inverse CDF of the tent filter on [-1, 1] for u in [0, 1).
float sampleTent(float u) {
    return u < 0.5 ? sqrt(2.0 * u) - 1.0 : 1.0 - sqrt(2.0 - 2.0 * u);
}

// Offset of the sample from the pixel centre, in pixels.
vec2 samplePixelFilter(vec2 u) {
    uint filterType = frame.camInfo.y;
    if (filterType == FILTER_TENT) return vec2(sampleTent(u.x), sampleTent(u.y));
    if (filterType == FILTER_GAUSSIAN) {
        // Box-Muller; the rare offsets beyond 1.5 pixels (0.27%) are folded back by clamping.
        float r = 0.5 * sqrt(-2.0 * log(max(1.0 - u.x, 1e-12)));
        return clamp(r * vec2(cos(2.0 * PI * u.y), sin(2.0 * PI * u.y)), vec2(-1.5), vec2(1.5));
    }
    return u - 0.5;
}

// Uniform point in the regular n-gon inscribed in the unit circle, one vertex at angle `rotation`:
// choose one of the n triangles of the fan around the centre, then a uniform point in it.
vec2 samplePolygon(vec2 u, uint n, float rotation) {
    float fn = float(n);
    float k = min(floor(u.x * fn), fn - 1.0);
    float ux = u.x * fn - k;                       // reuse the remainder
    float a0 = rotation + 2.0 * PI * k / fn, a1 = a0 + 2.0 * PI / fn;
    vec2 v0 = vec2(cos(a0), sin(a0)), v1 = vec2(cos(a1), sin(a1));
    float su = sqrt(ux);                           // uniform in triangle (0, v0, v1)
    return su * ((1.0 - u.y) * v0 + u.y * v1);
}

// The sample's position in the image in normalised device coordinates ([-1, 1]^2, +y up): the
// pixel's centre plus the pixel filter's offset.
vec2 cameraNdc(uvec2 pixel, vec2 uFilter) {
    vec2 size = vec2(frame.image.xy);
    vec2 p = vec2(pixel) + 0.5 + samplePixelFilter(uFilter);
    return vec2(2.0 * p.x / size.x - 1.0, 1.0 - 2.0 * p.y / size.y);
}

Ray cameraRay(uvec2 pixel, vec2 uFilter, vec2 uLens) {
    vec2 ndc = cameraNdc(pixel, uFilter);
    Ray r;
    r.o = frame.camPosition.xyz;
    r.d = normalize(frame.camForward.xyz + ndc.x * frame.camRight.xyz + ndc.y * frame.camUp.xyz);
    float aperture = frame.camLens.x;
    if (aperture > 0.0) {
        // The ray through the lens point aims at the pinhole ray's point on the plane of focus,
        // o + d s with s = focal / (d . forward): its direction is (d s - offset) / |...|, computed
        // as d - offset / s, whose length stays near 1 (the far point's would overflow a float's
        // square beyond a focal distance of ~1e19).
        float s = frame.camLens.y / dot(r.d, frame.camForward.xyz);
        vec2 lens = HAS_CAMERA(CAMERA_APERTURE_IMAGE) && frame.aperture.w != 0u ? sampleApertureImage(uLens)
                    : frame.camInfo.x >= 3u ? samplePolygon(uLens, frame.camInfo.x, frame.camLens.w)
                                            : sampleConcentricDisk(uLens);
        lens.x /= frame.camLens.z;
        vec3 right = normalize(frame.camRight.xyz), up = normalize(frame.camUp.xyz);
        vec3 offset = aperture * (lens.x * right + lens.y * up);
        r.o += offset;
        r.d = normalize(r.d - offset / s);
    }
    return r;
}

// The integrator's camera ray and its weight per channel: the thin lens's (weight 1), or a lens
// system's where the camera has one (integrator/lens_camera.glsl; compiled out of programs
// specialised for scenes without, CAUSTIC_CAMERA).
Ray cameraRayWeighted(uvec2 pixel, vec2 uFilter, vec2 uLens, out vec3 weight) {
    weight = vec3(1.0);
    if (HAS_CAMERA(CAMERA_LENS_SYSTEM) && frame.camInfo.z != 0u) return lensCameraRay(cameraNdc(pixel, uFilter), uLens, weight);
    return cameraRay(pixel, uFilter, uLens);
}

#endif
