// The script harness (editor/script/): the parser, and the command table it parses against (every
// command once, named in docs/editor.md's list).
#include "editor/script/script.h"
#include "editor/script/script_commands.h"

#include <catch2/catch.hpp>

#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace caustic::editor;

TEST_CASE("scripts parse with quotes and comments, mistakes name the line", "[editor]") {
    ScriptParseResult r = parseScript("# a comment\nselect object \"small box\"\n\ntranslate 0.1 0 -2e-1  # move\nquit\n", "s.txt");
    REQUIRE(r.error.empty());
    REQUIRE(r.lines.size() == 3);
    CHECK(r.lines[0].op == "select");
    CHECK(r.lines[0].args == std::vector<std::string>{"object", "small box"});
    CHECK(r.lines[1].line == 4);
    CHECK(r.lines[1].args[2] == "-2e-1");
    CHECK(parseScript("fly 1", "s.txt").error == "s.txt:1: unknown command 'fly'");
    CHECK(parseScript("quit\ntranslate 1 2", "s.txt").error == "s.txt:2: translate: expected 3 arguments, got 2");
    CHECK(parseScript("wait_samples many", "s.txt").error == "s.txt:1: wait_samples: argument 1: expected a number, got 'many'");
    CHECK(parseScript("select \"open", "s.txt").error == "s.txt:1: unterminated quote");
}

TEST_CASE("every script command is in the table once, with a handler and sane arguments", "[editor][script]") {
    std::set<std::string_view> names;
    for (const ScriptCommand& c : scriptCommands()) {
        INFO(c.name);
        CHECK(names.insert(c.name).second);
        CHECK(c.run != nullptr);
        CHECK(c.minArgs <= c.maxArgs);
        CHECK(static_cast<int>(c.numeric.size()) <= c.maxArgs);
        CHECK(c.numeric.find_first_not_of('n') == std::string_view::npos);
        CHECK(findScriptCommand(c.name) == &c);
    }
    CHECK(findScriptCommand("fly") == nullptr);
}

TEST_CASE("docs/editor.md describes every script command", "[editor][script]") {
    std::ifstream in(std::string(CAUSTIC_SOURCE_DIR) + "/docs/editor.md");
    REQUIRE(in);
    std::stringstream text;
    text << in.rdbuf();
    const std::string docs = text.str();
    for (const ScriptCommand& c : scriptCommands()) {
        INFO(c.name);
        // The commands' table names each as `name` or `name ARGS...`.
        const std::string name(c.name);
        CHECK((docs.find("`" + name + "`") != std::string::npos || docs.find("`" + name + " ") != std::string::npos));
    }
}
