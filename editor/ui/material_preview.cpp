#include "editor/ui/material_preview.h"

#include "editor/ui/editor_ui.h"
#include "renderer/image_io.h"
#include "renderer/tonemap.h"

#include <utility>

namespace caustic::editor {

MaterialPreview::MaterialPreview() = default;
MaterialPreview::~MaterialPreview() = default;

void MaterialPreview::request(const Scene& edited, const Material& material) {
    m_wanted = makePreviewScene(edited, material, lighting, kSize, kSamples);
    m_requested = true;
}

void MaterialPreview::requestScene(Scene scene) {
    m_wanted = std::move(scene);
    m_requested = true;
}

unsigned MaterialPreview::texture() const { return m_display && m_shown ? m_display->texture() : 0u; }

int MaterialPreview::samples() const { return m_renderer && m_shown ? m_renderer->samplesDone() : 0; }

bool MaterialPreview::current() const {
    return m_shown && m_wanted && *m_shown == *m_wanted && m_shown->sourcePath == m_wanted->sourcePath && m_error.empty();
}

namespace {

// What differs between two preview scenes, as the renderer's dirty flags: the ball's material
// (a slider) re-uploads the material table only; the environment its own; anything else all.
std::uint32_t previewDirty(const Scene& a, const Scene& b) {
    if (a.objects != b.objects || a.lights != b.lights || !(a.camera == b.camera) || !(a.render == b.render) ||
        a.sourcePath != b.sourcePath)
        return kDirtyAll;
    std::uint32_t d = kDirtyNone;
    if (a.materials != b.materials) d |= kDirtyMaterials;
    if (!(a.environment == b.environment)) d |= kDirtyEnvironment;
    return d;
}

}  // namespace

void MaterialPreview::tick(EditorUi& ui) {
    const bool requested = std::exchange(m_requested, false);
    m_shownLastFrame = requested;
    if (!requested || !m_wanted || m_createFailed) return;
    std::string error;
    if (!m_renderer) {
        m_renderer = Renderer::create(ui.app.shaderDir, ui.app.integratorConfig, &error);
        if (m_renderer) m_display = Display::create(ui.app.shaderDir, &error);
        if (!m_renderer || !m_display) {
            m_createFailed = true;
            m_error = "the preview could not start: " + error;
            m_renderer.reset();
            return;
        }
        m_renderer->setImageReader(readImage);
        m_renderer->setDeferredProgramBuilds(true);
        m_renderer->setProgramBuilder(ui.app.programBuilder);
    }
    auto same = [](const Scene& x, const Scene& y) { return x == y && x.sourcePath == y.sourcePath; };
    const bool failedBefore = m_failedFor && same(*m_failedFor, *m_wanted);
    if ((!m_shown || !same(*m_shown, *m_wanted)) && !failedBefore) {
        const bool ok = m_shown ? m_renderer->update(*m_wanted, previewDirty(*m_shown, *m_wanted), &error)
                                : m_renderer->setScene(*m_wanted, &error);
        // A scene the renderer refuses (a texture that cannot be read) keeps the last image, with
        // the reason; it is not tried again until the material changes again.
        if (ok) {
            m_shown = *m_wanted;
            m_error.clear();
            m_failedFor.reset();
        } else {
            m_error = error;
            m_failedFor = *m_wanted;
        }
    }
    if (!m_shown) return;
    // A program to build: the last image stays while "Building shaders" shows (as the viewport
    // does: render_session.h). Built in the background, the renderer asks for it and renders
    // nothing until it is done; built here, a frame shows the words first, then this tick builds.
    if (m_renderer->programPending()) {
        if (m_buildWait < 0) m_buildWait = m_renderer->buildsInBackground() ? 0 : 2;
        if (m_buildWait > 0) {
            --m_buildWait;
            return;
        }
    }
    const int target = m_shown->render.samples;
    if (m_renderer->samplesDone() < target) m_renderer->renderFor(kBudgetSeconds, target - m_renderer->samplesDone());
    m_buildWait = m_renderer->programPending() ? 0 : -1;
    // While a slider drags, every step restarts the ball: until its first whole sample the last
    // image stays (it used to go black).
    if (m_renderer->samplesDone() == 0) return;
    m_display->update(m_renderer->accumulationTexture(), m_shown->render.width, m_shown->render.height,
                      ui.app.state.view.toneMap, ui.app.state.view.exposure);
}

void MaterialPreview::reloadShaders() {
    m_renderer.reset();
    m_display.reset();
    m_shown.reset();
    m_failedFor.reset();
    m_createFailed = false;
    m_error.clear();
}

bool MaterialPreview::buildingShaders() const { return m_buildWait >= 0; }

bool MaterialPreview::converging() const {
    return m_shownLastFrame && m_renderer && m_shown && m_error.empty() && m_renderer->samplesDone() < m_shown->render.samples;
}

bool MaterialPreview::writeImage(const std::string& file, const EditorUi& ui, std::string* error) const {
    if (!m_renderer || !m_shown) {
        *error = "no material preview rendered yet";
        return false;
    }
    const Film film = m_renderer->readFilm();
    ImageMetadata meta = {{"Software", "caustic editor (material preview)"},
                          {"caustic:samples", std::to_string(m_renderer->samplesDone())}};
    return writeImage8(file, film.width, film.height, toSrgb8(film, ui.app.state.view.toneMap, ui.app.state.view.exposure), meta,
                       error);
}

}  // namespace caustic::editor
