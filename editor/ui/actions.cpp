// The actions the panels, menus, shortcuts and scripts share (editor_ui.h): messages, files,
// camera views, framing, shader reload, render to file, denoising; and the key names.
#include "editor/ui/editor_ui.h"

#include "editor/model/keymap.h"
#include "editor/model/viewport_math.h"
#include "editor/ui/frame_driver.h"
#include "editor/ui/material_preview.h"
#include "editor/ui/mesh_import.h"
#include "editor/ui/viewport_denoise.h"
#include "renderer/denoise.h"
#include "renderer/image_io.h"
#include "renderer/scene_io.h"

#include <imgui.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>

namespace fs = std::filesystem;

namespace caustic::editor {
namespace {

constexpr double kAutosaveSeconds = 30.0;   // $CAUSTIC_EDITOR_AUTOSAVE_SECONDS overrides it

}  // namespace

ImGuiKey imguiKey(std::string_view k) {
    if (k.size() == 1 && k[0] >= 'A' && k[0] <= 'Z') return static_cast<ImGuiKey>(ImGuiKey_A + (k[0] - 'A'));
    if (k.size() >= 2 && k.size() <= 3 && k[0] == 'F' && k.substr(1).find_first_not_of("0123456789") == std::string_view::npos) {
        const int n = std::stoi(std::string(k.substr(1)));
        return n >= 1 && n <= 12 ? static_cast<ImGuiKey>(ImGuiKey_F1 + (n - 1)) : ImGuiKey_None;
    }
    if (k == "Delete") return ImGuiKey_Delete;
    if (k == "Escape") return ImGuiKey_Escape;
    if (k == "Enter") return ImGuiKey_Enter;
    if (k.size() == 7 && k.substr(0, 6) == "Numpad" && k[6] >= '0' && k[6] <= '9')
        return static_cast<ImGuiKey>(ImGuiKey_Keypad0 + (k[6] - '0'));
    return ImGuiKey_None;
}

// A key map chord (editor/model/keymap.h) pressed this frame, with exactly its modifiers.
bool chordPressed(const Chord& chord) {
    const ImGuiIO& io = ImGui::GetIO();
    if (io.KeyCtrl != chord.ctrl || io.KeyShift != chord.shift || io.KeyAlt != chord.alt) return false;
    if (chord.key == "Enter") return ImGui::IsKeyPressed(ImGuiKey_Enter, false) || ImGui::IsKeyPressed(ImGuiKey_KeypadEnter, false);
    const ImGuiKey key = imguiKey(chord.key);
    return key != ImGuiKey_None && ImGui::IsKeyPressed(key, false);
}

AppState::AppState()
    : preview(std::make_unique<MaterialPreview>()), bokehPreview(std::make_unique<MaterialPreview>()), driver(std::make_unique<FrameDriver>()),
      meshImports(std::make_unique<MeshImports>()) {}
AppState::~AppState() = default;

// ---- Actions shared by the panels ---------------------------------------------------------------

void notify(EditorUi& ui, const std::string& message, bool isError) {
    ui.app.lastMessage = message;
    ui.app.lastMessageIsError = isError;
    ui.app.lastMessageAt = ImGui::GetCurrentContext() ? ImGui::GetTime() : 0.0;
    if (isError) ui.app.shownError = {false, ui.app.state.history.revision()};
    if (isError) std::fprintf(stderr, "caustic: %s\n", message.c_str());
}

void showError(EditorUi& ui, const std::string& message) {
    notify(ui, message, true);
    ui.errorPopup = message;
    ui.errorPopupRequested = true;
}

bool shadersBuilding(const EditorUi& ui) {
    return ui.app.session.buildingShaders || (ui.app.preview && ui.app.preview->buildingShaders()) ||
           (ui.app.bokehPreview && ui.app.bokehPreview->buildingShaders());
}

bool openFile(EditorUi& ui, const std::string& file) {
    // The JSON is parsed and validated here (fast): a broken file is refused at once.
    SceneLoadResult loaded = loadScene(file);
    if (!loaded) {
        showError(ui, "could not open the scene; the current one is kept.\n" + loaded.error);
        ui.app.recent.remove(file);
        return false;
    }
    // Its meshes import in the background; the scene is adopted when they are ready (at once
    // when there is nothing to import). docs/editor.md, "Opening scenes".
    ui.app.meshImports->openScene(ui, std::move(*loaded.scene), file, false);
    return true;
}

bool saveFile(EditorUi& ui, const std::string& file, std::string* errorOut) {
    std::string error;
    const std::string before = ui.app.state.path;
    auto fail = [&](const std::string& why) {
        const std::string message = "could not save " + file + "; nothing was overwritten: " + why;
        notify(ui, message, true);
        if (errorOut) *errorOut = message;
        else showError(ui, message);
        return false;
    };
    if (const fs::path folder = fs::absolute(file).parent_path(); !folder.empty()) {
        std::error_code ec;
        if (!fs::is_directory(folder, ec)) {
            fs::create_directories(folder, ec);
            if (ec) return fail("cannot create the folder " + folder.string() + ": " + ec.message());
        }
    }
    if (!ui.app.state.saveAs(file, &error)) return fail(error);
    ui.app.views.carry(before, file);   // the saved camera views go with the scene to its new path
    if (!ui.app.viewsPath.empty() && !ui.app.views.of(file).empty() && !ui.app.views.save(ui.app.viewsPath, &error))
        notify(ui, "could not save the camera views: " + error, true);
    ui.app.recent.add(fs::absolute(file).lexically_normal().string());
    std::string ignored;
    ui.app.recent.save(ui.app.recentListPath, &ignored);
    ui.app.autosave.remove();
    notify(ui, "saved " + file);
    return true;
}

SaveResult requestSave(EditorUi& ui, const std::string& file, std::string* error) {
    SavePrompt p;
    std::error_code ec;
    if (const fs::path folder = fs::absolute(file).parent_path(); !folder.empty() && !fs::is_directory(folder, ec))
        p.missingFolder = folder.string();
    // The renderer refused the scene as it stands (render_session.h): batch mode would refuse the
    // saved file for the same reason.
    if (ui.app.session.behind) p.refusedBecause = ui.app.session.renderError;
    if (p.missingFolder.empty() && p.refusedBecause.empty())
        return saveFile(ui, file, error) ? SaveResult::Saved : SaveResult::Failed;
    p.file = file;
    p.requested = true;
    ui.savePrompt = std::move(p);
    return SaveResult::Asked;
}

bool answerSavePrompt(EditorUi& ui, bool save) {
    const std::string file = std::exchange(ui.savePrompt, SavePrompt{}).file;
    if (!save || file.empty()) {
        ui.afterUnsavedPrompt = nullptr;
        notify(ui, "not saved");
        return false;
    }
    if (!saveFile(ui, file)) return false;
    if (ui.afterUnsavedPrompt) std::exchange(ui.afterUnsavedPrompt, nullptr)();
    return true;
}

void storeCameraView(EditorUi& ui, const std::string& name) {
    ui.app.views.store(ui.app.state.path, name, ui.app.state.scene.camera);
    std::string error;
    if (!ui.app.viewsPath.empty() && !ui.app.state.path.empty() && !ui.app.views.save(ui.app.viewsPath, &error))
        notify(ui, "could not save the camera views: " + error, true);
    else
        notify(ui, "stored camera view '" + name + "'");
}

bool recallCameraView(EditorUi& ui, const std::string& name) {
    const CameraView* v = ui.app.views.find(ui.app.state.path, name);
    if (!v) {
        notify(ui, "no camera view '" + name + "'", true);
        return false;
    }
    std::string why;
    if (!ui.app.state.apply(makeSetCamera(ui.app.state, v->camera), &why)) {
        notify(ui, why, true);
        return false;
    }
    return true;
}

void deleteCameraView(EditorUi& ui, const std::string& name) {
    ui.app.views.remove(ui.app.state.path, name);
    std::string error;
    if (!ui.app.viewsPath.empty() && !ui.app.state.path.empty() && !ui.app.views.save(ui.app.viewsPath, &error))
        notify(ui, "could not save the camera views: " + error, true);
}

void saveOrSaveAs(EditorUi& ui) {
    if (ui.app.state.path.empty()) openFileBrowser(ui, FileBrowserState::Mode::SaveAs);
    else requestSave(ui, ui.app.state.path);
}

void guardUnsaved(EditorUi& ui, std::function<void()> action) {
    if (!ui.app.state.modified()) {
        action();
        return;
    }
    ui.afterUnsavedPrompt = std::move(action);
    ui.unsavedPromptRequested = true;
}

void frameSelection(EditorUi& ui, bool camera) {
    auto b = entityBounds(ui.app.state.scene, ui.app.state.selection, meshBoundsLookup(ui));
    if (!b) b = sceneBounds(ui.app.state.scene, meshBoundsLookup(ui));
    if (!b) return;
    const RenderSettings& rs = ui.app.state.scene.render;
    // The free view (Blender key map) or the camera, as navigation moves it.
    const float aspect = float(rs.width) / float(rs.height);
    if (camera) ui.app.state.apply(makeSetCamera(ui.app.state, frameBounds(ui.app.state.scene.camera, b->first, b->second, aspect)));
    else ui.app.state.moveView(frameBounds(ui.app.state.viewCamera(), b->first, b->second, aspect), ui.app.keymap == KeymapStyle::Blender, false);
}

void reloadShaders(EditorUi& ui) {
    // Every program is compiled before any is replaced: a failed compile keeps all of the last
    // working ones (the viewport's tone mapping included), never a mix.
    std::string error;
    auto fresh = Renderer::create(ui.app.shaderDir, ui.app.integratorConfig, &error);
    if (fresh && !fresh->checkSource(&error)) fresh.reset();   // create() no longer compiles it on llvmpipe
    std::unique_ptr<Display> display = fresh ? Display::create(ui.app.shaderDir, &error) : nullptr;
    if (!fresh || !display) {
        showError(ui, "shader reload failed; the last working shaders stay in use.\n" + error);
        return;
    }
    fresh->setImageReader(readImage);
    fresh->setDeferredProgramBuilds(true);
    fresh->setProgramBuilder(ui.app.programBuilder);
    if (ui.app.renderer) fresh->meshCache() = std::move(ui.app.renderer->meshCache());   // no re-import of meshes
    ui.app.renderer = std::move(fresh);
    if (ui.app.display) ui.app.display->takeProgram(*display);   // keeps the lookdev snapshot to compare against
    else ui.app.display = std::move(display);
    ui.app.session.sceneUploaded = false;   // the next frame uploads the scene to the new renderer
    if (ui.app.preview) ui.app.preview->reloadShaders();
    if (ui.app.bokehPreview) ui.app.bokehPreview->reloadShaders();   // its own renderer, rebuilt from the new shaders on its next tick
    notify(ui, "shaders reloaded");
}

void startRenderToFile(EditorUi& ui, const std::string& file) {
    ui.app.renderToFile = file;
    ui.app.session.sampleCap.reset();
    notify(ui, "rendering " + std::to_string(ui.app.state.scene.render.samples) + " spp to " + file);
}

bool writeFilmImage(EditorUi& ui, const std::string& file, std::string* error) {
    if (!ui.app.renderer || !ui.app.session.sceneUploaded) {
        *error = "nothing rendered yet";
        return false;
    }
    const Film film = ui.app.renderer->readFilm();
    ImageMetadata meta = {
        {"Software", "caustic editor"},
        {"caustic:scene", ui.app.state.path},
        {"caustic:samples", std::to_string(ui.app.renderer->samplesDone())},
        {"caustic:seed", std::to_string(ui.app.state.scene.render.seed)},
    };
    return writeImage8(file, film.width, film.height, toSrgb8(film, ui.app.state.view.toneMap, ui.app.state.view.exposure), meta, error);
}

bool writeViewportImage(EditorUi& ui, const std::string& file, std::string* error) {
    if (!ui.app.denoiser || !ui.app.denoiser->shown(ui)) return writeFilmImage(ui, file, error);
    const Film film = ui.app.denoiser->shownFilm();
    ImageMetadata meta = {
        {"Software", "caustic editor"},
        {"caustic:scene", ui.app.state.path},
        {"caustic:samples", std::to_string(ui.app.renderer->samplesDone())},
        {"caustic:seed", std::to_string(ui.app.state.scene.render.seed)},
        {"caustic:denoiser", "Open Image Denoise " + denoiserVersion()},
    };
    return writeImage8(file, film.width, film.height, toSrgb8(film, ui.app.state.view.toneMap, ui.app.state.view.exposure), meta, error);
}

void denoiseNow(EditorUi& ui) {
    if (!ui.app.denoiser) return;
    std::string why;
    if (ui.app.denoiser->request(ui, true, &why)) {
        ui.app.denoiser->settings.showDenoised = true;
        notify(ui, "denoising " + std::to_string(ui.app.renderer->samplesDone()) + " spp");
    } else {
        notify(ui, "cannot denoise: " + why, true);
    }
}

double autosaveIntervalSeconds() {
    static const double seconds = [] {
        if (const char* v = std::getenv("CAUSTIC_EDITOR_AUTOSAVE_SECONDS"); v && *v) {
            char* end = nullptr;
            const double s = std::strtod(v, &end);
            if (end && *end == '\0' && s > 0.0) return s;
            std::fprintf(stderr, "caustic: ignoring CAUSTIC_EDITOR_AUTOSAVE_SECONDS='%s' (not a positive number)\n", v);
        }
        return kAutosaveSeconds;
    }();
    return seconds;
}

bool scriptMayUseAutosave() {
    const char* home = std::getenv("CAUSTIC_EDITOR_HOME");
    return home && *home;
}

}  // namespace caustic::editor
