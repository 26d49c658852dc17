#include "editor/script/script_run.h"

#include "editor/ui/editor_ui.h"
#include "editor/ui/mesh_import.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace caustic::editor {
namespace {

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t i = std::min(v.size() - 1, static_cast<size_t>(p * double(v.size() - 1) + 0.5));
    return v[i];
}

std::string list(const std::vector<double>& v) {
    std::ostringstream o;
    o << "[";
    for (size_t i = 0; i < v.size(); ++i) o << (i ? ", " : "") << v[i];
    o << "]";
    return o.str();
}

}  // namespace

void ScriptRun::fail(EditorUi& ui, const ScriptLine& line, const std::string& why) {
    std::fprintf(stderr, "caustic: script %s:%d: %s: %s\n", file.c_str(), line.line, line.op.c_str(), why.c_str());
    failed = true;
    ui.app.quit = true;
}

std::string ScriptRun::resolve(const std::string& path) const {
    if (fs::path(path).is_absolute() || dir.empty()) return path;
    return (fs::path(dir) / path).string();
}

void ScriptRun::markEdit(const EditorUi& ui) {
    if (ui.app.state.pendingDirty() != kDirtyNone) {
        editTime = glfwGetTime();
        editPending = true;
        sinceEditFrameMs.clear();
    }
}

bool ScriptRun::startLine() {
    if (lineStarted == next) return false;
    lineStarted = next;
    lineStartTime = glfwGetTime();
    pressed = false;
    return true;
}

double ScriptRun::secondsOnLine() const { return glfwGetTime() - lineStartTime; }

bool ScriptRun::waitFor(EditorUi& ui, const ScriptLine& line, bool done, double timeout, const char* what) {
    if (done) {
        waitImportSince = -1.0;
        markEdit(ui);   // an edit the wait applied: the frame showing it is timed
        return true;
    }
    if (waitImportSince < 0.0) waitImportSince = glfwGetTime();
    if (glfwGetTime() - waitImportSince <= timeout) return false;
    waitImportSince = -1.0;
    fail(ui, line, std::string(what) + " after " + std::to_string(int(timeout)) + " s: " + ui.app.meshImports->status());
    return true;
}

void ScriptRun::recordFrame(const EditorUi& ui, double frameSeconds) {
    allFrameMs.push_back(frameSeconds * 1e3);
    if (editTime >= 0.0) sinceEditFrameMs.push_back(frameSeconds * 1e3);
    if (ui.app.session.buildingShaders) ++framesBuilding;
    // The viewport's render size, divisor and samples, whenever one of the first two changes
    // (`record_sizes` starts the list afresh): the refinement after an edit, panel resizes.
    if (ui.app.session.sceneUploaded) {
        const std::array<int, 4> now{ui.app.session.renderedSize.x, ui.app.session.renderedSize.y, ui.app.session.previewDivisor,
                                     ui.app.renderer ? ui.app.renderer->samplesDone() : 0};
        if (sizes.empty() || sizes.back()[0] != now[0] || sizes.back()[1] != now[1] || sizes.back()[2] != now[2])
            sizes.push_back(now);
        else
            sizes.back()[3] = now[3];   // the samples the size reached before it changed
    }
    if (ui.app.meshImports->pending()) {
        importFrameMs.push_back(frameSeconds * 1e3);
        if (ui.app.session.renderedThisFrame) ++importRenderingFrames;
    }
    if (ui.app.meshImports->opening()) {
        openFrameMs.push_back(frameSeconds * 1e3);
        if (ui.app.session.renderedThisFrame) ++openRenderingFrames;
    }
    if (ui.app.session.renderedThisFrame) {
        frameMs.push_back(frameSeconds * 1e3);
        overheadMs.push_back((frameSeconds - ui.app.session.renderSeconds) * 1e3);
        const RenderSession::FramePhases& ph = ui.app.session.phases;
        phaseMs[0].push_back(ph.ui * 1e3);
        phaseMs[1].push_back((ph.render - ui.app.session.renderSeconds) * 1e3);
        phaseMs[2].push_back(ph.previews * 1e3);
        phaseMs[3].push_back(ph.drawSwap * 1e3);
        samplesPerFrame.push_back(ui.app.session.samplesThisFrame);
        if (editPending && ui.app.state.pendingDirty() == kDirtyNone) {
            editLatencyMs.push_back((glfwGetTime() - editTime) * 1e3);
            editPending = false;
        }
    }
}

