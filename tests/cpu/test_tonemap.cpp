// Display transforms: the ACES and Reinhard curves against their published formulas, the sRGB
// transfer function (IEC 61966-2-1) and its inverse, and Film -> 8-bit bytes end to end.
#include "renderer/film.h"
#include "renderer/tonemap.h"

#include <catch2/catch.hpp>

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

using namespace caustic;

namespace {

// Reference formulas in double precision, written out independently of the implementation.
double acesRef(double x) {
    x = std::max(x, 0.0);
    double y = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
    return std::min(std::max(y, 0.0), 1.0);
}
double srgbEncodeRef(double v) {
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

Film makeFilm(int width, int height, const std::vector<glm::vec3>& mean) {
    Film film;
    film.width = width;
    film.height = height;
    film.mean = mean;
    film.varianceOfMean.assign(mean.size(), glm::vec3(0.0f));
    film.count.assign(mean.size(), 1.0f);
    return film;
}

}  // namespace

TEST_CASE("ACES fitted curve matches Narkowicz 2015 at hand-computed points", "[tonemap]") {
    CHECK(toneAces(0.0f) == 0.0f);
    // 1: 2.54 / 3.16; 0.18 (middle grey): 0.086724 / 0.324932.
    CHECK(toneAces(1.0f) == Approx(2.54 / 3.16).epsilon(1e-5));
    CHECK(toneAces(0.18f) == Approx(0.086724 / 0.324932).epsilon(1e-5));
    // The fit exceeds 1 for large x (its limit is 2.51 / 2.43), so it must be clamped.
    CHECK(toneAces(10.0f) == 1.0f);
    CHECK(toneAces(100.0f) == 1.0f);
    // Negative radiance (never physical) maps to black, not to a negative value.
    CHECK(toneAces(-1.0f) == 0.0f);
}

TEST_CASE("ACES curve matches the reference formula and is monotone", "[tonemap]") {
    float previous = -1.0f;
    for (float x : {0.001f, 0.01f, 0.05f, 0.1f, 0.3f, 0.5f, 0.8f, 1.5f, 2.0f, 4.0f, 8.0f, 16.0f}) {
        INFO("x = " << x);
        CHECK(toneAces(x) == Approx(acesRef(x)).epsilon(1e-5).margin(1e-7));
        CHECK(toneAces(x) >= previous);
        previous = toneAces(x);
    }
}

TEST_CASE("Tone curves saturate for huge finite inputs instead of producing NaN", "[tonemap]") {
    // x * x overflows float above ~1.8e19; the curve must still give 1 (white), not NaN (black).
    for (float x : {1e10f, 1e20f, 1e30f, std::numeric_limits<float>::max()}) {
        INFO("x = " << x);
        CHECK(toneAces(x) == 1.0f);
        CHECK(toneReinhard(x) == Approx(1.0f));
        const Film film = makeFilm(1, 1, {glm::vec3(x)});
        CHECK(toSrgb8(film, ToneMap::Aces) == std::vector<std::uint8_t>{255, 255, 255});
        CHECK(toSrgb8(film, ToneMap::Reinhard) == std::vector<std::uint8_t>{255, 255, 255});
    }
}

TEST_CASE("Reinhard curve is x / (1 + x)", "[tonemap]") {
    CHECK(toneReinhard(0.0f) == 0.0f);
    CHECK(toneReinhard(1.0f) == Approx(0.5f));
    CHECK(toneReinhard(3.0f) == Approx(0.75f));
    CHECK(toneReinhard(0.25f) == Approx(0.2f));
    CHECK(toneReinhard(99.0f) == Approx(0.99f));
    CHECK(toneReinhard(-2.0f) == 0.0f);
}

TEST_CASE("sRGB encode matches IEC 61966-2-1 including the linear segment", "[tonemap][srgb]") {
    CHECK(srgbEncode(0.0f) == 0.0f);
    CHECK(srgbEncode(1.0f) == Approx(1.0f).epsilon(1e-6));
    // Linear segment below 0.0031308: exactly 12.92 x.
    CHECK(srgbEncode(0.001f) == Approx(0.01292f).epsilon(1e-5));
    CHECK(srgbEncode(0.003f) == Approx(12.92 * 0.003).epsilon(1e-5));
    // The two pieces meet at 0.0031308 -> 0.04045 (continuous within the standard's rounding).
    CHECK(srgbEncode(0.0031308f) == Approx(0.04045f).margin(1e-5));
    CHECK(srgbEncode(0.0031309f) == Approx(0.04045f).margin(1e-5));
    // Power segment: 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357.
    CHECK(srgbEncode(0.5f) == Approx(0.735357).epsilon(1e-5));
    for (float v : {0.01f, 0.05f, 0.2f, 0.7f, 0.9f}) {
        INFO("v = " << v);
        CHECK(srgbEncode(v) == Approx(srgbEncodeRef(v)).epsilon(1e-5));
    }
    // Out-of-range inputs are clamped.
    CHECK(srgbEncode(-0.5f) == 0.0f);
    CHECK(srgbEncode(2.0f) == Approx(1.0f).epsilon(1e-6));
}

TEST_CASE("sRGB decode inverts encode", "[tonemap][srgb]") {
    CHECK(srgbDecode(0.5f) == Approx(0.2140).margin(5e-5));
    CHECK(srgbDecode(0.04045f) == Approx(0.0031308f).epsilon(1e-4));
    CHECK(srgbDecode(0.02f) == Approx(0.02 / 12.92).epsilon(1e-5));
    CHECK(srgbDecode(0.0f) == 0.0f);
    CHECK(srgbDecode(1.0f) == Approx(1.0f).epsilon(1e-6));
    for (int i = 0; i <= 1000; ++i) {
        float v = float(i) / 1000.0f;
        INFO("v = " << v);
        CHECK(srgbDecode(srgbEncode(v)) == Approx(v).margin(2e-6).epsilon(1e-4));
        CHECK(srgbEncode(srgbDecode(v)) == Approx(v).margin(2e-6).epsilon(1e-4));
    }
}

TEST_CASE("toSrgb8 turns a hand-made film into the expected bytes", "[tonemap]") {
    // 2x2, row 0 at the top, pixels in reading order. Reinhard then sRGB then round:
    // 1 -> 0.5 -> 187.52 -> 188; 3 -> 0.75 -> 224.61 -> 225; 0.25 -> 0.2 -> 123.55 -> 124;
    // 0.5 -> 1/3 -> 156.19 -> 156; 0.01 -> 25.30 -> 25.
    const Film film = makeFilm(2, 2, {
        glm::vec3(0.0f, 0.0f, 0.0f), glm::vec3(1e6f, 1e6f, 1e6f),
        glm::vec3(1.0f, 0.0f, 3.0f), glm::vec3(0.25f, 0.5f, 0.01f),
    });
    const std::vector<std::uint8_t> reinhard = {
        0, 0, 0,       255, 255, 255,
        188, 0, 225,   124, 156, 25,
    };
    CHECK(toSrgb8(film, ToneMap::Reinhard) == reinhard);
    // ACES: 1 -> 0.803797 -> 231.60 -> 232; 3 -> 249.74 -> 250; 0.25 -> 164.57 -> 165;
    // 0.5 -> 205.87 -> 206; 0.01 -> 12.27 -> 12.
    const std::vector<std::uint8_t> aces = {
        0, 0, 0,       255, 255, 255,
        232, 0, 250,   165, 206, 12,
    };
    CHECK(toSrgb8(film, ToneMap::Aces) == aces);
    CHECK(toSrgb8(film, ToneMap::Aces, 0.0f) == aces);
}

TEST_CASE("toSrgb8 exposure scales by 2^EV before the tone curve", "[tonemap]") {
    const Film half = makeFilm(1, 1, {glm::vec3(0.5f, 0.125f, 1.5f)});
    const Film one = makeFilm(1, 1, {glm::vec3(1.0f, 0.25f, 3.0f)});
    for (ToneMap op : {ToneMap::Aces, ToneMap::Reinhard}) {
        CHECK(toSrgb8(half, op, 1.0f) == toSrgb8(one, op));
        CHECK(toSrgb8(one, op, -1.0f) == toSrgb8(half, op));
        CHECK(toSrgb8(half, op, 1.0f) != toSrgb8(half, op));
    }
    // Reinhard at exposure +1: 0.5 -> 1 -> 188 (not 156, which is 0.5 unscaled).
    CHECK(toSrgb8(half, ToneMap::Reinhard, 1.0f)[0] == 188);
    CHECK(toSrgb8(half, ToneMap::Reinhard, 0.0f)[0] == 156);
}

TEST_CASE("toLinearRgb copies the film's mean in order without transforming it", "[tonemap]") {
    const Film film = makeFilm(3, 1, {glm::vec3(0.0f, 1.0f, 2.0f), glm::vec3(100.0f, 0.5f, 0.25f),
                                      glm::vec3(1e-4f, 7.0f, 3.5f)});
    const std::vector<float> expected = {0.0f, 1.0f, 2.0f, 100.0f, 0.5f, 0.25f, 1e-4f, 7.0f, 3.5f};
    CHECK(toLinearRgb(film) == expected);
}
