// The editor's keyboard shortcuts and mouse actions, listed once: the frame loop and the viewport
// look their keys up here (editor/ui/editor_app.cpp, viewport_panel.cpp), and Help > Keyboard and
// mouse shows this list, so the help cannot drift from what the keys do. No ImGui here: a chord is
// a key name ("Z", "Delete", "F5") and its modifiers; editor/ui maps the names to ImGui keys.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace caustic::editor {

enum class Action {
    Undo, Redo, RedoAlt, Save, SaveAs, Open, Duplicate, Delete, ReloadShaders, DenoiseNow,
    FrameSelection, GizmoTranslate, GizmoRotate, GizmoScale, GizmoLocal,
};

// Where a key works: anywhere (unless a text field has the keys), or with the viewport hovered
// or focused (and the fly mode's right button up).
enum class KeyScope { Global, Viewport };

struct Chord {
    std::string_view key;  // "Z", "Delete", "F5", ...
    bool ctrl = false;
    bool shift = false;
};

struct KeyBinding {
    Action action;
    Chord chord;
    KeyScope scope;
    std::string_view what;  // for the help
};

std::span<const KeyBinding> keyBindings();

// Mouse and modifier actions the viewport and the panels interpret directly (for the help only).
struct MouseAction {
    std::string_view input;
    std::string_view what;
};
std::span<const MouseAction> mouseActions();

// "Ctrl+Shift+Z".
std::string chordText(const Chord& chord);

}  // namespace caustic::editor
