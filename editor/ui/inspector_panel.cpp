// The inspector: the selection's parameters, drawn from the scene schema (param_widgets.h), so
// every parameter a file may hold has its widget, with the loader's own range. Every widget edits
// a copy; a change becomes one step of an edit command (continuous while a drag or slider is held,
// sealed on release, so one drag is one undo step), checked by the loader's rules before it
// applies (an invalid edit is refused with the reason in the status bar; the scene keeps its last
// good state).
#include "editor/model/viewport_math.h"
#include "renderer/camera.h"
#include "editor/ui/editor_ui.h"
#include "editor/ui/asset_picker.h"
#include "editor/ui/material_preview.h"
#include "editor/ui/mesh_import.h"
#include "editor/ui/param_widgets.h"
#include "editor/model/lookdev.h"
#include "editor/ui/viewport_denoise.h"
#include "renderer/denoise.h"
#include "renderer/mesh_cache.h"
#include "renderer/renderer.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <variant>

namespace caustic::editor {
namespace {

// The thin lens's f-stop field: scenes may open the aperture wider than any real lens (dof.json is
// f/0.09 in its scene units), so the field goes far below f/0.5.
constexpr float kMinFStop = 0.01f;

template <size_t N>
bool combo(const char* label, int* value, const char* const (&items)[N]) {
    return ImGui::Combo(label, value, items, static_cast<int>(N));
}

// A name field; renames through a command when the field is left.
void nameField(EditorUi& ui, EntityRef ref) {
    traceWidget("name", ParamKind::Name);
    static EntityRef s_for;
    static char s_buffer[256];
    const std::string current = entityName(ui.app.state.scene, ref);
    if (!(s_for == ref) || !ImGui::IsItemActive()) {
        if (!(s_for == ref) || std::strcmp(s_buffer, current.c_str()) != 0) {
            std::strncpy(s_buffer, current.c_str(), sizeof s_buffer - 1);
            s_buffer[sizeof s_buffer - 1] = '\0';
        }
        s_for = ref;
    }
    ImGui::InputText("Name", s_buffer, sizeof s_buffer);
    if (ImGui::IsItemDeactivatedAfterEdit()) {
        std::string why;
        if (auto c = makeRename(ui.app.state, ref, s_buffer, &why)) ui.app.state.apply(std::move(c));
        else if (!why.empty()) notify(ui, why, true);
    }
}

// The library's presets, grouped, as menu items; returns the one picked (null: none).
const Material* presetMenuItems() {
    const Material* picked = nullptr;
    std::string_view group;
    for (const LibraryMaterial& l : materialLibrary()) {
        if (l.group != group) {
            group = l.group;
            ImGui::SeparatorText(std::string(group).c_str());
        }
        if (ImGui::Selectable(l.material.name.c_str())) picked = &l.material;
    }
    return picked;
}

// The preview ball (material_preview.h) and its lighting, above the material's parameters.
void previewSection(EditorUi& ui, const Material& m) {
    if (!ui.app.preview) return;
    MaterialPreview& p = *ui.app.preview;
    p.request(ui.app.state.scene, m);
    const float side = static_cast<float>(MaterialPreview::kSize) * ImGui::GetFontSize() / 13.0f;
    if (const unsigned tex = p.texture())
        ImGui::Image(ImTextureRef(static_cast<ImTextureID>(tex)), ImVec2(side, side));
    else
        ImGui::Dummy(ImVec2(side, side));
    ImGui::SameLine();
    ImGui::BeginGroup();
    ImGui::TextUnformatted("Preview");
    int lighting = static_cast<int>(p.lighting);
    if (ImGui::RadioButton("Scene light", &lighting, 0)) p.lighting = PreviewLighting::Scene;
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("the scene's environment (a studio light when it has none)");
    if (ImGui::RadioButton("Studio", &lighting, 1)) p.lighting = PreviewLighting::Studio;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("a key light and an even grey fill");
    if (p.lighting == PreviewLighting::Scene && ui.app.state.scene.environment.type == EnvironmentType::None)
        ImGui::TextDisabled("(no environment:\n a studio light)");
    if (p.buildingShaders()) ImGui::TextDisabled("building shaders...");
    else ImGui::TextDisabled("%d / %d spp", p.samples(), MaterialPreview::kSamples);
    ImGui::EndGroup();
    if (!p.error().empty()) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "preview: %s", p.error().c_str());
}

// The material's parameters (its type's, from the schema), with the preview ball and the preset
// library above them. From the object inspector (shared material) the name is shown, not edited.
void materialParams(EditorUi& ui, int index, bool renamable) {
    EditorState& s = ui.app.state;
    Material m = s.scene.materials[static_cast<size_t>(index)];
    previewSection(ui, m);
    if (ImGui::BeginCombo("Preset", "apply a preset...", ImGuiComboFlags_HeightLarge)) {
        if (const Material* preset = presetMenuItems()) s.apply(makeApplyPreset(s, index, *preset));
        ImGui::EndCombo();
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("gives this material a preset's model and parameters (its name and objects stay)");
    m = s.scene.materials[static_cast<size_t>(index)];
    const MaterialType before = m.type;
    Edit e{ui};
    drawParams<Material>(e, m, [&](const Param<Material>& p, Material& value) {
        if (p.kind == ParamKind::Enum && p.key == "type") {
            // The models by what an artist calls them; the file's names in the tooltip.
            const auto choices = p.choices();
            traceWidget(p.key, p.kind, 0, static_cast<double>(choices.size()) - 1);
            const int current = p.getEnum(value);
            if (ImGui::BeginCombo(std::string(p.label).c_str(),
                                  std::string(materialTypeArtistName(static_cast<MaterialType>(current))).c_str(),
                                  ImGuiComboFlags_HeightLarge)) {
                for (const EnumChoice& c : choices) {
                    const std::string label = std::string(materialTypeArtistName(static_cast<MaterialType>(c.value))) + "  (" +
                                              std::string(c.label) + ")";
                    if (ImGui::Selectable(label.c_str(), c.value == current) && c.value != current) {
                        p.setEnum(value, c.value);
                        e.changed = e.seal = true;
                    }
                    if (ImGui::IsItemHovered()) ImGui::SetTooltip("\"%s\" in scene files: %s", c.name.data(), c.label.data());
                }
                ImGui::EndCombo();
            }
            return true;
        }
        if (p.kind != ParamKind::Name) return false;
        if (renamable) nameField(ui, {EntityKind::Material, index});
        else traceWidget(p.key, p.kind);
        return true;
    });
    if (m.type != before) {
        // A new type takes its own defaults for the parameters (schema rows) the old type did not
        // have (an eon's roughness 0.5, a dielectric's GGX alpha 0); everything else is kept.
        const Material defaults = materialDefaults(m.type);
        for (const Param<Material>& p : schemaOf<Material>()) {
            if (!takesKey(p, int(m.type)) || takesKey(p, int(before))) continue;
            if (p.kind == ParamKind::Enum) p.setEnum(m, p.getEnum(defaults));
            else
                std::visit([&](auto member) {
                    if constexpr (!std::is_same_v<decltype(member), std::monostate>) m.*member = defaults.*member;
                }, p.member);
        }
    }
    e.commit(e.changed ? makeSetMaterial(s, index, m) : nullptr);
}

// A mesh with its file's own materials lists them (as the renderer's import mapped them).
void fileMaterialList(EditorUi& ui, const Object& o) {
    if (!ui.app.renderer) return;
    const auto entry = ui.app.renderer->meshCache().find(meshCacheKey(ui.app.state.scene, o.file));
    if (!entry) return;
    std::string names;
    for (const Material& m : entry->materials) names += (names.empty() ? "" : ", ") + m.name;
    ImGui::TextDisabled("%zu material%s from the file: %s", entry->materials.size(), entry->materials.size() == 1 ? "" : "s",
                        names.c_str());
}

// The object's material: New (from the library or the default), Make unique, and, with several
// objects selected, an assignment that reaches all of them.
void objectMaterialButtons(EditorUi& ui, int index) {
    EditorState& s = ui.app.state;
    std::vector<int> targets = s.selectedObjects();
    if (targets.empty()) targets = {index};
    if (ImGui::Button("New material")) ImGui::OpenPopup("new-material");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("a new material (the default or a preset) for the selected object%s", targets.size() > 1 ? "s" : "");
    if (ImGui::BeginPopup("new-material")) {
        std::string why;
        if (ImGui::Selectable("Default material")) {
            if (auto c = makeNewMaterialFor(s, targets, nullptr, &why)) s.apply(std::move(c));
            else notify(ui, why, true);
        }
        if (const Material* preset = presetMenuItems()) {
            if (auto c = makeNewMaterialFor(s, targets, preset, &why)) s.apply(std::move(c));
            else notify(ui, why, true);
        }
        ImGui::EndPopup();
    }
    ImGui::SameLine();
    std::string why;
    const bool canUnique = makeMakeUnique(s, targets, &why) != nullptr;
    ImGui::BeginDisabled(!canUnique);
    if (ImGui::Button("Make unique")) {
        if (auto c = makeMakeUnique(s, targets, &why)) s.apply(std::move(c));
    }
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("%s", canUnique ? "a copy of the shared material for the selection alone, so edits reach no other object"
                                          : why.c_str());
    const std::string& name = s.scene.objects[static_cast<size_t>(index)].material;
    if (!name.empty()) {
        const int users = materialUsers(s.scene, name);
        ImGui::TextDisabled(users == 1 ? "material of this object only" : "material shared by %d objects", users);
    }
}

void objectInspector(EditorUi& ui, int index) {
    EditorState& s = ui.app.state;
    Object o = s.scene.objects[static_cast<size_t>(index)];
    const std::vector<int> selected = s.selectedObjects();
    if (selected.size() > 1)
        ImGui::TextWrapped("%d objects selected (Ctrl+click adds or removes one); the material applies to all of them, "
                           "the rest to '%s'.", int(selected.size()), o.name.c_str());
    Edit e{ui};
    drawParams<Object>(e, o, [&](const Param<Object>& p, Object& obj) {
        switch (p.kind) {
            case ParamKind::Name: nameField(ui, {EntityKind::Object, index}); return true;
            case ParamKind::Reference:
                traceWidget(p.key, p.kind);
                if (ImGui::BeginCombo("Material", obj.material.empty() ? "(the file's own)" : obj.material.c_str())) {
                    // A mesh may go back to its file's own materials (an import keeps them).
                    if (obj.shape == Shape::Mesh && selected.size() <= 1 &&
                        ImGui::Selectable("(the file's own)", obj.material.empty())) {
                        obj.material.clear();
                        e.changed = e.seal = true;
                    }
                    for (const Material& m : s.scene.materials) {
                        if (ImGui::Selectable(m.name.c_str(), m.name == obj.material)) {
                            if (selected.size() > 1) {
                                // Every selected object, one undo step.
                                std::string why;
                                if (auto c = makeAssignMaterial(s, selected, m.name, &why)) s.apply(std::move(c));
                            } else {
                                obj.material = m.name;
                                e.changed = e.seal = true;
                            }
                        }
                    }
                    ImGui::EndCombo();
                }
                if (obj.shape == Shape::Mesh && obj.material.empty()) fileMaterialList(ui, obj);
                objectMaterialButtons(ui, index);
                return true;
            case ParamKind::File:
                // Another file: imported in the background, applied when ready (mesh_import.h).
                traceWidget(p.key, p.kind);
                ImGui::TextDisabled("File: %s", obj.file.empty() ? "(none)" : obj.file.c_str());
                if (s.scene.objects[static_cast<size_t>(index)].shape == Shape::Mesh) {
                    ImGui::SameLine();
                    if (ImGui::SmallButton("Replace...")) openFileBrowser(ui, FileBrowserState::Mode::MeshFile);
                    ImGui::SameLine();
                    // The scene's and the assets folder's model files; imported in the background.
                    if (const auto picked = assetPickerButton(ui, "mesh-file", AssetKind::Mesh))
                        ui.app.meshImports->setObjectFile(ui, index, picked->absolute);
                }
                return true;
            default: return false;
        }
    });
    e.commit(e.changed ? makeSetObject(s, index, o) : nullptr);
    if (const Material* m = s.scene.findMaterial(o.material); m && ImGui::TreeNode("Material parameters and preview")) {
        if (materialUsers(s.scene, m->name) > 1) ImGui::TextDisabled("(edits the shared material '%s')", m->name.c_str());
        materialParams(ui, findEntity(s.scene, EntityKind::Material, m->name).index, false);
        ImGui::TreePop();
    }
}

void materialInspector(EditorUi& ui, int index) {
    materialParams(ui, index, true);
    const std::string& name = ui.app.state.scene.materials[static_cast<size_t>(index)].name;
    int users = 0;
    for (const Object& o : ui.app.state.scene.objects) users += o.material == name;
    ImGui::TextDisabled("Used by %d object%s", users, users == 1 ? "" : "s");
}

void lightInspector(EditorUi& ui, int index) {
    EditorState& s = ui.app.state;
    Light l = s.scene.lights[static_cast<size_t>(index)];
    Edit e{ui};
    drawParams<Light>(e, l, [&](const Param<Light>& p, Light& light) {
        if (p.kind == ParamKind::Name) {
            nameField(ui, {EntityKind::Light, index});
            return true;
        }
        if (p.key == "color") {
            // Radiance for area lights, intensity for point and spot lights.
            traceWidget(p.key, p.kind, 0.0, p.range.max);
            const bool area = light.type == LightType::Rect || light.type == LightType::Sphere;
            colourAndStrength(e, "Colour", area ? "Radiance" : "Intensity", &light.color, p.range.max);
            return true;
        }
        return false;
    });
    // Dragging the outer angle below the inner one takes the inner one along.
    if (e.changed && l.type == LightType::Spot) l.innerAngle = std::min(l.innerAngle, l.outerAngle);
    e.commit(e.changed ? makeSetLight(s, index, l) : nullptr);
}

void cameraInspector(EditorUi& ui) {
    EditorState& s = ui.app.state;
    Camera c = s.scene.camera;
    const int blades = c.blades;
    Edit e{ui};
    drawParams<Camera>(e, c);
    // A lens system: what the renderer made of it (focal length, stops, focus), read-only.
    if (!c.lens.empty()) {
        ImGui::SeparatorText("As traced");
        if (const LensCamera* lens = ui.app.renderer ? ui.app.renderer->lensCamera() : nullptr) {
            ImGui::TextWrapped("%s", lens->lens.name.c_str());
            ImGui::Text("focal length %.1f mm, f/%.2f (wide open f/%.2f)", lens->efl, lens->fNumber, lens->fNumberOpen);
            ImGui::Text("focused at %.3g m%s", lens->focusDistanceMm / kMillimetresPerSceneUnit,
                        lens->notes.empty() ? "" : " (see the note below)");
            for (const std::string& note : lens->notes) ImGui::TextDisabled("%s", note.c_str());
        } else {
            ImGui::TextDisabled("not loaded (see the status line)");
        }
    }
    // The same lens in a photographer's terms (renderer/camera.h): views of fov and the aperture
    // radius, with scene units read as metres (the thin lens only).
    if (c.lens.empty()) {
        ImGui::SeparatorText("Photographic (35 mm, metres)");
        const RenderSettings& rs = s.scene.render;
        const double aspect = double(rs.width) / double(rs.height);
        const CameraFrame frame = cameraFrame(c, aspect);
        float mm = static_cast<float>(focalLengthMm(frame));
        const bool mmChanged = ImGui::DragFloat("Focal length", &mm, 0.2f, 1.0f, 10000.0f, "%.1f mm");
        e.track(mmChanged);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("of a 36 x 24 mm sensor whose 36 mm span the image's longer side, with scene units read as "
                              "metres; sets the field of view");
        if (mmChanged) c.fovDegrees = static_cast<float>(fovForFocalLength(c, aspect, std::clamp(mm, 1.0f, 10000.0f)));
        const double n = fNumber(frame);
        float stop = std::isfinite(n) ? static_cast<float>(n) : 0.0f;
        const bool stopChanged = ImGui::DragFloat("f-stop", &stop, 0.05f, kMinFStop, 256.0f, std::isfinite(n) ? "f/%.2f" : "pinhole");
        e.track(stopChanged);
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("N = focal length / (2 x aperture radius); sets the aperture radius");
        if (stopChanged)
            c.apertureRadius = static_cast<float>(apertureRadiusForFNumber(cameraFrame(c, aspect), std::clamp(stop, kMinFStop, 256.0f)));
    }
    // 1 and 2 blades are no polygon: step over them.
    if (c.blades == 1 || c.blades == 2) c.blades = blades > c.blades ? 0 : 3;
    e.commit(e.changed ? makeSetCamera(s, c) : nullptr);
    if (ImGui::Button("Frame all (F)")) {
        s.selection = {EntityKind::Camera, -1};
        frameSelection(ui, true);
    }
    // Saved views (camera_views.h): the editor's own, by scene file, not in the scene.
    // The bokeh preview (lookdev.h): points across the frame behind the focus, through this camera.
    // Closed until opened: its first render builds a program of its own (seconds on llvmpipe).
    if (ImGui::CollapsingHeader("Bokeh preview") && ui.app.bokehPreview) {
        MaterialPreview& p = *ui.app.bokehPreview;
        p.requestScene(makeBokehPreviewScene(s.scene, ui.app.renderer ? ui.app.renderer->lensCamera() : nullptr));
        const float w = ImGui::GetContentRegionAvail().x;
        const float h = w * float(p.height()) / float(std::max(p.width(), 1));
        if (const unsigned tex = p.texture()) ImGui::Image(ImTextureRef(static_cast<ImTextureID>(tex)), ImVec2(w, h));
        else ImGui::Dummy(ImVec2(w, h));
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("points of light across the frame at ten times the focus distance: the bokeh's shape at "
                              "each place of the frame");
        if (p.buildingShaders()) ImGui::TextDisabled("building shaders...");
        else ImGui::TextDisabled("%d / %d spp", p.samples(), p.targetSamples());
        if (!p.error().empty()) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "preview: %s", p.error().c_str());
    }
    ImGui::SeparatorText("Saved views");
    static char s_viewName[128] = "";
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 10.0f);
    ImGui::InputTextWithHint("##viewname", ui.app.views.nextName(s.path).c_str(), s_viewName, sizeof s_viewName);
    ImGui::SameLine();
    if (ImGui::Button("Store view")) {
        storeCameraView(ui, s_viewName[0] ? std::string(s_viewName) : ui.app.views.nextName(s.path));
        s_viewName[0] = '\0';
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("keeps this camera under the name (kept by the editor for this scene file, not saved in the scene)");
    std::string remove;
    for (const CameraView& v : ui.app.views.of(s.path)) {
        ImGui::PushID(v.name.c_str());
        if (ImGui::SmallButton("Recall")) recallCameraView(ui, v.name);
        ImGui::SameLine();
        if (ImGui::SmallButton("x")) remove = v.name;
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("forget this view");
        ImGui::SameLine();
        ImGui::TextUnformatted(v.name.c_str());
        ImGui::PopID();
    }
    if (!remove.empty()) deleteCameraView(ui, remove);
    if (ui.app.views.of(s.path).empty()) ImGui::TextDisabled("none yet%s", s.path.empty() ? " (an untitled scene's last until it closes)" : "");
}

void renderInspector(EditorUi& ui) {
    EditorState& s = ui.app.state;
    RenderSettings r = s.scene.render;
    Edit e{ui};
    drawParams<RenderSettings>(e, r);
    e.commit(e.changed ? makeSetRender(s, r) : nullptr);

    ImGui::SeparatorText("Display (not saved in the scene)");
    static const char* const tones[] = {"ACES filmic", "Reinhard"};
    int tone = static_cast<int>(s.view.toneMap);
    if (combo("Tone mapping", &tone, tones)) s.view.toneMap = static_cast<ToneMap>(tone);
    ImGui::DragFloat("Exposure", &s.view.exposure, 0.02f, -20.0f, 20.0f, "%.2f EV");
    if (ui.app.denoiser) {
        // Denoising (view state like the tone curve): viewport_denoise.h.
        DenoiseSettings& d = ui.app.denoiser->settings;
        const bool available = denoiserAvailable();
        ImGui::BeginDisabled(!available);
        ImGui::Checkbox("Denoise (OIDN) at target", &d.autoDenoise);
        if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
            ImGui::SetTooltip(available ? "Denoise with Open Image Denoise when the render reaches its target samples"
                                        : "Open Image Denoise is not in this build");
        ImGui::Checkbox("Denoise when idle", &d.idleDenoise);
        if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
            ImGui::SetTooltip("a second after the last input, at 4 spp and at each doubling; shown while the render goes on");
        if (ImGui::Button("Denoise now (F6)")) denoiseNow(ui);
        ImGui::SameLine();
        bool raw = !d.showDenoised;
        if (ImGui::Checkbox("Show raw", &raw)) d.showDenoised = !raw;
        if (ui.app.denoiser->holding()) {
            ImGui::SameLine();
            if (ImGui::Button("Resume")) ui.app.denoiser->resume(ui);
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("Denoise now paused the render at its sample count; continue it");
        }
        ImGui::Checkbox("Prefilter guides", &d.prefilterGuides);
        ImGui::EndDisabled();
        if (const std::string st = ui.app.denoiser->status(ui); !st.empty()) ImGui::TextDisabled("%s", st.c_str());
    }
    ImGui::Separator();
    if (ImGui::Button("Restart render")) s.markDirty(kDirtySettings);
    ImGui::SameLine();
    if (ImGui::Button("Render to file...")) openFileBrowser(ui, FileBrowserState::Mode::RenderTo);
}

void environmentInspector(EditorUi& ui) {
    EditorState& s = ui.app.state;
    Environment env = s.scene.environment;
    Edit e{ui};
    drawParams<Environment>(e, env, [&](const Param<Environment>& p, Environment& value) {
        if (p.kind != ParamKind::Preset) return false;
        // The named looks (docs/scene-format.md): one click sets horizon, zenith and intensity.
        traceWidget(p.key, p.kind);
        ImGui::TextUnformatted("Preset:");
        for (const SkyPreset& preset : skyPresets()) {
            ImGui::SameLine();
            if (ImGui::SmallButton(std::string(preset.name).c_str())) {
                applySkyPreset(preset, value);
                e.changed = e.seal = true;
            }
        }
        return true;
    });
    if (env.type == EnvironmentType::None) ImGui::TextDisabled("Rays that leave the scene see black.");
    e.commit(e.changed ? makeSetEnvironment(s, env) : nullptr);
}

}  // namespace

void drawInspectorPanel(EditorUi& ui) {
    if (!ImGui::Begin("Inspector")) {
        ImGui::End();
        return;
    }
    ui.app.state.validateSelection();
    const EntityRef sel = ui.app.state.selection;
    // Room for the longest labels ("Roughness texture", "Russian roulette") beside the fields.
    ImGui::PushItemWidth(-ImGui::CalcTextSize("Roughness texture  ").x);
    switch (sel.kind) {
        case EntityKind::None:
            ImGui::TextWrapped("Nothing selected. Click an object in the viewport or pick an entry in the Outliner; "
                               "the camera, render settings and environment are at the top of the Outliner.");
            break;
        case EntityKind::Object: objectInspector(ui, sel.index); break;
        case EntityKind::Light: lightInspector(ui, sel.index); break;
        case EntityKind::Material: materialInspector(ui, sel.index); break;
        case EntityKind::Camera: cameraInspector(ui); break;
        case EntityKind::Render: renderInspector(ui); break;
        case EntityKind::Environment: environmentInspector(ui); break;
    }
    ImGui::PopItemWidth();
    ImGui::End();
}

}  // namespace caustic::editor
