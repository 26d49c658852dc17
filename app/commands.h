// caustic's subcommands besides rendering: `caustic merge`, `caustic compare`, `caustic sheet`
// (app/merge.cpp, app/compare.cpp, app/sheet_command.cpp). Each returns the exit status.
#pragma once

#include "app/cli.h"

#include <string>
#include <vector>

namespace caustic {

inline constexpr int kExitFailed = 1;
inline constexpr int kExitBadUsage = 2;

int runMerge(const CliOptions& o);
int runCompare(const CliOptions& o);
int runSheet(const CliOptions& o);

// The layout of `caustic sheet`: {"output": "sheet.png", "columns": 2, "cells": [{"image": "a.png",
// "label": "..."}]}, paths as written (relative to the layout file's folder).
struct SheetLayout {
    struct Cell {
        std::string image, label;
    };
    std::string output;
    int columns = 0;   // [1, 4096]
    std::vector<Cell> cells;
};
// Parses and checks a layout as strictly as a scene file (parseJsonStrict: a duplicate key, a
// syntax error, an unknown key are errors): output a file name (not empty, no NUL), columns an
// integer in [1, 4096], cells a non-empty array of objects with an image (no NUL) and an optional
// label. False with a one-line message starting with layoutPath.
bool parseSheetLayout(const std::string& text, const std::string& layoutPath, SheetLayout* out, std::string* error);

// Prints "caustic: error: <message>" and returns code.
int commandFailed(const std::string& message, int code = kExitFailed);

}  // namespace caustic
