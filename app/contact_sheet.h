// Contact sheets for --sweep: a grid of 8-bit RGB images, each cell with a text label under it,
// drawn with a built-in 5x7 pixel font (ASCII letters, digits and the punctuation of JSON paths).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace caustic {

struct SheetCell {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  // width * height * 3, row 0 at the top
    std::string label;
};

struct Sheet {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;
};

// Lays the cells out row by row, `columns` per row; each cell's label is printed under it
// (several lines if it contains '\n'), scaled up for legibility on large images.
Sheet makeContactSheet(const std::vector<SheetCell>& cells, int columns);

// Draws text into an RGB buffer at (x, y), `scale` pixels per font pixel. Characters the font
// lacks are drawn as a hollow box.
void drawText(std::vector<std::uint8_t>& rgb, int width, int height, int x, int y, const std::string& text,
              int scale, std::uint8_t r, std::uint8_t g, std::uint8_t b);

}  // namespace caustic
