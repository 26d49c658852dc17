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

RenderStep RenderSession::step(Renderer& renderer, EditorState& state, double now, bool holdUpdates) {
    RenderStep out;
    const RenderSettings& rs = state.scene.render;
    const glm::ivec2 full = viewportResolution(state.scene);
    const long long fullPixels = static_cast<long long>(full.x) * full.y;
    // While something is dragged, shrink the image if one full sample would not fit the budget.
    // The path tracer gets what the rest of the frame leaves of it, less a margin for the spread
    // of both.
    const double budget = idle(now) ? kIdleBudget : std::clamp(kFrameTarget - overheadSeconds - 0.002, 0.004, kFrameTarget);
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
    // While interacting: the pacer's preview divisor (one sample of the whole image per frame).
    // After it: the image refines by halves, each step once the current one has a whole sample
    // (or at once when the renderer has nothing at this size yet).
    int divisor = previewDivisor;
    if (recentlyInteracting) divisor = std::max(previewDivisor, pacer.previewDivisor(fullPixels, budget));
    else if (previewDivisor > 1 && renderer.samplesDone() >= 1) divisor = previewDivisor / 2;
    divisor = std::max(1, divisor);
    const glm::ivec2 size = glm::max(full / divisor, glm::ivec2(1));
    if ((divisor != previewDivisor || size != renderedSize) && !holding) dirty |= kDirtySettings;
    if (hidden != m_appliedHidden && !holding) dirty |= kDirtyGeometry;   // objects left out or back
    if (dirty != kDirtyNone || !sceneUploaded) {
        Scene scene = hidden.empty() ? state.scene : withoutHidden(state.scene, hidden, &renderedObjects);
        if (hidden.empty()) renderedObjects.clear();
        m_appliedHidden = hidden;
        scene.render.width = size.x;
        scene.render.height = size.y;
        std::string error;
        const bool ok = sceneUploaded ? renderer.update(scene, dirty, &error) : renderer.setScene(scene, &error);
        ++accumulationGeneration;   // accumulation restarted: older denoised images are stale
        out.restarted = true;
        if (ok) {
            sceneUploaded = true;
            previewDivisor = divisor;
            renderedSize = size;
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
    out.targetReached = previewDivisor == 1 && renderedSize == glm::ivec2(rs.width, rs.height) &&
                        renderer.samplesDone() >= rs.samples;
    return out;
}

}  // namespace caustic::editor
