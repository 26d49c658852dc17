// The editor's preferences section of layout.ini (editor/model/preferences.h): what it writes
// reads back, and a damaged or hand-edited file never sets a value the editor cannot use.
#include "editor/model/preferences.h"

#include <catch2/catch.hpp>

#include <sstream>
#include <string>

using namespace caustic::editor;

namespace {

Preferences readAll(const std::string& lines, Preferences p = {}) {
    std::istringstream in(lines);
    for (std::string line; std::getline(in, line);) readPreferenceLine(line, &p);
    return p;
}

}  // namespace

TEST_CASE("editor preferences: written lines read back as the same preferences", "[editor][preferences]") {
    for (const KeymapStyle k : {KeymapStyle::Default, KeymapStyle::Blender})
        for (const float scale : {0.0f, 0.5f, 1.0f, 1.25f, 1.5f, 2.0f, 4.0f, 1.0f / 3.0f + 1.0f}) {
            const Preferences p{k, scale};
            INFO(writePreferenceLines(p));
            CHECK(readAll(writePreferenceLines(p)) == p);
        }
    CHECK(writePreferenceLines({KeymapStyle::Blender, 2.0f}) == "Keymap=blender\nUiScale=2\n");
}

TEST_CASE("editor preferences: unknown lines and values out of range leave the preference as it was", "[editor][preferences]") {
    const Preferences start{KeymapStyle::Blender, 1.5f};
    for (const char* bad : {"Keymap=emacs", "Keymap=", "Keymap", "UiScale=nan", "UiScale=inf", "UiScale=-1", "UiScale=0.25",
                            "UiScale=4.5", "UiScale=1e39", "UiScale=1.5x", "UiScale=", "Color=blue", "", "=2"}) {
        INFO(bad);
        CHECK(readAll(bad, start) == start);
    }
    // Windows line ends and trailing blanks are tolerated.
    CHECK(readAll("Keymap=default\r\nUiScale=1.25 \r\n", start) == Preferences{KeymapStyle::Default, 1.25f});
}
