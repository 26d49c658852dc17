// What drives the editor's frame loop besides the person at the keyboard: the test-script harness
// (editor/script/script_runner.h) or nothing (this base class, which does nothing). The frame loop
// (editor_app.cpp) calls it at three points of every frame and asks it four questions; no other
// part of the editor knows whether a script runs.
#pragma once

namespace caustic::editor {

struct EditorUi;

class FrameDriver {
public:
    virtual ~FrameDriver() = default;
    // After the panels are built, before ImGui renders: a script runs its commands here.
    virtual void step(EditorUi&) {}
    // After the frame is drawn, before the swap (screenshots).
    virtual void afterDraw(EditorUi&, int /*framebufferWidth*/, int /*framebufferHeight*/) {}
    // After the swap, with the frame's wall-clock length.
    virtual void afterSwap(EditorUi&, double /*frameSeconds*/) {}

    // Whether the loop may sleep until input when nothing renders (a script never waits for it).
    virtual bool mayWaitForInput() const { return true; }
    // Whether the periodic autosave runs, and the autosave is removed at a clean exit (a script:
    // only after `autosave on`).
    virtual bool usesAutosave() const { return true; }
    // Whether an autosave left by a crash is offered for recovery at start-up (a script sees the
    // offer only with $CAUSTIC_EDITOR_HOME set: scriptMayUseAutosave).
    virtual bool offersRecovery() const { return true; }
    // True once when the recovery prompt's "Recover" should be pressed this frame (`recover`).
    virtual bool pressRecover() { return false; }
    // Whether the viewport renders at the scene's output resolution instead of the panel's size
    // (scripts do by default, so that what they write and measure is the batch image; `viewport
    // panel` turns it off).
    virtual bool wantsOutputSize() const { return false; }
    // The editor exits with status 1 when the driver failed (a script's check failed).
    virtual bool failed() const { return false; }
};

}  // namespace caustic::editor
