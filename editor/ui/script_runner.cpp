#include "editor/ui/script_runner.h"

#include "editor/model/viewport_math.h"
#include "editor/ui/editor_ui.h"
#include "editor/ui/material_preview.h"
#include "editor/ui/mesh_import.h"
#include "editor/model/asset_files.h"
#include "editor/model/lookdev.h"
#include "editor/model/scene_paths.h"
#include "editor/ui/viewport_denoise.h"
#include "renderer/file_util.h"
#include "renderer/image_io.h"

#include <glad/gl.h>
#include <imgui.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace caustic::editor {

// How long a script's waits (for an import, an open, the denoiser, an autosave, the recovery
// prompt) may take before the script fails, when the line names no time-out: generous, because
// they wait for events and a loaded machine is slow, not wrong (tests fail on wrong results).
constexpr double kScriptWaitSeconds = 900.0;
namespace {

EntityKind kindFromWord(const std::string& w) {
    if (w == "object") return EntityKind::Object;
    if (w == "light") return EntityKind::Light;
    if (w == "material") return EntityKind::Material;
    if (w == "camera") return EntityKind::Camera;
    if (w == "render") return EntityKind::Render;
    if (w == "environment") return EntityKind::Environment;
    return EntityKind::None;
}

float num(const std::string& s) {
    float f = 0.0f;
    parseFloat(s, &f);
    return f;
}

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t i = std::min(v.size() - 1, static_cast<size_t>(p * double(v.size() - 1) + 0.5));
    return v[i];
}

// Moves the selected object or light by d: one step of an edit.
bool moveSelection(EditorUi& ui, glm::vec3 d, bool continuous, std::string* why) {
    EditorState& s = ui.state;
    std::unique_ptr<Command> c;
    if (s.selection.kind == EntityKind::Object) {
        Object o = s.scene.objects.at(static_cast<size_t>(s.selection.index));
        o.transform.translate += d;
        c = makeSetObject(s, s.selection.index, o);
    } else if (s.selection.kind == EntityKind::Light) {
        Light l = s.scene.lights.at(static_cast<size_t>(s.selection.index));
        l.transform.translate += d;
        l.position += d;
        c = makeSetLight(s, s.selection.index, l);
    } else {
        *why = "nothing movable is selected";
        return false;
    }
    return continuous ? s.applyContinuous(std::move(c), why) : s.apply(std::move(c), why);
}

}  // namespace

bool ScriptRunner::load(const std::string& file, std::string* error) {
    std::optional<std::string> text = readTextFile(file, error);
    if (!text) return false;
    ScriptParseResult parsed = parseScript(*text, file);
    if (!parsed.error.empty()) {
        *error = parsed.error;
        return false;
    }
    m_file = file;
    m_dir = fs::path(file).parent_path().string();
    m_lines = std::move(parsed.lines);
    return true;
}

std::string ScriptRunner::resolve(const std::string& path) const {
    if (fs::path(path).is_absolute() || m_dir.empty()) return path;
    return (fs::path(m_dir) / path).string();
}

void ScriptRunner::fail(EditorUi& ui, const ScriptLine& line, const std::string& why) {
    std::fprintf(stderr, "caustic: script %s:%d: %s: %s\n", m_file.c_str(), line.line, line.op.c_str(), why.c_str());
    m_failed = true;
    ui.quit = true;
}

void ScriptRunner::step(EditorUi& ui) {
    if (m_failed) return;
    if (!m_screenshotPending.empty()) return;   // finishes after this frame is drawn
    if (m_waitFrames > 0) {
        --m_waitFrames;
        return;
    }
    // Run lines until one has to wait for frames to pass.
    while (m_next < m_lines.size() && !ui.quit) {
        if (!run(ui, m_lines[m_next])) return;
        ++m_next;
        if (m_failed) return;
    }
    if (m_next >= m_lines.size()) ui.quit = true;   // a script always ends the session
}

// A wait on the background imports: true (the line is done) once `done`, or, failing the script,
// after `timeout` seconds of waiting; false to be called again next frame.
bool ScriptRunner::waitFor(EditorUi& ui, const ScriptLine& line, bool done, double timeout, const char* what) {
    if (done) {
        m_waitImportSince = -1.0;
        if (ui.state.pendingDirty() != kDirtyNone) {   // as markEdit(): the frame showing it is timed
            m_editTime = glfwGetTime();
            m_editPending = true;
        }
        return true;
    }
    if (m_waitImportSince < 0.0) m_waitImportSince = glfwGetTime();
    if (glfwGetTime() - m_waitImportSince <= timeout) return false;
    m_waitImportSince = -1.0;
    fail(ui, line, std::string(what) + " after " + std::to_string(int(timeout)) + " s: " + ui.meshImports->status());
    return true;
}

