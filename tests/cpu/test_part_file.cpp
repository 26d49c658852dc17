// Part files (app/part_file.h): what a render writes reads back exactly, and a part whose pixels
// no render writes (NaN, infinite or negative sums) is refused even when its checksum was made
// to match, naming the file, the pixel and the channel.
#include "app/part_file.h"
#include "tests/support/meshes.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>

using namespace caustic;

namespace {

Part smallPart() {
    Part p;
    p.info.scene = "scene.json";
    p.info.renderHash = "0123456789abcdef";
    p.info.version = "test";
    p.info.seed = 3;
    p.info.width = 8;
    p.info.height = 6;
    p.info.sample0 = 0;
    p.info.sample1 = 4;
    p.info.crop = {2, 1, 6, 4};  // 4 x 3 pixels
    Accumulators& s = p.sums;
    s.width = 4;
    s.height = 3;
    for (int i = 0; i < 12; ++i) {
        s.sum.push_back(glm::vec4(0.5f * i, 0.25f, 1.0f, 4.0f));
        s.sumSq.push_back(glm::vec4(0.1f * i, 0.02f, 0.3f, 0.0f));
        s.albedo.push_back(glm::vec4(0.8f, 0.5f, 0.2f, 4.0f));
        s.normal.push_back(glm::vec4(0.0f, -4.0f, 0.5f, 4.0f));  // normals may be negative
    }
    return p;
}

}  // namespace

TEST_CASE("part files: a part reads back bit for bit, and sums no render writes are refused with their place",
          "[part]") {
    test::TempDir dir;
    const std::string path = (dir.path / "p.exr").string();
    std::string error;
    const Part good = smallPart();
    REQUIRE(writePart(path, good, &error));
    Part back;
    REQUIRE(readPart(path, &back, &error));
    CHECK(back.sums.sum == good.sums.sum);
    CHECK(back.sums.normal == good.sums.normal);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    struct Case { const char* what; int pixel; int row; int component; float value; const char* channel; };
    for (const Case c : {Case{"a NaN sum", 5, 0, 1, nan, "sum.G"}, Case{"an infinite square", 0, 1, 2, inf, "sumsq.B"},
                         Case{"a negative count", 11, 0, 3, -1.0f, "sum.A"},
                         Case{"a negative albedo", 7, 2, 0, -0.5f, "albedo.R"}}) {
        Part bad = smallPart();
        std::vector<glm::vec4>* rows[] = {&bad.sums.sum, &bad.sums.sumSq, &bad.sums.albedo, &bad.sums.normal};
        (*rows[c.row])[size_t(c.pixel)][c.component] = c.value;
        const std::string badPath = (dir.path / "bad.exr").string();
        REQUIRE(writePart(badPath, bad, &error));  // its checksum is the one of these pixels
        Part read;
        error.clear();
        INFO(c.what);
        CHECK_FALSE(readPart(badPath, &read, &error));
        INFO(error);
        const int x = 2 + c.pixel % 4, y = 1 + c.pixel / 4;
        CHECK(error.rfind(badPath + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") channel " +
                              c.channel,
                          0) == 0);
        CHECK(error.find("which no render writes") != std::string::npos);
    }
}

TEST_CASE("part files: an image size no render has and a render time that is not a number of seconds are refused",
          "[part]") {
    // Written while writing fuzz_part's properties: readPart took any positive image size (merge
    // then sized its work by it) and read the render time with atof, so "nan", "inf", "-1" and
    // text went through to the merged image's report.
    test::TempDir dir;
    const std::string path = (dir.path / "p.exr").string();
    std::string error;
    struct Case { int width, height; double seconds; const char* message; };
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (const Case c : {Case{16385, 6, 0.5, "metadata caustic:image_size = '16385x6' is not valid"},
                         Case{8, 100000, 0.5, "metadata caustic:image_size = '8x100000' is not valid"},
                         Case{8, 6, nan, "metadata caustic:render_seconds = 'nan' is not valid"},
                         Case{8, 6, inf, "metadata caustic:render_seconds = 'inf' is not valid"},
                         Case{8, 6, -1.0, "metadata caustic:render_seconds = '-1.000000' is not valid"}}) {
        INFO(c.message);
        Part bad = smallPart();
        bad.info.width = c.width;
        bad.info.height = c.height;
        bad.info.seconds = c.seconds;
        REQUIRE(writePart(path, bad, &error));
        for (const bool pixels : {false, true}) {
            Part read;
            error.clear();
            CHECK_FALSE(readPart(path, &read, &error, pixels));
            CHECK(error == path + ": " + c.message);
        }
    }
    // The largest render's parts, and any time a render can take, read.
    Part edge = smallPart();
    edge.info.width = kMaxRenderSide;
    edge.info.height = kMaxRenderSide;
    edge.info.seconds = 86400.0 * 365;
    REQUIRE(writePart(path, edge, &error));
    Part read;
    INFO(error);
    CHECK(readPart(path, &read, &error));
    CHECK(read.info.width == kMaxRenderSide);
    CHECK(read.info.seconds == 86400.0 * 365);
}
