// Camera rays. Pinhole: the pixel's jittered position on the image plane at distance 1, with the
// half-extents tan(fov/2) folded into camRight / camUp on the CPU. Image row 0 is the top.
// The pixel filter is a box: the jitter is uniform over the pixel.
#ifndef INTEGRATOR_CAMERA_GLSL
#define INTEGRATOR_CAMERA_GLSL
#include "../geometry/intersect.glsl"

Ray cameraRay(uvec2 pixel, vec2 jitter) {
    vec2 size = vec2(frame.image.xy);
    vec2 ndc = vec2(2.0 * (float(pixel.x) + jitter.x) / size.x - 1.0,
                    1.0 - 2.0 * (float(pixel.y) + jitter.y) / size.y);
    Ray r;
    r.o = frame.camPosition.xyz;
    r.d = normalize(frame.camForward.xyz + ndc.x * frame.camRight.xyz + ndc.y * frame.camUp.xyz);
    return r;
}

#endif
