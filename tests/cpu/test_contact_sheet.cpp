// The contact sheet (app/contact_sheet.cpp): where its labels are drawn, that they keep their case,
// and the message when the font is missing.
#include "app/contact_sheet.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

using namespace caustic;

namespace {

constexpr int kW = 64, kH = 48;
constexpr std::array<std::array<std::uint8_t, 3>, 4> kColours = {{{200, 30, 30}, {30, 200, 30}, {30, 30, 200}, {200, 200, 30}}};

// Four cells of one colour each, 2 x 2: the first three with the given labels, the fourth with as
// many empty lines as a label keeps (kSheetMaxLabelLines), so that every sheet made here has the same layout (no label here takes more).
std::vector<SheetCell> cells(const std::array<std::string, 3>& labels) {
    std::vector<SheetCell> out;
    for (std::size_t i = 0; i < 4; ++i) {
        SheetCell c{kW, kH, {}, i < 3 ? labels[i] : std::string(kSheetMaxLabelLines, '\n')};
        for (int p = 0; p < kW * kH; ++p) c.rgb.insert(c.rgb.end(), kColours[i].begin(), kColours[i].end());
        out.push_back(std::move(c));
    }
    return out;
}

Sheet sheetOf(const std::vector<SheetCell>& c, int columns) {
    Sheet s;
    std::string error;
    if (!makeContactSheet(c, columns, &s, &error)) FAIL(error);
    REQUIRE(s.rgb.size() == std::size_t(s.width) * s.height * 3);
    return s;
}

struct Box {
    int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;  // [x0, x1) x [y0, y1); empty while x1 < 0
    void add(int x, int y) {
        x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x + 1), y1 = std::max(y1, y + 1);
    }
};

// The pixels where a and b differ.
Box difference(const Sheet& a, const Sheet& b, int* count) {
    Box box;
    *count = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const std::size_t p = (std::size_t(y) * a.width + x) * 3;
            if (!std::equal(&a.rgb[p], &a.rgb[p] + 3, &b.rgb[p])) {
                box.add(x, y);
                ++*count;
            }
        }
    return box;
}

// Where the image of colour k lies on the sheet.
Box imageBox(const Sheet& s, std::size_t k) {
    Box box;
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x)
            if (std::equal(kColours[k].begin(), kColours[k].end(), &s.rgb[(std::size_t(y) * s.width + x) * 3])) box.add(x, y);
    return box;
}

}  // namespace

TEST_CASE("contact sheet: each label is drawn under its own image, within its cell's width, wrapped when long",
          "[sheet]") {
    const std::string longLabel = "camera.aperture_radius=0.125, camera.focus_distance=4";
    const std::string utf8 = "\xce\xb1\xce\xb2\xce\xb3=\xe2\x88\x9a" + std::string(40, 'x');   // "αβγ=√xxx..."
    const std::array<std::string, 3> labels = {"camera.squeeze=1", longLabel, utf8};
    const Sheet none = sheetOf(cells({"", "", ""}), 2);
    const Box secondRow = imageBox(none, 2);
    Box inks[3];
    for (std::size_t i = 0; i < 3; ++i) {
        std::array<std::string, 3> one;
        one[i] = labels[i];
        const Sheet only = sheetOf(cells(one), 2);
        REQUIRE(only.width == none.width);
        REQUIRE(only.height == none.height);
        // The label's pixels: those that differ from the sheet without labels.
        int inked = 0;
        const Box ink = inks[i] = difference(only, none, &inked);
        const Box image = imageBox(none, i);
        INFO("label " << i << " '" << labels[i] << "': ink in x [" << ink.x0 << ", " << ink.x1 << "), y [" << ink.y0
                      << ", " << ink.y1 << "); its image in x [" << image.x0 << ", " << image.x1 << "), y ["
                      << image.y0 << ", " << image.y1 << ")");
        REQUIRE(image.x1 - image.x0 == kW);
        REQUIRE(image.y1 - image.y0 == kH);
        CHECK(inked > 20);
        CHECK(ink.x0 >= image.x0);
        CHECK(ink.x1 <= image.x1);
        CHECK(ink.y0 >= image.y1);                              // under its image
        CHECK(ink.y1 <= (i < 2 ? secondRow.y0 : only.height));  // above the next row's images
        // Light grey text on the dark grey background: every changed pixel is a grey level.
        for (int y = ink.y0; y < ink.y1; ++y)
            for (int x = ink.x0; x < ink.x1; ++x) {
                const std::uint8_t* p = &only.rgb[(std::size_t(y) * only.width + x) * 3];
                CHECK((p[0] == p[1] && p[1] == p[2] && p[0] >= 24 && p[0] <= 235));
            }
    }
    // The long labels took several lines where the short one took one or two.
    CHECK(inks[1].y1 - inks[1].y0 > 2 * (inks[0].y1 - inks[0].y0));
    CHECK(inks[2].y1 - inks[2].y0 > 2 * (inks[0].y1 - inks[0].y0));
}

