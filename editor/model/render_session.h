// The editor's render session: what the viewport's path tracer is doing and what it does next,
// with no window and no ImGui (editor/ui/editor_app.cpp calls step() once a frame and shows what it
// says). It decides when a scene edit goes to the renderer (and restarts accumulation), at which
// preview resolution while the user drags (FramePacer), how many samples fit this frame's budget
// (whole samples, or a band of rows of one: Renderer::renderFor), and keeps the figures the status
// bar and the scripts read. A GPU test (tests/gpu/test_render_session.cpp) drives it headless.
//
// The viewport renders at its own size: the output frame's aspect fitted into the panel's pixels
// (setViewport), so a 256 x 256 scene is not stretched over a 900-pixel panel; the scene's output
// resolution still decides what Render to file and batch mode produce (outputSize: the session
// renders at it while one waits). After an edit the image refines in steps, 1/8 -> 1/4 -> 1/2 -> 1
// of that size, each shown as soon as it has one whole sample, never freezing on the coarsest.
#pragma once

#include "editor/model/editor_state.h"
#include "editor/model/frame_pacer.h"
#include "editor/model/status.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace caustic {
class Renderer;
}

namespace caustic::editor {

// The UI must keep at least 30 frames per second; the path tracer gets what the rest of a frame
// (UI, display, swap; measured) leaves of that.
inline constexpr double kFrameTarget = 1.0 / 30.0;
// Preview resolution lasts this long after a drag (or any edit).
inline constexpr double kInteractionHold = 0.25;
// When nobody has touched the editor for kIdleAfter seconds, a frame gives the path tracer
// kIdleBudget instead of what is left of 1/30 s: the UI then redraws about 4 times a second and
// the render gets most of the machine (on llvmpipe the UI, display and swap take 26-40 ms of
// every frame); the first input after that waits at most one such frame.
inline constexpr double kIdleAfter = 1.0;
inline constexpr double kIdleBudget = 0.25;

// What one step did, for the UI to show.
struct RenderStep {
    bool restarted = false;     // the scene went to the renderer (accumulation restarted)
    bool compiled = false;      // ... and compiled (a shown render error may be cleared)
    std::string error;          // ... and failed: the renderer keeps its last good scene
    bool show = false;          // the accumulation should be displayed, at width x height
    int width = 0, height = 0;
    bool targetReached = false; // full resolution with all its target samples (Render to file)
};

// Where the session sends the scene: the renderer (step) or, in the model's tests, a stand-in that
// compiles on the CPU only (tests/editor/test_scene_sync.cpp). Both keep the last scene they
// accepted when they refuse one.
class SceneSink {
public:
    virtual ~SceneSink() = default;
    virtual bool setScene(const Scene& scene, std::string* error) = 0;
    virtual bool update(const Scene& scene, std::uint32_t dirty, std::string* error) = 0;
    virtual int samplesDone() const = 0;
};

// The automatic viewport scale (View > Viewport resolution > Automatic): the largest of 1, 1/2 and
// 1/4 of the panel's pixels at which the path tracer, at its measured rate (pixel samples per
// second of its time), renders kAutoScaleSpp samples per second, so an image is clean enough to
// judge within a second on any machine; 1/4 at the least. Going up needs twice the rate
// (hysteresis: a rate measured at one size must not flip the next).
inline constexpr double kAutoScaleSpp = 4.0;
float chooseViewportScale(double pixelSamplesPerSecond, double panelPixels, float current);

class RenderSession {
public:
    // Sends pending edits of `state` (takeDirty) to `renderer` and renders this frame's samples.
    // `now`: seconds on the frame loop's clock. `holdUpdates`: scene updates wait (meshes are
    // being imported again in the background); the renderer keeps rendering what it has.
    RenderStep step(Renderer& renderer, EditorState& state, double now, bool holdUpdates);
    // The first half of step: pending edits to `sink` (no samples rendered).
    RenderStep sync(SceneSink& sink, EditorState& state, double now, bool holdUpdates);
    // The scene the renderer gets for the model's: the viewport's size and divisor, hidden objects
    // left out.
    Scene viewportScene(const EditorState& state, glm::ivec2 size);
    // After the frame is shown: its wall-clock length, for the overhead estimate.
    void endFrame(double frameSeconds);
    // The panel's size in pixels that the image is drawn into (0 x 0: the output resolution), and
    // whether the viewport follows it ("fit"; else it renders at the output resolution, 1:1).
    void setViewport(int width, int height, bool fit);
    // Render at the scene's output resolution regardless of the panel (Render to file, scripts).
    bool outputSize = false;
    // The full-resolution size the viewport renders at now (before the preview divisor).
    glm::ivec2 viewportResolution(const Scene& scene) const;

