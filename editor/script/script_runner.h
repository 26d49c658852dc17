// Replays an editor script (script.h) inside the running editor, one step per frame, through the
// same actions as the mouse and keyboard: each line's command (script_commands.h) runs until it is
// done; records frame times and the time from each edit to the first frame that shows it (the
// `report` command writes them as JSON).
#pragma once

#include "editor/script/script_run.h"
#include "editor/ui/frame_driver.h"

#include <string>
#include <utility>

namespace caustic::editor {

struct EditorUi;

class ScriptRunner : public FrameDriver {
public:
    bool load(const std::string& file, std::string* error);
    void step(EditorUi& ui) override;                       // during the UI frame, before ImGui::Render
    void afterDraw(EditorUi& ui, int fbWidth, int fbHeight) override;   // the frame is drawn, not swapped
    void afterSwap(EditorUi& ui, double frameSeconds) override;
    bool mayWaitForInput() const override { return m_run.idle; }   // `idle on` (benchmarks)
    bool usesAutosave() const override { return m_run.autosave; }
    bool offersRecovery() const override;
    bool pressRecover() override { return std::exchange(m_run.pressRecover, false); }
    bool wantsOutputSize() const override { return m_run.outputSize; }
    bool failed() const override { return m_run.failed; }

private:
    ScriptRun m_run;
};

}  // namespace caustic::editor
