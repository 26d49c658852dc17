// Contact sheets for --sweep and `caustic sheet`: a grid of 8-bit RGB images, each cell with a
// text label under it, drawn by OpenImageIO (ImageBufAlgo::render_text, FreeType) in DejaVu Sans
// Mono.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace caustic {

// The largest sheet (pixels a side, and bytes of RGB): beyond, makeContactSheet refuses the layout.
inline constexpr std::int64_t kSheetMaxSide = 65535;
inline constexpr std::int64_t kSheetMaxBytes = std::int64_t(1) << 31;
// A label keeps at most this many lines under its cell.
inline constexpr std::size_t kSheetMaxLabelLines = 16;

// The labels' font, from Debian's fonts-dejavu-core (setup.sh installs it).
inline constexpr const char* kSheetFont = "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf";

struct SheetCell {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  // width * height * 3, row 0 at the top
    std::string label;              // UTF-8
};

struct Sheet {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;
};

// Lays the cells out row by row, `columns` per row; each cell's label is printed under it
// (several lines if it contains '\n' or is wider than the cell), scaled up for legibility on
// large images, and never drawn outside its cell (at most kSheetMaxLabelLines lines, the last
// ending in "..." when cut). False with a message when the font cannot be loaded (a missing file
// names the Debian package) or when the sheet would exceed kSheetMaxSide or kSheetMaxBytes.
bool makeContactSheet(const std::vector<SheetCell>& cells, int columns, Sheet* sheet, std::string* error,
                      const std::string& fontPath = kSheetFont);

}  // namespace caustic
