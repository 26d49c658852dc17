// Editor scripts: a text file of editor commands, one per line, replayed by the real editor
// (`CAUSTIC_EDITOR_SCRIPT=file caustic scene.json`) so end-to-end tests and measurements drive
// the same code paths as the mouse. The commands are one table (script_commands.h); docs/editor.md
// describes each. Words are separated by spaces; "double quotes" group words; # starts a comment.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace caustic::editor {

struct ScriptLine {
    int line = 0;                       // 1-based, for messages
    std::string op;
    std::vector<std::string> args;
};

struct ScriptParseResult {
    std::vector<ScriptLine> lines;
    std::string error;                  // "<file>:<line>: ..." when parsing failed
};

// Parses and checks every line (known command, argument count, numbers) before anything runs.
ScriptParseResult parseScript(const std::string& text, const std::string& fileForMessages);

// Helpers for the runner.
bool parseFloat(const std::string& s, float* out);
bool parseInt(const std::string& s, int* out);

}  // namespace caustic::editor
