#include "app/contact_sheet.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <sstream>

namespace caustic {
namespace {

constexpr int kGlyphW = 5, kGlyphH = 7;

// 5x7 glyphs, one string of 7 rows of 5 columns each ('#' = ink). Upper case letters serve for
// lower case too.
const std::map<char, std::array<const char*, 7>>& font() {
    static const std::map<char, std::array<const char*, 7>> kFont = {
        {'0', {" ### ", "#   #", "#  ##", "# # #", "##  #", "#   #", " ### "}},
        {'1', {"  #  ", " ##  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "}},
        {'2', {" ### ", "#   #", "    #", "   # ", "  #  ", " #   ", "#####"}},
        {'3', {"#####", "   # ", "  #  ", "   # ", "    #", "#   #", " ### "}},
        {'4', {"   # ", "  ## ", " # # ", "#  # ", "#####", "   # ", "   # "}},
        {'5', {"#####", "#    ", "#### ", "    #", "    #", "#   #", " ### "}},
        {'6', {"  ## ", " #   ", "#    ", "#### ", "#   #", "#   #", " ### "}},
        {'7', {"#####", "    #", "   # ", "  #  ", " #   ", " #   ", " #   "}},
        {'8', {" ### ", "#   #", "#   #", " ### ", "#   #", "#   #", " ### "}},
        {'9', {" ### ", "#   #", "#   #", " ####", "    #", "   # ", " ##  "}},
        {'A', {" ### ", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"}},
        {'B', {"#### ", "#   #", "#   #", "#### ", "#   #", "#   #", "#### "}},
        {'C', {" ### ", "#   #", "#    ", "#    ", "#    ", "#   #", " ### "}},
        {'D', {"###  ", "#  # ", "#   #", "#   #", "#   #", "#  # ", "###  "}},
        {'E', {"#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#####"}},
        {'F', {"#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#    "}},
        {'G', {" ### ", "#   #", "#    ", "# ###", "#   #", "#   #", " ####"}},
        {'H', {"#   #", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"}},
        {'I', {" ### ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "}},
        {'J', {"  ###", "   # ", "   # ", "   # ", "   # ", "#  # ", " ##  "}},
        {'K', {"#   #", "#  # ", "# #  ", "##   ", "# #  ", "#  # ", "#   #"}},
        {'L', {"#    ", "#    ", "#    ", "#    ", "#    ", "#    ", "#####"}},
        {'M', {"#   #", "## ##", "# # #", "# # #", "#   #", "#   #", "#   #"}},
        {'N', {"#   #", "#   #", "##  #", "# # #", "#  ##", "#   #", "#   #"}},
        {'O', {" ### ", "#   #", "#   #", "#   #", "#   #", "#   #", " ### "}},
        {'P', {"#### ", "#   #", "#   #", "#### ", "#    ", "#    ", "#    "}},
        {'Q', {" ### ", "#   #", "#   #", "#   #", "# # #", "#  # ", " ## #"}},
        {'R', {"#### ", "#   #", "#   #", "#### ", "# #  ", "#  # ", "#   #"}},
        {'S', {" ####", "#    ", "#    ", " ### ", "    #", "    #", "#### "}},
        {'T', {"#####", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  "}},
        {'U', {"#   #", "#   #", "#   #", "#   #", "#   #", "#   #", " ### "}},
        {'V', {"#   #", "#   #", "#   #", "#   #", "#   #", " # # ", "  #  "}},
        {'W', {"#   #", "#   #", "#   #", "# # #", "# # #", "# # #", " # # "}},
        {'X', {"#   #", "#   #", " # # ", "  #  ", " # # ", "#   #", "#   #"}},
        {'Y', {"#   #", "#   #", " # # ", "  #  ", "  #  ", "  #  ", "  #  "}},
        {'Z', {"#####", "    #", "   # ", "  #  ", " #   ", "#    ", "#####"}},
        {'.', {"     ", "     ", "     ", "     ", "     ", " ##  ", " ##  "}},
        {',', {"     ", "     ", "     ", "     ", " ##  ", "  #  ", " #   "}},
        {':', {"     ", " ##  ", " ##  ", "     ", " ##  ", " ##  ", "     "}},
        {'=', {"     ", "     ", "#####", "     ", "#####", "     ", "     "}},
        {'-', {"     ", "     ", "     ", "#####", "     ", "     ", "     "}},
        {'+', {"     ", "  #  ", "  #  ", "#####", "  #  ", "  #  ", "     "}},
        {'_', {"     ", "     ", "     ", "     ", "     ", "     ", "#####"}},
        {'/', {"    #", "    #", "   # ", "  #  ", " #   ", "#    ", "#    "}},
        {'[', {" ### ", " #   ", " #   ", " #   ", " #   ", " #   ", " ### "}},
        {']', {" ### ", "   # ", "   # ", "   # ", "   # ", "   # ", " ### "}},
        {'(', {"   # ", "  #  ", " #   ", " #   ", " #   ", "  #  ", "   # "}},
        {')', {" #   ", "  #  ", "   # ", "   # ", "   # ", "  #  ", " #   "}},
        {'"', {" # # ", " # # ", "     ", "     ", "     ", "     ", "     "}},
        {' ', {"     ", "     ", "     ", "     ", "     ", "     ", "     "}},
    };
    return kFont;
}

}  // namespace

void drawText(std::vector<std::uint8_t>& rgb, int width, int height, int x, int y, const std::string& text,
              int scale, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    static const std::array<const char*, 7> kMissing = {"#####", "#   #", "#   #", "#   #", "#   #", "#   #", "#####"};
    int penX = x;
    for (char ch : text) {
        const auto it = font().find(static_cast<char>(std::toupper(static_cast<unsigned char>(ch))));
        const auto& glyph = it != font().end() ? it->second : kMissing;
        for (int gy = 0; gy < kGlyphH; ++gy)
            for (int gx = 0; gx < kGlyphW; ++gx) {
                if (glyph[gy][gx] != '#') continue;
                for (int sy = 0; sy < scale; ++sy)
                    for (int sx = 0; sx < scale; ++sx) {
                        const int px = penX + gx * scale + sx, py = y + gy * scale + sy;
                        if (px < 0 || py < 0 || px >= width || py >= height) continue;
                        std::uint8_t* p = &rgb[(static_cast<size_t>(py) * width + px) * 3];
                        p[0] = r;
                        p[1] = g;
                        p[2] = b;
                    }
            }
        penX += (kGlyphW + 1) * scale;
    }
}

namespace {

// The label's lines, each wrapped to at most `maxChars` characters.
std::vector<std::string> wrapLabel(const std::string& label, int maxChars) {
    std::vector<std::string> out;
    std::istringstream lines(label);
    std::string line;
    while (std::getline(lines, line)) {
        do {
            out.push_back(line.substr(0, static_cast<size_t>(maxChars)));
            line = line.size() > static_cast<size_t>(maxChars) ? line.substr(static_cast<size_t>(maxChars)) : "";
        } while (!line.empty());
    }
    return out;
}

}  // namespace

Sheet makeContactSheet(const std::vector<SheetCell>& cells, int columns) {
    Sheet sheet;
    if (cells.empty()) return sheet;
    columns = std::max(1, std::min(columns, static_cast<int>(cells.size())));
    const int rows = (static_cast<int>(cells.size()) + columns - 1) / columns;
    int cellW = 0, cellH = 0;
    for (const SheetCell& c : cells) {
        cellW = std::max(cellW, c.width);
        cellH = std::max(cellH, c.height);
    }
    const int scale = std::clamp(cellW / 160, 1, 4);
    const int maxChars = std::max(1, cellW / ((kGlyphW + 1) * scale));
    int maxLines = 1;
    for (const SheetCell& c : cells) maxLines = std::max(maxLines, static_cast<int>(wrapLabel(c.label, maxChars).size()));
    const int lineH = (kGlyphH + 3) * scale, pad = 4 * scale;
    const int labelH = maxLines * lineH + pad;
    sheet.width = columns * cellW + (columns + 1) * pad;
    sheet.height = rows * (cellH + labelH) + (rows + 1) * pad;
    sheet.rgb.assign(static_cast<size_t>(sheet.width) * sheet.height * 3, 24);  // dark grey
    for (size_t i = 0; i < cells.size(); ++i) {
        const SheetCell& c = cells[i];
        const int col = static_cast<int>(i) % columns, row = static_cast<int>(i) / columns;
        const int x0 = pad + col * (cellW + pad), y0 = pad + row * (cellH + labelH + pad);
        for (int y = 0; y < c.height; ++y)
            std::copy_n(&c.rgb[static_cast<size_t>(y) * c.width * 3], static_cast<size_t>(c.width) * 3,
                        &sheet.rgb[(static_cast<size_t>(y0 + y) * sheet.width + x0) * 3]);
        int ly = y0 + c.height + pad / 2;
        for (const std::string& line : wrapLabel(c.label, maxChars)) {
            drawText(sheet.rgb, sheet.width, sheet.height, x0, ly, line, scale, 235, 235, 235);
            ly += lineH;
        }
    }
    return sheet;
}

}  // namespace caustic
