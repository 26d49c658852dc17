// Display transforms: exposure, a tone curve, and the sRGB encoding for 8-bit output.
#pragma once

#include "renderer/film.h"

#include <cstdint>
#include <vector>

namespace caustic {

enum class ToneMap { Aces, Reinhard };

// Narkowicz 2015, "ACES Filmic Tone Mapping Curve": the fit
// (x (2.51 x + 0.03)) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1], per channel.
float toneAces(float x);
// Reinhard et al. 2002, eq. 3: x / (1 + x), per channel.
float toneReinhard(float x);
// The sRGB transfer function (IEC 61966-2-1): 12.92 x below 0.0031308, else 1.055 x^(1/2.4) - 0.055.
float srgbEncode(float linear);
float srgbDecode(float encoded);

// Film -> 8-bit sRGB RGB pixels, row 0 at the top: mean * 2^exposure, tone curve, sRGB, rounding.
std::vector<std::uint8_t> toSrgb8(const Film& film, ToneMap op, float exposureEv = 0.0f);
// Film -> linear float RGB (for HDR and EXR files).
std::vector<float> toLinearRgb(const Film& film);

}  // namespace caustic
