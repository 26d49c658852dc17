#include "renderer/tonemap.h"

#include <algorithm>
#include <cmath>

namespace caustic {

float toneAces(float x) {
    if (!(x > 0.0f)) return 0.0f;  // negative and NaN
    if (x > 8.0f) return 1.0f;     // the fit reaches 1 at x = 7.24; avoids inf / inf for huge x
    return std::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

float toneReinhard(float x) {
    if (!(x > 0.0f)) return 0.0f;
    if (std::isinf(x)) return 1.0f;
    return x / (1.0f + x);
}

float srgbEncode(float v) {
    v = std::clamp(v, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float srgbDecode(float v) {
    v = std::clamp(v, 0.0f, 1.0f);
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

std::vector<std::uint8_t> toSrgb8(const Film& film, ToneMap op, float exposureEv) {
    const float scale = std::exp2(exposureEv);
    std::vector<std::uint8_t> out(film.mean.size() * 3);
    for (size_t i = 0; i < film.mean.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            float x = film.mean[i][c] * scale;
            float t = op == ToneMap::Aces ? toneAces(x) : toneReinhard(x);
            out[i * 3 + c] = static_cast<std::uint8_t>(std::lround(srgbEncode(t) * 255.0f));
        }
    }
    return out;
}

std::vector<float> toLinearRgb(const Film& film) {
    std::vector<float> out(film.mean.size() * 3);
    for (size_t i = 0; i < film.mean.size(); ++i)
        for (int c = 0; c < 3; ++c) out[i * 3 + c] = film.mean[i][c];
    return out;
}

}  // namespace caustic
