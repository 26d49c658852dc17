// The accumulated image read back from the GPU: per-pixel mean radiance, the variance of that
// mean (from the sum of squares, for statistical tests and error estimates) and the sample count,
// and the two AOVs (the denoiser's guides): the mean albedo and the mean world normal at each
// path's first non-specular vertex (zero where paths escape before one; see integrator/path.glsl).
#pragma once

#include <glm/glm.hpp>

#include <vector>

namespace caustic {

struct Film {
    int width = 0;
    int height = 0;
    std::vector<glm::vec3> mean;            // linear radiance, row 0 = top of the image
    std::vector<glm::vec3> varianceOfMean;  // unbiased sample variance / count, per channel
    std::vector<float> count;               // samples that went into each pixel
    std::vector<glm::vec3> albedo;          // reflectance in [0, 1]
    std::vector<glm::vec3> normal;          // world space, components in [-1, 1] (an average: not unit length)

    size_t index(int x, int y) const { return static_cast<size_t>(y) * width + x; }
};

// The accumulation images as the GPU holds them (row 0 = top), before any division: what a
// part of a split render keeps so that parts merge exactly (app/part_file.h, docs/farm.md).
struct Accumulators {
    int width = 0;
    int height = 0;
    std::vector<glm::vec4> sum;     // rgb: sum of the samples, a: samples counted (NaN/Inf ones are not)
    std::vector<glm::vec4> sumSq;   // rgb: sum of the squared samples, a: unused (0)
    std::vector<glm::vec4> albedo;  // rgb: sum of the first non-specular albedos, a: samples (all)
    std::vector<glm::vec4> normal;  // rgb: sum of the first non-specular world normals, a: samples (all)
};

// Means, variance of the mean and counts from the sums: the one rule for a render read back
// from the GPU (Renderer::readFilm) and for merged parts (caustic merge), so both give the same
// floats from the same sums.
Film resolveFilm(const Accumulators& a);

}  // namespace caustic
