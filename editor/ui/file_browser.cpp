// The in-app file browser (a modal): folders and .json scenes (or .png images when choosing a
// render's output, or model files), a path field, Up, and OK/Cancel. Used for Open, Save As,
// Render to file, Import mesh and a mesh object's file. Save As proposes a name that exists
// nowhere in the folder (suggestSaveAsName), and Save As and Render to file ask before they
// replace an existing file.
#include "editor/model/scene_paths.h"
#include "editor/ui/editor_ui.h"
#include "editor/ui/mesh_import.h"
#include "renderer/mesh_import.h"

#include <imgui.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <utility>

namespace fs = std::filesystem;

namespace caustic::editor {

void openFileBrowser(EditorUi& ui, FileBrowserState::Mode mode) {
    FileBrowserState& b = ui.browser;
    b.open = true;
    b.justOpened = true;
    b.error.clear();
    b.mode = mode;
    std::error_code ec;
    const fs::path current = ui.app.state.path.empty() ? fs::current_path(ec) : fs::absolute(ui.app.state.path, ec).parent_path();
    if (b.directory.empty() || mode != FileBrowserState::Mode::RenderTo) b.directory = current.string();
    b.confirmOverwrite.clear();
    if (mode == FileBrowserState::Mode::SaveAs) b.fileName = suggestSaveAsName(b.directory, ui.app.state.path);
    else if (mode == FileBrowserState::Mode::RenderTo) b.fileName = (ui.app.state.path.empty() ? std::string("render") : fs::path(ui.app.state.path).stem().string()) + ".png";
    else b.fileName.clear();
}

void drawFileBrowser(EditorUi& ui) {
    FileBrowserState& b = ui.browser;
    const char* title = b.mode == FileBrowserState::Mode::Open ? "Open scene###files"
                        : b.mode == FileBrowserState::Mode::SaveAs ? "Save scene as###files"
                        : b.mode == FileBrowserState::Mode::RenderTo ? "Render to file###files"
                        : b.mode == FileBrowserState::Mode::MeshFile ? "Mesh file###files"
                                                                     : "Import mesh###files";
    if (b.justOpened) {
        ImGui::OpenPopup("###files");
        b.justOpened = false;
    }
    ImGui::SetNextWindowSize(ImVec2(640.0f, 440.0f), ImGuiCond_Appearing);
    if (!ImGui::BeginPopupModal(title, &b.open)) return;
    const std::string wanted = b.mode == FileBrowserState::Mode::RenderTo ? ".png" : (b.mode == FileBrowserState::Mode::ImportMesh || b.mode == FileBrowserState::Mode::MeshFile) ? "mesh" : ".json";
    auto listed = [&](const fs::path& p) { return wanted == "mesh" ? isMeshFileExtensionSupported(p.string()) : p.extension() == wanted; };

    char dir[1024];
    std::strncpy(dir, b.directory.c_str(), sizeof dir - 1);
    dir[sizeof dir - 1] = '\0';
    if (ImGui::Button("Up")) b.directory = fs::path(b.directory).parent_path().string();
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1.0f);
    if (ImGui::InputText("##dir", dir, sizeof dir, ImGuiInputTextFlags_EnterReturnsTrue)) b.directory = dir;

