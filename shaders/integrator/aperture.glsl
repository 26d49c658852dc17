// The camera's aperture image (Camera::apertureImage, GpuFrame::aperture): a greyscale mask over
// the square [-1, 1]^2 that circumscribes the aperture's circle (the thin lens's, or a lens
// system's stop), +y up. The thin lens draws its lens samples from it in proportion to its
// transmission; a lens system's stop multiplies a ray's weight by it (integrator/lens_camera.glsl).
// Its tables are the tables buffer's (renderer/gpu_scene.h, ApertureImage).
#ifndef INTEGRATOR_APERTURE_GLSL
#define INTEGRATOR_APERTURE_GLSL
#include "../scene/buffers.glsl"

// A point of the aperture image's square [-1, 1]^2 (+y up: its row 0 is the top) with density
// proportional to its texels: a row by the row CDF, a texel by that row's CDF, then uniform in the
// texel (the environment map's scheme; binary searches, an image has at most 256 texels a side).
// Each search finds the last entry <= u, so rows and texels of zero weight are never chosen.
vec2 sampleApertureImage(vec2 u) {
    uint base = frame.aperture.x, w = frame.aperture.y, h = frame.aperture.z;
    uint lo = 0u, hi = h;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (sceneTable(base + mid) <= u.y) lo = mid; else hi = mid;
    }
    uint row = lo;
    float c0 = sceneTable(base + row), c1 = sceneTable(base + row + 1u);
    float fy = clamp((u.y - c0) / max(c1 - c0, 1e-30), 0.0, 1.0);
    uint rowBase = base + h + 1u + row * (w + 1u);
    lo = 0u;
    hi = w;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (sceneTable(rowBase + mid) <= u.x) lo = mid; else hi = mid;
    }
    float d0 = sceneTable(rowBase + lo), d1 = sceneTable(rowBase + lo + 1u);
    float fx = clamp((u.x - d0) / max(d1 - d0, 1e-30), 0.0, 1.0);
    vec2 p = vec2((float(lo) + fx) / float(w), (float(row) + fy) / float(h));
    return vec2(2.0 * p.x - 1.0, 1.0 - 2.0 * p.y);
}

// The aperture image's transmission at a point of its square [-1, 1]^2 (0 outside), nearest texel.
float apertureTransmission(vec2 p) {
    if (any(greaterThan(abs(p), vec2(1.0)))) return 0.0;
    uint w = frame.aperture.y, h = frame.aperture.z;
    uint x = min(uint((p.x * 0.5 + 0.5) * float(w)), w - 1u);
    uint y = min(uint((0.5 - p.y * 0.5) * float(h)), h - 1u);
    return sceneTable(frame.aperture.x + h + 1u + h * (w + 1u) + y * w + x);
}

#endif
