#include "editor/ui/viewport_denoise.h"

#include "editor/ui/editor_ui.h"
#include "renderer/denoise.h"

#include <glad/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdio>

namespace caustic::editor {

namespace {
constexpr int kIdleDenoiseFirst = 4;   // the first idle denoise waits for this many samples
}

ViewportDenoiser::ViewportDenoiser()
    : m_worker([](const Film& film, const DenoiseOptions& options, DenoiseResult* out, std::string* error) {
          return denoise(film, options, out, error);
      }) {}

ViewportDenoiser::~ViewportDenoiser() {
    if (m_texture) glDeleteTextures(1, &m_texture);
}

bool ViewportDenoiser::request(EditorUi& ui, bool hold, std::string* why, bool progressive) {
    if (!denoiserAvailable()) {
        *why = "Open Image Denoise is not in this build: " + denoiserVersion();
        return false;
    }
    if (!ui.app.renderer || !ui.app.session.sceneUploaded) {
        *why = "nothing rendered yet";
        return false;
    }
    const int done = ui.app.renderer->samplesDone();
    if (done <= 0) {
        *why = "no samples yet";
        return false;
    }
    // The same image is already being denoised: nothing to add.
    if (m_lastRequest == std::make_pair(ui.app.session.accumulationGeneration, done) && m_worker.busy()) return true;
    // Stop accumulating here so that the result is still current when it arrives.
    if (hold && done < ui.app.state.scene.render.samples && (!ui.app.session.sampleCap || *ui.app.session.sampleCap > done)) {
        ui.app.session.sampleCap = done;
        m_hold = std::make_pair(ui.app.session.accumulationGeneration, done);
    }
    DenoiseJob job;
    job.generation = ui.app.session.accumulationGeneration;
    job.samples = done;
    job.progressive = progressive;
    job.film = ui.app.renderer->readFilm();   // GL: on this thread; the worker gets its own copy
    job.options.prefilterGuides = settings.prefilterGuides;
    m_worker.request(std::move(job));
    m_lastRequest = std::make_pair(ui.app.session.accumulationGeneration, done);
    return true;
}

void ViewportDenoiser::resume(EditorUi& ui) {
    if (m_hold && ui.app.session.sampleCap && *ui.app.session.sampleCap == m_hold->second) ui.app.session.sampleCap.reset();
    m_hold.reset();
}

void ViewportDenoiser::upload(const DenoiseOutput& out) {
    if (!m_texture || out.width != m_texWidth || out.height != m_texHeight) {
        if (m_texture) glDeleteTextures(1, &m_texture);
        glCreateTextures(GL_TEXTURE_2D, 1, &m_texture);
        glTextureStorage2D(m_texture, 1, GL_RGBA32F, out.width, out.height);
        glTextureParameteri(m_texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(m_texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        m_texWidth = out.width;
        m_texHeight = out.height;
    }
    // The accumulation layout (rgb = sum, a = count) with a count of one: the display pass
    // divides by it and tone maps exactly as it does the live image.
    std::vector<float> rgba(out.image.size() * 4);
    for (size_t i = 0; i < out.image.size(); ++i) {
        rgba[i * 4 + 0] = out.image[i].x;
        rgba[i * 4 + 1] = out.image[i].y;
        rgba[i * 4 + 2] = out.image[i].z;
        rgba[i * 4 + 3] = 1.0f;
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(m_texture, 0, 0, 0, out.width, out.height, GL_RGBA, GL_FLOAT, rgba.data());
}

void ViewportDenoiser::tick(EditorUi& ui) {
    const std::uint64_t generation = ui.app.session.accumulationGeneration;
    // An edit restarted accumulation: a waiting job and a kept result are of no use any more,
    // and a hold placed for the old image is lifted.
    m_worker.dropOlderThan(generation);
    if (m_result && m_result->generation != generation) m_result.reset();
    if (m_hold && m_hold->first != generation) resume(ui);

    if (std::optional<DenoiseOutput> out = m_worker.take()) {
        if (!out->ok) {
            ++m_failures;
            m_lastError = out->error;
            notify(ui, "denoise failed: " + out->error, true);
        } else if (out->generation == generation) {
            upload(*out);
            m_result = std::move(out);
        }
        // else: the image was restarted while the denoiser ran; never shown.
    }

    // Automatic: once the full-resolution image reaches its target sample count.
    if (settings.autoDenoise && ui.app.renderer && ui.app.session.sceneUploaded && ui.app.session.previewDivisor == 1 && !ui.app.session.interacting &&
        ui.app.state.pendingDirty() == kDirtyNone && denoiserAvailable()) {
        int target = ui.app.state.scene.render.samples;
        if (ui.app.session.sampleCap && !m_hold) target = std::min(target, *ui.app.session.sampleCap);
        const int done = ui.app.renderer->samplesDone();
        const auto key = std::make_pair(generation, done);
        if (done > 0 && done >= target && m_lastRequest != key) {
            std::string why;
            request(ui, false, &why);
        }
    }

    // When idle: at 4 spp, at each doubling of the image's samples and at its target (progressive
    // results stay shown while the render goes on). Scripts never idle unless they ask (`idle on`).
    if (settings.idleDenoise && ui.app.renderer && ui.app.session.sceneUploaded && ui.app.session.previewDivisor == 1 &&
        ui.app.session.idle(glfwGetTime()) && !m_worker.busy() && !m_hold && denoiserAvailable()) {
        const int done = ui.app.renderer->samplesDone();
        const int last = m_result && m_result->generation == generation ? m_result->samples : 0;
        const auto key = std::make_pair(generation, done);
        const int target = ui.app.session.target(ui.app.state.scene);
        if (done >= kIdleDenoiseFirst && (done >= 2 * last || (done >= target && done != last)) && m_lastRequest != key) {
            std::string why;
            request(ui, false, &why, true);
        }
    }

    if (shown(ui) && ui.app.display)
        ui.app.display->update(m_texture, m_result->width, m_result->height, ui.app.state.view.toneMap, ui.app.state.view.exposure);
}

bool ViewportDenoiser::current(const EditorUi& ui) const {
    return m_result && m_texture && ui.app.renderer && ui.app.session.sceneUploaded && m_result->generation == ui.app.session.accumulationGeneration &&
           (m_result->samples == ui.app.renderer->samplesDone() || (m_result->progressive && settings.idleDenoise));
}

bool ViewportDenoiser::shown(const EditorUi& ui) const { return settings.showDenoised && current(ui); }

Film ViewportDenoiser::shownFilm() const {
    Film film;
    if (!m_result) return film;
    film.width = m_result->width;
    film.height = m_result->height;
    film.mean = m_result->image;
    film.count.assign(film.mean.size(), static_cast<float>(m_result->samples));
    return film;
}

std::string ViewportDenoiser::status(const EditorUi& ui) const {
    char text[256];
    if (shown(ui)) {
        std::snprintf(text, sizeof text, "denoised (%d spp%s, %.0f ms, %s)", m_result->samples,
                      m_result->progressive ? " when idle" : "", m_result->seconds * 1e3, m_result->device.c_str());
        return text;
    }
    if (busy()) return holding() ? "denoising (render paused) ..." : "denoising ...";
    if (current(ui)) return "raw (denoised available)";
    if (holding()) return "render paused";
    return "";
}

}  // namespace caustic::editor
