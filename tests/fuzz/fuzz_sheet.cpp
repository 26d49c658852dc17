// Fuzz harness: the layout of `caustic sheet` (app/commands.h parseSheetLayout, which reads it
// with renderer/scene_io.h parseJsonStrict) and, for a layout it accepts, the sheet itself
// (app/contact_sheet.h makeContactSheet: the layout's sizes and the labels' wrapping and drawing).
// Properties beyond "no crash, no hang, no leak, no undefined behaviour":
//   - a refused layout gets a one-line message starting with the layout's file name;
//   - an accepted one has what parseSheetLayout promises: an output name that is not empty and has
//     no NUL, columns in [1, 4096], at least one cell, image names without NUL;
//   - the sheet of its first kMaxCells cells (each a small image whose size comes from its image
//     name, so the fuzzer chooses it) is made, has the size the layout gives, and holds each cell's
//     pixels where the layout puts them.
// Seeds: tests/fuzz/seeds/sheet/ (make_seeds.py), dictionary tests/fuzz/scene.dict.
#include "app/commands.h"
#include "app/contact_sheet.h"
#include "tests/fuzz/fuzz_common.h"

#include <algorithm>

using namespace caustic;

namespace {

// The sheet is drawn for at most this many cells of at most kMaxSide pixels a side: enough for
// every layout rule (rows, a last row not full, labels of several lines and cut ones), small
// enough that drawing stays fast under the sanitizers.
constexpr std::size_t kMaxCells = 24;
constexpr int kMaxSide = 40;

// FNV-1a of the image name: the cell's size and colour.
std::uint32_t hashOf(const std::string& s) {
    std::uint32_t h = 2166136261u;
    for (const char c : s) h = (h ^ static_cast<unsigned char>(c)) * 16777619u;
    return h;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const std::string file = "layout.json";
    SheetLayout layout;
    std::string error;
    if (!parseSheetLayout(text, file, &layout, &error)) {
        FUZZ_CHECK(error.rfind(file + ":", 0) == 0, "the message does not name the layout: " + error);
        FUZZ_CHECK(error.find('\n') == std::string::npos, error);
        return 0;
    }
    FUZZ_CHECK(error.empty(), error);
    FUZZ_CHECK(!layout.output.empty() && layout.output.find('\0') == std::string::npos, layout.output);
    FUZZ_CHECK(layout.columns >= 1 && layout.columns <= 4096, std::to_string(layout.columns));
    FUZZ_CHECK(!layout.cells.empty(), "no cells");
    for (const SheetLayout::Cell& c : layout.cells) FUZZ_CHECK(c.image.find('\0') == std::string::npos, c.image);

    std::vector<SheetCell> cells;
    for (std::size_t i = 0; i < layout.cells.size() && i < kMaxCells; ++i) {
        const std::uint32_t h = hashOf(layout.cells[i].image);
        SheetCell cell;
        cell.width = 1 + int(h % kMaxSide);
        cell.height = 1 + int((h >> 8) % kMaxSide);
        cell.rgb.assign(std::size_t(cell.width) * std::size_t(cell.height) * 3, std::uint8_t(h >> 16));
        cell.rgb[0] = std::uint8_t(i);   // its first pixel says which cell it is
        cell.label = layout.cells[i].label;
        cells.push_back(std::move(cell));
    }
    Sheet sheet;
    FUZZ_CHECK(makeContactSheet(cells, layout.columns, &sheet, &error), error);
    FUZZ_CHECK(sheet.width > 0 && sheet.height > 0 && sheet.width <= kSheetMaxSide && sheet.height <= kSheetMaxSide,
               std::to_string(sheet.width) + " x " + std::to_string(sheet.height));
    FUZZ_CHECK(sheet.rgb.size() == std::size_t(sheet.width) * std::size_t(sheet.height) * 3,
               std::to_string(sheet.rgb.size()));
    // Where each cell's first pixel is: a grid of the widest and tallest cell, `columns` wide, with
    // the same padding left and right of every column; the width is the whole of it.
    const int columns = std::min(layout.columns, int(cells.size()));
    int cellW = 0;
    for (const SheetCell& c : cells) cellW = std::max(cellW, c.width);
    const int pad = (sheet.width - columns * cellW) / (columns + 1);
    FUZZ_CHECK(pad > 0 && columns * cellW + (columns + 1) * pad == sheet.width,
               "width " + std::to_string(sheet.width) + " for " + std::to_string(columns) + " columns of " +
                   std::to_string(cellW));
    const int rows = (int(cells.size()) + columns - 1) / columns;
    const int rowPitch = (sheet.height - pad) / rows;
    FUZZ_CHECK(rows * rowPitch + pad == sheet.height, "height " + std::to_string(sheet.height));
    for (std::size_t i = 0; i < cells.size(); ++i) {
        const int x = pad + int(i % std::size_t(columns)) * (cellW + pad);
        const int y = pad + int(i / std::size_t(columns)) * rowPitch;
        const std::size_t at = (std::size_t(y) * std::size_t(sheet.width) + std::size_t(x)) * 3;
        FUZZ_CHECK(sheet.rgb[at] == cells[i].rgb[0] && sheet.rgb[at + 1] == cells[i].rgb[1],
                   "cell " + std::to_string(i) + " is not at (" + std::to_string(x) + ", " + std::to_string(y) + ")");
    }
    return 0;
}
