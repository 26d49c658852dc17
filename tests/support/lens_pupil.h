// The pupil a lens camera's film point sees (renderer/lens.h): the points of its exit-pupil bound
// whose rays pass, from an n x n grid over the bound, for the film point at radius r on +x: their
// spread along x (radial) and y (tangential), in mm, and their area (the passing share of the
// bound times its area, mm^2). The cat's eye off axis is narrow radially; a defocused point's
// bokeh on the film has this shape.
#pragma once

#include "renderer/lens.h"

#include <algorithm>
#include <cmath>

namespace caustic::test {

struct PupilShape {
    double radial = 0.0, tangential = 0.0, area = 0.0;
};

inline PupilShape passingPupil(const LensCamera& cam, double r, int n = 200) {
    const int bin = std::min(int(r / cam.filmRadius * kLensPupilBins), kLensPupilBins - 1);
    const glm::dvec4 b = cam.pupilBounds[std::size_t(bin)];
    glm::dvec2 mean(0.0), sq(0.0);
    int count = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const glm::dvec2 u((i + 0.5) / n, (j + 0.5) / n);
            double w = 0.0;
            if (!lensCameraRay(cam, glm::dvec2(r, 0.0), u, -1, &w)) continue;
            const glm::dvec2 q(b.x + u.x * (b.z - b.x), b.y + u.y * (b.w - b.y));
            mean += q;
            sq += q * q;
            ++count;
        }
    if (count == 0) return {};
    mean /= double(count);
    const glm::dvec2 sd = glm::sqrt(glm::max(sq / double(count) - mean * mean, glm::dvec2(0.0)));
    return {sd.x, sd.y, double(count) / (double(n) * n) * (b.z - b.x) * (b.w - b.y)};
}

}  // namespace caustic::test
