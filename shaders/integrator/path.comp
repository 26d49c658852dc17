#version 450 core
#ifdef CAUSTIC_WALK_STATS
// The walks' statistics elect one lane per SIMD group (geometry/bvh.glsl, WALK_STATS_STEP).
#extension GL_ARB_shader_ballot : require
#extension GL_ARB_gpu_shader_int64 : require
#define CAUSTIC_BALLOT 1
#endif
// The integrator kernel: frame.dispatch.x samples per pixel per dispatch, each with the random
// numbers of (seed, pixel, sample index) from the sampler (lib/sampler.glsl), summed into the
// accumulation images. A sample that
// is NaN or infinite is dropped, counted in counters[0], and not averaged in.
// The albedo and normal images (the denoiser's guides, written as AOVs) are accumulated in the
// same loop from every sample, dropped ones included (their first hit is still well defined).
#include "film.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
    // One work group per 8x8 tile; a dispatch covers tiles [dispatch.z, dispatch.w), numbered row
    // by row, on a grid of work groups that may have a few too many (Renderer::dispatch). Work
    // group g takes tile (g % S) M + g / S of the dispatch's (M = its tiles / S, rounded up; S =
    // DISPATCH_STRIDES): consecutive groups take tiles M apart. llvmpipe hands each of its threads
    // one contiguous run of the grid's work groups, so with tiles in image order the thread with
    // the image's busy half (mesh-knot's knots) worked on while the other slept: 1.5 of 2 cores
    // busy. Now each run holds tiles from every band of the image (docs/performance.md).
    uint count = frame.dispatch.w - frame.dispatch.z;
    uint bandTiles = (count + DISPATCH_STRIDES - 1u) / DISPATCH_STRIDES;
    uint g = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint t = (g % DISPATCH_STRIDES) * bandTiles + g / DISPATCH_STRIDES;
    if (t >= count) return;
    uint tile = frame.dispatch.z + t;
    // The accumulation images cover the crop being rendered (the whole image unless a part of a
    // split render: Renderer::setCrop), whose origin in the image is frame.options.yz; pixel
    // indices and camera rays are those of the whole image, so a crop's pixels are the same.
    uvec2 cropSize = uvec2(imageSize(accumImage));
    uint tilesX = (cropSize.x + 7u) / 8u;
    uvec2 local = uvec2(tile % tilesX, tile / tilesX) * 8u + gl_LocalInvocationID.xy;
    if (local.x >= cropSize.x || local.y >= cropSize.y) return;
    uvec2 pixel = local + frame.options.yz;
    ivec2 ip = ivec2(local);
    PixelSums px = loadPixelSums(ip);
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
        vec3 weight;
        PathState st = pathBegin(sampleCameraRay(pixel, pixelIndex, s, smp, weight));
        st.beta = weight;
        bool blocked = weight == vec3(0.0);   // by a lens system: it runs as a path of weight 0
        while (true) {
            if (!pathStep(st, smp)) continue;
            if (blocked) addBlockedSample(px);
            else addSample(px, st.L, st.aov);
            if (++s >= frame.dispatch.x) break;
            st = pathBegin(sampleCameraRay(pixel, pixelIndex, s, smp, weight));
            st.beta = weight;
            blocked = weight == vec3(0.0);
        }
    }
#else
    for (uint s = 0u; s < frame.dispatch.x; ++s) {
        Sampler smp;
        vec3 weight;
        Ray ray = sampleCameraRay(pixel, pixelIndex, s, smp, weight);
        if (weight != vec3(0.0)) {
            PathAov aov;
            vec3 L = weight * pathRadiance(ray, smp, aov);
            addSample(px, L, aov);
        } else {
            addBlockedSample(px);   // a ray the lens system blocks: a sample of 0, not traced
        }
    }
#endif
    countRays(g_rayCount);
#ifdef BVH_WALK_STATS
    countWalkStats();
#endif
    storePixelSums(ip, px);
}