bool ScriptRunner::run(EditorUi& ui, const ScriptLine& line) {
    const auto& a = line.args;
    const std::string& op = line.op;
    EditorState& s = ui.state;
    auto markEdit = [&] {
        if (s.pendingDirty() != kDirtyNone) {
            m_editTime = glfwGetTime();
            m_editPending = true;
        }
    };
    if (op == "wait_samples") {
        const int n = static_cast<int>(num(a[0]));
        ui.session.sampleCap = n;
        const bool settled = ui.session.sceneUploaded && ui.session.previewDivisor == 1 && s.pendingDirty() == kDirtyNone &&
                             !ui.session.interacting && ui.renderer;
        if (!ui.renderer) { fail(ui, line, "no renderer (the shaders did not compile)"); return true; }
        if (settled && !ui.session.renderError.empty() && ui.renderer->samplesDone() == 0) { fail(ui, line, ui.session.renderError); return true; }
        return settled && ui.renderer->samplesDone() >= std::min(n, s.scene.render.samples);
    }
    if (op == "frames") {
        m_waitFrames = static_cast<int>(num(a[0])) - 1;
        ++m_next;
        return false;
    }
    if (op == "select") {
        const EntityKind kind = kindFromWord(a[0]);
        if (kind == EntityKind::None) { fail(ui, line, "unknown kind '" + a[0] + "'"); return true; }
        const EntityRef ref = findEntity(s.scene, kind, a.size() > 1 ? a[1] : "");
        if (!ref) { fail(ui, line, "no " + a[0] + " called '" + (a.size() > 1 ? a[1] : "") + "'"); return true; }
        s.select(ref);
        return true;
    }
    if (op == "select_add") {   // as Ctrl+click in the viewport (or Ctrl/Shift+click in the outliner)
        const EntityRef ref = findEntity(s.scene, kindFromWord(a[0]), a[1]);
        if (!ref) { fail(ui, line, "no " + a[0] + " called '" + a[1] + "'"); return true; }
        s.select(ref, EditorState::SelectMode::Toggle);
        return true;
    }
    if (op == "expect_selected") {
        const std::size_t n = s.selectedObjects().size();
        if (n != static_cast<std::size_t>(num(a[0]))) fail(ui, line, "expected " + a[0] + " selected objects, have " + std::to_string(n));
        return true;
    }
    if (op == "assign_material" || op == "new_material" || op == "make_unique") {
        // The inspector's actions on the selected objects (editor/model/lookdev.h).
        std::string why;
        std::unique_ptr<Command> c;
        if (op == "assign_material") c = makeAssignMaterial(s, s.selectedObjects(), a[0], &why);
        else if (op == "make_unique") c = makeMakeUnique(s, s.selectedObjects(), &why);
        else {
            const Material* preset = a.empty() ? nullptr : findLibraryMaterial(a[0]);
            if (!a.empty() && !preset) { fail(ui, line, "no preset called '" + a[0] + "'"); return true; }
            c = makeNewMaterialFor(s, s.selectedObjects(), preset, &why);
        }
        if (!c || !s.apply(std::move(c), &why)) fail(ui, line, why);
        markEdit();
        return true;
    }
    if (op == "apply_preset") {
        const Material* preset = findLibraryMaterial(a[0]);
        if (!preset) { fail(ui, line, "no preset called '" + a[0] + "'"); return true; }
        int index = -1;
        if (s.selection.kind == EntityKind::Material) index = s.selection.index;
        else if (s.selection.kind == EntityKind::Object)
            index = findEntity(s.scene, EntityKind::Material, s.scene.objects[size_t(s.selection.index)].material).index;
        if (index < 0) { fail(ui, line, "no material is selected"); return true; }
        std::string why;
        if (!s.apply(makeApplyPreset(s, index, *preset), &why)) fail(ui, line, why);
        markEdit();
        return true;
    }
    if (op == "expect_material") {
        const EntityRef ref = findEntity(s.scene, EntityKind::Object, a[0]);
        if (!ref) { fail(ui, line, "no object called '" + a[0] + "'"); return true; }
        const std::string& has = s.scene.objects[size_t(ref.index)].material;
        if (has != a[1]) fail(ui, line, "object '" + a[0] + "' has material '" + has + "'");
        return true;
    }
    if (op == "preview_lighting") {
        if (a[0] != "scene" && a[0] != "studio") { fail(ui, line, "expected scene or studio"); return true; }
        ui.preview->lighting = a[0] == "scene" ? PreviewLighting::Scene : PreviewLighting::Studio;
        return true;
    }
    if (op == "wait_preview") {
        // The inspector asks for the preview while it shows a material (this frame, before us).
        // A selection made on this frame shows in the inspector from the next one.
        if (!ui.preview->requested()) {
            if (++m_previewMissing > 5) {
                m_previewMissing = 0;
                fail(ui, line, "the inspector shows no material (select a material, or an object with its material open)");
                return true;
            }
            return false;
        }
        m_previewMissing = 0;
        // The request this line sees must come from a frame after it started (an edit on the
        // line before shows in the inspector, and so in the request, from the next frame).
        if (m_previewLine != m_next) {
            m_previewLine = m_next;
            return false;
        }
        if (!ui.preview->error().empty()) { fail(ui, line, "the preview failed: " + ui.preview->error()); return true; }
        const bool done = ui.preview->current() && ui.preview->samples() >= static_cast<int>(num(a[0]));
        if (done) m_previewLine = static_cast<size_t>(-1);
        return waitFor(ui, line, done, a.size() > 1 ? num(a[1]) : kScriptWaitSeconds, "the material preview did not converge");
    }
    if (op == "pick_file" || op == "expect_picker_lists") {
        // The listing the inspector's "..." shows (asset_files.h) and the path a pick stores.
        const bool env = a[0] == "environment";
        const AssetKind kind = env ? AssetKind::EnvironmentMap : AssetKind::Texture;
        if (!env && a[0] != "albedo_texture" && a[0] != "normal_texture" && a[0] != "roughness_texture") {
            fail(ui, line, "unknown slot '" + a[0] + "'");
            return true;
        }
        const std::string folder = sceneFolderOf(s.path);
        const std::vector<AssetFile> files = listAssetFiles(kind, folder, assetsFolderFor(folder));
        const AssetFile* found = nullptr;
        for (const AssetFile& f : files)
            if (f.display == a[1]) found = &f;
        if (!found) { fail(ui, line, "the picker does not list '" + a[1] + "' (" + std::to_string(files.size()) + " files)"); return true; }
        if (op == "expect_picker_lists") return true;
        std::string why;
        if (env) {
            Environment e = s.scene.environment;
            e.type = EnvironmentType::Map;
            e.file = found->stored;
            if (!s.apply(makeSetEnvironment(s, e), &why)) fail(ui, line, why);
        } else {
            if (s.selection.kind != EntityKind::Material) { fail(ui, line, "no material is selected"); return true; }
            Material m = s.scene.materials[size_t(s.selection.index)];
            (a[0] == "albedo_texture" ? m.albedoTexture : a[0] == "normal_texture" ? m.normalTexture : m.roughnessTexture) = found->stored;
            if (!s.apply(makeSetMaterial(s, s.selection.index, m), &why)) fail(ui, line, why);
        }
        markEdit();
        return true;
    }
    if (op == "set_focus") {
        Camera c = s.scene.camera;
        c.focalDistance = num(a[0]);
        c.focusPoint.reset();
        std::string why;
        if (!s.apply(makeSetCamera(s, c), &why)) fail(ui, line, why);
        markEdit();
        m_waitFrames = 1;   // the overlay is drawn by the next frame's viewport
        ++m_next;
        return false;
    }
    if (op == "expect_focus_overlay") {
        if (ui.focusOverlayCells < static_cast<int>(num(a[0])))
            fail(ui, line, ui.focusOverlayCells < 0 ? std::string("the focus overlay is not shown")
                                                    : "the focus overlay marks " + std::to_string(ui.focusOverlayCells) + " cells");
        return true;
    }
    if (op == "expect_no_focus_overlay") {
        if (ui.focusOverlayCells >= 0) fail(ui, line, "the focus overlay is shown");
        return true;
    }
    if (op == "store_view") {
        storeCameraView(ui, a[0]);
        return true;
    }
    if (op == "recall_view") {
        if (!recallCameraView(ui, a[0])) fail(ui, line, ui.lastMessage);
        markEdit();
        return true;
    }
    if (op == "expect_views") {
        const std::size_t n = ui.views.of(s.path).size();
        if (n != static_cast<std::size_t>(num(a[0]))) fail(ui, line, "expected " + a[0] + " views, have " + std::to_string(n));
        return true;
    }
    if (op == "ui_scale") {   // View > UI scale (0: follow the monitor)
        ui.uiScaleChoice = num(a[0]);
        ui.resetLayout = true;   // as the menu does
        return true;
    }
    if (op == "expect_font_size") {   // the UI's font size in pixels, within half a pixel
        const float size = ImGui::GetFontSize();
        if (std::abs(size - num(a[0])) > 0.5f) fail(ui, line, "the font size is " + std::to_string(size));
        return true;
    }
    if (op == "show_help") {   // Help > Keyboard and mouse (screenshots)
        ui.showShortcuts = a[0] == "on";
        return true;
    }
    if (op == "record_sizes") {   // the viewport sizes the report lists start from here
        m_sizes.clear();
        return true;
    }
    if (op == "window_size") {   // as the user resizing the window
        glfwSetWindowSize(ui.window, static_cast<int>(num(a[0])), static_cast<int>(num(a[1])));
        m_waitFrames = 3;
        ++m_next;
        return false;
    }
    if (op == "idle") {   // on: idle pacing as for a person who stopped touching the mouse (benchmarks)
        m_idle = a[0] == "on";
        return true;
    }
    if (op == "expect_keymap") {
        const char* in = ui.keymap == KeymapStyle::Blender ? "blender" : "default";
        if (a[0] != in) fail(ui, line, std::string("the key map is ") + in);
        return true;
    }
    if (op == "keymap") {
        if (a[0] != "default" && a[0] != "blender") { fail(ui, line, "expected default or blender"); return true; }
        ui.keymap = a[0] == "blender" ? KeymapStyle::Blender : KeymapStyle::Default;
        return true;
    }
    if (op == "mouse_move" || op == "mouse_click") {
        // Through ImGui's input queue, as GLFW's callbacks feed it.
        ImGuiIO& io = ImGui::GetIO();
        if (op == "mouse_move") {
            ImVec2 p = io.MousePos;
            const float* v = ui.viewportImage;
            if (!ImGui::IsMousePosValid(&p) || p.x < v[0] || p.y < v[1] || p.x > v[0] + v[2] || p.y > v[1] + v[3])
                p = ImVec2(v[0] + v[2] * 0.5f + 0.25f, v[1] + v[3] * 0.5f + 0.25f);
            io.AddMousePosEvent(p.x + num(a[0]), p.y + num(a[1]));
        } else {
            const int button = a[0] == "right" ? ImGuiMouseButton_Right : ImGuiMouseButton_Left;
            io.AddMouseButtonEvent(button, true);
            io.AddMouseButtonEvent(button, false);
        }
        m_waitFrames = 2;
        ++m_next;
        return false;
    }
    if (op == "expect_hidden" || op == "expect_rendered_objects") {
        const std::size_t n = op == "expect_hidden" ? ui.hidden.size()
                              : ui.session.renderedObjects.empty() ? s.scene.objects.size() : ui.session.renderedObjects.size();
        if (n != static_cast<std::size_t>(num(a[0]))) fail(ui, line, "expected " + a[0] + ", have " + std::to_string(n));
        return true;
    }
    if (op == "expect_modal") {
        if (ui.modal.active != (a[0] == "yes")) fail(ui, line, ui.modal.active ? "a transform is in progress" : "no transform is in progress");
        return true;
    }
    if (op == "shader_dir") {   // where the next reload (F5) reads the shaders from
        ui.shaderDir = resolve(a[0]);
        return true;
    }
    if (op == "write_preview") {
        std::string why;
        if (!ui.preview->writeImage(resolve(a[0]), ui, &why)) fail(ui, line, why);
        return true;
    }
    if (op == "translate") {
        std::string why;
        if (!moveSelection(ui, {num(a[0]), num(a[1]), num(a[2])}, false, &why)) fail(ui, line, why);
        markEdit();
        return true;
    }
    if (op == "drag") {
        // One step per frame, like a gizmo drag; sealed after the last step, as on release.
        if (m_dragStepsLeft == 0) {
            m_dragStepsLeft = std::max(1, static_cast<int>(num(a[3])));
            for (int i = 0; i < 3; ++i) m_drag[i] = num(a[static_cast<size_t>(i)]) / float(m_dragStepsLeft);
        }
        std::string why;
        if (!moveSelection(ui, {m_drag[0], m_drag[1], m_drag[2]}, true, &why)) { fail(ui, line, why); return true; }
        markEdit();
        ui.session.interacting = true;
        ui.session.lastInteraction = glfwGetTime();
        if (--m_dragStepsLeft > 0) return false;
        ui.session.interacting = false;
        s.seal();
        return true;
    }
    if (op == "orbit") {
        s.apply(makeSetCamera(s, orbit(s.scene.camera, num(a[0]), num(a[1]))));
        markEdit();
        return true;
    }
    if (op == "set_samples") {
        RenderSettings r = s.scene.render;
        r.samples = static_cast<int>(num(a[0]));
        std::string why;
        if (!s.apply(makeSetRender(s, r), &why)) fail(ui, line, why);
        markEdit();
        return true;
    }
    if (op == "undo" || op == "redo") {
        if (!(op == "undo" ? s.undo() : s.redo())) fail(ui, line, "nothing to " + op);
        markEdit();
        return true;
    }
    if (op == "open") {
        openFile(ui, resolve(a[0]));   // a failure shows the error and keeps the scene
        markEdit();
        return true;
    }
    if (op == "save") {
        const std::string file = a.empty() ? s.path : resolve(a[0]);
        if (!saveFile(ui, file)) fail(ui, line, ui.lastMessage);
        return true;
    }
    if (op == "write_image") {
        std::string error;   // what the viewport shows: the denoised image while it is shown
        if (!writeViewportImage(ui, resolve(a[0]), &error)) fail(ui, line, error);
        return true;
    }
    if (op == "screenshot") {
        m_screenshotPending = resolve(a[0]);
        ++m_next;
        return false;
    }
    if (op == "snapshot") {
        if (ui.display) ui.display->takeSnapshot();
        return true;
    }
    if (op == "viewport") {
        if (a[0] != "output" && a[0] != "panel") {
            fail(ui, line, "viewport: expected output or panel, got '" + a[0] + "'");
            return true;
        }
        m_outputSize = a[0] == "output";
        return true;
    }
    if (op == "compare") {
        ui.compare = a[0] == "on";
        return true;
    }
    if (op == "render_to_file") {
        if (!m_renderStarted) {
            startRenderToFile(ui, resolve(a[0]));
            m_renderStarted = true;
            return false;
        }
        if (ui.renderToFile) return false;   // still rendering
        m_renderStarted = false;
        return true;
    }
    if (op == "expect_message") {   // the status bar's last message, info or error, contains the text
        if (ui.lastMessage.find(a[0]) == std::string::npos)
            fail(ui, line, "expected a message containing '" + a[0] + "', the last message is '" + ui.lastMessage + "'");
        return true;
    }
    if (op == "expect_error") {
        if (!ui.lastMessageIsError || ui.lastMessage.find(a[0]) == std::string::npos)
            fail(ui, line, "expected an error containing '" + a[0] + "', the last message is '" + ui.lastMessage + "'");
        return true;
    }
    if (op == "expect_undo_steps") {
        const int n = static_cast<int>(num(a[0]));
        if (static_cast<int>(s.history.undoCount()) != n)
            fail(ui, line, "expected " + std::to_string(n) + " undo steps, have " + std::to_string(s.history.undoCount()));
        return true;
    }
    if (op == "report") {
        std::ostringstream j;
        auto list = [&](const std::vector<double>& v) {
            std::ostringstream o;
            o << "[";
            for (size_t i = 0; i < v.size(); ++i) o << (i ? ", " : "") << v[i];
            o << "]";
            return o.str();
        };
        double sppMean = 0.0;
        for (int n : m_samplesPerFrame) sppMean += n;
        if (!m_samplesPerFrame.empty()) sppMean /= double(m_samplesPerFrame.size());
        j << "{\n  \"rendering_frames\": " << m_frameMs.size()
          << ",\n  \"frame_ms_median\": " << percentile(m_frameMs, 0.5)
          << ",\n  \"frame_ms_p95\": " << percentile(m_frameMs, 0.95)
          << ",\n  \"frame_ms_max\": " << percentile(m_frameMs, 1.0)
          << ",\n  \"all_frames_ms_median\": " << percentile(m_allFrameMs, 0.5)
          << ",\n  \"frame_overhead_ms_median\": " << percentile(m_overheadMs, 0.5)
          << ",\n  \"samples_per_frame_mean\": " << sppMean
          << ",\n  \"edit_to_frame_ms\": " << list(m_editLatencyMs)
          << ",\n  \"edit_to_frame_ms_median\": " << percentile(m_editLatencyMs, 0.5)
          << ",\n  \"frames_during_import\": " << m_importFrameMs.size()
          << ",\n  \"rendering_frames_during_import\": " << m_importRenderingFrames
          << ",\n  \"frame_ms_median_during_import\": " << percentile(m_importFrameMs, 0.5)
          << ",\n  \"frame_ms_max_during_import\": " << percentile(m_importFrameMs, 1.0)
          << ",\n  \"import_seconds\": " << list(ui.meshImports->importSeconds())
          << ",\n  \"frames_during_open\": " << m_openFrameMs.size()
          << ",\n  \"rendering_frames_during_open\": " << m_openRenderingFrames
          << ",\n  \"frame_ms_median_during_open\": " << percentile(m_openFrameMs, 0.5)
          << ",\n  \"frame_ms_max_during_open\": " << percentile(m_openFrameMs, 1.0)
          << ",\n  \"open_seconds\": " << list(ui.meshImports->openSeconds())
          << ",\n  \"viewport_sizes\": " << [&] {
                 std::ostringstream o;
                 o << "[";
                 for (size_t i = 0; i < m_sizes.size(); ++i)
                     o << (i ? ", " : "") << "[" << m_sizes[i][0] << ", " << m_sizes[i][1] << ", " << m_sizes[i][2] << ", "
                       << m_sizes[i][3] << "]";
                 o << "]";
                 return o.str();
             }()
          << ",\n  \"viewport_resolution\": [" << ui.session.viewportResolution(s.scene).x << ", "
          << ui.session.viewportResolution(s.scene).y << "]"
          << ",\n  \"samples\": " << (ui.renderer ? ui.renderer->samplesDone() : 0)
          << ",\n  \"render_elapsed_seconds\": " << ui.session.sampleRate.elapsedSeconds()
          << ",\n  \"idle_pacing\": " << (m_idle ? "true" : "false")
          << ",\n  \"width\": " << s.scene.render.width << ", \"height\": " << s.scene.render.height << "\n}\n";
        std::string error;
        if (!writeFileAtomically(resolve(a[0]), j.str(), &error)) fail(ui, line, error);
        return true;
    }
    if (op == "import_mesh") {   // starts a background import; the object appears when it is ready
        ui.meshImports->importFile(ui, resolve(a[0]));
        return true;
    }
    if (op == "set_mesh_file") {   // the selected mesh object's file, through the same background import
        const bool mesh = s.selection.kind == EntityKind::Object && s.selection.index >= 0 &&
                          static_cast<size_t>(s.selection.index) < s.scene.objects.size() &&
                          s.scene.objects[static_cast<size_t>(s.selection.index)].shape == Shape::Mesh;
        if (!mesh) { fail(ui, line, "select a mesh object first"); return true; }
        ui.meshImports->setObjectFile(ui, s.selection.index, resolve(a[0]));
        return true;
    }
    if (op == "wait_import")   // until every import has finished and its edit applied [timeout s]
        return waitFor(ui, line, !ui.meshImports->pending(), a.empty() ? kScriptWaitSeconds : double(num(a[0])), "still importing");
    if (op == "wait_open")   // until the scene being opened is adopted (or refused) [timeout s]
        return waitFor(ui, line, !ui.meshImports->opening(), a.empty() ? kScriptWaitSeconds : double(num(a[0])), "still opening");
    if (op == "uncap") {
        ui.session.sampleCap.reset();
        return true;
    }
    if (op == "touch") {   // as if another program had written the file
        std::error_code ec;
        std::filesystem::last_write_time(resolve(a[0]), std::filesystem::file_time_type::clock::now(), ec);
        if (ec) fail(ui, line, resolve(a[0]) + ": " + ec.message());
        return true;
    }
    if (op == "frame") {   // F: frame the selection (or everything)
        frameSelection(ui);
        markEdit();
        return true;
    }
    if (op == "focus") {   // as a click on the panel's title would
        const char* window = a[0] == "viewport" ? "Viewport" : a[0] == "outliner" ? "Outliner" : a[0] == "inspector" ? "Inspector" : nullptr;
        if (!window) { fail(ui, line, "unknown panel '" + a[0] + "'"); return true; }
        ImGui::SetWindowFocus(window);
        m_waitFrames = 1;   // focused from the next frame on
        ++m_next;
        return false;
    }
    if (op == "key") {   // through ImGui's input queue, as GLFW's key callback feeds it
        // Shift+, Ctrl+, Alt+ prefixes hold the modifier around the key.
        std::string name = a[0];
        std::vector<ImGuiKey> mods;
        for (const auto& [prefix, mod] : {std::pair{"Shift+", ImGuiMod_Shift}, std::pair{"Ctrl+", ImGuiMod_Ctrl}, std::pair{"Alt+", ImGuiMod_Alt}})
            if (name.rfind(prefix, 0) == 0) {
                mods.push_back(mod);
                name = name.substr(std::string(prefix).size());
            }
        const ImGuiKey key = imguiKey(name);
        if (key == ImGuiKey_None) { fail(ui, line, "unknown key '" + a[0] + "'"); return true; }
        for (ImGuiKey m : mods) ImGui::GetIO().AddKeyEvent(m, true);
        ImGui::GetIO().AddKeyEvent(key, true);
        ImGui::GetIO().AddKeyEvent(key, false);   // trickled: down next frame, up the one after
        for (ImGuiKey m : mods) ImGui::GetIO().AddKeyEvent(m, false);
        m_waitFrames = 2;
        ++m_next;
        markEdit();
        return false;
    }
    if (op == "expect_count") {
        const std::size_t n = a[0] == "objects" ? s.scene.objects.size() : a[0] == "lights" ? s.scene.lights.size()
                            : a[0] == "materials" ? s.scene.materials.size() : ~std::size_t(0);
        if (n == ~std::size_t(0)) { fail(ui, line, "unknown list '" + a[0] + "'"); return true; }
        if (n != static_cast<std::size_t>(num(a[1])))
            fail(ui, line, "expected " + a[1] + " " + a[0] + ", have " + std::to_string(n));
        return true;
    }
    if (op == "add_material") {
        std::string why;
        if (!s.apply(makeAddMaterial(s), &why)) fail(ui, line, why);
        markEdit();
        return true;
    }
    if (op == "mark") {
        m_markedGeneration = ui.session.accumulationGeneration;
        return true;
    }
    if (op == "expect_restarted") {
        const bool restarted = ui.session.accumulationGeneration != m_markedGeneration;
        if (restarted != (a[0] == "yes"))
            fail(ui, line, std::string("accumulation ") + (restarted ? "restarted" : "did not restart") + " since `mark`");
        return true;
    }
    if (op == "quit") {
        ui.quit = true;
        return true;
    }
    bool finished = true;
    if (runDenoiseOrAutosave(ui, line, &finished)) return finished;
    fail(ui, line, "not implemented");
    return true;
}

