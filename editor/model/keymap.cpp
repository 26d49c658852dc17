#include "editor/model/keymap.h"

namespace caustic::editor {

std::span<const KeyBinding> keyBindings() {
    using A = Action;
    using S = KeyScope;
    static constexpr KeyBinding k[] = {
        {A::Undo, {"Z", true, false}, S::Global, "undo the last edit"},
        {A::Redo, {"Z", true, true}, S::Global, "redo"},
        {A::RedoAlt, {"Y", true, false}, S::Global, "redo"},
        {A::Save, {"S", true, false}, S::Global, "save (asks for a file the first time)"},
        {A::SaveAs, {"S", true, true}, S::Global, "save as"},
        {A::Open, {"O", true, false}, S::Global, "open a scene (asks about unsaved changes first)"},
        {A::Duplicate, {"D", true, false}, S::Global, "duplicate the selection"},
        {A::Delete, {"Delete", false, false}, S::Global,
         "delete the selection (with the viewport or the outliner focused, no text field or slider active)"},
        {A::ReloadShaders, {"F5", false, false}, S::Global, "reload the shaders (a failed compile keeps the last good ones)"},
        {A::DenoiseNow, {"F6", false, false}, S::Global, "denoise now (holds the render at its sample count)"},
        {A::FrameSelection, {"F", false, false}, S::Viewport, "frame the selection, or everything"},
        {A::GizmoTranslate, {"W", false, false}, S::Viewport, "gizmo: move"},
        {A::GizmoRotate, {"E", false, false}, S::Viewport, "gizmo: rotate"},
        {A::GizmoScale, {"R", false, false}, S::Viewport, "gizmo: scale"},
        {A::GizmoLocal, {"T", false, false}, S::Viewport, "gizmo: local / world axes"},
    };
    return k;
}

std::span<const MouseAction> mouseActions() {
    static constexpr MouseAction k[] = {
        {"Click", "select what is under the cursor (nothing: clear the selection)"},
        {"Ctrl+click", "add the object under the cursor to the selection, or take it out (not with compare on)"},
        {"Shift+click", "focus the lens on the point under the cursor (the camera's focus point)"},
        {"Middle drag, or Alt+left drag", "orbit the camera about its look-at point"},
        {"Shift+middle drag", "pan"},
        {"Wheel", "zoom (dolly towards the look-at point); a pause ends one undo step"},
        {"Right button held", "fly: the mouse looks around, W A S D move, Q E down and up, Shift faster"},
        {"Ctrl+left drag (compare on)", "move the snapshot / live divider"},
        {"Ctrl+click or Shift+click in the outliner", "add an object to the selection, or take it out"},
        {"Double-click in the outliner", "rename"},
    };
    return k;
}

std::string chordText(const Chord& chord) {
    std::string out;
    if (chord.ctrl) out += "Ctrl+";
    if (chord.shift) out += "Shift+";
    out += chord.key;
    return out;
}

}  // namespace caustic::editor
