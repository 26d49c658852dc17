// The environment map's sampling tables (EnvironmentMap, renderer/gpu_scene.h).
#include "renderer/gpu_scene.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <utility>

namespace caustic {

namespace {
constexpr float kPi = std::numbers::pi_v<float>;

// guide[k], k = 0 ... g: the largest i < n with cdf[i] <= k / g (cdf: n + 1 non-decreasing
// entries from 0). k / g and the float entries compare exactly in double, as u and the entries do
// in the shader's float comparisons.
void buildGuide(const float* cdf, int n, int g, float* guide) {
    int i = 0;
    for (int k = 0; k <= g; ++k) {
        const double x = double(k) / g;
        while (i + 1 < n && double(cdf[i + 1]) <= x) ++i;
        guide[k] = float(i);
    }
}
}  // namespace

bool buildEnvironmentMap(const ImageData& image, EnvironmentMap* out, std::string* error) {
    const int w = image.width, h = image.height, ch = image.channels;
    if (w <= 0 || h <= 0 || ch <= 0 || image.pixels.size() < size_t(w) * h * ch) {
        *error = "empty environment image";
        return false;
    }
    EnvironmentMap m;
    m.width = w;
    m.height = h;
    m.texels.resize(size_t(w) * h);
    std::vector<float> lum(size_t(w) * h);
    for (size_t i = 0; i < m.texels.size(); ++i) {
        const float* px = &image.pixels[i * ch];
        glm::vec3 rgb = ch >= 3 ? glm::vec3(px[0], px[1], px[2]) : glm::vec3(px[0]);
        if (!std::isfinite(rgb.r) || !std::isfinite(rgb.g) || !std::isfinite(rgb.b)) {
            *error = "environment image has a non-finite pixel at (" + std::to_string(i % w) + ", " +
                     std::to_string(i / w) + ")";
            return false;
        }
        // An environment emits no negative radiance (a negative constant one is refused too);
        // Radiance HDR files cannot hold one, an EXR can.
        if (rgb.r < 0.0f || rgb.g < 0.0f || rgb.b < 0.0f) {
            *error = "environment image has a negative pixel at (" + std::to_string(i % w) + ", " +
                     std::to_string(i / w) + "): (" + std::to_string(rgb.r) + ", " + std::to_string(rgb.g) + ", " +
                     std::to_string(rgb.b) + "); radiance cannot be negative";
            return false;
        }
        m.texels[i] = glm::vec4(rgb, 1.0f);
        lum[i] = luminance(rgb);
    }
    // The average radiance (solid angle of texel row j: (2 pi / w) (pi / h) sin theta_j).
    glm::dvec3 radiance(0.0);
    for (int j = 0; j < h; ++j) {
        const double sinTheta = std::sin(double(kPi) * (j + 0.5) / h);
        for (int i = 0; i < w; ++i) radiance += glm::dvec3(m.texels[size_t(j) * w + i]) * sinTheta;
    }
    m.average = glm::vec3(radiance * (2.0 * double(kPi) / w) * (double(kPi) / h) / (4.0 * double(kPi)));
    // The sampling table: cells of 1/s texel per axis (s = 4, 2 or 1: the largest that keeps the
    // table within 2^22 cells, 16 MB), each weighted by the integral over it of the bilinearly
    // filtered luminance (what a ray escaping through it sees) times sin(theta) at its centre.
    // Per axis that integral takes the tent between texel centres over the cell (a whole texel:
    // 1/8, 3/4, 1/8 of the previous, this and the next texel). Rows clamp at the poles and columns
    // wrap, as the texture does. The weight is non-zero wherever the filter can give a non-zero
    // radiance, so light sampling alone stays unbiased. Measured under assets/sky.hdr
    // (tests/variance, docs/performance.md), var/spp: a 3 x 3 maximum, the first version, which
    // spread a one-texel sun evenly over nine texels, 6.4; whole-texel integrals 3.3; half-texel
    // cells 2.2; the finer cells follow the filter's slopes closer (Mitsuba's warp follows them
    // exactly: it samples the bilinear patch itself).
    int s = 4;
    while (s > 1 && size_t(w) * size_t(h) * size_t(s) * size_t(s) > (size_t(1) << 22)) s /= 2;
    const int W = w * s, H = h * s;
    m.tableScale = s;
    // axis[k][d + 1]: the integral over [k / s, (k + 1) / s] of a texel (texel-local t in [0, 1],
    // centre 1/2) of the tent of texel offset d: (1/2 - t) for the previous texel and (1/2 + t) for
    // this one left of the centre, (3/2 - t) for this one and (t - 1/2) for the next right of it.
    std::vector<std::array<float, 3>> axis(static_cast<size_t>(s));
    for (int k = 0; k < s; ++k) {
        const double a = double(k) / s, b = double(k + 1) / s;
        const double l0 = a, l1 = std::min(b, 0.5), r0 = std::max(a, 0.5), r1 = b;
        auto integral = [](double c, double slope, double x0, double x1) {  // of c + slope t
            return x1 > x0 ? c * (x1 - x0) + 0.5 * slope * (x1 * x1 - x0 * x0) : 0.0;
        };
        axis[size_t(k)] = {float(integral(0.5, -1.0, l0, l1)),
                           float(integral(0.5, 1.0, l0, l1) + integral(1.5, -1.0, r0, r1)),
                           float(integral(-0.5, 1.0, r0, r1))};
    }
    std::vector<double> weight(size_t(W) * H);
    for (int J = 0; J < H; ++J) {
        const int j = J / s;
        const float* wy = axis[size_t(J % s)].data();
        const double sinTheta = std::sin(double(kPi) * (J + 0.5) / H);
        for (int I = 0; I < W; ++I) {
            const int i = I / s;
            const float* wx = axis[size_t(I % s)].data();
            float filtered = 0.0f;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    if (wy[dj + 1] == 0.0f || wx[di + 1] == 0.0f) continue;
                    const int jj = std::clamp(j + dj, 0, h - 1), ii = (i + di + w) % w;
                    filtered += wy[dj + 1] * wx[di + 1] * lum[size_t(jj) * w + ii];
                }
            weight[size_t(J) * W + I] = filtered * sinTheta;
        }
    }
    m.marginalCdf.assign(size_t(H) + 1, 0.0f);
    m.conditionalCdf.assign(size_t(H) * (W + 1), 0.0f);
    std::vector<double> rowSum(H, 0.0);
    double total = 0.0;
    for (int j = 0; j < H; ++j) {
        double acc = 0.0;
        for (int i = 0; i < W; ++i) acc += weight[size_t(j) * W + i];
        rowSum[j] = acc;
        total += acc;
        double run = 0.0;
        float* row = &m.conditionalCdf[size_t(j) * (W + 1)];
        for (int i = 0; i < W; ++i) {
            // A black row is sampled uniformly (it is never chosen: its marginal probability is 0).
            run += acc > 0.0 ? weight[size_t(j) * W + i] / acc : 1.0 / W;
            row[i + 1] = float(run);
        }
        row[W] = 1.0f;
    }
    double run = 0.0;
    for (int j = 0; j < H; ++j) {
        run += total > 0.0 ? rowSum[j] / total : 1.0 / H;
        m.marginalCdf[size_t(j) + 1] = float(run);
    }
    m.marginalCdf[H] = 1.0f;
    // Guide tables (gpu_scene.h): as many buckets as intervals, rounded down to a power of two,
    // and for the rows' together at most about 2^22 entries (a map too large for 4 cells per
    // texel gets coarser guides, still far shorter searches than the whole row).
    const auto floorLog2 = [](std::size_t v) { int l = 0; while ((std::size_t(2) << l) <= v) ++l; return l; };
    m.marginalGuideLog2 = floorLog2(size_t(H));
    m.conditionalGuideLog2 = std::min(floorLog2(size_t(W)), floorLog2(std::max<std::size_t>(1, (std::size_t(1) << 22) / H)));
    const int gm = 1 << m.marginalGuideLog2, gc = 1 << m.conditionalGuideLog2;
    m.marginalGuide.resize(size_t(gm) + 1);
    buildGuide(m.marginalCdf.data(), H, gm, m.marginalGuide.data());
    m.conditionalGuide.resize(size_t(H) * (gc + 1));
    for (int j = 0; j < H; ++j)
        buildGuide(&m.conditionalCdf[size_t(j) * (W + 1)], W, gc, &m.conditionalGuide[size_t(j) * (gc + 1)]);
    *out = std::move(m);
    return true;
}

}  // namespace caustic