// The denoising and autosave/recovery commands. Returns false when `line` is not one of them;
// else *finished is false while the command waits (it is called again next frame).
bool ScriptRunner::runDenoiseOrAutosave(EditorUi& ui, const ScriptLine& line, bool* finished) {
    const auto& a = line.args;
    const std::string& op = line.op;
    EditorState& s = ui.state;
    const bool first = m_lineStarted != m_next;
    if (first) {
        m_lineStarted = m_next;
        m_lineStartTime = glfwGetTime();
        m_pressed = false;
    }
    const double waited = glfwGetTime() - m_lineStartTime;
    auto onOff = [&](bool* out) {
        if (a[0] != "on" && a[0] != "off" && a[0] != "yes" && a[0] != "no") {
            fail(ui, line, "expected on or off, got '" + a[0] + "'");
            return false;
        }
        *out = a[0] == "on" || a[0] == "yes";
        return true;
    };
    ViewportDenoiser* dn = ui.denoiser.get();
    if (op == "denoise" || op == "wait_denoised") {
        const double timeout = a.empty() ? kScriptWaitSeconds : double(num(a[0]));
        if (!dn) { fail(ui, line, "no denoiser"); return true; }
        if (first) m_countAtStart = dn->failures();
        if (dn->shown(ui)) return true;
        if (dn->failures() != m_countAtStart) { fail(ui, line, "the denoiser failed: " + dn->lastError()); return true; }
        if (waited > timeout) {
            fail(ui, line, "no denoised image after " + std::to_string(int(timeout)) + " s (" + dn->status(ui) + ")");
            return true;
        }
        const bool settled = ui.renderer && ui.session.sceneUploaded && ui.session.previewDivisor == 1 && s.pendingDirty() == kDirtyNone && !ui.session.interacting;
        // denoise: one request for the settled image (again if an edit made the first one stale).
        if (op == "denoise" && settled && !dn->busy() && !dn->current(ui)) {
            const std::pair<std::uint64_t, int> key(ui.session.accumulationGeneration, ui.renderer->samplesDone());
            if (!m_pressed || m_denoiseKey != key) {
                std::string why;
                if (!dn->request(ui, false, &why)) { fail(ui, line, why); return true; }
                dn->settings.showDenoised = true;
                m_pressed = true;
                m_denoiseKey = key;
            }
        }
        *finished = false;
        return true;
    }
    if (op == "denoise_auto" || op == "show_raw") {
        bool on = false;
        if (!onOff(&on)) return true;
        if (!dn) { fail(ui, line, "no denoiser"); return true; }
        if (op == "denoise_auto") dn->settings.autoDenoise = on;
        else dn->settings.showDenoised = !on;
        return true;
    }
    if (op == "expect_denoised") {
        bool yes = false;
        if (!onOff(&yes)) return true;
        const bool shown = dn && dn->shown(ui);
        if (shown != yes) fail(ui, line, std::string("the viewport ") + (shown ? "shows" : "does not show") + " a denoised image");
        return true;
    }
    if (op == "autosave" || op == "autosave_now" || op == "wait_autosave") {
        // Scripts never touch the user's autosave: only with $CAUSTIC_EDITOR_HOME (a test's folder).
        if (!scriptMayUseAutosave()) {
            fail(ui, line, "scripts use the autosave only when $CAUSTIC_EDITOR_HOME names the config folder");
            return true;
        }
        if (op == "autosave") {
            bool on = false;
            if (!onOff(&on)) return true;
            m_autosave = on;
            ui.lastAutosave = glfwGetTime();   // the interval counts from here
            return true;
        }
        if (op == "autosave_now") {
            if (!s.modified()) { fail(ui, line, "nothing to autosave: no unsaved changes"); return true; }
            std::string error;
            if (!ui.autosave.write(s.scene, s.path, &error)) { fail(ui, line, error); return true; }
            ++ui.autosaveWrites;
            return true;
        }
        // wait_autosave: the periodic autosave has written since this line started.
        const double timeout = a.empty() ? kScriptWaitSeconds : double(num(a[0]));
        if (!m_autosave) { fail(ui, line, "autosave is off (autosave on)"); return true; }
        if (first) m_countAtStart = ui.autosaveWrites;
        if (ui.autosaveWrites > m_countAtStart) return true;
        if (waited > timeout) { fail(ui, line, "no autosave within " + std::to_string(int(timeout)) + " s"); return true; }
        *finished = false;
        return true;
    }
    if (op == "crash") {
        // A simulated crash: no destructors, no clean exit, so the autosave stays behind.
        std::fprintf(stderr, "caustic: script %s:%d: crash: exiting without clean-up\n", m_file.c_str(), line.line);
        std::_Exit(3);
    }
    if (op == "expect_recovery_offered") {
        if (ui.recoveryPromptRequested) {   // the prompt opens during this frame's drawing
            *finished = false;
            return true;
        }
        if (!ui.recovered || !ImGui::IsPopupOpen("Recover unsaved work?"))
            fail(ui, line, "no recovery was offered");
        return true;
    }
    if (op == "recover") {
        if (!m_pressed) {
            if (!ui.recovered) { fail(ui, line, "no recovery was offered"); return true; }
            m_pressRecover = true;   // the prompt's "Recover" button takes it next frame
            m_pressed = true;
            *finished = false;
            return true;
        }
        if (ui.recovered) {
            if (waited > kScriptWaitSeconds) fail(ui, line, "the recovery prompt did not take the answer");
            else *finished = false;
        }
        return true;
    }
    if (op == "expect_modified") {
        bool yes = false;
        if (!onOff(&yes)) return true;
        if (s.modified() != yes) fail(ui, line, std::string("the scene is ") + (s.modified() ? "modified" : "not modified"));
        return true;
    }
    return false;
}

