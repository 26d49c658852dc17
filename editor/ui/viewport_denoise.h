// Viewport denoising with Open Image Denoise, off the UI thread. The UI thread reads the film
// (GL) and hands it to a DenoiseWorker (editor/model/denoise_worker.h); the result comes back
// on a later frame, is uploaded as an RGBA32F texture (rgb = denoised radiance, a = 1: the
// accumulation layout with one "sample") and tone mapped by the same Display pass as the live
// image. It is shown only while it is current: the same accumulation generation (no edit since)
// and the same sample count (nothing rendered since); a result of Denoise when idle only needs
// the same generation (it shows while the render goes on, replaced at each doubling and at the
// target). Settings are view state, not saved.
#pragma once

#include "editor/model/denoise_worker.h"
#include "renderer/film.h"

#include <cstdint>
#include <optional>
#include <string>

namespace caustic::editor {

struct EditorUi;

struct DenoiseSettings {
    bool autoDenoise = false;      // denoise when accumulation reaches the target samples
    // Denoise when idle (as Blender's viewport does): a second after the last input, at 4 spp, at
    // each doubling after it and at the target; that image is shown while the render goes on
    // (until an edit).
    // The editor turns it off on llvmpipe, where OIDN and the path tracer share the CPU.
    bool idleDenoise = true;
    bool showDenoised = true;      // false: show the raw render even when a denoised one is current
    bool prefilterGuides = true;   // OIDN's cleanAux path (renderer/denoise.h)
};

class ViewportDenoiser {
public:
    ViewportDenoiser();
    ~ViewportDenoiser();   // deletes the texture (the GL context must be current); joins the worker
    ViewportDenoiser(const ViewportDenoiser&) = delete;
    ViewportDenoiser& operator=(const ViewportDenoiser&) = delete;

    DenoiseSettings settings;

    // "Denoise now": reads the film and queues it. hold: also stop accumulating at the current
    // sample count (if the render is still converging) so the result stays current; any edit
    // or resume() lifts the hold. False with *why when there is nothing to denoise.
    bool request(EditorUi& ui, bool hold, std::string* why, bool progressive = false);
    void resume(EditorUi& ui);
    bool holding() const { return m_hold.has_value(); }

    // Once a frame on the UI thread, after the renderer's frame: collects a finished result
    // (uploads it, or drops it if the image changed since), triggers the automatic denoise,
    // and puts the denoised image on the display when it is shown.
    void tick(EditorUi& ui);

    bool current(const EditorUi& ui) const;   // a result for the image exactly as it is now
    bool shown(const EditorUi& ui) const;     // current and not switched to the raw render
    bool busy() const { return m_worker.busy(); }
    // The shown image as a Film (mean = denoised radiance), for write_image.
    Film shownFilm() const;
    // "denoised (N spp, X ms, device)", "denoising ...", or "" for the status bar.
    std::string status(const EditorUi& ui) const;
    std::uint64_t failures() const { return m_failures; }
    const std::string& lastError() const { return m_lastError; }

private:
    void upload(const DenoiseOutput& out);

    DenoiseWorker m_worker;
    std::optional<DenoiseOutput> m_result;   // the latest good result (its image kept for files)
    unsigned m_texture = 0;
    int m_texWidth = 0, m_texHeight = 0;
    std::optional<std::pair<std::uint64_t, int>> m_lastRequest;   // (generation, samples)
    std::optional<std::pair<std::uint64_t, int>> m_hold;          // (generation, samples) held at
    std::uint64_t m_failures = 0;
    std::string m_lastError;
};

}  // namespace caustic::editor
