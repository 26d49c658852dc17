// caustic sheet LAYOUT.json: a contact sheet made from image files, the way --sweep makes one
// from its renders (the farm renders each variant elsewhere and assembles the sheet at the end).
// The layout: {"output": "sheet.png", "columns": 2, "cells": [{"image": "a.png", "label": "..."}]}
// (paths relative to the layout file's folder). Cells are read as 8-bit RGB.
#include "app/commands.h"
#include "app/contact_sheet.h"
#include "renderer/file_util.h"
#include "renderer/image_io.h"
#include "renderer/scene_io.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

namespace fs = std::filesystem;

namespace caustic {
namespace {

// A key of the layout as a message names it: on one line (a newline as \n, other control
// characters as '?') and at most kMaxKeyBytes of it, cut between UTF-8 code points, with "..."
// when cut: the message of a hostile layout stays one short line.
std::string keyForMessage(const std::string& key) {
    constexpr std::size_t kMaxKeyBytes = 64;
    std::size_t keep = std::min(key.size(), kMaxKeyBytes);
    while (keep > 0 && keep < key.size() && (static_cast<unsigned char>(key[keep]) & 0xC0) == 0x80) --keep;
    std::string out;
    for (std::size_t i = 0; i < keep; ++i) {
        const char c = key[i];
        if (c == '\n') out += "\\n";
        else if (c == '\r') out += "\\r";
        else if (c == '\t') out += "\\t";
        else if (static_cast<unsigned char>(c) < 0x20) out += '?';
        else out += c;
    }
    return keep < key.size() ? out + "..." : out;
}

}  // namespace

bool parseSheetLayout(const std::string& text, const std::string& layoutPath, SheetLayout* out, std::string* error) {
    // Read as strictly as a scene file (a duplicate key is an error, not the last one winning).
    nlohmann::json layout;
    if (!parseJsonStrict(text, layoutPath, &layout, error)) return false;
    if (!layout.is_object()) {
        *error = layoutPath + ": not a JSON object";
        return false;
    }
    const auto bad = [&](const std::string& where, const std::string& what) {
        *error = layoutPath + ": " + where + ": " + what;
        return false;
    };
    if (!layout.contains("output") || !layout["output"].is_string() || layout["output"].get<std::string>().empty() ||
        layout["output"].get<std::string>().find('\0') != std::string::npos)
        return bad("output", "expected a file name (not empty, no NUL character)");
    if (!layout.contains("columns") || !layout["columns"].is_number_integer() || layout["columns"].get<long long>() < 1 ||
        layout["columns"].get<long long>() > 4096)
        return bad("columns", "expected an integer in [1, 4096]");
    if (!layout.contains("cells") || !layout["cells"].is_array() || layout["cells"].empty())
        return bad("cells", "expected a non-empty array");
    for (const auto& [key, value] : layout.items())
        if (key != "output" && key != "columns" && key != "cells") return bad(keyForMessage(key), "unknown key");
    SheetLayout result;
    result.output = layout["output"].get<std::string>();
    result.columns = int(layout["columns"].get<long long>());
    for (size_t i = 0; i < layout["cells"].size(); ++i) {
        const auto& c = layout["cells"][i];
        const std::string where = "cells[" + std::to_string(i) + "]";
        if (!c.is_object() || !c.contains("image") || !c["image"].is_string()) return bad(where + ".image", "expected a file name");
        if (c.contains("label") && !c["label"].is_string()) return bad(where + ".label", "expected a string");
        for (const auto& [key, value] : c.items())
            if (key != "image" && key != "label")
                return bad(where + "." + keyForMessage(key), "unknown key (a cell has image and label)");
        if (c["image"].get<std::string>().find('\0') != std::string::npos)
            return bad(where + ".image", "expected a file name (no NUL character)");
        result.cells.push_back({c["image"].get<std::string>(), c.value("label", std::string())});
    }
    *out = std::move(result);
    return true;
}

int runSheet(const CliOptions& o) {
    const std::string& layoutPath = o.inputs[0];
    std::string error;
    const auto text = readTextFile(layoutPath, &error);
    if (!text) return commandFailed(error);
    SheetLayout layout;
    if (!parseSheetLayout(*text, layoutPath, &layout, &error)) return commandFailed(error);
    const fs::path folder = fs::path(layoutPath).parent_path();
    auto resolve = [&](const std::string& p) { return fs::path(p).is_absolute() ? p : (folder / p).string(); };
    std::vector<SheetCell> cells;
    for (size_t i = 0; i < layout.cells.size(); ++i) {
        const SheetLayout::Cell& c = layout.cells[i];
        ImageData img;
        if (!readImage(resolve(c.image), &img, &error)) return commandFailed(error);
        if (img.channels < 3)
            return commandFailed(layoutPath + ": cells[" + std::to_string(i) + "]: " + c.image + " is not an RGB image");
        SheetCell cell{img.width, img.height, std::vector<std::uint8_t>(size_t(img.width) * img.height * 3), c.label};
        for (size_t p = 0; p < size_t(img.width) * img.height; ++p)
            for (int k = 0; k < 3; ++k)
                cell.rgb[p * 3 + k] = std::uint8_t(std::lround(std::clamp(img.pixels[p * img.channels + k], 0.0f, 1.0f) * 255.0f));
        cells.push_back(std::move(cell));
    }
    Sheet sheet;
    if (!makeContactSheet(cells, layout.columns, &sheet, &error)) return commandFailed(error);
    const std::string out = resolve(layout.output);
    const ImageMetadata meta = {{"Software", std::string("caustic ") + CAUSTIC_VERSION}};
    if (!writeImage8(out, sheet.width, sheet.height, sheet.rgb, meta, &error)) return commandFailed(error);
    std::cout << out << std::endl;
    return 0;
}

}  // namespace caustic
