// Replays an editor script (editor/model/script.h) inside the running editor, one step per
// frame, through the same actions as the mouse and keyboard; records frame times and the time
// from each edit to the first frame that shows it (the `report` command writes them as JSON).
#pragma once

#include "editor/model/script.h"
#include "editor/ui/frame_driver.h"

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace caustic::editor {

struct EditorUi;

class ScriptRunner : public FrameDriver {
public:
    bool load(const std::string& file, std::string* error);
    void step(EditorUi& ui) override;                       // during the UI frame, before ImGui::Render
    void afterDraw(EditorUi& ui, int fbWidth, int fbHeight) override;   // the frame is drawn, not swapped
    void afterSwap(EditorUi& ui, double frameSeconds) override;
    bool mayWaitForInput() const override { return m_idle; }   // `idle on` (benchmarks)
    bool usesAutosave() const override { return m_autosave; }
    bool offersRecovery() const override;
    bool pressRecover() override { return std::exchange(m_pressRecover, false); }
    bool wantsOutputSize() const override { return m_outputSize; }
    bool failed() const override { return m_failed; }

private:
    bool run(EditorUi& ui, const ScriptLine& line);   // false: wait, call again next frame
    bool runDenoiseOrAutosave(EditorUi& ui, const ScriptLine& line, bool* finished);
    void fail(EditorUi& ui, const ScriptLine& line, const std::string& why);
    bool waitFor(EditorUi& ui, const ScriptLine& line, bool done, double timeout, const char* what);
    std::string resolve(const std::string& path) const;   // relative to the script's folder

    std::string m_file, m_dir;
    std::vector<ScriptLine> m_lines;
    size_t m_next = 0;
    bool m_failed = false;
    bool m_idle = false;            // `idle on`: the idle pacing of a session nobody touches
    bool m_autosave = false;        // `autosave on` (needs $CAUSTIC_EDITOR_HOME)
    bool m_outputSize = true;       // `viewport output` (the default) or `viewport panel`
    bool m_pressRecover = false;    // `recover`: the prompt's "Recover" button takes it next frame
    int m_waitFrames = 0;
    int m_previewMissing = 0;
    size_t m_previewLine = static_cast<size_t>(-1);   // wait_preview: the line that has waited a frame       // wait_preview: frames without a material in the inspector
    int m_dragStepsLeft = 0;
    std::uint64_t m_markedGeneration = 0;     // `mark`: accumulation's generation then (expect_restarted)
    bool m_renderStarted = false;
    float m_drag[3] = {0, 0, 0};
    std::string m_screenshotPending;
    // Waiting commands (denoise, wait_denoised, wait_autosave, recover): when the current line
    // started, and what it has done so far.
    size_t m_lineStarted = static_cast<size_t>(-1);
    double m_lineStartTime = 0.0;
    std::uint64_t m_countAtStart = 0;
    bool m_pressed = false;
    std::pair<std::uint64_t, int> m_denoiseKey{0, 0};

    // Measurements.
    std::vector<double> m_frameMs;            // frames that rendered samples
    std::vector<double> m_allFrameMs;
    std::vector<double> m_overheadMs;         // rendering frames: all but the path tracing
    std::vector<double> m_editLatencyMs;      // edit -> end of the first frame showing it
    std::vector<int> m_samplesPerFrame;
    std::vector<std::array<int, 4>> m_sizes;   // viewport: width, height, divisor, samples (report)
    double m_editTime = -1.0;
    bool m_editPending = false;
    // Mesh imports (import_mesh, wait_import): frames while an import was pending.
    std::vector<double> m_importFrameMs;      // every frame swapped while importing
    int m_importRenderingFrames = 0;          // of those, frames that rendered samples
    double m_waitImportSince = -1.0;          // wait_import, wait_open: when it started waiting
    // Opening a scene (open, wait_open): frames while its meshes imported.
    std::vector<double> m_openFrameMs;
    int m_openRenderingFrames = 0;
};

}  // namespace caustic::editor
