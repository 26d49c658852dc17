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
