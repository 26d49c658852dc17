// The editor application's state, apart from any widget: the document (EditorState: the scene,
// selection, history and file), the renderer and what it shows, the render session, the config
// folder's files (recent files, autosave, saved camera views), the preferences, the status line,
// the background work and what drives the frame loop. The UI (EditorUi, editor_ui.h) holds its
// own state beside it and a reference to it.
#pragma once

#include "editor/model/camera_views.h"
#include "editor/model/editor_config.h"
#include "editor/model/editor_state.h"
#include "editor/model/keymap.h"
#include "editor/model/render_session.h"
#include "editor/model/status.h"
#include "editor/ui/display.h"
#include "renderer/renderer.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

struct GLFWwindow;

namespace caustic::editor {

class FrameDriver;
class MaterialPreview;
class MeshImports;
class ViewportDenoiser;

struct AppState {
    AppState();    // actions.cpp
    ~AppState();
    AppState(const AppState&) = delete;
    AppState& operator=(const AppState&) = delete;

    GLFWwindow* window = nullptr;

    // The document.
    EditorState state;

    // Rendering: the renderer, the display of its image, the render session (scheduling, preview
    // resolution, the figures the status bar shows; editor/model/render_session.h).
    std::unique_ptr<Renderer> renderer;
    // Builds the renderers' integrator programs on a thread of its own (renderer/program_builder.h),
    // so that a build never freezes the window; null where the driver gives no second context
    // (or $CAUSTIC_BACKGROUND_BUILDS=0): then they are built on this thread, announced first.
    std::shared_ptr<ProgramBuilder> programBuilder;
    std::unique_ptr<Display> display;
    std::string shaderDir;
    IntegratorConfig integratorConfig;  // filled once at start (IntegratorConfig::fromEnvironment)
    RenderSession session;
    std::unique_ptr<ViewportDenoiser> denoiser;   // viewport_denoise.h (view state, not saved)
    // The material preview ball (material_preview.h): rendered only while a material is shown.
    std::unique_ptr<MaterialPreview> preview;
    // The camera's bokeh preview (the same machinery, lookdev.h makeBokehPreviewScene): rendered
    // only while the camera inspector shows it.
    std::unique_ptr<MaterialPreview> bokehPreview;
    std::vector<std::string> hidden;   // objects hidden in the viewport (H; view state, not saved)
    std::optional<std::string> renderToFile;   // written when the target sample count is reached

    // Files in the config folder.
    RecentFiles recent;
    std::string recentListPath;
    Autosave autosave;
    double lastAutosave = 0.0;
    std::uint64_t autosaveWrites = 0;   // autosaves written this session (scripts wait on it)
    std::optional<std::pair<Scene, std::string>> recovered;   // an autosave offered back at start-up
    CameraViews views;                // saved camera views (camera_views.h), in <config>/views.json
    std::string viewsPath;

    // Preferences (View > Key map, View > UI scale; kept in layout.ini, preferences.h).
    KeymapStyle keymap = KeymapStyle::Default;
    float uiScaleChoice = 0.0f;       // 0 follows the window's content scale (HiDPI), else this factor

    // Status.
    std::string lastMessage;          // status bar: the latest info or error
    bool lastMessageIsError = false;
    double lastMessageAt = 0.0;       // ImGui's clock when it was said (info messages fade)
    ShownError shownError;            // where the shown error came from (cleared when its cause is gone)
    bool fallbackNoticed = false;     // the status bar said the general integrator stands in (editor_app.cpp)
    bool quit = false;

    // What drives the frame loop besides the user (frame_driver.h): the test-script harness, or
    // the base class, which does nothing. Never null.
    std::unique_ptr<FrameDriver> driver;

    // Mesh imports in the background (mesh_import.h): the edit applies when the mesh is ready.
    std::unique_ptr<MeshImports> meshImports;
};

}  // namespace caustic::editor
