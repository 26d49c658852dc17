#version 450 core
// caustic-bench --rays: traversal speed alone, no shading. One invocation per pixel.
//   u_pass 0 (primary): the camera ray of the pixel (pinhole through the pixel's centre jittered
//     by the sample's random numbers), closest hit; writes the hit point and geometric normal.
//   u_pass 1 (diffuse): from the stored hit point a cosine-distributed direction about the normal
//     (incoherent rays, as the first bounce of a path tracer), closest hit.
// Each pass counts its hits into counters[0], so the benchmark can tell it traced real geometry.
#include "../integrator/camera.glsl"
#include "../lib/rng.glsl"
#include "../lib/sampling.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer HitPoints { vec4 hitPoints[]; };  // 2 per pixel
uniform uint u_pass;
uniform uint u_sample;

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= frame.image.x || pixel.y >= frame.image.y) return;
    uint index = pixel.y * frame.image.x + pixel.x;
    uint rng = rngInit(index, u_sample, 0x9e3779b9u);
    Hit hit;
    bool found;
    if (u_pass == 0u) {
        Ray ray = cameraRay(pixel, rngNext2(rng), vec2(0.5));
        found = sceneIntersect(ray, FLT_MAX, hit);
        hitPoints[2u * index] = vec4(found ? hit.p : vec3(0.0), found ? 1.0 : 0.0);
        // The normal on the side the ray came from.
        vec3 n = dot(hit.ng, ray.d) < 0.0 ? hit.ng : -hit.ng;
        hitPoints[2u * index + 1u] = vec4(found ? n : vec3(0.0), 0.0);
    } else {
        vec4 p = hitPoints[2u * index];
        if (p.w == 0.0) return;
        vec3 n = hitPoints[2u * index + 1u].xyz;
        Frame f = frameFromNormal(n);
        vec3 d = toWorld(f, sampleCosineHemisphere(rngNext2(rng)));
        Ray ray;
        ray.d = d;
        ray.o = offsetRayOrigin(p.xyz, n, d);
        found = sceneIntersect(ray, FLT_MAX, hit);
    }
    if (found) atomicAdd(counters[0], 1u);
}
