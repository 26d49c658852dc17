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
    // The Blender-style key map (KeymapStyle::Blender).
    ModalGrab, ModalRotate, ModalScale, DuplicateMove, Hide, UnhideAll,
    ViewFront, ViewBack, ViewRight, ViewLeft, ViewTop, ViewBottom, CameraView, CameraToView,
    // While a modal transform runs (KeyScope::Modal).
    ConstrainX, ConstrainY, ConstrainZ, ModalConfirm, ModalCancel,
};

// Where a key works: anywhere (unless a text field has the keys), with the viewport hovered
// or focused (and the fly mode's right button up), or while a modal transform (G, R, S) runs.
enum class KeyScope { Global, Viewport, Modal };

// Which key map is active (View > Key map): the editor's own (gizmo keys W E R T), or one a
// Blender user's hands know (G R S modal transforms with X Y Z constraints, Shift+D, H, numpad
// views). The global keys (undo, save, Del, ...) are the same in both.
enum class KeymapStyle { Default, Blender };

struct Chord {
    std::string_view key;  // "Z", "Delete", "F5", "Numpad1", "Escape", "Enter", ...
    bool ctrl = false;
    bool shift = false;
    bool alt = false;
};

struct KeyBinding {
    Action action;
    Chord chord;
    KeyScope scope;
    std::string_view what;  // for the help
};

// The bindings of a key map: the global keys, then the style's viewport (and modal) keys.
std::span<const KeyBinding> keyBindings(KeymapStyle style = KeymapStyle::Default);

// Mouse and modifier actions the viewport and the panels interpret directly (for the help only).
struct MouseAction {
    std::string_view input;
    std::string_view what;
};
std::span<const MouseAction> mouseActions(KeymapStyle style = KeymapStyle::Default);

// "Ctrl+Shift+Z".
std::string chordText(const Chord& chord);

}  // namespace caustic::editor
