// The main menu: File (new, open, recent, save, save as, render to file, quit), Edit (undo,
// redo, duplicate, delete), View (fit, snapshot, compare, denoise, layout), Render (restart, reload
// shaders).
#include "editor/ui/editor_ui.h"
#include "editor/ui/viewport_denoise.h"
#include "renderer/denoise.h"

#include <imgui.h>

#include <utility>

#include <filesystem>

namespace caustic::editor {

void drawMenuBar(EditorUi& ui) {
    if (!ImGui::BeginMainMenuBar()) return;
    EditorState& s = ui.app.state;
    if (ImGui::BeginMenu("File")) {
        if (ImGui::MenuItem("New")) guardUnsaved(ui, [&ui] { ui.app.state.newScene(); ui.app.renderToFile.reset(); });
        if (ImGui::MenuItem("Open...", "Ctrl+O")) guardUnsaved(ui, [&ui] { openFileBrowser(ui, FileBrowserState::Mode::Open); });
        if (ImGui::BeginMenu("Open recent", !ui.app.recent.files().empty())) {
            std::string chosen;
            for (const std::string& f : ui.app.recent.files())
                if (ImGui::MenuItem(f.c_str())) chosen = f;
            ImGui::EndMenu();
            if (!chosen.empty()) guardUnsaved(ui, [&ui, chosen] { openFile(ui, chosen); });
        }
        ImGui::Separator();
        if (ImGui::MenuItem("Save", "Ctrl+S")) saveOrSaveAs(ui);
        if (ImGui::MenuItem("Save as...", "Ctrl+Shift+S")) openFileBrowser(ui, FileBrowserState::Mode::SaveAs);
        ImGui::Separator();
        if (ImGui::MenuItem("Render to file...")) openFileBrowser(ui, FileBrowserState::Mode::RenderTo);
        ImGui::Separator();
        if (ImGui::MenuItem("Quit")) guardUnsaved(ui, [&ui] { ui.app.quit = true; });
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Edit")) {
        const std::string undo = s.history.canUndo() ? "Undo " + s.history.undoName() : std::string("Undo");
        const std::string redo = s.history.canRedo() ? "Redo " + s.history.redoName() : std::string("Redo");
        if (ImGui::MenuItem(undo.c_str(), "Ctrl+Z", false, s.history.canUndo())) s.undo();
        if (ImGui::MenuItem(redo.c_str(), "Ctrl+Shift+Z", false, s.history.canRedo())) s.redo();
        ImGui::Separator();
        const bool listEntry = s.selection && s.selection.index >= 0;
        if (ImGui::MenuItem("Duplicate", "Ctrl+D", false, listEntry)) {
            std::string why;
            if (auto c = makeDuplicate(s, s.selection, &why)) s.apply(std::move(c));
        }
        if (ImGui::MenuItem("Delete", "Del", false, listEntry)) {
            std::string why;
            if (auto c = makeDelete(s, s.selection, &why)) s.apply(std::move(c));
            else notify(ui, why, true);
        }
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("View")) {
        ImGui::MenuItem("Fit image to panel", nullptr, &s.view.fitToWindow);
        if (ImGui::BeginMenu("Viewport resolution", s.view.fitToWindow)) {
            // The viewport renders at the panel's size (a fraction of it is faster); Render to file
            // and batch mode use the scene's output resolution.
            // Automatic: from the measured rate, 4 samples a second (render_session.h).
            for (const auto& [label, scale] : {std::pair{"Automatic", 0.0f}, std::pair{"Panel size", 1.0f}, std::pair{"Half", 0.5f}, std::pair{"Quarter", 0.25f}})
                if (ImGui::MenuItem(label, nullptr, s.view.viewportScale == scale)) s.view.viewportScale = scale;
            ImGui::EndMenu();
        }
        if (ImGui::MenuItem("Frame selection", "F")) frameSelection(ui);
        // A view of the viewport's own: navigating moves it and leaves the render camera where it
        // is (the Blender map's Numpad 0); "Camera to view" then moves the camera there (one step).
        const bool blender = ui.app.keymap == KeymapStyle::Blender;
        if (ImGui::MenuItem("Free view", blender ? "Numpad 0" : nullptr, s.freeView.has_value())) s.toggleCameraView();
        if (ImGui::MenuItem("Camera to view", blender ? "Ctrl+Alt+Numpad 0" : nullptr, false, s.freeView.has_value())) {
            std::string why;
            if (!s.cameraToView(&why)) notify(ui, why, true);
        }
        ImGui::Separator();
        if (ImGui::MenuItem("Take snapshot", nullptr, false, ui.app.display != nullptr)) {
            ui.app.display->takeSnapshot();
            ui.compare = true;
        }
        ImGui::MenuItem("Compare with snapshot", nullptr, &ui.compare, ui.app.display && ui.app.display->hasSnapshot());
        if (ui.app.denoiser) {
            ImGui::Separator();
            if (ImGui::MenuItem("Denoise now", "F6", false, denoiserAvailable())) denoiseNow(ui);
            ImGui::MenuItem("Denoise at target samples", nullptr, &ui.app.denoiser->settings.autoDenoise, denoiserAvailable());
            ImGui::MenuItem("Denoise when idle", nullptr, &ui.app.denoiser->settings.idleDenoise, denoiserAvailable());
            ImGui::MenuItem("Show denoised", nullptr, &ui.app.denoiser->settings.showDenoised);
        }
        ImGui::Separator();
        if (ImGui::BeginMenu("Key map")) {
            if (ImGui::MenuItem("Default (W E R gizmo)", nullptr, ui.app.keymap == KeymapStyle::Default)) ui.app.keymap = KeymapStyle::Default;
            if (ImGui::MenuItem("Blender (G R S, Shift+D, H, numpad)", nullptr, ui.app.keymap == KeymapStyle::Blender))
                ui.app.keymap = KeymapStyle::Blender;
            ImGui::EndMenu();
        }
        if (ImGui::BeginMenu("UI scale")) {
            // 0: the window's content scale (glfwGetWindowContentScale: HiDPI monitors).
            for (const auto& [label, f] : {std::pair{"Follow the monitor", 0.0f}, std::pair{"100%", 1.0f}, std::pair{"125%", 1.25f},
                                           std::pair{"150%", 1.5f}, std::pair{"200%", 2.0f}})
                if (ImGui::MenuItem(label, nullptr, ui.app.uiScaleChoice == f)) {
                    ui.app.uiScaleChoice = f;
                    ui.resetLayout = true;   // the panels laid out again for the new size of their labels
                }
            ImGui::EndMenu();
        }
        if (!ui.app.hidden.empty() && ImGui::MenuItem("Show hidden objects", "Alt+H (Blender keys)")) ui.app.hidden.clear();
        if (ImGui::MenuItem("Reset layout")) ui.resetLayout = true;
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Render")) {
        if (ImGui::MenuItem("Restart")) s.markDirty(kDirtySettings);
        if (ImGui::MenuItem("Reload shaders", "F5")) reloadShaders(ui);
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Help")) {
        ImGui::MenuItem("Keyboard and mouse", nullptr, &ui.showShortcuts);
        ImGui::EndMenu();
    }
    ImGui::EndMainMenuBar();
}

}  // namespace caustic::editor
