// Image values the GPU cannot hold, or that no light can have, are refused when a texture or an
// environment map is built, naming the pixel: material texels are stored as 16-bit halves (a
// texel beyond 65,504 would become infinite, rendering black or losing its emission), and an
// environment's radiance is never negative (a negative constant radiance is refused too).
#include "renderer/gpu_scene.h"

#include <catch2/catch.hpp>
#include <glm/gtc/packing.hpp>

#include <string>

using namespace caustic;

namespace {

ImageData image(float value, int x, int y) {
    ImageData im;
    im.width = 4;
    im.height = 3;
    im.channels = 3;
    im.pixels.assign(4 * 3 * 3, 0.5f);
    im.pixels[size_t(y * 4 + x) * 3 + 1] = value;
    return im;
}

}  // namespace

TEST_CASE("textures: texels beyond the half-float range are refused with their pixel, those within are kept",
          "[textures]") {
    for (const float ok : {65504.0f, -65504.0f, 3.0f}) {
        CompiledScene c;
        std::string error;
        INFO(ok);
        CHECK(addTexture(image(ok, 1, 2), TextureEncoding::Linear, &c, &error));
    }
    for (const float bad : {65520.0f, 70000.0f, 3e38f, -1e5f}) {
        CompiledScene c;
        std::string error;
        INFO(bad);
        CHECK_FALSE(addTexture(image(bad, 1, 2), TextureEncoding::Linear, &c, &error));
        CHECK(error.rfind("pixel (1, 2) holds ", 0) == 0);
        CHECK(error.find("beyond 65504") != std::string::npos);
        CHECK(c.texels.empty());
    }
}

TEST_CASE("environment maps: a negative pixel is refused with its place, zero and positive ones are kept",
          "[textures][environment]") {
    EnvironmentMap map;
    std::string error;
    CHECK(buildEnvironmentMap(image(0.0f, 2, 1), &map, &error));
    CHECK_FALSE(buildEnvironmentMap(image(-0.25f, 2, 1), &map, &error));
    CHECK(error.rfind("environment image has a negative pixel at (2, 1)", 0) == 0);
}

TEST_CASE("textures: an HDR albedo's texels above 1 are clamped to 1, other encodings keep them", "[textures]") {
    // An albedo of 3 would reflect three times what it receives; as linear data (emission) 3 stays 3.
    for (const TextureEncoding enc : {TextureEncoding::LinearReflectance, TextureEncoding::Linear}) {
        CompiledScene c;
        std::string error;
        REQUIRE(addTexture(image(3.0f, 1, 2), enc, &c, &error));
        const glm::uvec2 t = c.texels[2 * 4 + 1];  // level 0, pixel (1, 2)
        const glm::vec2 rg = glm::unpackHalf2x16(t.x);
        CHECK(rg.x == 0.5f);
        CHECK(rg.y == (enc == TextureEncoding::LinearReflectance ? 1.0f : 3.0f));
    }
}
