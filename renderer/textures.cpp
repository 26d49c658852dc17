// Textures: decoding to linear, mip chains, and their place in CompiledScene (addTexture).
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

float srgbToLinear(float c) {
    // IEC 61966-2-1 (the sRGB standard's decoding curve).
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

bool addTexture(const ImageData& image, TextureEncoding encoding, CompiledScene* out, std::string* error) {
    const int w = image.width, h = image.height, ch = image.channels;
    if (w <= 0 || h <= 0 || ch <= 0 || image.pixels.size() < size_t(w) * size_t(h) * size_t(ch)) {
        *error = "empty or truncated image";
        return false;
    }
    const size_t total = size_t(out->texels.size()) + size_t(w) * size_t(h) * 2;  // a mip chain is < 4/3 of level 0
    if (total > size_t(1) << 31) {
        *error = "too many texels in all (" + std::to_string(total) + "; at most 2^31)";
        return false;
    }
    // Level 0 in linear floats; grey and grey+alpha images are expanded to RGBA.
    std::vector<glm::vec4> level(size_t(w) * size_t(h));
    for (size_t i = 0; i < level.size(); ++i) {
        const float* px = &image.pixels[i * size_t(ch)];
        glm::vec4 c = ch >= 3 ? glm::vec4(px[0], px[1], px[2], ch >= 4 ? px[3] : 1.0f)
                              : glm::vec4(px[0], px[0], px[0], ch == 2 ? px[1] : 1.0f);
        for (int k = 0; k < 4; ++k)
            if (!std::isfinite(c[k])) {
                *error = "non-finite pixel at (" + std::to_string(i % size_t(w)) + ", " + std::to_string(i / size_t(w)) + ")";
                return false;
            }
        if (encoding == TextureEncoding::Srgb) c = glm::vec4(srgbToLinear(c.r), srgbToLinear(c.g), srgbToLinear(c.b), c.a);
        level[i] = c;
    }
    gpu::GpuTexture t{};
    t.info = glm::uvec4(static_cast<std::uint32_t>(out->texels.size()), w, h, 0);
    // The mip chain by 2x2 box filtering in linear space (odd sizes clamp the last row/column).
    int lw = w, lh = h;
    for (;;) {
        for (const glm::vec4& c : level)
            out->texels.emplace_back(glm::packHalf2x16(glm::vec2(c.r, c.g)), glm::packHalf2x16(glm::vec2(c.b, c.a)));
        ++t.info.w;
        if (lw == 1 && lh == 1) break;
        const int nw = std::max(1, lw / 2), nh = std::max(1, lh / 2);
        std::vector<glm::vec4> next(size_t(nw) * size_t(nh));
        for (int y = 0; y < nh; ++y)
            for (int x = 0; x < nw; ++x) {
                const int x0 = std::min(2 * x, lw - 1), x1 = std::min(2 * x + 1, lw - 1);
                const int y0 = std::min(2 * y, lh - 1), y1 = std::min(2 * y + 1, lh - 1);
                next[size_t(y) * size_t(nw) + size_t(x)] =
                    0.25f * (level[size_t(y0) * size_t(lw) + size_t(x0)] + level[size_t(y0) * size_t(lw) + size_t(x1)] +
                             level[size_t(y1) * size_t(lw) + size_t(x0)] + level[size_t(y1) * size_t(lw) + size_t(x1)]);
            }
        level = std::move(next);
        lw = nw;
        lh = nh;
    }
    out->textures.push_back(t);
    return true;
}

}  // namespace caustic
