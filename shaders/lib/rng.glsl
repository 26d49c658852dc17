// Deterministic random numbers: each (pixel, sample index, seed) gets its own PCG32 stream, so an
// image depends only on the scene, the seed and the sample range, never on how the samples were
// split into dispatches.
// PCG: O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient Statistically Good Algorithms
// for Random Number Generation"; the hash is the RXS-M-XS output of a single LCG step, as in
// Jarzynski and Olano 2020, "Hash Functions for GPU Rendering", JCGT 9(3).
#ifndef LIB_RNG_GLSL
#define LIB_RNG_GLSL

uint pcgHash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

uint rngInit(uint pixelIndex, uint sampleIndex, uint seed) {
    uint s = pcgHash(seed);
    s = pcgHash(s + sampleIndex);
    return pcgHash(s + pixelIndex);
}

uint rngNextUint(inout uint state) {
    state = state * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Uniform in [0, 1): 24 random bits, exactly representable.
float rngNext(inout uint state) { return float(rngNextUint(state) >> 8) * (1.0 / 16777216.0); }
vec2 rngNext2(inout uint state) { return vec2(rngNext(state), rngNext(state)); }

#endif
