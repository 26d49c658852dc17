// The core's Radiance HDR reader: flat and run-length encoded scanlines decode to the same
// values, which are the RGBE definition's; bad files fail with the file's name.
#include "renderer/hdr_file.h"
#include "tests/support/meshes.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>

using namespace caustic;

namespace {

void writeHeader(std::ofstream& f, int w, int h) {
    f << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " << h << " +X " << w << "\n";
}

}  // namespace

TEST_CASE("Radiance HDR: flat and RLE scanlines decode to mantissa * 2^(e - 136)", "[cpu][image]") {
    test::TempDir dir;
    const int w = 10, h = 2;
    // Pixel x of row y: R = 10 x + y, G = 128, B = 0, exponent 129 (scale 2^-7).
    auto pixel = [](int x, int y) { return std::array<unsigned char, 4>{static_cast<unsigned char>(10 * x + y), 128, 0, 129}; };
    {
        std::ofstream f(dir.file("flat.hdr"), std::ios::binary);
        writeHeader(f, w, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (unsigned char b : pixel(x, y)) f.put(static_cast<char>(b));
    }
    {
        std::ofstream f(dir.file("rle.hdr"), std::ios::binary);
        writeHeader(f, w, h);
        for (int y = 0; y < h; ++y) {
            f.put(2); f.put(2); f.put(0); f.put(static_cast<char>(w));
            // R: literal run of 10; G: a run of 10 x 128; B: run of 10 x 0; E: run of 10 x 129.
            f.put(static_cast<char>(w));
            for (int x = 0; x < w; ++x) f.put(static_cast<char>(pixel(x, y)[0]));
            for (int v : {128, 0, 129}) { f.put(static_cast<char>(128 + w)); f.put(static_cast<char>(v)); }
        }
    }
    for (const char* name : {"flat.hdr", "rle.hdr"}) {
        INFO(name);
        ImageData img;
        std::string error;
        REQUIRE(readRadianceHdr(dir.file(name), &img, &error));
        REQUIRE(img.width == w);
        REQUIRE(img.height == h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float* p = &img.pixels[(size_t(y) * w + x) * 3];
                CHECK(p[0] == float(10 * x + y) * std::ldexp(1.0f, -7));
                CHECK(p[1] == 1.0f);
                CHECK(p[2] == 0.0f);
            }
    }
    // The project's own sky loads, with its sun far brighter than the sky.
    ImageData sky;
    std::string error;
    REQUIRE(readRadianceHdr(CAUSTIC_SOURCE_DIR "/assets/sky.hdr", &sky, &error));
    CHECK(sky.width == 2 * sky.height);
    float peak = 0.0f;
    for (float v : sky.pixels) peak = std::max(peak, v);
    CHECK(peak > 1000.0f);
}

TEST_CASE("Radiance HDR: bad files are refused with their name", "[cpu][image]") {
    test::TempDir dir;
    std::string error;
    ImageData img;
    CHECK_FALSE(readRadianceHdr(dir.file("missing.hdr"), &img, &error));
    CHECK(error.find("missing.hdr") != std::string::npos);
    {
        std::ofstream f(dir.file("short.hdr"), std::ios::binary);
        writeHeader(f, 4, 4);
        f << "abcd";
    }
    CHECK_FALSE(readRadianceHdr(dir.file("short.hdr"), &img, &error));
    CHECK(error.find("truncated") != std::string::npos);
    {
        std::ofstream f(dir.file("odd.hdr"), std::ios::binary);
        f << "#?RADIANCE\n\n+Y 4 +X 4\n";
    }
    CHECK_FALSE(readRadianceHdr(dir.file("odd.hdr"), &img, &error));
    CHECK(error.find("resolution") != std::string::npos);
}
