// The sampler: the random numbers of one pixel sample, as a function of (seed, pixel, sample
// index, dimension) only, so that an image never depends on how its samples were split into
// dispatches, frames, sample ranges or processes.
//
// SAMPLER_SOBOL (the default): Owen-scrambled Sobol points, padded in 2-D (and 1-D) pieces, with
// hash-based scrambling (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)):
//   - each piece (a dimension slot of the table below) uses the first two Sobol dimensions, a
//     (0, 2)-sequence in base 2: dimension 0 is the van der Corput sequence (the index's bits
//     reversed); dimension 1 has the generator matrix of Pascal's triangle mod 2 (Sobol 1967;
//     its direction numbers v_{k+1} = v_k ^ (v_k >> 1)), applied here as a subset-XOR transform in
//     five shift-and-mask steps (bit j of the result is the XOR of the index bits k whose binary
//     digits contain j's, by Lucas' theorem C(k, j) mod 2 = [j & k == j]);
//   - the sample index is shuffled per (pixel, slot) by a nested uniform (Owen) scramble of its
//     bits (Burley 2020, sec. 4): an aligned block of 2^k indices maps to an aligned block, so the
//     first 2^k samples of a pixel are still a (0, k, 2)-net in every slot, while different slots
//     (and pixels) are decorrelated; this is what pbrt-v4's PaddedSobolSampler and Cycles'
//     Sobol-Burley do with different hashes;
//   - each coordinate is then Owen-scrambled with its own seed, which keeps the net property and
//     makes the estimator unbiased (every point is uniform on [0, 1)).
//   The Owen scramble is the Laine-Karras-style hash on the reversed bits, with the constants of
//   Vegdahl 2021 ("Building a Better LK Hash"), as Burley's paper recommends improving: each output
//   bit of the hash depends only on lower input bits (multiplication by an even constant, addition
//   and multiplication by an odd number propagate upwards only), which is Owen's condition once the
//   bits are reversed.
// SAMPLER_INDEPENDENT: one PCG32 stream per (seed, pixel, sample), read in the order of the calls
//   (the dimension is ignored): the renderer's sampler before the Sobol one, kept for comparisons.
//
// Dimension slots (one 1-D or 2-D value each; the same slot at the same bounce whatever the path
// did before, so samples of one pixel stay stratified against each other):
//   camera: SLOT_FILTER (2-D pixel filter), SLOT_LENS (2-D lens)
//   bounce b: bounceSlot(b, k) with k one of
//     SLOT_LIGHT_SELECT (1-D), SLOT_LIGHT (2-D point on the light), SLOT_BSDF_DIR (2-D direction),
//     SLOT_BSDF_LOBE (1-D lobe choice), SLOT_RR (1-D Russian roulette).
#ifndef LIB_SAMPLER_GLSL
#define LIB_SAMPLER_GLSL
#include "rng.glsl"
#include "../shared/layout.h"
#include "../scene/features.glsl"

#define SLOT_FILTER 0u
#define SLOT_LENS 1u
#define SLOTS_CAMERA 2u
#define SLOT_LIGHT_SELECT 0u
#define SLOT_LIGHT 1u
#define SLOT_BSDF_DIR 2u
#define SLOT_BSDF_LOBE 3u
#define SLOT_RR 4u
#define SLOTS_PER_BOUNCE 5u

uint bounceSlot(uint bounce, uint k) { return SLOTS_CAMERA + SLOTS_PER_BOUNCE * bounce + k; }

struct Sampler {
    uint type;       // SAMPLER_*
    uint index;      // the sample's index in its pixel
    uint pixelSeed;  // hash of (seed, pixel)
    uint rng;        // the independent sampler's PCG32 state
};

Sampler samplerStart(uint type, uint pixelIndex, uint sampleIndex, uint seed) {
    Sampler s;
    s.type = type;
    s.index = sampleIndex;
    s.pixelSeed = pcgHash(pcgHash(seed ^ 0x5bd1e995u) + pixelIndex);
    s.rng = rngInit(pixelIndex, sampleIndex, seed);
    return s;
}

// The Owen scramble of x's reversed bits (see the header): a bijection where bit k of the result
// is bit k of x flipped by a function of the seed and of x's bits below k.
uint owenHashReversed(uint x, uint seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

// Nested uniform scramble of x read most significant bit first (a value in [0, 1) as 0.b31 b30 ...).
uint owenScramble(uint x, uint seed) { return bitfieldReverse(owenHashReversed(bitfieldReverse(x), seed)); }

// Sobol dimension 1 of index i, least significant digit first (bit j = digit 2^-(j+1)).
uint sobolPascal(uint i) {
    i ^= (i >> 1) & 0x55555555u;
    i ^= (i >> 2) & 0x33333333u;
    i ^= (i >> 4) & 0x0f0f0f0fu;
    i ^= (i >> 8) & 0x00ff00ffu;
    i ^= (i >> 16) & 0x0000ffffu;
    return i;
}

float bitsToUnit(uint bits) { return float(bits >> 8) * (1.0 / 16777216.0); }  // 24 bits, < 1

uint slotSeed(Sampler s, uint slot) { return pcgHash(s.pixelSeed ^ pcgHash(slot * 0x9e3779b9u + 0x7f4a7c15u)); }

// (A scene-specialised program keeps only the sampler it renders with: scene/features.glsl.)
bool samplerIsIndependent(Sampler s) {
    if (!HAS_SAMPLER(SAMPLER_INDEPENDENT)) return false;
    if (!HAS_SAMPLER(SAMPLER_SOBOL)) return true;
    return s.type == SAMPLER_INDEPENDENT;
}

vec2 sample2D(inout Sampler s, uint slot) {
    if (samplerIsIndependent(s)) return rngNext2(s.rng);
    uint h = slotSeed(s, slot);
    uint i = owenScramble(s.index, h);  // the shuffled index (digits read from the top)
    // Dimension 0 is i's bits reversed, so its scramble is owenHashReversed on i itself; dimension
    // 1 likewise on the least-significant-first form of its digits.
    uint x = bitfieldReverse(owenHashReversed(i, pcgHash(h + 0x68e31da4u)));
    uint y = bitfieldReverse(owenHashReversed(sobolPascal(i), pcgHash(h + 0xb5297a4du)));
    return vec2(bitsToUnit(x), bitsToUnit(y));
}

float sample1D(inout Sampler s, uint slot) {
    if (samplerIsIndependent(s)) return rngNext(s.rng);
    uint h = slotSeed(s, slot);
    uint i = owenScramble(s.index, h);
    return bitsToUnit(bitfieldReverse(owenHashReversed(i, pcgHash(h + 0x68e31da4u))));
}

#endif
