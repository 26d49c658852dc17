#version 450 core
// The integrator kernel: frame.dispatch.x samples per pixel per dispatch, each from its own
// random stream (pixel, sample index, seed), summed into the accumulation images. A sample that
// is NaN or infinite is dropped, counted in counters[0], and not averaged in.
#include "path.glsl"
#include "camera.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = BINDING_ACCUM_IMAGE) uniform image2D accumImage;
layout(rgba32f, binding = BINDING_ACCUM_SQ_IMAGE) uniform image2D accumSqImage;

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= frame.image.x || pixel.y >= frame.image.y) return;
    ivec2 ip = ivec2(pixel);
    vec4 sum = imageLoad(accumImage, ip);
    vec4 sumSq = imageLoad(accumSqImage, ip);
    uint pixelIndex = pixel.y * frame.image.x + pixel.x;
    uint dropped = 0u;
    for (uint s = 0u; s < frame.dispatch.x; ++s) {
        uint rng = rngInit(pixelIndex, frame.image.z + s, frame.image.w);
        vec2 uFilter = rngNext2(rng);
        Ray ray = cameraRay(pixel, uFilter, rngNext2(rng));
        vec3 L = pathRadiance(ray, rng);
        if (any(isnan(L)) || any(isinf(L))) { ++dropped; continue; }
        sum += vec4(L, 1.0);
        sumSq += vec4(L * L, 0.0);
    }
    if (dropped > 0u) atomicAdd(counters[COUNTER_DROPPED], dropped);
    // A 64-bit ray count from two 32-bit words: carry into the high word on wrap-around.
    uint before = atomicAdd(counters[COUNTER_RAYS_LO], g_rayCount);
    if (before + g_rayCount < before) atomicAdd(counters[COUNTER_RAYS_HI], 1u);
    imageStore(accumImage, ip, sum);
    imageStore(accumSqImage, ip, sumSq);
}