void ScriptRunner::afterDraw(EditorUi& ui, int fbWidth, int fbHeight) {
    if (m_screenshotPending.empty() || fbWidth <= 0 || fbHeight <= 0) return;
    std::vector<std::uint8_t> rgba(static_cast<size_t>(fbWidth) * fbHeight * 4), rgb(static_cast<size_t>(fbWidth) * fbHeight * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, fbWidth, fbHeight, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    for (int y = 0; y < fbHeight; ++y)          // GL rows go bottom-up, images top-down
        for (int x = 0; x < fbWidth; ++x)
            for (int c = 0; c < 3; ++c)
                rgb[(static_cast<size_t>(y) * fbWidth + x) * 3 + c] =
                    rgba[(static_cast<size_t>(fbHeight - 1 - y) * fbWidth + x) * 4 + c];
    std::string error;
    if (!writeImage8(m_screenshotPending, fbWidth, fbHeight, rgb, {{"Software", "caustic editor"}}, &error)) {
        std::fprintf(stderr, "caustic: screenshot: %s\n", error.c_str());
        m_failed = true;
        ui.quit = true;
    }
    m_screenshotPending.clear();
}

void ScriptRunner::afterSwap(EditorUi& ui, double frameSeconds) {
    m_allFrameMs.push_back(frameSeconds * 1e3);
    // The viewport's render size, divisor and samples, whenever one of the first two changes
    // (`record_sizes` starts the list afresh): the refinement after an edit, panel resizes.
    if (ui.session.sceneUploaded) {
        const std::array<int, 4> now{ui.session.renderedSize.x, ui.session.renderedSize.y, ui.session.previewDivisor,
                                     ui.renderer ? ui.renderer->samplesDone() : 0};
        if (m_sizes.empty() || m_sizes.back()[0] != now[0] || m_sizes.back()[1] != now[1] || m_sizes.back()[2] != now[2])
            m_sizes.push_back(now);
        else
            m_sizes.back()[3] = now[3];   // the samples the size reached before it changed
    }
    if (ui.meshImports->pending()) {
        m_importFrameMs.push_back(frameSeconds * 1e3);
        if (ui.session.renderedThisFrame) ++m_importRenderingFrames;
    }
    if (ui.meshImports->opening()) {
        m_openFrameMs.push_back(frameSeconds * 1e3);
        if (ui.session.renderedThisFrame) ++m_openRenderingFrames;
    }
    if (ui.session.renderedThisFrame) {
        m_frameMs.push_back(frameSeconds * 1e3);
        m_overheadMs.push_back((frameSeconds - ui.session.renderSeconds) * 1e3);
        m_samplesPerFrame.push_back(ui.session.samplesThisFrame);
        if (m_editPending && ui.state.pendingDirty() == kDirtyNone) {
            m_editLatencyMs.push_back((glfwGetTime() - m_editTime) * 1e3);
            m_editPending = false;
        }
    }
}

bool ScriptRunner::offersRecovery() const { return scriptMayUseAutosave(); }

}  // namespace caustic::editor
