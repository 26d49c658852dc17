#include "editor/model/render_session.h"

#include "renderer/renderer.h"

#include <algorithm>

namespace caustic::editor {

int RenderSession::target(const Scene& scene) const {
    return sampleCap ? std::min(scene.render.samples, *sampleCap) : scene.render.samples;
}

bool RenderSession::busy(const Renderer* renderer, const Scene& scene) const {
    return renderer && sceneUploaded && renderer->samplesDone() < target(scene);
}

void RenderSession::endFrame(double seconds) {
    frameSeconds = seconds;
    // Frames that rendered only: an idle frame includes waiting for events.
    if (renderedThisFrame) overheadSeconds = 0.8 * overheadSeconds + 0.2 * std::max(0.0, frameSeconds - renderSeconds);
}

RenderStep RenderSession::step(Renderer& renderer, EditorState& state, double now, bool holdUpdates) {
    RenderStep out;
    const RenderSettings& rs = state.scene.render;
    const long long fullPixels = static_cast<long long>(rs.width) * rs.height;
    // While something is dragged, shrink the image if one full sample would not fit the budget.
    // The path tracer gets what the rest of the frame leaves of it, less a margin for the spread
    // of both.
    const double budget = std::clamp(kFrameTarget - overheadSeconds - 0.002, 0.004, kFrameTarget);
    // Edits that change nothing on screen (the target samples, unused materials) restart nothing.
    std::uint32_t dirty = dirtyForRenderer(state.takeDirty(), &m_deferredDirty) | std::exchange(heldDirty, kDirtyNone);
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
    const int divisor = recentlyInteracting ? std::max(previewDivisor, pacer.previewDivisor(fullPixels, budget)) : 1;
    if (divisor != previewDivisor && !holding) dirty |= kDirtySettings;
    if (dirty != kDirtyNone || !sceneUploaded) {
        Scene scene = state.scene;
        scene.render.width = std::max(1, rs.width / divisor);
        scene.render.height = std::max(1, rs.height / divisor);
        std::string error;
        const bool ok = sceneUploaded ? renderer.update(scene, dirty, &error) : renderer.setScene(scene, &error);
        ++accumulationGeneration;   // accumulation restarted: older denoised images are stale
        out.restarted = true;
        if (ok) {
            sceneUploaded = true;
            previewDivisor = divisor;
            renderError.clear();
            sampleRate.restart(now);
            out.compiled = true;
        } else {
            // The renderer keeps the last scene it could compile; the message stays on screen.
            renderError = error;
            out.error = error;
        }
    }
    if (!sceneUploaded) return out;
    const int width = std::max(1, rs.width / previewDivisor), height = std::max(1, rs.height / previewDivisor);
    const int goal = target(state.scene);
    const int done = renderer.samplesDone();
    samplesThisFrame = 0;
    renderedThisFrame = false;
    if (done < goal) {
        // Whole samples while one fits the frame's budget, else a band of rows of the next one
        // (Renderer::renderFor), so the frame rate holds at full resolution however slow the GPU.
        const long long pixels = static_cast<long long>(width) * height;
        const Renderer::Progress p = renderer.renderFor(budget, goal - done);
        pacer.record(1, p.pixelSamples, p.seconds);
        renderSeconds = p.seconds;
        samplesThisFrame = p.samplesCompleted;
        renderedThisFrame = p.pixelSamples > 0;
        const double rate = double(p.pixelSamples) / double(pixels) / std::max(p.seconds, 1e-6);
        samplesPerSecond = samplesPerSecond == 0.0 ? rate : 0.8 * samplesPerSecond + 0.2 * rate;
    } else {
        renderSeconds = 0.0;
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
    out.targetReached = previewDivisor == 1 && renderer.samplesDone() >= rs.samples;
    return out;
}

}  // namespace caustic::editor
