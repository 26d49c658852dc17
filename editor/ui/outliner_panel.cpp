// The outliner: the camera, render settings, environment, objects, lights and materials. Click
// to select; right-click to rename, duplicate or delete; "Add" makes primitives, lights and
// materials. The lights' section also lists the emissive objects (scene_lights.h), marked as such.
#include "editor/ui/editor_ui.h"
#include "editor/ui/mesh_import.h"
#include "editor/model/lookdev.h"
#include "editor/model/scene_lights.h"

#include <imgui.h>

#include <algorithm>
#include <cstring>

namespace caustic::editor {
namespace {

// Inline rename state: which entity is being renamed, and the text being typed.
struct RenameState {
    EntityRef ref;
    char buffer[256] = {};
    bool focus = false;
};
RenameState g_rename;

void beginRename(const EditorUi& ui, EntityRef ref) {
    g_rename.ref = ref;
    std::strncpy(g_rename.buffer, entityName(ui.app.state.scene, ref).c_str(), sizeof g_rename.buffer - 1);
    g_rename.buffer[sizeof g_rename.buffer - 1] = '\0';
    g_rename.focus = true;
}

void contextMenu(EditorUi& ui, EntityRef ref) {
    if (!ImGui::BeginPopupContextItem()) return;
    if (!ui.app.state.isSelected(ref)) ui.app.state.select(ref);   // a right-click in a multi-selection keeps it
    if (ImGui::MenuItem("Rename")) beginRename(ui, ref);
    if (ImGui::MenuItem("Duplicate", "Ctrl+D")) {
        std::string why;
        if (auto c = makeDuplicate(ui.app.state, ref, &why)) ui.app.state.apply(std::move(c));
        else notify(ui, why, true);
    }
    if (ImGui::MenuItem("Delete", "Del")) {
        std::string why;
        if (auto c = makeDelete(ui.app.state, ref, &why)) ui.app.state.apply(std::move(c));
        else notify(ui, why, true);
    }
    if (ref.kind != EntityKind::Material && ImGui::MenuItem("Frame", "F")) frameSelection(ui);
    ImGui::EndPopup();
}

// suffix: shown after the name (the lights' section marks the emissive objects it lists).
void entityRow(EditorUi& ui, EntityRef ref, const char* icon, const char* suffix = "") {
    ImGui::PushID(static_cast<int>(ref.kind) * 100000 + ref.index);
    std::string name = entityName(ui.app.state.scene, ref);
    if (g_rename.ref == ref && ref) {
        if (g_rename.focus) {
            ImGui::SetKeyboardFocusHere();
            g_rename.focus = false;
        }
        ImGui::SetNextItemWidth(-1.0f);
        const bool done = ImGui::InputText("##rename", g_rename.buffer, sizeof g_rename.buffer,
                                           ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
        if (done || ImGui::IsItemDeactivated()) {
            std::string why;
            if (auto c = makeRename(ui.app.state, ref, g_rename.buffer, &why)) ui.app.state.apply(std::move(c));
            else if (!why.empty()) notify(ui, why, true);
            g_rename.ref = {};
        }
    } else {
        const bool hidden = ref.kind == EntityKind::Object && std::find(ui.app.hidden.begin(), ui.app.hidden.end(), name) != ui.app.hidden.end();
        const std::string label = std::string(icon) + "  " + (name.empty() ? std::string("(unnamed)") : name) +
                                  (hidden ? "  (hidden)" : "") + suffix;
        if (ImGui::Selectable(label.c_str(), ui.app.state.isSelected(ref), ImGuiSelectableFlags_AllowDoubleClick)) {
            // Ctrl or Shift+click adds an object to the selection or takes it out (EditorState::select).
            const ImGuiIO& io = ImGui::GetIO();
            ui.app.state.select(ref, io.KeyCtrl || io.KeyShift ? EditorState::SelectMode::Toggle : EditorState::SelectMode::Replace);
            if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left) && ref.index >= 0) beginRename(ui, ref);
        }
        if (ref.index >= 0) contextMenu(ui, ref);
    }
    ImGui::PopID();
}

void addMenu(EditorUi& ui) {
    if (ImGui::Button("Add")) ImGui::OpenPopup("add-menu");
    if (ImGui::BeginPopup("add-menu")) {
        if (ImGui::MenuItem("Sphere")) ui.app.state.apply(makeAddObject(ui.app.state, Shape::Sphere));
        if (ImGui::MenuItem("Box")) ui.app.state.apply(makeAddObject(ui.app.state, Shape::Box));
        if (ImGui::MenuItem("Quad")) ui.app.state.apply(makeAddObject(ui.app.state, Shape::Quad));
        ImGui::Separator();
        if (ImGui::MenuItem("Point light")) ui.app.state.apply(makeAddLight(ui.app.state, LightType::Point, meshBoundsLookup(ui)));
        if (ImGui::MenuItem("Spot light")) ui.app.state.apply(makeAddLight(ui.app.state, LightType::Spot, meshBoundsLookup(ui)));
        if (ImGui::MenuItem("Rect light")) ui.app.state.apply(makeAddLight(ui.app.state, LightType::Rect, meshBoundsLookup(ui)));
        if (ImGui::MenuItem("Sphere light")) ui.app.state.apply(makeAddLight(ui.app.state, LightType::Sphere, meshBoundsLookup(ui)));
        ImGui::Separator();
        if (ImGui::MenuItem("Material")) ui.app.state.apply(makeAddMaterial(ui.app.state));
        if (ImGui::BeginMenu("Material preset")) {
            // The library (editor/model/lookdev.h), by group.
            std::string_view group;
            for (const LibraryMaterial& l : materialLibrary()) {
                if (l.group != group) {
                    group = l.group;
                    ImGui::SeparatorText(std::string(group).c_str());
                }
                if (ImGui::MenuItem(l.material.name.c_str())) ui.app.state.apply(makeAddMaterial(ui.app.state, &l.material));
            }
            ImGui::EndMenu();
        }
        ImGui::Separator();
        if (ImGui::MenuItem("Import mesh...")) openFileBrowser(ui, FileBrowserState::Mode::ImportMesh);
        ImGui::EndPopup();
    }
}

template <class List>
void section(EditorUi& ui, const char* title, const List& list, EntityKind kind, const char* icon) {
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    const std::string header = std::string(title) + " (" + std::to_string(list.size()) + ")";
    if (!ImGui::CollapsingHeader(header.c_str())) return;
    if (list.empty()) ImGui::TextDisabled("  none: use Add");
    for (size_t i = 0; i < list.size(); ++i) entityRow(ui, {kind, static_cast<int>(i)}, icon);
}

// The lights, then the emissive objects (a row selects the object): both light the scene.
void lightsSection(EditorUi& ui) {
    const Scene& scene = ui.app.state.scene;
    const std::vector<int> emissive = emissiveObjects(scene);
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    const std::string header = "Lights (" + std::to_string(scene.lights.size() + emissive.size()) + ")";
    if (!ImGui::CollapsingHeader(header.c_str())) return;
    if (scene.lights.empty() && emissive.empty()) ImGui::TextDisabled("  none: use Add");
    for (size_t i = 0; i < scene.lights.size(); ++i) entityRow(ui, {EntityKind::Light, static_cast<int>(i)}, "[L]");
    ImGui::PushID("emissive");   // the objects' rows again, in their own ID scope
    for (int i : emissive) entityRow(ui, {EntityKind::Object, i}, "[O]", "  (emissive object)");
    ImGui::PopID();
}

}  // namespace

