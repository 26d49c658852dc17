#include "editor/model/keymap.h"

#include <iterator>
#include <vector>

namespace caustic::editor {

namespace {

using A = Action;
using S = KeyScope;

#define CAUSTIC_GLOBAL_KEYS                                                                                         \
    {A::Undo, {"Z", true, false}, S::Global, "undo the last edit"},                                                 \
        {A::Redo, {"Z", true, true}, S::Global, "redo"}, {A::RedoAlt, {"Y", true, false}, S::Global, "redo"},      \
        {A::Save, {"S", true, false}, S::Global, "save (asks for a file the first time)"},                          \
        {A::SaveAs, {"S", true, true}, S::Global, "save as"},                                                       \
        {A::Open, {"O", true, false}, S::Global, "open a scene (asks about unsaved changes first)"},                \
        {A::Duplicate, {"D", true, false}, S::Global, "duplicate the selection"},                                   \
        {A::Delete, {"Delete", false, false}, S::Global,                                                            \
         "delete the selection (with the viewport or the outliner focused, no text field or slider active)"},       \
        {A::ReloadShaders, {"F5", false, false}, S::Global, "reload the shaders (a failed compile keeps the last good ones)"}, \
        {A::DenoiseNow, {"F6", false, false}, S::Global, "denoise now (holds the render at its sample count)"},      \
        {A::FrameSelection, {"F", false, false}, S::Viewport, "frame the selection, or everything"}

constexpr KeyBinding kDefault[] = {
    CAUSTIC_GLOBAL_KEYS,
    {A::GizmoTranslate, {"W", false, false}, S::Viewport, "gizmo: move"},
    {A::GizmoRotate, {"E", false, false}, S::Viewport, "gizmo: rotate"},
    {A::GizmoScale, {"R", false, false}, S::Viewport, "gizmo: scale"},
    {A::GizmoLocal, {"T", false, false}, S::Viewport, "gizmo: local / world axes"},
};

constexpr KeyBinding kBlender[] = {
    CAUSTIC_GLOBAL_KEYS,
    {A::ModalGrab, {"G", false, false}, S::Viewport, "grab: move the selection with the mouse (modal)"},
    {A::ModalRotate, {"R", false, false}, S::Viewport, "rotate the selection with the mouse about its centre (modal)"},
    {A::ModalScale, {"S", false, false}, S::Viewport, "scale the selection with the mouse (modal)"},
    {A::DuplicateMove, {"D", false, true}, S::Viewport, "duplicate the selection, then grab the copy"},
    {A::Hide, {"H", false, false}, S::Viewport, "hide the selected objects in the viewport (Render to file still renders them)"},
    {A::UnhideAll, {"H", false, false, true}, S::Viewport, "show every hidden object again"},
    {A::ViewFront, {"Numpad1", false, false}, S::Viewport, "view from the front (+z), about the look-at point"},
    {A::ViewBack, {"Numpad1", true, false}, S::Viewport, "view from the back (-z)"},
    {A::ViewRight, {"Numpad3", false, false}, S::Viewport, "view from the right (+x)"},
    {A::ViewLeft, {"Numpad3", true, false}, S::Viewport, "view from the left (-x)"},
    {A::ViewTop, {"Numpad7", false, false}, S::Viewport, "view from the top (+y)"},
    {A::ViewBottom, {"Numpad7", true, false}, S::Viewport, "view from the bottom (-y)"},
    {A::CameraView, {"Numpad0", false, false}, S::Viewport, "look through the scene's camera; again: back to the free view"},
    {A::CameraToView, {"Numpad0", true, false, true}, S::Viewport, "move the scene's camera to the free view (one undo step)"},
    {A::ConstrainX, {"X", false, false}, S::Modal, "during G / R / S: along (about) the world x axis only; again: free"},
    {A::ConstrainY, {"Y", false, false}, S::Modal, "during G / R / S: Blender's y axis only (depth: the scene's z)"},
    {A::ConstrainZ, {"Z", false, false}, S::Modal, "during G / R / S: Blender's z axis only (up: the scene's y)"},
    {A::ModalConfirm, {"Enter", false, false}, S::Modal, "during G / R / S: confirm (or left click): one undo step"},
    {A::ModalCancel, {"Escape", false, false}, S::Modal, "during G / R / S: cancel (or right click): nothing changes"},
};

#undef CAUSTIC_GLOBAL_KEYS

}  // namespace

std::span<const KeyBinding> keyBindings(KeymapStyle style) {
    if (style == KeymapStyle::Blender) return kBlender;
    return kDefault;
}

std::span<const MouseAction> mouseActions(KeymapStyle style) {
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
    static constexpr MouseAction blender[] = {
        {"Left click (during G / R / S)", "confirm the transform"},
        {"Right click (during G / R / S)", "cancel it"},
    };
    static const std::vector<MouseAction> withBlender = [] {
        std::vector<MouseAction> v(std::begin(k), std::end(k));
        v.insert(v.end(), std::begin(blender), std::end(blender));
        return v;
    }();
    if (style == KeymapStyle::Blender) return withBlender;
    return k;
}

std::string chordText(const Chord& chord) {
    std::string out;
    if (chord.ctrl) out += "Ctrl+";
    if (chord.shift) out += "Shift+";
    if (chord.alt) out += "Alt+";
    out += chord.key;
    return out;
}

}  // namespace caustic::editor
