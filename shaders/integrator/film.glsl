// The integrator's film: the accumulation images a dispatch adds its samples to, a sample's
// camera ray, and how a finished sample is added (integrator/path.comp).
#ifndef INTEGRATOR_FILM_GLSL
#define INTEGRATOR_FILM_GLSL
#include "path.glsl"
#include "camera.glsl"

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
// index), its camera ray and the ray's weight (1 but through a lens system).
Ray sampleCameraRay(uvec2 pixel, uint pixelIndex, uint s, out Sampler smp, out vec3 weight) {
    smp = samplerStart(frame.sampling.x, pixelIndex, frame.image.z + s, frame.image.w);
    vec2 uFilter = sample2D(smp, SLOT_FILTER);
    return cameraRayWeighted(pixel, uFilter, sample2D(smp, SLOT_LENS), weight);
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

// Adds a sample of a camera ray the lens system blocked: a radiance of 0 that counts in the
// pixel's mean, and nothing in the AOVs (it saw no surface; counting it would darken the albedo
// guide where the lens vignettes).
void addBlockedSample(inout PixelSums p) { p.sum += vec4(0.0, 0.0, 0.0, 1.0); }

PixelSums loadPixelSums(ivec2 ip) {
    PixelSums px;
    px.sum = imageLoad(accumImage, ip);
    px.sumSq = imageLoad(accumSqImage, ip);
    px.albedo = imageLoad(albedoImage, ip);
    px.normal = imageLoad(normalImage, ip);
    px.dropped = 0u;
    return px;
}

// Adds n to the 64-bit count in words (lo, lo + 1) of the counter buffer (carry into the high
// word on wrap-around).
void addCount64(uint lo, uint n) {
    uint before = atomicAdd(counters[lo], n);
    if (before + n < before) atomicAdd(counters[lo + 1u], 1u);
}

void countRays(uint rays) { addCount64(COUNTER_RAYS_LO, rays); }

#ifdef BVH_WALK_STATS
// This invocation's share of the walks' statistics (geometry/bvh.glsl, WALK_STATS_STEP).
void countWalkStats() {
    addCount64(COUNTER_WALK_GROUP_STEPS, g_walkGroupSteps);
    addCount64(COUNTER_WALK_LANE_STEPS, g_walkLaneSteps);
    addCount64(COUNTER_WALK_TREES, g_walkTrees);
    atomicMax(counters[COUNTER_SUBGROUP_SIZE], gl_SubGroupSizeARB);
}
#endif

// Stores the sums and counts the dropped samples.
void storePixelSums(ivec2 ip, PixelSums px) {
    if (px.dropped > 0u) atomicAdd(counters[COUNTER_DROPPED], px.dropped);
    imageStore(accumImage, ip, px.sum);
    imageStore(accumSqImage, ip, px.sumSq);
    imageStore(albedoImage, ip, px.albedo);
    imageStore(normalImage, ip, px.normal);
}

#endif
