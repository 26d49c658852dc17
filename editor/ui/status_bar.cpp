// The status bar along the bottom: samples so far / target, samples per second of wall-clock
// time, the time since the restart and the ETA to the target, "paused" (with Resume) while Denoise now holds the render, resolution
// (and the preview divisor while dragging), dropped NaN/Inf samples, frame time, the denoiser's
// state, the latest message.
#include "editor/ui/editor_ui.h"
#include "editor/ui/mesh_import.h"
#include "editor/ui/viewport_denoise.h"

#include <imgui.h>

namespace caustic::editor {

void drawStatusBar(EditorUi& ui) {
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    const float h = ImGui::GetFrameHeight();
    ImGui::SetNextWindowPos(ImVec2(vp->WorkPos.x, vp->WorkPos.y + vp->WorkSize.y - h));
    ImGui::SetNextWindowSize(ImVec2(vp->WorkSize.x, h));
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoDocking |
                                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav;
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(8.0f, 3.0f));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowRounding, 0.0f);
    const bool open = ImGui::Begin("##status", nullptr, flags);
    ImGui::PopStyleVar(2);
    if (!open) {
        ImGui::End();
        return;
    }
    const RenderSettings& rs = ui.app.state.scene.render;
    if (!ui.app.renderer) {
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "no renderer (shader error: see the message, fix, F5)");
    } else {
        const int done = ui.app.renderer->samplesDone();
        // On a slow GPU a sample takes many frames (tiles): say how far the next one is.
        if (ui.app.renderer->bandInProgress() && done < rs.samples)
            ImGui::Text("%d / %d spp (next %d%%)", done, rs.samples, static_cast<int>(ui.app.renderer->bandProgress() * 100.0f));
        else
            ImGui::Text("%d / %d spp", done, rs.samples);
        // A script's wait_samples holds the render below the scene's target: say where, or the bar
        // reads "1 / 256 spp ... done".
        if (ui.app.session.sampleCap && *ui.app.session.sampleCap < rs.samples) {
            ImGui::SameLine();
            ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "(held at %d by the script)", *ui.app.session.sampleCap);
        }
        ImGui::SameLine(0.0f, 16.0f);
        // Wall clock: what the image gains per second as the user waits (the path tracer's own
        // rate, per second of its time, is in the tooltip: the UI takes the rest of each frame).
        if (ui.app.session.sampleRate.known()) ImGui::Text("%.2f spp/s (wall clock)", ui.app.session.sampleRate.samplesPerSecond());
        else ImGui::TextDisabled("- spp/s (wall clock)");
        const double progress = done + (ui.app.renderer->bandInProgress() ? ui.app.renderer->bandProgress() : 0.0);
        const double eta = ui.app.session.sampleRate.etaSeconds(progress, ui.app.session.target(ui.app.state.scene));
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("samples accumulated per second of elapsed time since the render restarted (%.1f s);\n"
                              "per second of path-tracer time alone: %.2f spp/s",
                              ui.app.session.sampleRate.elapsedSeconds(), ui.app.session.samplesPerSecond);
        // Elapsed since the restart, and the time left to the target at the rate so far.
        ImGui::SameLine(0.0f, 16.0f);
        if (eta > 0.0)
            ImGui::Text("%s, ETA %s", durationText(ui.app.session.sampleRate.elapsedSeconds()).c_str(), durationText(eta).c_str());
        else
            ImGui::TextDisabled("%s%s", durationText(ui.app.session.sampleRate.elapsedSeconds()).c_str(), eta == 0.0 ? ", done" : "");
        if (ui.app.denoiser && ui.app.denoiser->holding()) {
            // Denoise now holds the render at its sample count: say so, and offer to go on.
            ImGui::SameLine(0.0f, 16.0f);
            ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "paused at %d spp (Denoise now)", done);
            ImGui::SameLine();
            if (ImGui::SmallButton("Resume")) ui.app.denoiser->resume(ui);
        }
        ImGui::SameLine(0.0f, 16.0f);
        // The output resolution, and what the viewport renders at when that differs (its panel's
        // size, a preview or refinement step).
        const glm::ivec2 vr = ui.app.session.renderedSize;
        if (vr == glm::ivec2(rs.width, rs.height)) ImGui::Text("%d x %d", rs.width, rs.height);
        else if (ui.app.session.previewDivisor > 1)
            ImGui::Text("%d x %d (viewport %d x %d, preview 1/%d)", rs.width, rs.height, vr.x, vr.y, ui.app.session.previewDivisor);
        else ImGui::Text("%d x %d (viewport %d x %d)", rs.width, rs.height, vr.x, vr.y);
        ImGui::SameLine(0.0f, 16.0f);
        if (ui.app.session.droppedSamples > 0) ImGui::TextColored(ImVec4(1.0f, 0.7f, 0.2f, 1.0f), "%llu NaN samples dropped", static_cast<unsigned long long>(ui.app.session.droppedSamples));
        else ImGui::TextDisabled("0 NaN");
        ImGui::SameLine(0.0f, 16.0f);
        ImGui::TextDisabled("%.1f ms/frame", ui.app.session.frameSeconds * 1e3);
        // ("render paused" alone is said above already, with its Resume button.)
        if (const std::string dn = ui.app.denoiser ? ui.app.denoiser->status(ui) : std::string(); !dn.empty() && dn != "render paused") {
            ImGui::SameLine(0.0f, 16.0f);
            ImGui::TextColored(ImVec4(0.6f, 0.9f, 0.6f, 1.0f), "%s", dn.c_str());
        }
        if (ui.app.renderToFile) {
            ImGui::SameLine(0.0f, 16.0f);
            ImGui::TextColored(ImVec4(0.5f, 0.8f, 1.0f, 1.0f), "rendering to %s", ui.app.renderToFile->c_str());
        }
        if (const std::string importing = ui.app.meshImports->status(); !importing.empty()) {
            ImGui::SameLine(0.0f, 16.0f);
            ImGui::TextColored(ImVec4(0.5f, 0.8f, 1.0f, 1.0f), "%s", importing.c_str());
        }
    }
    // An info message ("saved ...") goes after kInfoSeconds, so the bar never says something
    // stale; an error stays until what caused it is fixed (editor_app.cpp, renderFrame).
    constexpr double kInfoSeconds = 8.0;
    const bool fresh = ui.app.lastMessageIsError || ImGui::GetTime() - ui.app.lastMessageAt < kInfoSeconds;
    if (!ui.app.lastMessage.empty() && fresh) {
        ImGui::SameLine(0.0f, 24.0f);
        // First line only; the whole message is in the tooltip (and in the error dialog).
        const std::string first = ui.app.lastMessage.substr(0, ui.app.lastMessage.find('\n'));
        if (ui.app.lastMessageIsError) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "%s", first.c_str());
        else ImGui::TextDisabled("%s", first.c_str());
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", ui.app.lastMessage.c_str());
    }
    ImGui::End();
}

}  // namespace caustic::editor
