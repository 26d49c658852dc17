// The material preview ball (issue 15, lookdev): the material being edited on a sphere over a
// checker floor (editor/model/lookdev.h makePreviewScene), rendered by the same Renderer and
// shaders as the viewport, in a second, small film, and tone mapped by a second Display. The
// inspector asks for it each frame it shows a material (request); after the viewport's samples the
// frame loop gives it a few milliseconds (tick), so the main render keeps its pace. An edit of the
// material (a slider step) restarts it with only the material table re-uploaded, so it follows
// sliders as they move. Nothing is rendered while no material is shown.
#pragma once

#include "editor/model/lookdev.h"
#include "renderer/renderer.h"
#include "editor/ui/display.h"

#include <memory>
#include <optional>
#include <string>

namespace caustic::editor {

struct EditorUi;

class MaterialPreview {
public:
    static constexpr int kSize = 128;       // pixels, square
    static constexpr int kSamples = 64;     // then it stops
    static constexpr double kBudgetSeconds = 0.004;   // of each frame, while it converges

    MaterialPreview();
    ~MaterialPreview();
    MaterialPreview(const MaterialPreview&) = delete;
    MaterialPreview& operator=(const MaterialPreview&) = delete;

    // This frame shows `material` of `edited` (its textures resolve from the scene's folder).
    void request(const Scene& edited, const Material& material);
    // This frame shows `scene` as it is (its size and sample count its own): the camera
    // inspector's bokeh preview (lookdev.h, makeBokehPreviewScene) is a second MaterialPreview.
    void requestScene(Scene scene);
    // After the viewport rendered: updates the preview's scene if it changed, renders for a few
    // milliseconds and tone maps (the viewport's tone curve and exposure).
    void tick(EditorUi& ui);

    PreviewLighting lighting = PreviewLighting::Scene;
    unsigned texture() const;          // 0 until something is rendered
    int samples() const;               // of the current preview scene
    int targetSamples() const { return m_shown ? m_shown->render.samples : kSamples; }
    int width() const { return m_shown ? m_shown->render.width : kSize; }
    int height() const { return m_shown ? m_shown->render.height : kSize; }
    bool current() const;              // the image is of the last requested material and lighting
    bool requested() const { return m_requested; }
    // Shown last frame and still short of its samples: the frame loop must not sleep for input.
    bool converging() const;
    // A program build is announced (its tick builds it two ticks later; the window freezes then).
    bool buildingShaders() const;
    const std::string& error() const { return m_error; }   // why the last preview scene failed ("" if not)
    // F5: the next tick renders with a renderer and a display made from the shaders as they are
    // now (until then the inspector shows no preview image).
    void reloadShaders();
    // The preview as PNG, tone mapped as the viewport's images (scripts, tests).
    bool writeImage(const std::string& file, const EditorUi& ui, std::string* error) const;

private:
    std::unique_ptr<Renderer> m_renderer;
    std::unique_ptr<Display> m_display;
    std::optional<Scene> m_wanted;     // requested this frame
    std::optional<Scene> m_shown;      // what the renderer has
    std::optional<Scene> m_failedFor;  // the scene the renderer last refused (not retried)
    bool m_requested = false;
    bool m_shownLastFrame = false;     // requested at the last tick
    bool m_createFailed = false;
    int m_buildWait = -1;              // >= 0: a program build is announced, this many ticks ahead
    std::string m_error;
};

}  // namespace caustic::editor
