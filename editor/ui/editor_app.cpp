#include "editor/ui/editor_app.h"

#include "editor/model/keymap.h"
#include "editor/model/preferences.h"
#include "editor/model/shortcuts.h"
#include "editor/model/viewport_math.h"
#include "editor/ui/editor_ui.h"
#include "editor/ui/frame_driver.h"
#include "editor/ui/material_preview.h"
#include "editor/ui/mesh_import.h"
#include "editor/script/script_runner.h"
#include "editor/ui/viewport_denoise.h"
#include "renderer/file_util.h"
#include "renderer/program_cache.h"
#include "renderer/gl_context.h"
#include "renderer/image_io.h"
#include "renderer/scene_io.h"
#include "renderer/shader_loader.h"

#include <glad/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <imgui.h>
#include <imgui_internal.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <ImGuizmo.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <utility>

namespace fs = std::filesystem;

namespace caustic::editor {
namespace {

double now() { return glfwGetTime(); }

void glfwError(int code, const char* what) { std::fprintf(stderr, "caustic: GLFW error %d: %s\n", code, what); }

void* glfwLoader(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

void updateTitle(EditorUi& ui) {
    std::string title = (ui.app.state.modified() ? "* " : "") + ui.app.state.displayName() + " - caustic";
    glfwSetWindowTitle(ui.app.window, title.c_str());
}

// The default layout: outliner left, inspector right, viewport in the middle.
void buildDefaultLayout(ImGuiID dockspace, ImVec2 size) {
    ImGui::DockBuilderRemoveNode(dockspace);
    ImGui::DockBuilderAddNode(dockspace, ImGuiDockNodeFlags_DockSpace);
    ImGui::DockBuilderSetNodeSize(dockspace, size);
    ImGuiID centre = dockspace;
    // Side panels wide enough for their labels at the UI's font size (View > UI scale), within
    // limits that leave the viewport most of the window.
    // At 100% (ImGui's 13-pixel font) a fifth and 27% of the rest, as always; more at a larger scale.
    const float scale = std::max(1.0f, ImGui::GetFontSize() / 13.0f);
    const float leftRatio = std::min(0.20f * scale, 0.30f);
    const float rightRatio = std::min(0.27f * scale, 0.45f);
    ImGuiID left = ImGui::DockBuilderSplitNode(centre, ImGuiDir_Left, leftRatio, nullptr, &centre);
    ImGuiID right = ImGui::DockBuilderSplitNode(centre, ImGuiDir_Right, rightRatio, nullptr, &centre);
    ImGui::DockBuilderDockWindow("Outliner", left);
    ImGui::DockBuilderDockWindow("Inspector", right);
    ImGui::DockBuilderDockWindow("Viewport", centre);
    ImGui::DockBuilderFinish(dockspace);
}

void drawDockSpace(EditorUi& ui) {
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    // Leave room for the status bar at the bottom.
    const float statusHeight = ImGui::GetFrameHeight();
    ImGui::SetNextWindowPos(vp->WorkPos);
    ImGui::SetNextWindowSize(ImVec2(vp->WorkSize.x, vp->WorkSize.y - statusHeight));
    ImGui::SetNextWindowViewport(vp->ID);
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoResize |
                                   ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoBringToFrontOnFocus |
                                   ImGuiWindowFlags_NoNavFocus | ImGuiWindowFlags_NoDocking | ImGuiWindowFlags_NoBackground;
    ImGui::PushStyleVar(ImGuiStyleVar_WindowRounding, 0.0f);
    ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 0.0f);
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0.0f, 0.0f));
    ImGui::Begin("##dockspace-host", nullptr, flags);
    ImGui::PopStyleVar(3);
    const ImGuiID id = ImGui::GetID("caustic-dockspace");
    if (ui.resetLayout || !ImGui::DockBuilderGetNode(id) || ImGui::DockBuilderGetNode(id)->IsLeafNode()) {
        buildDefaultLayout(id, ImVec2(vp->WorkSize.x, vp->WorkSize.y - statusHeight));
        ui.resetLayout = false;
    }
    ImGui::DockSpace(id, ImVec2(0.0f, 0.0f), ImGuiDockNodeFlags_None);
    ImGui::End();
}