    // The listing (folders first); an unreadable folder says so instead of throwing.
    std::vector<fs::directory_entry> dirs, files;
    std::error_code ec;
    for (fs::directory_iterator it(b.directory, fs::directory_options::skip_permission_denied, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.empty() || name[0] == '.') continue;
        std::error_code e2;
        if (it->is_directory(e2)) dirs.push_back(*it);
        else if (listed(it->path())) files.push_back(*it);
    }
    auto byName = [](const fs::directory_entry& a, const fs::directory_entry& c) { return a.path().filename() < c.path().filename(); };
    std::sort(dirs.begin(), dirs.end(), byName);
    std::sort(files.begin(), files.end(), byName);
    bool accept = false;
    ImGui::BeginChild("listing", ImVec2(0.0f, -ImGui::GetFrameHeightWithSpacing() * 2.2f), ImGuiChildFlags_Borders);
    if (ec) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "cannot list this folder: %s", ec.message().c_str());
    else if (dirs.empty() && files.empty()) ImGui::TextDisabled("no folders or %s files here", wanted.c_str());
    for (const auto& d : dirs) {
        if (ImGui::Selectable(("[dir] " + d.path().filename().string()).c_str(), false, ImGuiSelectableFlags_AllowDoubleClick) &&
            ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left))
            b.directory = d.path().string();
    }
    for (const auto& f : files) {
        const std::string name = f.path().filename().string();
        if (ImGui::Selectable(name.c_str(), name == b.fileName, ImGuiSelectableFlags_AllowDoubleClick)) {
            b.fileName = name;
            if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) accept = true;
        }
    }
    ImGui::EndChild();
    char nameBuf[512];
    std::strncpy(nameBuf, b.fileName.c_str(), sizeof nameBuf - 1);
    nameBuf[sizeof nameBuf - 1] = '\0';
    ImGui::SetNextItemWidth(-180.0f);
    if (ImGui::InputText("##name", nameBuf, sizeof nameBuf, ImGuiInputTextFlags_EnterReturnsTrue)) accept = true;
    b.fileName = nameBuf;
    ImGui::SameLine();
    const char* okLabel = b.mode == FileBrowserState::Mode::Open ? "Open" : b.mode == FileBrowserState::Mode::SaveAs ? "Save" : b.mode == FileBrowserState::Mode::RenderTo ? "Render" : b.mode == FileBrowserState::Mode::MeshFile ? "Use" : "Import";
    if (ImGui::Button(okLabel)) accept = true;
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) {
        b.open = false;
        ui.afterUnsavedPrompt = nullptr;
    }
    if (!b.error.empty()) {
        ImGui::PushTextWrapPos(ImGui::GetContentRegionAvail().x);
        ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "%s", b.error.c_str());
        ImGui::PopTextWrapPos();
    }
    // Does what the browser was opened for; false keeps it open (a failed open or save).
    auto finish = [&](const std::string& path) {
        bool ok = true;
        switch (b.mode) {
            case FileBrowserState::Mode::Open: ok = openFile(ui, path); break;
            case FileBrowserState::Mode::SaveAs:
                // A failure is shown here, in the browser, which stays open; a question (a folder
                // to create, a scene batch mode would refuse) is asked once the browser closes.
                switch (requestSave(ui, path, &b.error)) {
                    case SaveResult::Saved:
                        b.error.clear();
                        if (ui.afterUnsavedPrompt) std::exchange(ui.afterUnsavedPrompt, nullptr)();   // "Save" in the unsaved-changes prompt of an untitled scene
                        break;
                    case SaveResult::Asked: b.error.clear(); break;
                    case SaveResult::Failed: ok = false; break;
                }
                break;
            case FileBrowserState::Mode::RenderTo: startRenderToFile(ui, path); break;
            // Imported in the background; the edit applies when the mesh is ready, and a broken
            // file shows its error then, changing nothing (mesh_import.h).
            case FileBrowserState::Mode::ImportMesh: ui.app.meshImports->importFile(ui, path); break;
            case FileBrowserState::Mode::MeshFile:
                ui.app.meshImports->setObjectFile(ui, ui.app.state.selection.kind == EntityKind::Object ? ui.app.state.selection.index : -1, path);
                break;
        }
        if (ok) b.open = false;
    };
    if (accept && !b.fileName.empty()) {
        std::string path = (fs::path(b.directory) / b.fileName).string();
        const bool writes = b.mode == FileBrowserState::Mode::SaveAs || b.mode == FileBrowserState::Mode::RenderTo;
        if (writes && fs::path(path).extension() != wanted) path += wanted;
        std::error_code existsError;
        if (writes && fs::exists(path, existsError)) {
            b.confirmOverwrite = path;   // asked below; nothing is written until "Replace"
            ImGui::OpenPopup("Replace file?");
        } else {
            finish(path);
        }
    }
    if (ImGui::BeginPopupModal("Replace file?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::Text("'%s' exists. Replace it?", b.confirmOverwrite.c_str());
        if (ImGui::Button("Replace")) {
            ImGui::CloseCurrentPopup();
            finish(std::exchange(b.confirmOverwrite, std::string()));
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel##replace") || ImGui::IsKeyPressed(ImGuiKey_Escape)) {
            b.confirmOverwrite.clear();
            ImGui::CloseCurrentPopup();
        }
        ImGui::EndPopup();
    }
    if (!b.open) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
}

}  // namespace caustic::editor
