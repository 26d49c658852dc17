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

// The pixel's sums over the dispatch's samples (the accumulation images' texels, added to).
struct PixelSums {
    vec4 sum, sumSq, albedo, normal;
    uint dropped;
};

// Sample s of the dispatch at `pixel`: its sampler (the random numbers of seed, pixel and sample
// index) and its camera ray.
Ray sampleCameraRay(uvec2 pixel, uint pixelIndex, uint s, out Sampler smp) {
    smp = samplerStart(frame.sampling.x, pixelIndex, frame.image.z + s, frame.image.w);
    vec2 uFilter = sample2D(smp, SLOT_FILTER);
    return cameraRay(pixel, uFilter, sample2D(smp, SLOT_LENS));
}

// Adds a finished sample: its AOVs always, its radiance unless NaN or infinite (then counted).
void addSample(inout PixelSums p, vec3 L, PathAov aov) {
    p.albedo += vec4(aov.albedo, 1.0);
    p.normal += vec4(aov.normal, 1.0);
    if (any(isnan(L)) || any(isinf(L))) {
        ++p.dropped;
        return;
    }
    p.sum += vec4(L, 1.0);
    p.sumSq += vec4(L * L, 0.0);
}

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
    PixelSums px;
    px.sum = imageLoad(accumImage, ip);
    px.sumSq = imageLoad(accumSqImage, ip);
    px.albedo = imageLoad(albedoImage, ip);
    px.normal = imageLoad(normalImage, ip);
    px.dropped = 0u;
    uint pixelIndex = pixel.y * frame.image.x + pixel.x;
#ifdef CAUSTIC_REGENERATE
    // Path regeneration (Novak, Havran and Dachsbacher 2010, "Path Regeneration for Interactive
    // Path Tracing"): one loop over bounces, in which a lane whose path has ended starts its
    // pixel's next sample. On llvmpipe a work group's 8 neighbouring invocations run as the lanes
    // of one SIMD register until the last of them is done, so a loop over samples with the bounce
    // loop inside ran, for every sample, as many bounces as the longest of the 8 paths; here the
    // group runs about as many as the longest lane's sum over its samples. Each sample still has
    // the random numbers of (seed, pixel, sample index) and is summed in the same order: the
    // image is the same as the nested loops' (docs/performance.md).
    if (frame.dispatch.x > 0u) {
        uint s = 0u;
        Sampler smp;
        PathState st = pathBegin(sampleCameraRay(pixel, pixelIndex, s, smp));
        while (true) {
            if (!pathStep(st, smp)) continue;
            addSample(px, st.L, st.aov);
            if (++s >= frame.dispatch.x) break;
            st = pathBegin(sampleCameraRay(pixel, pixelIndex, s, smp));
        }
    }
#else
    for (uint s = 0u; s < frame.dispatch.x; ++s) {
        Sampler smp;
        Ray ray = sampleCameraRay(pixel, pixelIndex, s, smp);
        PathAov aov;
        vec3 L = pathRadiance(ray, smp, aov);
        addSample(px, L, aov);
    }
#endif
    if (px.dropped > 0u) atomicAdd(counters[COUNTER_DROPPED], px.dropped);
    // A 64-bit ray count from two 32-bit words: carry into the high word on wrap-around.
    uint before = atomicAdd(counters[COUNTER_RAYS_LO], g_rayCount);
    if (before + g_rayCount < before) atomicAdd(counters[COUNTER_RAYS_HI], 1u);
    imageStore(accumImage, ip, px.sum);
    imageStore(accumSqImage, ip, px.sumSq);
    imageStore(albedoImage, ip, px.albedo);
    imageStore(normalImage, ip, px.normal);
}
