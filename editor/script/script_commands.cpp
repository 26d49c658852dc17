#include "editor/script/script_commands.h"

#include "editor/script/script_run.h"

#include <algorithm>

namespace caustic::editor {

void ScriptContext::fail(const std::string& why) { run.fail(ui, line, why); }

float ScriptContext::num(std::size_t i) const {
    float f = 0.0f;
    parseFloat(a.at(i), &f);
    return f;
}

std::string ScriptContext::resolve(const std::string& path) const { return run.resolve(path); }

void ScriptContext::markEdit() { run.markEdit(ui); }

bool ScriptContext::onOff(bool* out) {
    if (a[0] != "on" && a[0] != "off" && a[0] != "yes" && a[0] != "no") {
        fail("expected on or off, got '" + a[0] + "'");
        return false;
    }
    *out = a[0] == "on" || a[0] == "yes";
    return true;
}

std::span<const ScriptCommand> scriptCommands() {
    static const std::vector<ScriptCommand> all = [] {
        std::vector<ScriptCommand> v;
        for (std::span<const ScriptCommand> group : {scriptEditCommands(), scriptCheckCommands(), scriptFileCommands(), scriptSessionCommands()})
            v.insert(v.end(), group.begin(), group.end());
        return v;
    }();
    return all;
}

const ScriptCommand* findScriptCommand(std::string_view name) {
    const std::span<const ScriptCommand> all = scriptCommands();
    const auto it = std::find_if(all.begin(), all.end(), [name](const ScriptCommand& c) { return c.name == name; });
    return it == all.end() ? nullptr : &*it;
}

}  // namespace caustic::editor
