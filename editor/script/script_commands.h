// The script commands as one table of {name, arguments, handler} (script.h parses against it, the
// runner dispatches through it; docs/editor.md describes each command). The handlers live with
// their kind: edits (script_edits.cpp), checks (script_checks.cpp), files and background work
// (script_files.cpp), rendering, view and input (script_session.cpp).
#pragma once

#include "editor/script/script.h"

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace caustic::editor {

struct AppState;
struct EditorUi;
struct ScriptRun;

// What a command's handler tells the runner.
struct ScriptStep {
    enum class Kind { Done, Again, DoneAfterFrames };
    Kind kind = Kind::Done;
    int frames = 0;   // DoneAfterFrames: frames to let pass after this one before the next line

    static ScriptStep done() { return {}; }
    // Not done yet: the same line runs again next frame.
    static ScriptStep again() { return {Kind::Again, 0}; }
    static ScriptStep doneIf(bool finished) { return finished ? done() : again(); }
    // Done; the next line runs once this frame and `frames` more have passed.
    static ScriptStep doneAfterFrames(int frames) { return {Kind::DoneAfterFrames, frames}; }
};

// What a handler works with: the editor (its UI and the application), the run, its line.
struct ScriptContext {
    EditorUi& ui;
    AppState& app;                       // ui.app
    ScriptRun& run;
    const ScriptLine& line;
    const std::vector<std::string>& a;   // line.args

    void fail(const std::string& why);              // the script fails at this line (and the session ends)
    float num(std::size_t i) const;                 // argument i as a number (checked by the parser)
    std::string resolve(const std::string& path) const;   // relative to the script's folder
    void markEdit();                                // an edit: the first frame showing it is timed
    // The first argument as on / off (or yes / no); anything else fails the script (false).
    bool onOff(bool* out);
};

struct ScriptCommand {
    std::string_view name;
    int minArgs = 0, maxArgs = 0;
    std::string_view numeric;   // 'n' for each leading argument that must be a number
    ScriptStep (*run)(ScriptContext&) = nullptr;
};

// Every command, in the groups named above.
std::span<const ScriptCommand> scriptCommands();
// The command called `name`, or null.
const ScriptCommand* findScriptCommand(std::string_view name);

// The groups' tables (one file each).
std::span<const ScriptCommand> scriptEditCommands();
std::span<const ScriptCommand> scriptCheckCommands();
std::span<const ScriptCommand> scriptFileCommands();
std::span<const ScriptCommand> scriptSessionCommands();

}  // namespace caustic::editor