TEST_CASE("contact sheet: labels keep their case", "[sheet]") {
    const Sheet lower = sheetOf(cells({"fov=1000", "", ""}), 2);
    const Sheet upper = sheetOf(cells({"FOV=1000", "", ""}), 2);
    REQUIRE(lower.width == upper.width);
    REQUIRE(lower.height == upper.height);
    // The letters differ, "=1000" is drawn the same in both.
    int changed = 0, inked = 0;
    const Box letters = difference(lower, upper, &changed);
    const Box label = difference(upper, sheetOf(cells({"", "", ""}), 2), &inked);
    CHECK(changed > 10);
    CHECK(letters.x0 >= label.x0);
    CHECK(letters.x1 < label.x0 + (label.x1 - label.x0) / 2);
}

TEST_CASE("contact sheet: a missing font is an error naming the file and the Debian package", "[sheet]") {
    Sheet sheet;
    std::string error;
    CHECK_FALSE(makeContactSheet(cells({"a", "b", "c"}), 2, &sheet, &error, "/nonexistent/DejaVuSansMono.ttf"));
    CHECK(error == "contact sheet: the label font /nonexistent/DejaVuSansMono.ttf is missing (Debian's package "
                   "fonts-dejavu-core holds it; ./setup.sh installs it)");
    CHECK(sheet.rgb.empty());
    // The font the program uses is there (setup.sh installs it).
    CHECK(makeContactSheet(cells({"a", "b", "c"}), 2, &sheet, &error));
}

TEST_CASE("contact sheet: a layout beyond the size limits is refused with its size, before anything is allocated",
          "[sheet]") {
    // Cells within the render limits whose sheet is taller than an int holds: one 1 x 65536 cell
    // above 65,519 1 x 1 cells, one column (65,520 rows of 65,536 pixels and a label each).
    std::vector<SheetCell> tall(65520, SheetCell{1, 1, {0, 0, 0}, "x"});
    tall[0] = SheetCell{1, 65536, std::vector<std::uint8_t>(65536 * 3, 0), "tall"};
    Sheet sheet;
    std::string error;
    CHECK_FALSE(makeContactSheet(tall, 1, &sheet, &error));
    INFO(error);
    CHECK(error.find("65520 cells of up to 1 x 65536 pixels in 1 columns") != std::string::npos);
    CHECK(error.find("more than the 65535 a side") != std::string::npos);
    CHECK(sheet.rgb.empty());
    // One row of them instead is as wide as it is refused.
    CHECK_FALSE(makeContactSheet(tall, 65520, &sheet, &error));
    CHECK(sheet.rgb.empty());
}

TEST_CASE("contact sheet: a label of a megabyte keeps its first lines and ends in an ellipsis", "[sheet]") {
    // Without the cut the label would take ~100,000 lines (a sheet too tall to draw); cut, the
    // sheet is the one a label of kSheetMaxLabelLines lines makes, and it is drawn at once.
    const Sheet huge = sheetOf(cells({std::string(1 << 20, 'w'), "", ""}), 2);
    const Sheet full = sheetOf(cells({std::string(kSheetMaxLabelLines * 200, 'w'), "", ""}), 2);
    const Sheet none = sheetOf(cells({"", "", ""}), 2);
    CHECK(huge.height == none.height);
    CHECK(huge.width == none.width);
    // Its ink stays in its own cell, above the next row's images, and is that of the cut label.
    int inked = 0;
    const Box ink = difference(huge, none, &inked);
    CHECK(inked > 100);
    CHECK(ink.y1 <= imageBox(none, 2).y0);
    CHECK(huge.rgb == full.rgb);
}
