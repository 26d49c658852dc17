// One script's run inside the editor: where it is, what its waiting commands have done so far,
// and what it measured (frame times, edit-to-frame latencies, viewport sizes; `report` writes them
// as JSON). The runner (script_runner.h) and the command handlers (script_commands.h) share it.
#pragma once

#include "editor/script/script.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace caustic::editor {

struct EditorUi;

// How long a script's waits (for an import, an open, the denoiser, an autosave, the recovery
// prompt, the material preview) may take before the script fails, when the line names no time-out:
// generous, because they wait for events and a loaded machine is slow, not wrong (tests fail on
// wrong results).
inline constexpr double kScriptWaitSeconds = 900.0;

struct ScriptRun {
    std::string file, dir;
    std::vector<ScriptLine> lines;
    std::size_t next = 0;           // the line running now
    bool failed = false;
    bool idle = false;              // `idle on`: the idle pacing of a session nobody touches
    bool autosave = false;          // `autosave on` (needs $CAUSTIC_EDITOR_HOME)
    bool outputSize = true;         // `viewport output` (the default) or `viewport panel`
    bool pressRecover = false;      // `recover`: the prompt's "Recover" button takes it next frame
    int waitFrames = 0;
    int previewMissing = 0;         // wait_preview: frames without a material in the inspector
    std::size_t previewLine = static_cast<std::size_t>(-1);   // wait_preview: the line that has waited a frame
    int dragStepsLeft = 0;
    std::uint64_t markedGeneration = 0;     // `mark`: accumulation's generation then (expect_restarted)
    bool renderStarted = false;
    float drag[3] = {0, 0, 0};
    std::string screenshotPending;
    // Waiting commands (denoise, wait_denoised, wait_autosave, recover): when the current line
    // started, and what it has done so far.
    std::size_t lineStarted = static_cast<std::size_t>(-1);
    double lineStartTime = 0.0;
    std::uint64_t countAtStart = 0;
    bool pressed = false;
    std::pair<std::uint64_t, int> denoiseKey{0, 0};

    // Measurements.
    std::vector<double> frameMs;            // frames that rendered samples
    std::vector<double> allFrameMs;
    std::vector<double> overheadMs;         // rendering frames: all but the path tracing
    std::vector<double> phaseMs[4];         // rendering frames: RenderSession::phases (ui, render step less path tracing, previews, draw and swap)
    std::vector<double> editLatencyMs;      // edit -> end of the first frame showing it
    std::vector<double> sinceEditFrameMs;   // every frame since the last edit (a build's frames among them)
    int framesBuilding = 0;                 // frames whose viewport showed "Building shaders..."
    std::vector<int> samplesPerFrame;
    std::vector<std::array<int, 4>> sizes;  // viewport: width, height, divisor, samples (report)
    double editTime = -1.0;
    bool editPending = false;
    // Mesh imports (import_mesh, wait_import): frames while an import was pending.
    std::vector<double> importFrameMs;      // every frame swapped while importing
    int importRenderingFrames = 0;          // of those, frames that rendered samples
    double waitImportSince = -1.0;          // wait_import, wait_open, wait_preview: when it started waiting
    // Opening a scene (open, wait_open): frames while its meshes imported.
    std::vector<double> openFrameMs;
    int openRenderingFrames = 0;

    void fail(EditorUi& ui, const ScriptLine& line, const std::string& why);
    std::string resolve(const std::string& path) const;   // relative to the script's folder
    // After an edit: the end of the first frame that shows it is timed (edit_to_frame_ms).
    void markEdit(const EditorUi& ui);
    // The first call for the current line (the waiting commands start their clock and counters).
    bool startLine();
    double secondsOnLine() const;
    // A wait on background work: done (the line is done) once `done`, or, failing the script,
    // after `timeout` seconds of waiting; else again next frame.
    bool waitFor(EditorUi& ui, const ScriptLine& line, bool done, double timeout, const char* what);
    // After each swapped frame (the measurements).
    void recordFrame(const EditorUi& ui, double frameSeconds);
    // The measurements as the `report` command writes them.
    std::string reportJson(const EditorUi& ui) const;
};

}  // namespace caustic::editor
