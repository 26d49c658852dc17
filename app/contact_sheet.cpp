#include "app/contact_sheet.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace caustic {
namespace {

// The label's lines: split at '\n' (a trailing one adds no line), each cut into pieces of at
// most `maxChars` characters. Cuts fall between UTF-8 code points, never inside one.
std::vector<std::string> wrapLabel(const std::string& label, std::size_t maxChars) {
    std::vector<std::string> out;
    std::istringstream lines(label);
    std::string line;
    while (std::getline(lines, line)) {
        std::size_t pieceStart = 0, chars = 0;
        for (std::size_t i = 0; i < line.size(); ++i) {
            if ((static_cast<unsigned char>(line[i]) & 0xC0) == 0x80) continue;  // a continuation byte
            if (chars == maxChars) {
                out.push_back(line.substr(pieceStart, i - pieceStart));
                pieceStart = i;
                chars = 0;
            }
            ++chars;
        }
        out.push_back(line.substr(pieceStart));
    }
    return out;
}

// Shortens `line` (whole UTF-8 code points from its end) until it and a trailing "..." fit in
// `maxChars` characters, and appends the "...".
void endWithEllipsis(std::string& line, std::size_t maxChars) {
    auto codePoints = [](const std::string& t) {
        std::size_t n = 0;
        for (const char c : t) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
        return n;
    };
    while (!line.empty() && codePoints(line) + 3 > maxChars) {
        while (!line.empty() && (static_cast<unsigned char>(line.back()) & 0xC0) == 0x80) line.pop_back();
        if (!line.empty()) line.pop_back();  // the code point's lead byte
    }
    line += "...";
}

}  // namespace

bool makeContactSheet(const std::vector<SheetCell>& cells, int columns, Sheet* sheet, std::string* error,
                      const std::string& fontPath) {
    *sheet = Sheet{};
    if (cells.empty()) return true;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(fontPath, ec)) {
        *error = "contact sheet: the label font " + fontPath +
                 " is missing (Debian's package fonts-dejavu-core holds it; ./setup.sh installs it)";
        return false;
    }
    columns = std::max(1, std::min(columns, static_cast<int>(cells.size())));
    const int rows = (static_cast<int>(cells.size()) + columns - 1) / columns;
    int cellW = 0, cellH = 0;
    for (const SheetCell& c : cells) {
        cellW = std::max(cellW, c.width);
        cellH = std::max(cellH, c.height);
    }
    const int scale = std::clamp(cellW / 160, 1, 4);
    const int fontSize = 12 * scale;  // pixels per em; DejaVu Sans Mono advances 0.6 em a character
    // The font's extent: above the baseline (ybegin < 0) to below it, from capitals, descenders
    // and a bar; and its advance, from a line of wide glyphs.
    const OIIO::ROI extent = OIIO::ImageBufAlgo::text_size("Hgj|", fontSize, fontPath);
    const OIIO::ROI wide = OIIO::ImageBufAlgo::text_size(std::string(16, 'W'), fontSize, fontPath);
    if (!extent.defined() || !wide.defined() || wide.width() <= 0) {
        *error = "contact sheet: " + fontPath + ": OpenImageIO cannot draw text with it: " + OIIO::geterror();
        return false;
    }
    const int advance = std::max(1, (wide.width() + 15) / 16);
    const int maxChars = std::max(1, cellW / advance);
    std::vector<std::vector<std::string>> labels;
    std::size_t maxLines = 1;
    for (const SheetCell& c : cells) {
        labels.push_back(wrapLabel(c.label, static_cast<std::size_t>(maxChars)));
        // A label of more lines than kSheetMaxLabelLines keeps its first ones, the last of them
        // ending in "..." (a sweep's label is a line or two; a longer one is not read under a cell).
        std::vector<std::string>& lines = labels.back();
        if (lines.size() > kSheetMaxLabelLines) {
            lines.resize(kSheetMaxLabelLines);
            endWithEllipsis(lines.back(), static_cast<std::size_t>(maxChars));
        }
        maxLines = std::max(maxLines, lines.size());
    }
    const int pad = 4 * scale;
    const int lineH = extent.height() + 2 * scale;
    const int labelH = static_cast<int>(maxLines) * lineH + pad;
    // The sheet's size in 64 bits (cells within the limits can add up to more than an int holds),
    // refused beyond kSheetMaxSide pixels a side or kSheetMaxBytes.
    const std::int64_t width = std::int64_t(columns) * cellW + std::int64_t(columns + 1) * pad;
    const std::int64_t height = std::int64_t(rows) * (std::int64_t(cellH) + labelH) + std::int64_t(rows + 1) * pad;
    if (width > kSheetMaxSide || height > kSheetMaxSide || width * height * 3 > kSheetMaxBytes) {
        *error = "contact sheet: " + std::to_string(cells.size()) + " cells of up to " + std::to_string(cellW) + " x " +
                 std::to_string(cellH) + " pixels in " + std::to_string(columns) + " columns make a sheet of " +
                 std::to_string(width) + " x " + std::to_string(height) + " pixels, more than the " +
                 std::to_string(kSheetMaxSide) + " a side (or " + std::to_string(kSheetMaxBytes >> 20) +
                 " MiB) a sheet may have: use more columns, smaller images or several sheets";
        return false;
    }
    sheet->width = static_cast<int>(width);
    sheet->height = static_cast<int>(height);
    sheet->rgb.assign(static_cast<size_t>(sheet->width) * sheet->height * 3, 24);  // dark grey
    // The sheet's pixels as an OpenImageIO image (no copy): render_text draws straight into them.
    OIIO::ImageBuf canvas(OIIO::ImageSpec(sheet->width, sheet->height, 3, OIIO::TypeDesc::UINT8), sheet->rgb.data());
    const float ink[3] = {235.0f / 255.0f, 235.0f / 255.0f, 235.0f / 255.0f};
    for (size_t i = 0; i < cells.size(); ++i) {
        const SheetCell& c = cells[i];
        const int col = static_cast<int>(i) % columns, row = static_cast<int>(i) / columns;
        const int x0 = pad + col * (cellW + pad), y0 = pad + row * (cellH + labelH + pad);
        for (int y = 0; y < c.height; ++y)
            std::copy_n(&c.rgb[static_cast<size_t>(y) * c.width * 3], static_cast<size_t>(c.width) * 3,
                        &sheet->rgb[(static_cast<size_t>(y0 + y) * sheet->width + x0) * 3]);
        // The label's area: under the image, as wide as the cell. Text is clipped to it.
        const OIIO::ROI area(x0, x0 + cellW, y0 + c.height, y0 + cellH + labelH, 0, 1, 0, 3);
        int baseline = y0 + c.height + pad / 2 - extent.ybegin;
        for (const std::string& line : labels[i]) {
            if (!line.empty() && !OIIO::ImageBufAlgo::render_text(canvas, x0, baseline, line, fontSize, fontPath, ink,
                                                                  OIIO::ImageBufAlgo::TextAlignX::Left,
                                                                  OIIO::ImageBufAlgo::TextAlignY::Baseline, 0, area)) {
                *error = "contact sheet: cell " + std::to_string(i) + ": " + canvas.geterror();
                return false;
            }
            baseline += lineH;
        }
    }
    return true;
}

}  // namespace caustic
