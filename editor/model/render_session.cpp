#include "editor/model/render_session.h"

#include "editor/model/modal_transform.h"

#include "renderer/renderer.h"

#include <algorithm>
#include <cmath>

namespace caustic::editor {

int RenderSession::target(const Scene& scene) const {
    return sampleCap ? std::min(scene.render.samples, *sampleCap) : scene.render.samples;
}

void RenderSession::setViewport(int width, int height, bool fit) {
    m_panelWidth = std::max(0, width);
    m_panelHeight = std::max(0, height);
    m_fit = fit;
}

glm::ivec2 RenderSession::viewportResolution(const Scene& scene) const {
    const int w = scene.render.width, h = scene.render.height;
    if (outputSize || !m_fit || m_panelWidth <= 0 || m_panelHeight <= 0) return {w, h};
    // The output's aspect fitted into the panel, at most 4096 on a side (a sample of a 4K viewport
    // is already a large dispatch on llvmpipe; the output resolution is for Render to file).
    const double scale = std::min({double(m_panelWidth) / w, double(m_panelHeight) / h, 4096.0 / std::max(w, h)});
    return {std::max(1, int(std::lround(w * scale))), std::max(1, int(std::lround(h * scale)))};
}

bool RenderSession::busy(const Renderer* renderer, const Scene& scene) const {
    return renderer && sceneUploaded && renderer->samplesDone() < target(scene);
}

void RenderSession::endFrame(double seconds) {
    frameSeconds = seconds;
    // Frames that rendered only: an idle frame includes waiting for events.
    if (renderedThisFrame) overheadSeconds = 0.8 * overheadSeconds + 0.2 * std::max(0.0, frameSeconds - renderSeconds);
}

float chooseViewportScale(double rate, double panelPixels, float current) {
    if (!(rate > 0.0) || !(panelPixels > 0.0)) return current;
    for (const float s : {1.0f, 0.5f, 0.25f}) {
        const double secondsPerSample = panelPixels * double(s) * double(s) / rate;
        const double goal = s > current ? 0.5 / kAutoScaleSpp : 1.0 / kAutoScaleSpp;   // up: twice the rate
        if (secondsPerSample <= goal || s == 0.25f) return s > current && secondsPerSample > goal ? current : s;
    }
    return current;
}

namespace {

class RendererSink final : public SceneSink {
public:
    explicit RendererSink(Renderer& r) : m_r(r) {}
    bool setScene(const Scene& scene, std::string* error) override { return m_r.setScene(scene, error); }
    bool update(const Scene& scene, std::uint32_t dirty, std::string* error) override {
        return m_r.update(scene, dirty, error);
    }
    int samplesDone() const override { return m_r.samplesDone(); }

private:
    Renderer& m_r;
};

}  // namespace

Scene RenderSession::viewportScene(const EditorState& state, glm::ivec2 size) {
    Scene scene = hidden.empty() ? state.scene : withoutHidden(state.scene, hidden, &renderedObjects);
    if (hidden.empty()) renderedObjects.clear();
    // The viewport's free view (EditorState::freeView); Render to file and scripts at the output
    // size render through the scene camera.
    if (state.freeView && !outputSize) scene.camera = *state.freeView;
    scene.render.width = size.x;
    scene.render.height = size.y;
    return scene;
}

RenderStep RenderSession::sync(SceneSink& sink, EditorState& state, double now, bool holdUpdates) {
    RenderStep out;
    const glm::ivec2 full = viewportResolution(state.scene);
    const long long fullPixels = static_cast<long long>(full.x) * full.y;
    // While something is dragged, shrink the image if one full sample would not fit the budget.
    // The path tracer gets what the rest of the frame leaves of it, less a margin for the spread
    // of both.
    const double budget = frameBudget(now);
    // Edits that change nothing on screen (the target samples, unused materials) restart nothing,
    // unless the renderer is behind the model: then any edit but the target may be what makes the
    // scene acceptable again (an unused material's texture cleared, say), and the renderer's
    // scene differs from the model's in more than the edit, so the whole scene goes.
    const std::uint32_t edits = state.takeDirty();
    std::uint32_t dirty = kDirtyNone;
    if (behind) {
        if ((edits & ~std::uint32_t(kDirtyTarget)) != 0) dirty = kDirtyAll;
        m_deferredDirty = kDirtyNone;
    } else {
        dirty = dirtyForRenderer(edits, &m_deferredDirty);
    }
    dirty |= std::exchange(heldDirty, kDirtyNone);
    // A mesh the scene uses changed on disk: it is imported again in the background, and the
    // scene's updates wait for it, since a compile now would import it here, freezing the window.
    const bool holding = sceneUploaded && holdUpdates;
    if (holding) {
        heldDirty = dirty;
        dirty = kDirtyNone;
    }
    // Any edit gets a quick first frame: it counts as interaction, so when one full-resolution
    // sample would not fit the frame budget, the first frames after it render at preview size.
    if (dirty != kDirtyNone && sceneUploaded) lastInteraction = now;
    const bool recentlyInteracting = interacting || (now - lastInteraction) < kInteractionHold;
    // While interacting: the pacer's preview divisor (one sample of the whole image per frame).
    // After it: the image refines by halves, each step once the current one has a whole sample
    // (or at once when the renderer has nothing at this size yet).
    int divisor = previewDivisor;
    if (recentlyInteracting) divisor = std::max(previewDivisor, pacer.previewDivisor(fullPixels, budget));
    else if (previewDivisor > 1 && sink.samplesDone() >= 1) divisor = previewDivisor / 2;
    divisor = std::max(1, divisor);
    const glm::ivec2 size = glm::max(full / divisor, glm::ivec2(1));
    if ((divisor != previewDivisor || size != renderedSize) && !holding) dirty |= kDirtySettings;
    if (hidden != m_appliedHidden && !holding) dirty |= kDirtyGeometry;   // objects left out or back
    // Through the free view or the scene camera (Render to file switches to the camera).
    if (const bool free = state.freeView && !outputSize; free != m_throughFreeView && !holding) {
        dirty |= kDirtyCamera;
        m_throughFreeView = free;
    }
    // A partial update of a renderer that is behind would pair the model's scene with compiled
    // parts of the last good one.
    if (behind && dirty != kDirtyNone) dirty = kDirtyAll;
    // A scene refused before any was accepted is tried again at the next edit, not every frame.
    if (dirty != kDirtyNone || (!sceneUploaded && !behind)) {
        const Scene scene = viewportScene(state, size);
        m_appliedHidden = hidden;
        std::string error;
        const bool ok = sceneUploaded ? sink.update(scene, dirty, &error) : sink.setScene(scene, &error);
        ++accumulationGeneration;   // accumulation restarted: older denoised images are stale
        out.restarted = true;
        if (ok) {
            sceneUploaded = true;
            behind = false;
            previewDivisor = divisor;
            renderedSize = size;
            renderError.clear();
            sampleRate.restart(now);
            out.compiled = true;
        } else {
            // The renderer keeps the last scene it could compile; the message stays on screen
            // until an edit makes the scene acceptable.
            behind = true;
            renderError = error;
            out.error = error;
        }
    }
    return out;
}

double RenderSession::frameBudget(double now) const {
    return idle(now) ? kIdleBudget : std::clamp(kFrameTarget - overheadSeconds - 0.002, 0.004, kFrameTarget);
}

RenderStep RenderSession::step(Renderer& renderer, EditorState& state, double now, bool holdUpdates) {
    RendererSink sink(renderer);
    RenderStep out = sync(sink, state, now, holdUpdates);
    const RenderSettings& rs = state.scene.render;
    const double budget = frameBudget(now);
    if (!sceneUploaded) return out;
    // The scene needs an integrator program not built yet (the editor defers builds to the first
    // dispatch: Renderer::setDeferredProgramBuilds). Built in the background (the editor's
    // ProgramBuilder), the dispatch asks for it and returns: the last image stays with "Building
    // shaders" over it until it is done (or the general program renders meanwhile). Built on this
    // thread, the build blocks it for seconds on llvmpipe, so first a whole frame is drawn with
    // the words over the last image (the frame that found it had drawn its UI already), and the
    // one after it builds.
    if (out.restarted || buildingShaders) {
        if (!renderer.programPending()) {
            buildingShaders = false;
        } else if (!buildingShaders) {
            buildingShaders = true;
            m_buildWait = renderer.buildsInBackground() ? 0 : 2;
        }
        if (buildingShaders && m_buildWait > 0) {
            --m_buildWait;
            return out;
        }
    }
    const int width = renderedSize.x, height = renderedSize.y;
    const int goal = target(state.scene);
    const int done = renderer.samplesDone();
    samplesThisFrame = 0;
    renderedThisFrame = false;
    if (done < goal) {
        // Whole samples while one fits the frame's budget, else a band of rows of the next one
        // (Renderer::renderFor), so the frame rate holds at full resolution however slow the GPU.
        const long long pixels = static_cast<long long>(width) * height;
        const Renderer::Progress p = renderer.renderFor(budget, goal - done);
        if (p.pixelSamples == 0 && renderer.waitingForBuild()) {
            buildingShaders = true;   // nothing renders until it is built: the last image stays
            return out;
        }
        pacer.record(1, p.pixelSamples, p.seconds);
        renderSeconds = p.seconds;
        samplesThisFrame = p.samplesCompleted;
        renderedThisFrame = p.pixelSamples > 0;
        const double rate = double(p.pixelSamples) / double(pixels) / std::max(p.seconds, 1e-6);
        samplesPerSecond = samplesPerSecond == 0.0 ? rate : 0.8 * samplesPerSecond + 0.2 * rate;
    } else {
        renderSeconds = 0.0;
    }
    // The automatic scale, from the rate measured at full size (not while dragging: the preview
    // divisor's rate is another size's).
    if (autoScaleUsed && previewDivisor == 1 && !interacting && now - lastInteraction > kInteractionHold &&
        renderer.samplesDone() >= 2 && samplesPerSecond > 0.0 && m_panelWidth > 0 && m_panelHeight > 0) {
        const double rate = samplesPerSecond * double(renderedSize.x) * double(renderedSize.y);
        const double panel = double(m_panelWidth) * double(m_panelHeight) / (double(autoScale) * double(autoScale));
        autoScale = chooseViewportScale(rate, panel, autoScale);
    }
    sampleRate.observe(now, renderer.samplesDone() + (renderer.bandInProgress() ? renderer.bandProgress() : 0.0),
                       renderedThisFrame);
    if (now - m_lastCounterRead > 0.5 || samplesThisFrame == 0) {
        droppedSamples = renderer.droppedSamples();
        m_lastCounterRead = now;
    }
    // While the first sample after a restart is still being rendered tile by tile (leaving the
    // preview for full resolution, say), the viewport keeps the last whole image instead of a
    // partly black one; the very first image of a scene shows its tiles as they come.
    const bool firstSampleInTiles = renderer.samplesDone() == 0 && renderer.bandInProgress();
    const bool wholeImageShown = m_displayedWholeImageOf && *m_displayedWholeImageOf == state.generation();
    if (!(firstSampleInTiles && wholeImageShown)) {
        out.show = true;
        out.width = width;
        out.height = height;
        if (!firstSampleInTiles) m_displayedWholeImageOf = state.generation();
    }
    // The last good scene's image is not the model's: Render to file waits for the model's.
    // A stand-in renders while a program builds in the background: nothing to announce.
    if (buildingShaders && (!renderer.programPending() || renderedThisFrame)) buildingShaders = false;
    // No integrator builds (deferred builds report it at the dispatch, not in setScene): the
    // viewport says so, as for a refused scene, until a dispatch renders again.
    if (const std::string& why = renderer.programError(); !why.empty()) {
        if (renderError != why) out.error = why;
        renderError = why;
        behind = true;
        m_programFailed = true;
    } else if (m_programFailed && renderedThisFrame) {
        m_programFailed = false;
        behind = false;
        renderError.clear();
        out.compiled = true;
    }
    out.targetReached = !behind && previewDivisor == 1 && renderedSize == glm::ivec2(rs.width, rs.height) &&
                        renderer.samplesDone() >= rs.samples;
    return out;
}

}  // namespace caustic::editor
