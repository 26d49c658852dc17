// Script commands about rendering, the view and input: waiting for samples, frames, the denoiser
// and the material preview; view options; keys, mouse and focus through ImGui's input queue, as
// GLFW's callbacks feed it (docs/editor.md, "Scripts").
#include "editor/script/script_commands.h"

#include "editor/script/script_run.h"
#include "editor/ui/editor_ui.h"
#include "editor/ui/material_preview.h"
#include "editor/ui/viewport_denoise.h"

#include <imgui.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <utility>
#include <vector>

namespace caustic::editor {
namespace {

// The viewport shows the scene as it is, at full resolution, with nothing being dragged.
bool settled(const EditorUi& ui) {
    return ui.app.renderer && ui.app.session.sceneUploaded && ui.app.session.previewDivisor == 1 && ui.app.state.pendingDirty() == kDirtyNone &&
           !ui.app.session.interacting;
}

// Render until N samples per pixel (and stop there).
ScriptStep waitSamples(ScriptContext& c) {
    EditorUi& ui = c.ui;
    const int n = static_cast<int>(c.num(0));
    ui.app.session.sampleCap = n;
    if (!ui.app.renderer) { c.fail("no renderer (the shaders did not compile)"); return ScriptStep::done(); }
    const bool ready = settled(ui);
    if (ready && !ui.app.session.renderError.empty() && ui.app.renderer->samplesDone() == 0) { c.fail(ui.app.session.renderError); return ScriptStep::done(); }
    return ScriptStep::doneIf(ready && ui.app.renderer->samplesDone() >= std::min(n, ui.app.state.scene.render.samples));
}

ScriptStep frames(ScriptContext& c) { return ScriptStep::doneAfterFrames(static_cast<int>(c.num(0)) - 1); }

ScriptStep uncap(ScriptContext& c) {
    c.app.session.sampleCap.reset();
    return ScriptStep::done();
}

ScriptStep snapshot(ScriptContext& c) {
    if (c.app.display) c.app.display->takeSnapshot();
    return ScriptStep::done();
}

ScriptStep compare(ScriptContext& c) {
    c.ui.compare = c.a[0] == "on";
    return ScriptStep::done();
}

ScriptStep viewport(ScriptContext& c) {
    if (c.a[0] != "output" && c.a[0] != "panel") {
        c.fail("viewport: expected output or panel, got '" + c.a[0] + "'");
        return ScriptStep::done();
    }
    c.run.outputSize = c.a[0] == "output";
    return ScriptStep::done();
}

// View > Viewport resolution: auto (from the measured rate) or a fraction of the panel.
ScriptStep viewportScale(ScriptContext& c) {
    float f = 0.0f;
    if (c.a[0] == "auto") f = 0.0f;
    else if (!parseFloat(c.a[0], &f) || !(f == 1.0f || f == 0.5f || f == 0.25f)) {
        c.fail("viewport_scale: expected auto, 1, 0.5 or 0.25, got '" + c.a[0] + "'");
        return ScriptStep::done();
    }
    c.app.state.view.viewportScale = f;
    return ScriptStep::done();
}

// The viewport renders at SCALE of its panel now (auto's choice, or the one set).
ScriptStep expectViewportScale(ScriptContext& c) {
    const float f = c.app.state.view.viewportScale > 0.0f ? c.app.state.view.viewportScale : c.app.session.autoScale;
    if (f != c.num(0)) c.fail("the viewport renders at " + std::to_string(f) + " of its panel");
    return ScriptStep::done();
}

// denoise: denoise now and wait until the viewport shows it; wait_denoised: only wait (auto).
ScriptStep denoiseAndWait(ScriptContext& c, bool press) {
    EditorUi& ui = c.ui;
    ScriptRun& r = c.run;
    const bool first = r.startLine();
    const double timeout = c.a.empty() ? kScriptWaitSeconds : double(c.num(0));
    ViewportDenoiser* dn = ui.app.denoiser.get();
    if (!dn) { c.fail("no denoiser"); return ScriptStep::done(); }
    if (first) r.countAtStart = dn->failures();
    if (dn->shown(ui)) return ScriptStep::done();
    if (dn->failures() != r.countAtStart) { c.fail("the denoiser failed: " + dn->lastError()); return ScriptStep::done(); }
    if (r.secondsOnLine() > timeout) {
        c.fail("no denoised image after " + std::to_string(int(timeout)) + " s (" + dn->status(ui) + ")");
        return ScriptStep::done();
    }
    // denoise: one request for the settled image (again if an edit made the first one stale).
    if (press && settled(ui) && !dn->busy() && !dn->current(ui)) {
        const std::pair<std::uint64_t, int> key(ui.app.session.accumulationGeneration, ui.app.renderer->samplesDone());
        if (!r.pressed || r.denoiseKey != key) {
            std::string why;
            if (!dn->request(ui, false, &why)) { c.fail(why); return ScriptStep::done(); }
            dn->settings.showDenoised = true;
            r.pressed = true;
            r.denoiseKey = key;
        }
    }
    return ScriptStep::again();
}

ScriptStep denoise(ScriptContext& c) { return denoiseAndWait(c, true); }
ScriptStep waitDenoised(ScriptContext& c) { return denoiseAndWait(c, false); }

// on | off into one of the denoiser's switches.
ScriptStep setDenoiseSwitch(ScriptContext& c, bool DenoiseSettings::*member) {
    bool on = false;
    if (!c.onOff(&on)) return ScriptStep::done();
    if (!c.app.denoiser) { c.fail("no denoiser"); return ScriptStep::done(); }
    c.app.denoiser->settings.*member = on;
    return ScriptStep::done();
}

ScriptStep denoiseAuto(ScriptContext& c) { return setDenoiseSwitch(c, &DenoiseSettings::autoDenoise); }
ScriptStep denoiseIdle(ScriptContext& c) { return setDenoiseSwitch(c, &DenoiseSettings::idleDenoise); }

ScriptStep showRaw(ScriptContext& c) {
    bool on = false;
    if (!c.onOff(&on)) return ScriptStep::done();
    if (!c.app.denoiser) { c.fail("no denoiser"); return ScriptStep::done(); }
    c.app.denoiser->settings.showDenoised = !on;
    return ScriptStep::done();
}

ScriptStep previewLighting(ScriptContext& c) {
    if (c.a[0] != "scene" && c.a[0] != "studio") { c.fail("expected scene or studio"); return ScriptStep::done(); }
    c.app.preview->lighting = c.a[0] == "scene" ? PreviewLighting::Scene : PreviewLighting::Studio;
    return ScriptStep::done();
}

ScriptStep waitPreview(ScriptContext& c) {
    EditorUi& ui = c.ui;
    ScriptRun& r = c.run;
    // The inspector asks for the preview while it shows a material (this frame, before us).
    // A selection made on this frame shows in the inspector from the next one.
    if (!ui.app.preview->requested()) {
        if (++r.previewMissing > 5) {
            r.previewMissing = 0;
            c.fail("the inspector shows no material (select a material, or an object with its material open)");
            return ScriptStep::done();
        }
        return ScriptStep::again();
    }
    r.previewMissing = 0;
    // The request this line sees must come from a frame after it started (an edit on the
    // line before shows in the inspector, and so in the request, from the next frame).
    if (r.previewLine != r.next) {
        r.previewLine = r.next;
        return ScriptStep::again();
    }
    if (!ui.app.preview->error().empty()) { c.fail("the preview failed: " + ui.app.preview->error()); return ScriptStep::done(); }
    const bool done = ui.app.preview->current() && ui.app.preview->samples() >= static_cast<int>(c.num(0));
    if (done) r.previewLine = static_cast<size_t>(-1);
    const double timeout = c.a.size() > 1 ? c.num(1) : kScriptWaitSeconds;
    return ScriptStep::doneIf(r.waitFor(ui, c.line, done, timeout, "the material preview did not converge"));
}

// View > UI scale (0: follow the monitor).
ScriptStep uiScale(ScriptContext& c) {
    c.app.uiScaleChoice = c.num(0);
    c.ui.resetLayout = true;   // as the menu does
    return ScriptStep::done();
}

// Help > Keyboard and mouse (screenshots).
ScriptStep showHelp(ScriptContext& c) {
    c.ui.showShortcuts = c.a[0] == "on";
    return ScriptStep::done();
}

// The viewport sizes the report lists start from here.
ScriptStep recordSizes(ScriptContext& c) {
    c.run.sizes.clear();
    return ScriptStep::done();
}

// As the user resizing the window.
ScriptStep windowSize(ScriptContext& c) {
    glfwSetWindowSize(c.app.window, static_cast<int>(c.num(0)), static_cast<int>(c.num(1)));
    return ScriptStep::doneAfterFrames(3);
}

// on: idle pacing as for a person who stopped touching the mouse (benchmarks).
ScriptStep idle(ScriptContext& c) {
    c.run.idle = c.a[0] == "on";
    return ScriptStep::done();
}

ScriptStep keymap(ScriptContext& c) {
    if (c.a[0] != "default" && c.a[0] != "blender") { c.fail("expected default or blender"); return ScriptStep::done(); }
    c.app.keymap = c.a[0] == "blender" ? KeymapStyle::Blender : KeymapStyle::Default;
    return ScriptStep::done();
}

// Through ImGui's input queue, as GLFW's key callback feeds it. Shift+, Ctrl+, Alt+ prefixes hold
// the modifier around the key.
ScriptStep key(ScriptContext& c) {
    std::string name = c.a[0];
    std::vector<ImGuiKey> mods;
    for (const auto& [prefix, mod] : {std::pair{"Shift+", ImGuiMod_Shift}, std::pair{"Ctrl+", ImGuiMod_Ctrl}, std::pair{"Alt+", ImGuiMod_Alt}})
        if (name.rfind(prefix, 0) == 0) {
            mods.push_back(mod);
            name = name.substr(std::string(prefix).size());
        }
    const ImGuiKey k = imguiKey(name);
    if (k == ImGuiKey_None) { c.fail("unknown key '" + c.a[0] + "'"); return ScriptStep::done(); }
    for (ImGuiKey m : mods) ImGui::GetIO().AddKeyEvent(m, true);
    ImGui::GetIO().AddKeyEvent(k, true);
    ImGui::GetIO().AddKeyEvent(k, false);   // trickled: down next frame, up the one after
    for (ImGuiKey m : mods) ImGui::GetIO().AddKeyEvent(m, false);
    c.markEdit();
    return ScriptStep::doneAfterFrames(2);
}

// Moves the mouse by (dx, dy) over the viewport (from its centre the first time).
ScriptStep mouseMove(ScriptContext& c) {
    ImGuiIO& io = ImGui::GetIO();
    ImVec2 p = io.MousePos;
    const float* v = c.ui.viewportImage;
    if (!ImGui::IsMousePosValid(&p) || p.x < v[0] || p.y < v[1] || p.x > v[0] + v[2] || p.y > v[1] + v[3])
        p = ImVec2(v[0] + v[2] * 0.5f + 0.25f, v[1] + v[3] * 0.5f + 0.25f);
    io.AddMousePosEvent(p.x + c.num(0), p.y + c.num(1));
    return ScriptStep::doneAfterFrames(2);
}

ScriptStep mouseClick(ScriptContext& c) {
    ImGuiIO& io = ImGui::GetIO();
    const int button = c.a[0] == "right" ? ImGuiMouseButton_Right : ImGuiMouseButton_Left;
    io.AddMouseButtonEvent(button, true);
    io.AddMouseButtonEvent(button, false);
    return ScriptStep::doneAfterFrames(2);
}

// As a click on the panel's title would.
ScriptStep focus(ScriptContext& c) {
    const std::string& p = c.a[0];
    const char* window = p == "viewport" ? "Viewport" : p == "outliner" ? "Outliner" : p == "inspector" ? "Inspector" : nullptr;
    if (!window) { c.fail("unknown panel '" + p + "'"); return ScriptStep::done(); }
    ImGui::SetWindowFocus(window);
    return ScriptStep::doneAfterFrames(1);   // focused from the next frame on
}

// on: the program builder starts no build until off (a test observes the editor while a build
// is outstanding, however fast the machine builds).
ScriptStep holdBuilds(ScriptContext& c) {
    bool on = false;
    if (!c.onOff(&on)) return ScriptStep::done();
    if (!c.app.programBuilder) { c.fail("shaders are built on the window's thread here (no program builder)"); return ScriptStep::done(); }
    c.app.programBuilder->hold(on);
    return ScriptStep::done();
}

// yes: the viewport says "Building shaders..." now; no: it does not (the previews say theirs).
ScriptStep expectBuilding(ScriptContext& c) {
    bool yes = false;
    if (!c.onOff(&yes)) return ScriptStep::done();
    if (c.app.session.buildingShaders != yes)
        c.fail(yes ? "the viewport builds no shaders" : "the viewport is building shaders");
    return ScriptStep::done();
}

ScriptStep quit(ScriptContext& c) {
    c.app.quit = true;
    return ScriptStep::done();
}

const ScriptCommand kCommands[] = {
    {"wait_samples", 1, 1, "n", waitSamples},          // render until N samples per pixel (and stop there)
    {"frames", 1, 1, "n", frames},                     // let N frames pass
    {"uncap", 0, 0, "", uncap},                        // lift wait_samples' cap: render on to the scene's target
    {"snapshot", 0, 0, "", snapshot},                  // lookdev snapshot
    {"compare", 1, 1, "", compare},                    // on | off: split view snapshot | live
    {"viewport", 1, 1, "", viewport},                  // output (the default) | panel: the viewport's render size
    {"viewport_scale", 1, 1, "", viewportScale},        // auto | 1 | 0.5 | 0.25: View > Viewport resolution
    {"expect_viewport_scale", 1, 1, "n", expectViewportScale},   // the viewport renders at this fraction of its panel now
    {"denoise", 0, 1, "n", denoise},                   // denoise now and wait until the viewport shows it [timeout s]
    {"wait_denoised", 0, 1, "n", waitDenoised},        // wait until a denoised image is shown (auto) [timeout s]
    {"denoise_auto", 1, 1, "", denoiseAuto},           // on | off: denoise when the target samples are reached
    {"denoise_idle", 1, 1, "", denoiseIdle},           // on | off: denoise when idle (needs `idle on` to happen in a script)
    {"show_raw", 1, 1, "", showRaw},                   // on | off: show the raw render instead of the denoised one
    {"preview_lighting", 1, 1, "", previewLighting},   // scene | studio: the material preview's lighting
    {"wait_preview", 1, 2, "nn", waitPreview},         // until the material preview has N samples of the current material [timeout s]
    {"ui_scale", 1, 1, "n", uiScale},                  // View > UI scale: a factor, 0 to follow the monitor
    {"show_help", 1, 1, "", showHelp},                 // on | off: the Help > Keyboard and mouse window
    {"record_sizes", 0, 0, "", recordSizes},           // the report's viewport_sizes start afresh
    {"window_size", 2, 2, "nn", windowSize},           // resize the window (W H)
    {"idle", 1, 1, "", idle},                          // on | off: idle pacing (off in scripts unless asked: they measure frames)
    {"keymap", 1, 1, "", keymap},                      // default | blender: View > Key map
    {"key", 1, 1, "", key},                            // press and release a key (Delete, F, W, E, R, F6) as the keyboard would
    {"mouse_move", 2, 2, "nn", mouseMove},             // move the mouse by (dx dy) pixels over the viewport (from its centre the first time)
    {"mouse_click", 1, 1, "", mouseClick},             // left | right: click where the mouse is
    {"focus", 1, 1, "", focus},                        // focus a panel: viewport | outliner | inspector
    {"hold_builds", 1, 1, "", holdBuilds},             // on | off: the background program builder starts no build while on
    {"expect_building", 1, 1, "", expectBuilding},     // yes | no: the viewport says "Building shaders..." (its own builds)
    {"quit", 0, 0, "", quit},
};

}  // namespace

std::span<const ScriptCommand> scriptSessionCommands() { return kCommands; }

}  // namespace caustic::editor