std::string ScriptRun::reportJson(const EditorUi& ui) const {
    const EditorState& s = ui.app.state;
    double sppMean = 0.0;
    for (int n : samplesPerFrame) sppMean += n;
    if (!samplesPerFrame.empty()) sppMean /= double(samplesPerFrame.size());
    std::ostringstream j;
    j << "{\n  \"rendering_frames\": " << frameMs.size()
      << ",\n  \"frame_ms_median\": " << percentile(frameMs, 0.5)
      << ",\n  \"frame_ms_p95\": " << percentile(frameMs, 0.95)
      << ",\n  \"frame_ms_max\": " << percentile(frameMs, 1.0)
      << ",\n  \"all_frames_ms_median\": " << percentile(allFrameMs, 0.5)
      << ",\n  \"all_frames_ms_max\": " << percentile(allFrameMs, 1.0)
      << ",\n  \"frame_ms_max_since_last_edit\": " << percentile(sinceEditFrameMs, 1.0)
      << ",\n  \"frames_building_shaders\": " << framesBuilding
      << ",\n  \"frame_overhead_ms_median\": " << percentile(overheadMs, 0.5)
      << ",\n  \"overhead_ms_median\": {\"ui\": " << percentile(phaseMs[0], 0.5) << ", \"render_step_less_path_tracing\": "
      << percentile(phaseMs[1], 0.5) << ", \"previews\": " << percentile(phaseMs[2], 0.5) << ", \"draw_and_swap\": "
      << percentile(phaseMs[3], 0.5) << "}"
      << ",\n  \"samples_per_frame_mean\": " << sppMean
      << ",\n  \"edit_to_frame_ms\": " << list(editLatencyMs)
      << ",\n  \"edit_to_frame_ms_median\": " << percentile(editLatencyMs, 0.5)
      << ",\n  \"frames_during_import\": " << importFrameMs.size()
      << ",\n  \"rendering_frames_during_import\": " << importRenderingFrames
      << ",\n  \"frame_ms_median_during_import\": " << percentile(importFrameMs, 0.5)
      << ",\n  \"frame_ms_max_during_import\": " << percentile(importFrameMs, 1.0)
      << ",\n  \"import_seconds\": " << list(ui.app.meshImports->importSeconds())
      << ",\n  \"frames_during_open\": " << openFrameMs.size()
      << ",\n  \"rendering_frames_during_open\": " << openRenderingFrames
      << ",\n  \"frame_ms_median_during_open\": " << percentile(openFrameMs, 0.5)
      << ",\n  \"frame_ms_max_during_open\": " << percentile(openFrameMs, 1.0)
      << ",\n  \"open_seconds\": " << list(ui.app.meshImports->openSeconds())
      << ",\n  \"viewport_sizes\": [";
    for (size_t i = 0; i < sizes.size(); ++i)
        j << (i ? ", " : "") << "[" << sizes[i][0] << ", " << sizes[i][1] << ", " << sizes[i][2] << ", " << sizes[i][3] << "]";
    j << "]"
      << ",\n  \"viewport_resolution\": [" << ui.app.session.viewportResolution(s.scene).x << ", "
      << ui.app.session.viewportResolution(s.scene).y << "]"
      << ",\n  \"samples\": " << (ui.app.renderer ? ui.app.renderer->samplesDone() : 0)
      << ",\n  \"render_elapsed_seconds\": " << ui.app.session.sampleRate.elapsedSeconds()
      << ",\n  \"seconds_since_last_edit\": " << (editTime >= 0.0 ? glfwGetTime() - editTime : -1.0)
      << ",\n  \"idle_pacing\": " << (idle ? "true" : "false")
      << ",\n  \"width\": " << s.scene.render.width << ", \"height\": " << s.scene.render.height << "\n}\n";
    return j.str();
}

}  // namespace caustic::editor
