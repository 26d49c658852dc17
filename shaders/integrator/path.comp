#version 450 core
// The integrator kernel: frame.dispatch.x samples per pixel per dispatch, each with the random
// numbers of (seed, pixel, sample index) from the sampler (lib/sampler.glsl), summed into the
// accumulation images. A sample that
// is NaN or infinite is dropped, counted in counters[0], and not averaged in.
// The albedo and normal images (the denoiser's guides, written as AOVs) are accumulated in the
// same loop from every sample, dropped ones included (their first hit is still well defined).
#include "path.glsl"
#include "camera.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = BINDING_ACCUM_IMAGE) uniform image2D accumImage;
layout(rgba32f, binding = BINDING_ACCUM_SQ_IMAGE) uniform image2D accumSqImage;
layout(rgba32f, binding = BINDING_ALBEDO_IMAGE) uniform image2D albedoImage;
layout(rgba32f, binding = BINDING_NORMAL_IMAGE) uniform image2D normalImage;

void main() {
    // One work group per 8x8 tile; a dispatch covers tiles [dispatch.z, dispatch.w), numbered row
    // by row, on a grid of work groups that may have a few too many (Renderer::dispatch).
    uint tile = frame.dispatch.z + gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (tile >= frame.dispatch.w) return;
    // The accumulation images cover the crop being rendered (the whole image unless a part of a
    // split render: Renderer::setCrop), whose origin in the image is frame.options.yz; pixel
    // indices and camera rays are those of the whole image, so a crop's pixels are the same.
    uvec2 cropSize = uvec2(imageSize(accumImage));
    uint tilesX = (cropSize.x + 7u) / 8u;
    uvec2 local = uvec2(tile % tilesX, tile / tilesX) * 8u + gl_LocalInvocationID.xy;
    if (local.x >= cropSize.x || local.y >= cropSize.y) return;
    uvec2 pixel = local + frame.options.yz;
    ivec2 ip = ivec2(local);
    vec4 sum = imageLoad(accumImage, ip);
    vec4 sumSq = imageLoad(accumSqImage, ip);
    vec4 albedoSum = imageLoad(albedoImage, ip);
    vec4 normalSum = imageLoad(normalImage, ip);
    uint pixelIndex = pixel.y * frame.image.x + pixel.x;
    uint dropped = 0u;
    for (uint s = 0u; s < frame.dispatch.x; ++s) {
        Sampler smp = samplerStart(frame.sampling.x, pixelIndex, frame.image.z + s, frame.image.w);
        vec2 uFilter = sample2D(smp, SLOT_FILTER);
        Ray ray = cameraRay(pixel, uFilter, sample2D(smp, SLOT_LENS));
        PathAov aov;
        vec3 L = pathRadiance(ray, smp, aov);
        albedoSum += vec4(aov.albedo, 1.0);
        normalSum += vec4(aov.normal, 1.0);
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
    imageStore(albedoImage, ip, albedoSum);
    imageStore(normalImage, ip, normalSum);
}
