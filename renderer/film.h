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

}  // namespace caustic