// A frame longer than this is a stall (a program build: seconds on llvmpipe): what the user typed
// or clicked meanwhile is not replayed afterwards (queued Del presses deleted more than intended).
constexpr double kStallSeconds = 0.5;

// Drops the presses, characters and wheel steps that the window system delivered since the queue
// held `from` events (the polling after a stall); releases, mouse positions and focus changes
// stay, so no key or button is left down. Events queued before (a script's) are kept. True when
// something was dropped.
bool dropStalledInput(int from) {
    ImVector<ImGuiInputEvent>& q = ImGui::GetCurrentContext()->InputEventsQueue;
    int kept = from, dropped = 0;
    for (int i = from; i < q.Size; ++i) {
        const ImGuiInputEvent& e = q[i];
        const bool press = (e.Type == ImGuiInputEventType_Key && e.Key.Down) || e.Type == ImGuiInputEventType_Text ||
                           (e.Type == ImGuiInputEventType_MouseButton && e.MouseButton.Down) ||
                           e.Type == ImGuiInputEventType_MouseWheel;
        if (press) ++dropped;
        else q[kept++] = e;
    }
    q.resize(kept);
    return dropped > 0;
}

void drawModals(EditorUi& ui) {
    if (ui.unsavedPromptRequested) {
        ImGui::OpenPopup("Unsaved changes");
        ui.unsavedPromptRequested = false;
    }
    if (ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::Text("'%s' has unsaved changes.", ui.app.state.displayName().c_str());
        if (ImGui::Button("Save")) {
            ImGui::CloseCurrentPopup();
            if (ui.app.state.path.empty()) {
                openFileBrowser(ui, FileBrowserState::Mode::SaveAs);   // the action runs after it saves
            } else if (requestSave(ui, ui.app.state.path) == SaveResult::Saved && ui.afterUnsavedPrompt) {
                auto action = std::move(ui.afterUnsavedPrompt);
                ui.afterUnsavedPrompt = nullptr;
                action();
            }
        }
        ImGui::SameLine();
        if (ImGui::Button("Discard")) {
            ImGui::CloseCurrentPopup();
            if (ui.afterUnsavedPrompt) {
                auto action = std::move(ui.afterUnsavedPrompt);
                ui.afterUnsavedPrompt = nullptr;
                action();
            }
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel") || ImGui::IsKeyPressed(ImGuiKey_Escape)) {
            ui.afterUnsavedPrompt = nullptr;
            ImGui::CloseCurrentPopup();
        }
        ImGui::EndPopup();
    }
    if (ui.recoveryPromptRequested) {
        ImGui::OpenPopup("Recover unsaved work?");
        ui.recoveryPromptRequested = false;
    }
    if (ImGui::BeginPopupModal("Recover unsaved work?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::TextUnformatted("The editor did not close cleanly last time. An autosave exists");
        if (ui.app.recovered) ImGui::Text("of '%s'.", ui.app.recovered->second.empty() ? "an untitled scene" : ui.app.recovered->second.c_str());
        // A script's `recover` presses the same button.
        if (ImGui::Button("Recover") || ui.app.driver->pressRecover()) {
            // Its meshes import in the background first, as when opening (mesh_import.h).
            if (ui.app.recovered) ui.app.meshImports->openScene(ui, std::move(ui.app.recovered->first), ui.app.recovered->second, true);
            ui.app.recovered.reset();
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Discard it")) {
            ui.app.recovered.reset();
            ui.app.autosave.remove();
            ImGui::CloseCurrentPopup();
        }
        ImGui::EndPopup();
    }
    if (ui.savePrompt.requested && !ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId)) {
        ImGui::OpenPopup("Save scene?");
        ui.savePrompt.requested = false;
    }
    if (ImGui::BeginPopupModal("Save scene?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        const SavePrompt& p = ui.savePrompt;
        ImGui::PushTextWrapPos(ImGui::GetFontSize() * 40.0f);
        ImGui::Text("Save %s?", p.file.c_str());
        if (!p.refusedBecause.empty()) {
            ImGui::TextColored(ImVec4(1.0f, 0.55f, 0.4f, 1.0f), "The scene cannot be rendered as it is (the viewport shows the last good scene), so `caustic --scene` will refuse the saved file:");
            ImGui::TextUnformatted(p.refusedBecause.c_str());
        }
        if (!p.missingFolder.empty()) ImGui::Text("The folder %s does not exist; it will be created.", p.missingFolder.c_str());
        ImGui::PopTextWrapPos();
        const char* label = p.refusedBecause.empty() ? "Create folder and save" : "Save anyway";
        if (ImGui::Button(label)) {
            ImGui::CloseCurrentPopup();
            answerSavePrompt(ui, true);
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel##save") || ImGui::IsKeyPressed(ImGuiKey_Escape)) {
            ImGui::CloseCurrentPopup();
            answerSavePrompt(ui, false);
        }
        // A script's answer_save (or an answer given elsewhere) closes it.
        if (!ui.savePrompt.isOpen()) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
    if (ui.errorPopupRequested) {
        ImGui::OpenPopup("Error");
        ui.errorPopupRequested = false;
    }
    if (ImGui::BeginPopupModal("Error", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::PushTextWrapPos(ImGui::GetFontSize() * 40.0f);
        ImGui::TextUnformatted(ui.errorPopup.c_str());
        ImGui::PopTextWrapPos();
        if (ImGui::Button("OK") || ImGui::IsKeyPressed(ImGuiKey_Enter) || ImGui::IsKeyPressed(ImGuiKey_Escape))
            ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
}

// Global shortcuts (editor/model/keymap.h, scope Global); ImGui text fields keep their keys.
void handleShortcuts(EditorUi& ui) {
    ImGuiIO& io = ImGui::GetIO();
    if (io.WantTextInput) return;
    for (const KeyBinding& b : keyBindings(ui.app.keymap)) {
        if (b.scope != KeyScope::Global || !chordPressed(b.chord)) continue;
        std::string why;
        switch (b.action) {
            case Action::Undo: ui.app.state.undo(); break;
            case Action::Redo:
            case Action::RedoAlt: ui.app.state.redo(); break;
            case Action::Save: saveOrSaveAs(ui); break;
            case Action::SaveAs: openFileBrowser(ui, FileBrowserState::Mode::SaveAs); break;
            case Action::Open: guardUnsaved(ui, [&ui] { openFileBrowser(ui, FileBrowserState::Mode::Open); }); break;
            case Action::Duplicate:
                if (!ui.app.state.selection) break;
                if (auto c = makeDuplicate(ui.app.state, ui.app.state.selection, &why)) ui.app.state.apply(std::move(c));
                break;
            case Action::Delete: {
                const KeyFocus focus{io.WantTextInput, ImGui::IsAnyItemActive(), ui.viewportFocused || ui.outlinerFocused};
                if (!ui.app.state.selection || !deleteKeyDeletes(focus)) break;
                if (auto c = makeDelete(ui.app.state, ui.app.state.selection, &why)) ui.app.state.apply(std::move(c));
                else if (!why.empty()) notify(ui, why, true);
                break;
            }
            case Action::ReloadShaders: reloadShaders(ui); break;
            case Action::DenoiseNow: denoiseNow(ui); break;
            default: break;  // the viewport's keys (viewport_panel.cpp)
        }
    }
}

// Help > Keyboard and mouse: the key map and the mouse actions, as the code uses them.
void drawShortcutsWindow(EditorUi& ui) {
    if (!ui.showShortcuts) return;
    ImGui::SetNextWindowSize(ImVec2(ImGui::GetFontSize() * 62.0f, ImGui::GetFontSize() * 40.0f), ImGuiCond_FirstUseEver);
    if (ImGui::Begin("Keyboard and mouse", &ui.showShortcuts)) {
        int style = static_cast<int>(ui.app.keymap);
        ImGui::TextUnformatted("Key map:");
        ImGui::SameLine();
        if (ImGui::RadioButton("Default", &style, 0)) ui.app.keymap = KeymapStyle::Default;
        ImGui::SameLine();
        if (ImGui::RadioButton("Blender", &style, 1)) ui.app.keymap = KeymapStyle::Blender;
        ImGui::SameLine();
        ImGui::TextDisabled("(also View > Key map)");
        if (ImGui::BeginTable("keys", 3, ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV | ImGuiTableFlags_SizingStretchProp)) {
            // The keys and the place narrow, the description takes the rest (no wrapping of short lines).
            const float em = ImGui::GetFontSize();
            ImGui::TableSetupColumn("Keys", ImGuiTableColumnFlags_WidthFixed, em * 11.0f);
            ImGui::TableSetupColumn("Where", ImGuiTableColumnFlags_WidthFixed, em * 7.5f);
            ImGui::TableSetupColumn("What", ImGuiTableColumnFlags_WidthStretch);
            ImGui::TableHeadersRow();
            for (const KeyBinding& b : keyBindings(ui.app.keymap)) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(chordText(b.chord).c_str());
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(b.scope == KeyScope::Global ? "anywhere" : b.scope == KeyScope::Viewport ? "viewport" : "during G R S");
                ImGui::TableNextColumn();
                ImGui::TextWrapped("%.*s", int(b.what.size()), b.what.data());
            }
            for (const MouseAction& m : mouseActions(ui.app.keymap)) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextWrapped("%.*s", int(m.input.size()), m.input.data());
                ImGui::TableNextColumn();
                ImGui::TextUnformatted("viewport");
                ImGui::TableNextColumn();
                ImGui::TextWrapped("%.*s", int(m.what.size()), m.what.data());
            }
            ImGui::EndTable();
        }
    }
    ImGui::End();
}

// One step of the render session (editor/model/render_session.h): pending edits to the renderer,
// this frame's samples; then what it says is shown: the image, a compile error (or its end), the
// file a "Render to file" waited for.
void renderFrame(EditorUi& ui) {
    if (!ui.app.renderer) return;
    // Render to file (and scripts, by default) render at the output resolution, else the viewport
    // renders at its panel's size.
    ui.app.session.outputSize = ui.app.renderToFile.has_value() || ui.app.driver->wantsOutputSize();
    // Idle pacing (render_session.h) for a person at the keyboard; scripts measure frames.
    ui.app.session.idlePacing = ui.app.driver->mayWaitForInput();
    // Hidden objects (H) are left out of the viewport only: Render to file renders them.
    ui.app.session.hidden = ui.app.renderToFile ? std::vector<std::string>{} : ui.app.hidden;
    const ImGuiIO& io = ImGui::GetIO();
    if (io.MouseDelta.x != 0.0f || io.MouseDelta.y != 0.0f || io.MouseWheel != 0.0f || ImGui::IsAnyMouseDown() ||
        io.InputQueueCharacters.Size > 0 || io.KeyCtrl || io.KeyShift || io.KeyAlt || ImGui::IsAnyItemActive())
        ui.app.session.noteInput(now());
    // Meshes the scene uses that changed on disk import again in the background meanwhile.
    const bool holding = ui.app.session.sceneUploaded && ui.app.meshImports->refreshing(ui);
    const RenderStep step = ui.app.session.step(*ui.app.renderer, ui.app.state, now(), holding);
    // A new, opened or recovered scene: the lookdev snapshot (A/B) was of the last one.
    if (ui.app.state.generation() != ui.snapshotGeneration) {
        ui.snapshotGeneration = ui.app.state.generation();
        if (ui.app.display) ui.app.display->dropSnapshot();
        ui.compare = false;
    }
    if (step.compiled && ui.app.lastMessageIsError && errorResolved(ui.app.shownError, true, ui.app.state.history.revision())) {
        // A stale error goes: the scene compiles again, or an edit since it went through.
        ui.app.lastMessage.clear();
        ui.app.lastMessageIsError = false;
    }
    if (!step.error.empty()) {
        notify(ui, step.error, true);
        ui.app.shownError.fromRender = true;
    }
    // The scene's own integrator failed to build and the general one renders it (right, slower;
    // the compiler's message is on stderr): said once in the status bar when it starts, so the
    // user knows why the viewport is slow (a defect of the shaders, not of the scene).
    const bool fellBack = ui.app.renderer->programFellBack();
    if (fellBack && !ui.app.fallbackNoticed)
        notify(ui, "the integrator built for this scene failed to compile (see the terminal); "
                   "rendering with the general one, which is slower");
    ui.app.fallbackNoticed = fellBack;
    if (step.show && ui.app.display)
        ui.app.display->update(ui.app.renderer->accumulationTexture(), step.width, step.height, ui.app.state.view.toneMap,
                           ui.app.state.view.exposure);
    // "Render to file": written once the full-resolution image has all its samples.
    if (ui.app.renderToFile && step.targetReached) {
        std::string error;
        const std::string file = *ui.app.renderToFile;
        ui.app.renderToFile.reset();
        if (writeFilmImage(ui, file, &error)) notify(ui, "wrote " + file);
        else showError(ui, error);
    }
}

void autosaveTick(EditorUi& ui) {
    const double t = now();
    if (t - ui.app.lastAutosave < autosaveIntervalSeconds()) return;
    ui.app.lastAutosave = t;
    if (!ui.app.state.modified() || ui.app.recovered || ui.app.autosave.frozen) return;
    std::string error;
    if (!ui.app.autosave.write(ui.app.state.scene, ui.app.state.path, &error)) notify(ui, "autosave failed: " + error, true);
    else ++ui.app.autosaveWrites;
}

// The preferences' section of layout.ini (editor/model/preferences.h), through an ImGui settings
// handler: read with the layout, written whenever ImGui saves it.
struct PreferenceSettings {
    AppState* app = nullptr;
    Preferences stored;   // as layout.ini had them
    // The session's changes are saved: not in a script without $CAUSTIC_EDITOR_HOME (a test that
    // switches key maps must not change the next session's, nor the user's).
    bool live = false;
    Preferences saved;    // last written (a change marks the settings dirty)
};

Preferences currentPreferences(const AppState& app) { return {app.keymap, app.uiScaleChoice}; }

void registerPreferenceSettings(PreferenceSettings* ps) {
    ImGuiSettingsHandler h;
    h.TypeName = "Caustic";
    h.TypeHash = ImHashStr("Caustic");
    h.UserData = ps;
    h.ReadOpenFn = [](ImGuiContext*, ImGuiSettingsHandler*, const char* name) -> void* {
        return std::strcmp(name, "Preferences") == 0 ? reinterpret_cast<void*>(1) : nullptr;
    };
    h.ReadLineFn = [](ImGuiContext*, ImGuiSettingsHandler* handler, void*, const char* line) {
        readPreferenceLine(line, &static_cast<PreferenceSettings*>(handler->UserData)->stored);
    };
    h.WriteAllFn = [](ImGuiContext*, ImGuiSettingsHandler* handler, ImGuiTextBuffer* buf) {
        auto* settings = static_cast<PreferenceSettings*>(handler->UserData);
        const Preferences p = settings->live ? currentPreferences(*settings->app) : settings->stored;
        buf->append("[Caustic][Preferences]\n");
        buf->append(writePreferenceLines(p).c_str());
        buf->append("\n");
        settings->saved = p;
    };
    ImGui::AddSettingsHandler(&h);
}

// layout.ini written as every other file of caustic's: whole or not at all (ImGui's own writer
// truncates the file first, so a kill in between lost the layout and the preferences).
void saveLayout(const std::string& path) {
    std::size_t size = 0;
    const char* data = ImGui::SaveIniSettingsToMemory(&size);
    std::string error;
    if (!writeFileAtomically(path, data, size, &error)) std::fprintf(stderr, "caustic: warning: %s\n", error.c_str());
    ImGui::GetIO().WantSaveIniSettings = false;
}

// The UI scale (View > UI scale): the window's content scale (HiDPI), or the chosen factor; the
// style's sizes are scaled from the base style each time it changes, the fonts by FontScaleDpi.
void applyUiScale(EditorUi& ui) {
    float scale = ui.app.uiScaleChoice;
    if (scale <= 0.0f) {
        float sx = 1.0f, sy = 1.0f;
        glfwGetWindowContentScale(ui.app.window, &sx, &sy);
        scale = std::clamp(std::max(sx, sy), kMinUiScale, kMaxUiScale);
    }
    if (scale == ui.uiScaleApplied) return;
    static ImGuiStyle base = ImGui::GetStyle();   // applyStyle's, before any scaling
    ImGuiStyle& style = ImGui::GetStyle();
    style = base;
    style.ScaleAllSizes(scale);
    style.FontScaleDpi = scale;
    ui.uiScaleApplied = scale;
}

void applyStyle() {
    ImGui::StyleColorsDark();
    ImGuiStyle& style = ImGui::GetStyle();
    style.WindowRounding = 2.0f;
    style.FrameRounding = 2.0f;
    style.GrabRounding = 2.0f;
    style.WindowPadding = ImVec2(6.0f, 6.0f);
    style.ItemSpacing = ImVec2(6.0f, 4.0f);
}

// Background builds are on unless $CAUSTIC_BACKGROUND_BUILDS is 0 (the editor benchmark's
// "before": builds on the window's thread).
bool backgroundBuildsWanted() {
    const char* v = std::getenv("CAUSTIC_BACKGROUND_BUILDS");
    return !(v && std::string(v) == "0");
}

}  // namespace

int runEditor(const std::optional<std::string>& sceneFile) {
    glfwSetErrorCallback(glfwError);
    if (!glfwInit()) {
        std::fprintf(stderr, "caustic: error: cannot open a window (no display? set DISPLAY or use xvfb-run); "
                             "render in batch mode with --scene <file.json>\n");
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    int winW = 1400, winH = 860;
    if (const char* size = std::getenv("CAUSTIC_EDITOR_WINDOW")) std::sscanf(size, "%dx%d", &winW, &winH);
    GLFWwindow* window = glfwCreateWindow(winW, winH, "caustic", nullptr, nullptr);
    if (!window) {
        std::fprintf(stderr, "caustic: error: cannot create an OpenGL 4.5 core window\n");
        glfwTerminate();
        return 1;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(0);   // the frame loop paces itself; vsync would only add latency
    std::string error;
    const char* debugEnv = std::getenv("CAUSTIC_GL_DEBUG");
    if (!loadGlFunctions(glfwLoader, debugEnv && *debugEnv && *debugEnv != '0', &error)) {
        std::fprintf(stderr, "caustic: error: %s\n", error.c_str());
        glfwDestroyWindow(window);
        glfwTerminate();
        return 1;
    }

    // A hidden window whose context shares the editor's objects, for the shader-building thread.
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    GLFWwindow* builderWindow = backgroundBuildsWanted() ? glfwCreateWindow(1, 1, "caustic: shader builds", nullptr, window)
                                                        : nullptr;
    glfwWindowHint(GLFW_VISIBLE, GLFW_TRUE);
    glfwMakeContextCurrent(window);

    int exitCode = 0;
    {
        auto app = std::make_unique<AppState>();
        if (builderWindow) {
            const bool debug = debugEnv && *debugEnv && *debugEnv != '0';
            ProgramBuilder::WorkerContext context{[builderWindow, debug] {
                                                       glfwMakeContextCurrent(builderWindow);
                                                       if (glfwGetCurrentContext() != builderWindow) return false;
                                                       if (debug) enableGlDebugOutput();   // errors there count too
                                                       return true;
                                                   },
                                                   [] { glfwMakeContextCurrent(nullptr); }};
            app->programBuilder = ProgramBuilder::start(std::move(context), &error);
            if (!app->programBuilder)
                std::fprintf(stderr, "caustic: warning: %s; shaders are built on the window's thread\n", error.c_str());
        }
        auto ui = std::make_unique<EditorUi>(*app);
        app->window = window;
        const std::string configDir = editorConfigDir();
        std::error_code ec;
        fs::create_directories(configDir, ec);
        app->recentListPath = (fs::path(configDir) / "recent.txt").string();
        app->recent.load(app->recentListPath);
        app->autosave = Autosave::in(configDir);

        static std::string iniPath;   // ImGui keeps the pointer
        iniPath = (fs::path(configDir) / "layout.ini").string();

        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        io.ConfigFlags |= ImGuiConfigFlags_DockingEnable | ImGuiConfigFlags_NavEnableKeyboard;
        io.IniFilename = nullptr;   // loaded below, once the driver is known; saved by saveLayout
        PreferenceSettings preferences;
        preferences.app = app.get();
        registerPreferenceSettings(&preferences);
        applyStyle();
        ImGui_ImplGlfw_InitForOpenGL(window, true);
        ImGui_ImplOpenGL3_Init("#version 450 core");

        app->shaderDir = defaultShaderDir();
        app->integratorConfig = IntegratorConfig::fromEnvironment();
        useProgramCache(app->integratorConfig.programCache);   // before the first build
        app->renderer = Renderer::create(app->shaderDir, app->integratorConfig, &error);
        if (app->renderer) {
            app->renderer->setImageReader(readImage);
            app->renderer->setDeferredProgramBuilds(true);   // "Building shaders" shows first (render_session.h)
            app->renderer->setProgramBuilder(app->programBuilder);
        }
        else showError(*ui, "the path tracer's shaders did not compile (fix them and press F5):\n" + error);
        app->display = Display::create(app->shaderDir, &error);
        app->denoiser = std::make_unique<ViewportDenoiser>();
        // Denoise when idle shares the CPU with the path tracer on llvmpipe (it slows convergence
        // there: docs/performance.md): off there by default, on where a GPU renders.
        if (app->renderer && onLlvmpipe()) app->denoiser->settings.idleDenoise = false;
        if (!app->display) showError(*ui, error);

        if (const char* scriptFile = std::getenv("CAUSTIC_EDITOR_SCRIPT"); scriptFile && *scriptFile) {
            auto script = std::make_unique<ScriptRunner>();
            const bool loaded = script->load(scriptFile, &error);
            app->driver = std::move(script);
            app->state.view.viewportScale = 1.0f;   // scripts measure sizes: the panel's, not a rate's
            if (!loaded) {
                std::fprintf(stderr, "caustic: error: %s\n", error.c_str());
                exitCode = 1;
                app->quit = true;
            }
        }
        // The layout and the preferences (View > Key map, UI scale) of the last session.
        ImGui::LoadIniSettingsFromDisk(iniPath.c_str());
        preferences.live = app->driver->offersRecovery();
        if (preferences.live) {
            app->keymap = preferences.stored.keymap;
            app->uiScaleChoice = preferences.stored.uiScale;
        }
        preferences.saved = currentPreferences(*app);
        // Saved camera views (camera_views.h), in the config folder; like the autosave, a script
        // touches them only with $CAUSTIC_EDITOR_HOME set (offersRecovery says so).
        if (app->driver->offersRecovery()) {
            app->viewsPath = (fs::path(configDir) / "views.json").string();
            if (std::string viewsError; !app->views.load(app->viewsPath, &viewsError))
                notify(*ui, "the saved camera views could not be read (they are ignored): " + viewsError, true);
        }
        // A script sees (and may answer) the recovery offer only with $CAUSTIC_EDITOR_HOME set.
        if (app->autosave.exists() && app->driver->offersRecovery()) {
            Autosave::Found found = app->autosave.recover();
            app->recovered = std::move(found.recovered);
            if (app->recovered) ui->recoveryPromptRequested = true;
            else showError(*ui, found.message);   // the window and stderr say it
        }
        if (sceneFile) openFile(*ui, *sceneFile);
        else app->state.newScene();   // the starter scene, as File > New

        app->lastAutosave = now();
        double frameStart = now();
        while (!app->quit) {
            // Converged and idle: sleep until input instead of spinning.
            const bool busy = app->session.busy(app->renderer.get(), app->state.scene) || app->preview->converging() ||
                              app->bokehPreview->converging();
            const int queuedBefore = ImGui::GetCurrentContext()->InputEventsQueue.Size;
            // Only waiting for a program built in the background: a few frames a second, leaving
            // the CPU to the build (on llvmpipe the window's drawing takes a core of its own).
            const bool onlyBuilding = app->renderer && app->renderer->waitingForBuild() && !app->preview->converging() &&
                                      !app->bokehPreview->converging();
            if (!busy && app->driver->mayWaitForInput() && app->state.pendingDirty() == kDirtyNone) glfwWaitEventsTimeout(0.25);
            else if (onlyBuilding && app->driver->mayWaitForInput() && app->state.pendingDirty() == kDirtyNone)
                glfwWaitEventsTimeout(0.1);
            else glfwPollEvents();
            if (app->session.frameSeconds > kStallSeconds && dropStalledInput(queuedBefore))
                notify(*ui, "input during the last " + std::to_string(int(app->session.frameSeconds + 0.5)) +
                                " s stall (" + (shadersBuilding(*ui) || app->session.buildingShaders ? "building shaders" : "busy") +
                                ") was ignored");
            if (glfwWindowShouldClose(window)) {
                glfwSetWindowShouldClose(window, GLFW_FALSE);
                guardUnsaved(*ui, [u = ui.get()] { u->app.quit = true; });
            }
            const double uiStart = now();
            applyUiScale(*ui);
            try {
                ImGui_ImplOpenGL3_NewFrame();
                ImGui_ImplGlfw_NewFrame();
                ImGui::NewFrame();
                ImGuizmo::BeginFrame();
                app->meshImports->finish(*ui);   // meshes imported in the background: their edits apply now
                drawMenuBar(*ui);
                drawDockSpace(*ui);
                drawOutlinerPanel(*ui);
                drawInspectorPanel(*ui);
                drawViewportPanel(*ui);
                drawStatusBar(*ui);
                drawFileBrowser(*ui);
                drawModals(*ui);
                drawShortcutsWindow(*ui);
                handleShortcuts(*ui);
                if (ui->lastWheel >= 0.0 && now() - ui->lastWheel > 0.5) {
                    app->state.seal();   // a pause ends one zoom gesture
                    ui->lastWheel = -1.0;
                }
                app->driver->step(*ui);
                ImGui::Render();
            } catch (const std::exception& e) {
                // No exception crosses the frame loop: report it and carry on with the next frame.
                showError(*ui, std::string("unexpected failure: ") + e.what());
                ImGui::EndFrame();
            }
            const double uiEnd = now();
            app->session.uiSeconds = 0.8 * app->session.uiSeconds + 0.2 * (uiEnd - uiStart);
            double renderEnd = uiEnd, previewsEnd = uiEnd;
            try {
                renderFrame(*ui);
                if (app->denoiser) app->denoiser->tick(*ui);
                renderEnd = previewsEnd = now();
                app->preview->tick(*ui);   // a few ms for the material preview, when one is shown
                app->bokehPreview->tick(*ui);   // and for the camera's bokeh preview
                previewsEnd = now();
            } catch (const std::exception& e) {
                showError(*ui, std::string("unexpected failure while rendering: ") + e.what());
            }
            int fbw = 0, fbh = 0;
            glfwGetFramebufferSize(window, &fbw, &fbh);
            glViewport(0, 0, fbw, fbh);
            glClearColor(0.1f, 0.1f, 0.11f, 1.0f);
            glClear(GL_COLOR_BUFFER_BIT);
            if (ImDrawData* dd = ImGui::GetDrawData(); dd && dd->Valid) ImGui_ImplOpenGL3_RenderDrawData(dd);
            app->driver->afterDraw(*ui, fbw, fbh);
            glfwSwapBuffers(window);
            const double t = now();
            app->session.phases = {uiEnd - uiStart, renderEnd - uiEnd, previewsEnd - renderEnd, t - previewsEnd};
            app->session.endFrame(t - frameStart);
            frameStart = t;
            app->driver->afterSwap(*ui, app->session.frameSeconds);
            updateTitle(*ui);
            if (app->driver->usesAutosave()) autosaveTick(*ui);
            if (preferences.live && !(currentPreferences(*app) == preferences.saved)) ImGui::MarkIniSettingsDirty();
            if (ImGui::GetIO().WantSaveIniSettings) saveLayout(iniPath);
        }
        saveLayout(iniPath);
        if (app->driver->failed()) exitCode = 1;
        // A clean exit: nothing to recover next time (unless the offer was never answered, or a
        // script ran without `autosave on`, which never touches the autosave).
        if (!app->recovered && app->driver->usesAutosave()) app->autosave.remove();
        std::string recentError;
        app->recent.save(app->recentListPath, &recentError);
        app->denoiser.reset();   // joins the worker; deletes its texture while GL is current
        app->preview.reset();    // its renderer and display, while GL is current
        app->bokehPreview.reset();
        app->display.reset();
        app->renderer.reset();
        app->programBuilder.reset();   // the last owner: finishes a build in progress, joins its thread
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    if (builderWindow) glfwDestroyWindow(builderWindow);
    glfwDestroyWindow(window);
    glfwTerminate();
    return exitCode;
}

}  // namespace caustic::editor
