// The editor's preferences kept between sessions: the key map and the UI scale (View menu). They
// live in the editor's layout.ini (ImGui's settings file, in editorConfigDir()) as a section of
// their own, [Caustic][Preferences], one "Key=value" line each. Pure text functions, unit-tested;
// editor/ui/editor_app.cpp registers them with ImGui.
#pragma once

#include "editor/model/keymap.h"

#include <string>
#include <string_view>

namespace caustic::editor {

struct Preferences {
    KeymapStyle keymap = KeymapStyle::Default;
    float uiScale = 0.0f;   // 0: follow the monitor's content scale; else kMinUiScale ... kMaxUiScale
    bool operator==(const Preferences&) const = default;
};

inline constexpr float kMinUiScale = 0.5f, kMaxUiScale = 4.0f;

// One line of the section ("Keymap=blender", "UiScale=1.5"). A line it does not know, or a value
// out of range, leaves *p as it was (a hand-edited or older file never breaks the editor).
void readPreferenceLine(std::string_view line, Preferences* p);
// The section's lines, each ending in '\n' (without the [Caustic][Preferences] header).
std::string writePreferenceLines(const Preferences& p);

}  // namespace caustic::editor
