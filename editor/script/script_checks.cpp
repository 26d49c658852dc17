// Script commands that check what the editor shows or holds: messages, counts, the selection,
// overlays, the key map, the denoised image, unsaved changes, restarts (docs/editor.md, "Scripts").
// A failed check fails the script.
#include "editor/script/script_commands.h"

#include "editor/model/viewport_math.h"
#include "editor/script/script_run.h"
#include "editor/ui/editor_ui.h"
#include "editor/ui/viewport_denoise.h"

#include <imgui.h>

#include <cmath>

namespace caustic::editor {
namespace {

// Fails with `why` unless `ok`.
ScriptStep check(ScriptContext& c, bool ok, const std::string& why) {
    if (!ok) c.fail(why);
    return ScriptStep::done();
}

ScriptStep expectError(ScriptContext& c) {
    const EditorUi& ui = c.ui;
    return check(c, ui.app.lastMessageIsError && ui.app.lastMessage.find(c.a[0]) != std::string::npos,
                 "expected an error containing '" + c.a[0] + "', the last message is '" + ui.app.lastMessage + "'");
}

// The status bar's last message, info or error, contains the text.
ScriptStep expectMessage(ScriptContext& c) {
    return check(c, c.app.lastMessage.find(c.a[0]) != std::string::npos,
                 "expected a message containing '" + c.a[0] + "', the last message is '" + c.app.lastMessage + "'");
}

ScriptStep expectUndoSteps(ScriptContext& c) {
    const int n = static_cast<int>(c.num(0));
    const std::size_t have = c.app.state.history.undoCount();
    return check(c, static_cast<int>(have) == n, "expected " + std::to_string(n) + " undo steps, have " + std::to_string(have));
}

ScriptStep expectCount(ScriptContext& c) {
    const Scene& scene = c.app.state.scene;
    const std::string& list = c.a[0];
    const std::size_t n = list == "objects" ? scene.objects.size() : list == "lights" ? scene.lights.size()
                        : list == "materials" ? scene.materials.size() : ~std::size_t(0);
    if (n == ~std::size_t(0)) return check(c, false, "unknown list '" + list + "'");
    return check(c, n == static_cast<std::size_t>(c.num(1)), "expected " + c.a[1] + " " + list + ", have " + std::to_string(n));
}

ScriptStep expectSelected(ScriptContext& c) {
    const std::size_t n = c.app.state.selectedObjects().size();
    return check(c, n == static_cast<std::size_t>(c.num(0)), "expected " + c.a[0] + " selected objects, have " + std::to_string(n));
}

ScriptStep expectMaterial(ScriptContext& c) {
    const Scene& scene = c.app.state.scene;
    const EntityRef ref = findEntity(scene, EntityKind::Object, c.a[0]);
    if (!ref) return check(c, false, "no object called '" + c.a[0] + "'");
    const std::string& has = scene.objects[size_t(ref.index)].material;
    return check(c, has == c.a[1], "object '" + c.a[0] + "' has material '" + has + "'");
}

ScriptStep expectFocusOverlay(ScriptContext& c) {
    const int cells = c.ui.focusOverlayCells;
    return check(c, cells >= static_cast<int>(c.num(0)),
                 cells < 0 ? std::string("the focus overlay is not shown") : "the focus overlay marks " + std::to_string(cells) + " cells");
}

ScriptStep expectNoFocusOverlay(ScriptContext& c) { return check(c, c.ui.focusOverlayCells < 0, "the focus overlay is shown"); }

ScriptStep expectViews(ScriptContext& c) {
    const std::size_t n = c.app.views.of(c.app.state.path).size();
    return check(c, n == static_cast<std::size_t>(c.num(0)), "expected " + c.a[0] + " views, have " + std::to_string(n));
}

// The UI's font size in pixels, within half a pixel.
ScriptStep expectFontSize(ScriptContext& c) {
    const float size = ImGui::GetFontSize();
    return check(c, std::abs(size - c.num(0)) <= 0.5f, "the font size is " + std::to_string(size));
}

ScriptStep expectKeymap(ScriptContext& c) {
    const char* in = c.app.keymap == KeymapStyle::Blender ? "blender" : "default";
    return check(c, c.a[0] == in, std::string("the key map is ") + in);
}

ScriptStep expectHidden(ScriptContext& c) {
    const std::size_t n = c.app.hidden.size();
    return check(c, n == static_cast<std::size_t>(c.num(0)), "expected " + c.a[0] + ", have " + std::to_string(n));
}

// What the renderer has, not what the model says it should have.
ScriptStep expectRenderedObjects(ScriptContext& c) {
    if (!c.app.renderer) return check(c, false, "no renderer");
    const std::size_t n = c.app.renderer->scene().objects.size();
    return check(c, n == static_cast<std::size_t>(c.num(0)), "expected " + c.a[0] + ", have " + std::to_string(n));
}

// current: the renderer renders the model's scene; last_good: it was refused, the viewport says so.
ScriptStep expectViewportScene(ScriptContext& c) {
    const bool behind = c.app.session.behind;
    if (c.a[0] != "current" && c.a[0] != "last_good") return check(c, false, "expected current or last_good");
    return check(c, behind == (c.a[0] == "last_good"),
                 behind ? "the viewport shows the last good scene: " + c.app.session.renderError : "the viewport shows the current scene");
}

ScriptStep expectModal(ScriptContext& c) {
    const bool active = c.ui.modal.active;
    return check(c, active == (c.a[0] == "yes"), active ? "a transform is in progress" : "no transform is in progress");
}

ScriptStep expectDenoised(ScriptContext& c) {
    bool yes = false;
    if (!c.onOff(&yes)) return ScriptStep::done();
    const bool shown = c.app.denoiser && c.app.denoiser->shown(c.ui);
    return check(c, shown == yes, std::string("the viewport ") + (shown ? "shows" : "does not show") + " a denoised image");
}

ScriptStep expectModified(ScriptContext& c) {
    bool yes = false;
    if (!c.onOff(&yes)) return ScriptStep::done();
    const bool modified = c.app.state.modified();
    return check(c, modified == yes, std::string("the scene is ") + (modified ? "modified" : "not modified"));
}

ScriptStep expectRecoveryOffered(ScriptContext& c) {
    if (c.ui.recoveryPromptRequested) return ScriptStep::again();   // the prompt opens during this frame's drawing
    return check(c, c.app.recovered && ImGui::IsPopupOpen("Recover unsaved work?"), "no recovery was offered");
}

ScriptStep mark(ScriptContext& c) {
    c.run.markedGeneration = c.app.session.accumulationGeneration;
    return ScriptStep::done();
}

ScriptStep expectRestarted(ScriptContext& c) {
    const bool restarted = c.app.session.accumulationGeneration != c.run.markedGeneration;
    return check(c, restarted == (c.a[0] == "yes"),
                 std::string("accumulation ") + (restarted ? "restarted" : "did not restart") + " since `mark`");
}

const ScriptCommand kCommands[] = {
    {"expect_error", 1, 1, "", expectError},           // the last error message contains the text
    {"expect_message", 1, 1, "", expectMessage},       // the last message, info or error, contains the text
    {"expect_undo_steps", 1, 1, "n", expectUndoSteps},
    {"expect_count", 2, 2, "", expectCount},           // expect_count objects|lights|materials N
    {"expect_selected", 1, 1, "n", expectSelected},    // N objects are selected
    {"expect_material", 2, 2, "", expectMaterial},     // expect_material OBJECT MATERIAL
    {"expect_focus_overlay", 1, 1, "n", expectFocusOverlay},   // the focus overlay is shown with at least N cells marked (0: shown)
    {"expect_no_focus_overlay", 0, 0, "", expectNoFocusOverlay},
    {"expect_views", 1, 1, "n", expectViews},          // the scene has N saved camera views
    {"expect_font_size", 1, 1, "n", expectFontSize},   // the UI's font size in pixels
    {"expect_keymap", 1, 1, "", expectKeymap},         // default | blender: the key map in use (kept between sessions)
    {"expect_hidden", 1, 1, "n", expectHidden},        // N objects are hidden in the viewport
    {"expect_rendered_objects", 1, 1, "n", expectRenderedObjects},   // the viewport's renderer has N objects
    {"expect_viewport_scene", 1, 1, "", expectViewportScene},   // current | last_good: what the viewport renders
    {"expect_modal", 1, 1, "", expectModal},           // yes | no: a G / R / S transform is in progress
    {"expect_denoised", 1, 1, "", expectDenoised},     // yes | no: the viewport shows a denoised image
    {"expect_modified", 1, 1, "", expectModified},     // yes | no: the scene has unsaved changes
    {"expect_recovery_offered", 0, 0, "", expectRecoveryOffered},   // the recovery prompt is open
    {"mark", 0, 0, "", mark},                          // remember where accumulation is (for expect_restarted)
    {"expect_restarted", 1, 1, "", expectRestarted},   // yes | no: accumulation restarted since `mark`
};

}  // namespace

std::span<const ScriptCommand> scriptCheckCommands() { return kCommands; }

}  // namespace caustic::editor
