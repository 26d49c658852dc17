// caustic compare A B: how far image A is from reference B, per pixel and in all. Metrics (over
// every pixel and RGB channel, on the values as stored: linear for EXR and HDR files):
//   RMSE   = sqrt(mean((a - b)^2))
//   relMSE = mean((a - b)^2 / (b^2 + 0.01)), the relative MSE of Rousselle et al. 2011 with the
//            usual 0.01 that keeps dark pixels from dominating (as tests/variance reports it)
//   max_abs, max_rel = the largest |a - b| and |a - b| / max(|a|, |b|) (0 where both are 0)
// --map writes a false-colour PNG of each pixel's relMSE (the mean over its channels) on a log
// scale, 1e-4 (black) to 1 (white) through purple, red and yellow. HDR-FLIP needs NVIDIA's
// reference implementation, which is a Python package: the farm's report (caustic-farm) adds it.
#include "app/commands.h"
#include "renderer/image_io.h"

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>

namespace caustic {
namespace {

// The RGB of an image by channel name (R, G, B; else the first three channels).
bool readRgb(const std::string& path, int* w, int* h, std::vector<double>* rgb, std::string* error) {
    ChannelImage img;
    if (!readChannelImage(path, &img, error)) return false;
    for (const auto& [key, value] : img.metadata)
        if (key == "caustic:part") {
            *error = path + ": is a part of a split render (sums and counts, not an image): merge its parts first "
                            "(caustic merge OUT PART...), then compare the merged image";
            return false;
        }
    int col[3] = {-1, -1, -1};
    for (size_t k = 0; k < img.names.size(); ++k)
        for (int c = 0; c < 3; ++c)
            if (img.names[k] == std::string(1, "RGB"[c])) col[c] = int(k);
    if (col[0] < 0 || col[1] < 0 || col[2] < 0) {
        if (img.names.size() < 3) {
            *error = path + ": has " + std::to_string(img.names.size()) + " channels, compare needs RGB";
            return false;
        }
        col[0] = 0, col[1] = 1, col[2] = 2;
    }
    *w = img.width;
    *h = img.height;
    const size_t n = size_t(img.width) * img.height, stride = img.names.size();
    rgb->resize(n * 3);
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) (*rgb)[i * 3 + c] = img.pixels[i * stride + size_t(col[c])];
    return true;
}

// A false-colour ramp over t in [0, 1]: black, purple, red, yellow, white.
glm::vec3 ramp(double t) {
    static const glm::vec3 stops[] = {{0, 0, 0}, {0.35f, 0.05f, 0.55f}, {0.85f, 0.15f, 0.2f}, {1.0f, 0.8f, 0.1f}, {1, 1, 1}};
    t = std::clamp(t, 0.0, 1.0) * 4.0;
    const int i = std::min(int(t), 3);
    return glm::mix(stops[i], stops[i + 1], float(t - i));
}

}  // namespace

int runCompare(const CliOptions& o) {
    const std::string& a = o.inputs[0];
    const std::string& b = o.inputs[1];
    int wa = 0, ha = 0, wb = 0, hb = 0;
    std::vector<double> x, r;
    std::string error;
    if (!readRgb(a, &wa, &ha, &x, &error) || !readRgb(b, &wb, &hb, &r, &error)) return commandFailed(error);
    if (wa != wb || ha != hb)
        return commandFailed("compare: " + a + " is " + std::to_string(wa) + "x" + std::to_string(ha) + ", " + b + " is " +
                             std::to_string(wb) + "x" + std::to_string(hb));
    const size_t n = size_t(wa) * ha;
    double se = 0, rel = 0, maxAbs = 0, maxRel = 0, meanA = 0, meanB = 0;
    bool finite = true;
    std::vector<double> pixelRel(n, 0.0);
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            const double va = x[i * 3 + c], vb = r[i * 3 + c], d = va - vb;
            if (!std::isfinite(va) || !std::isfinite(vb)) finite = false;
            se += d * d;
            const double e = d * d / (vb * vb + 0.01);
            rel += e;
            pixelRel[i] += e / 3.0;
            maxAbs = std::max(maxAbs, std::abs(d));
            const double m = std::max(std::abs(va), std::abs(vb));
            if (m > 0) maxRel = std::max(maxRel, std::abs(d) / m);
            meanA += va;
            meanB += vb;
        }
    if (!finite) return commandFailed("compare: " + a + " or " + b + " holds NaN or infinite values");
    const double count = double(n) * 3.0;
    nlohmann::json result = {
        {"image", a}, {"reference", b}, {"width", wa}, {"height", ha},
        {"rmse", std::sqrt(se / count)}, {"relmse", rel / count}, {"max_abs", maxAbs}, {"max_rel", maxRel},
        {"mean", meanA / count}, {"mean_reference", meanB / count},
    };
    if (o.map) {
        std::vector<std::uint8_t> rgb(n * 3);
        for (size_t i = 0; i < n; ++i) {
            const double t = (std::log10(std::max(pixelRel[i], 1e-12)) + 4.0) / 4.0;   // 1e-4 .. 1
            const glm::vec3 c = ramp(t);
            for (int k = 0; k < 3; ++k) rgb[i * 3 + k] = std::uint8_t(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
        }
        const ImageMetadata meta = {{"Software", std::string("caustic ") + CAUSTIC_VERSION},
                                    {"caustic:error_map", "relMSE per pixel, log10 from -4 (black) to 0 (white)"}};
        if (!writeImage8(*o.map, wa, ha, rgb, meta, &error)) return commandFailed(error);
        result["map"] = *o.map;
    }
    std::cout << result.dump() << std::endl;
    return 0;
}

}  // namespace caustic
