// caustic's subcommands besides rendering: `caustic merge`, `caustic compare`, `caustic sheet`
// (app/merge.cpp, app/compare.cpp, app/sheet_command.cpp). Each returns the exit status.
#pragma once

#include "app/cli.h"

#include <string>

namespace caustic {

inline constexpr int kExitFailed = 1;
inline constexpr int kExitBadUsage = 2;

int runMerge(const CliOptions& o);
int runCompare(const CliOptions& o);
int runSheet(const CliOptions& o);

// Prints "caustic: error: <message>" and returns code.
int commandFailed(const std::string& message, int code = kExitFailed);

}  // namespace caustic
