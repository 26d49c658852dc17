#include "editor/ui/asset_picker.h"

#include "editor/model/scene_paths.h"
#include "editor/ui/editor_ui.h"

#include <imgui.h>

#include <cstring>
#include <string>
#include <vector>

namespace caustic::editor {
namespace {

struct PickerCache {
    std::string id;
    std::vector<AssetFile> files;
    std::string sceneFolder, assetsFolder;
    char filter[128] = {};
};
PickerCache g_picker;

const char* kindText(AssetKind kind) {
    switch (kind) {
        case AssetKind::Texture: return "textures";
        case AssetKind::Mesh: return "model files";
        case AssetKind::EnvironmentMap: return "HDR maps (.hdr, .exr)";
        case AssetKind::Lens: return "lens prescriptions (.lens)";
    }
    return "files";
}

}  // namespace

float assetPickerButtonWidth() { return ImGui::CalcTextSize("...").x + ImGui::GetStyle().FramePadding.x * 2.0f; }

std::optional<AssetFile> assetPickerButton(EditorUi& ui, const char* id, AssetKind kind) {
    std::optional<AssetFile> picked;
    ImGui::PushID(id);
    if (ImGui::Button("...")) {
        g_picker.id = id;
        g_picker.sceneFolder = sceneFolderOf(ui.app.state.path);
        g_picker.assetsFolder = assetsFolderFor(g_picker.sceneFolder);
        g_picker.files = listAssetFiles(kind, g_picker.sceneFolder, g_picker.assetsFolder);
        g_picker.filter[0] = '\0';
        ImGui::OpenPopup("asset-picker");
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("pick one of the %s in the scene's folder and the assets folder (stored relative to the scene)",
                          kindText(kind));
    ImGui::SetNextWindowSizeConstraints(ImVec2(ImGui::GetFontSize() * 22.0f, 0.0f),
                                        ImVec2(ImGui::GetFontSize() * 40.0f, ImGui::GetFontSize() * 30.0f));
    if (ImGui::BeginPopup("asset-picker")) {
        ImGui::SetNextItemWidth(-1.0f);
        if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
        ImGui::InputTextWithHint("##filter", "filter", g_picker.filter, sizeof g_picker.filter);
        std::string root;
        int shown = 0;
        for (const AssetFile& f : g_picker.files) {
            if (g_picker.filter[0] && f.display.find(g_picker.filter) == std::string::npos) continue;
            if (f.root != root) {
                root = f.root;
                const std::string& folder = root == "assets" ? g_picker.assetsFolder : g_picker.sceneFolder;
                ImGui::SeparatorText((root + ": " + folder).c_str());
            }
            ++shown;
            if (ImGui::Selectable(f.display.c_str())) {
                picked = f;
                ImGui::CloseCurrentPopup();
            }
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("stored as %s", f.stored.c_str());
        }
        if (shown == 0)
            ImGui::TextDisabled("no %s in the scene's folder%s", kindText(kind),
                                g_picker.assetsFolder.empty() ? " (and no assets folder beside it)" : " or the assets folder");
        ImGui::EndPopup();
    }
    ImGui::PopID();
    return picked;
}

}  // namespace caustic::editor