void drawOutlinerPanel(EditorUi& ui) {
    const bool open = ImGui::Begin("Outliner");
    ui.outlinerFocused = open && ImGui::IsWindowFocused(ImGuiFocusedFlags_RootAndChildWindows);
    if (!open) {
        ImGui::End();
        return;
    }
    addMenu(ui);
    ImGui::SameLine();
    ImGui::BeginDisabled(!ui.app.state.selection || ui.app.state.selection.index < 0);
    if (ImGui::Button("Duplicate")) {
        std::string why;
        if (auto c = makeDuplicate(ui.app.state, ui.app.state.selection, &why)) ui.app.state.apply(std::move(c));
    }
    ImGui::SameLine();
    if (ImGui::Button("Delete")) {
        std::string why;
        if (auto c = makeDelete(ui.app.state, ui.app.state.selection, &why)) ui.app.state.apply(std::move(c));
        else notify(ui, why, true);
    }
    ImGui::EndDisabled();
    // A mesh being imported in the background appears in the list once it is ready.
    if (const std::string importing = ui.app.meshImports->status(); !importing.empty()) ImGui::TextDisabled("%s", importing.c_str());
    ImGui::Separator();
    entityRow(ui, {EntityKind::Camera, -1}, "[C]");
    entityRow(ui, {EntityKind::Render, -1}, "[R]");
    entityRow(ui, {EntityKind::Environment, -1}, "[E]");
    section(ui, "Objects", ui.app.state.scene.objects, EntityKind::Object, "[O]");
    lightsSection(ui);
    section(ui, "Materials", ui.app.state.scene.materials, EntityKind::Material, "[M]");
    ImGui::End();
}

}  // namespace caustic::editor