    // The last user input (mouse, keys) at `now`; idle pacing starts kIdleAfter seconds later.
    // `allowed`: whether idle pacing may start at all (scripts measure frames: they never idle).
    void noteInput(double now) { m_lastInput = now; }
    bool idlePacing = true;
    bool idle(double now) const { return idlePacing && !interacting && now - m_lastInput > kIdleAfter; }

    // Something is being dragged this frame (preview resolution), at `now`.
    void noteInteraction(double now) {
        interacting = true;
        lastInteraction = now;
    }

    // The target the session renders to: the scene's samples, or a script's cap below it.
    int target(const Scene& scene) const;
    // Samples still to render at the current settings.
    bool busy(const Renderer* renderer, const Scene& scene) const;

    // State the UI reads (and the scripts wait on).
    FramePacer pacer;
    int previewDivisor = 1;           // 1 = full resolution
    bool sceneUploaded = false;
    glm::ivec2 renderedSize{0, 0};    // the size the renderer renders at (viewport size / divisor)
    std::optional<int> sampleCap;     // scripts stop at an exact sample count
    std::string renderError;          // the renderer's last failure (scene compile, shader reload)
    // The renderer refused the model's scene and renders the last one it accepted, if any
    // (renderError says why): the viewport says so, every later edit is tried on the whole scene
    // until one is accepted, and Save warns. Never true when the renderer has the model's scene.
    bool behind = false;
    // An integrator program is about to be built (the viewport says "Building shaders"): the
    // frames until the build show the last image.
    bool buildingShaders = false;
    double samplesPerSecond = 0.0;    // per second of path-tracer time (the status bar's tooltip)
    // The automatic viewport scale (chooseViewportScale), updated from samplesPerSecond once the
    // full-size image has 2 samples with nothing being dragged; the panel applies it when the
    // view's scale is automatic.
    float autoScale = 1.0f;
    bool autoScaleUsed = false;       // the panel follows autoScale (set by the panel)
    SampleRateMeter sampleRate;       // per second of elapsed time since the restart (the status bar)
    std::uint64_t droppedSamples = 0;
    double frameSeconds = 0.0, uiSeconds = 0.004, renderSeconds = 0.0;
    // Where the last frame's time went (the frame loop measures it; the scripts' report gives the
    // medians): building the UI (ImGui), the render step (scene updates, path tracing, the display
    // pass, the denoiser's tick), the material and bokeh previews, drawing the UI and the swap.
    struct FramePhases {
        double ui = 0.0, render = 0.0, previews = 0.0, drawSwap = 0.0;
    } phases;
    double overheadSeconds = 0.01;    // a rendering frame's time outside the path tracer (smoothed)
    int samplesThisFrame = 0;         // whole samples finished this frame
    bool renderedThisFrame = false;   // any pixels rendered this frame (a band counts)
    bool interacting = false;         // something is being dragged this frame
    double lastInteraction = -1.0;
    // Bumped whenever accumulation restarts (every scene upload or update): a denoised image is
    // shown only for the generation it was read from.
    std::uint64_t accumulationGeneration = 0;
    std::uint32_t heldDirty = 0;      // scene updates waiting for meshes to import again
    // Objects hidden in the viewport (the Blender key map's H), by name: left out of what the
    // renderer gets (modal_transform.h withoutHidden); a change recompiles. renderedObjects[i] is
    // the scene's index of the renderer's object i (empty: the same indices), for picking.
    std::vector<std::string> hidden;
    std::vector<int> renderedObjects;

private:
    // The path tracer's share of this frame (seconds).
    double frameBudget(double now) const;

    int m_panelWidth = 0, m_panelHeight = 0;
    double m_lastInput = 0.0;
    bool m_fit = true;
    double m_lastCounterRead = 0.0;
    // The scene (EditorState::generation) of which the viewport shows a whole image, if any.
    std::optional<std::uint64_t> m_displayedWholeImageOf;
    std::vector<std::string> m_appliedHidden;
    std::uint32_t m_deferredDirty = 0;   // unseen material edits, handed over with the next real update
    int m_buildWait = 0;   // frames still to draw before the program build
    bool m_throughFreeView = false;   // the renderer's camera is the free view
    bool m_programFailed = false;     // renderError is the renderer's programError
};

}  // namespace caustic::editor
