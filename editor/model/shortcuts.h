// Which panel keys belong to, decided without ImGui so it can be unit-tested (tests/editor/).
#pragma once

namespace caustic::editor {

// Where the keyboard is this frame, as the UI sees it.
struct KeyFocus {
    bool textInput = false;            // a text field is being edited (ImGuiIO::WantTextInput)
    bool itemActive = false;           // a widget is held: a slider or drag (ImGui::IsAnyItemActive)
    bool viewportOrOutliner = false;   // the viewport or the outliner is focused (a click in it focuses it)
};

// Del deletes the selection only where it means "delete this": in the viewport or the outliner,
// never while a text field or a slider has the keys (a text field's Delete deletes a character).
// ImGuiIO::WantCaptureKeyboard is no guide: with keyboard navigation on it is true whenever any
// window is focused, so it used to block the key everywhere.
inline bool deleteKeyDeletes(const KeyFocus& f) { return f.viewportOrOutliner && !f.textInput && !f.itemActive; }

}  // namespace caustic::editor
