// The inspector: the selection's parameters. Every widget edits a copy; a change becomes one
// step of an edit command (continuous while a drag or slider is held, sealed on release, so one
// drag is one undo step). Written against renderer/scene.h: new material or light types extend
// the combo tables and the per-type sections below.
#include "editor/model/viewport_math.h"
#include "editor/ui/editor_ui.h"
#include "editor/ui/viewport_denoise.h"
#include "renderer/denoise.h"

#include <imgui.h>

#include <algorithm>
#include <cstring>

namespace caustic::editor {
namespace {

// Tracks the widgets of one inspector section: whether any changed the copy and whether the
// edit is complete (a released drag, a typed value, a combo or checkbox).
struct Edit {
    EditorUi& ui;
    bool changed = false, seal = false;
    void track(bool c, bool discrete = false) {
        changed |= c;
        if ((discrete && c) || ImGui::IsItemDeactivatedAfterEdit()) seal = true;
        if (ImGui::IsItemActive()) {
            ui.interacting = true;
            ui.lastInteraction = ImGui::GetTime();
        }
    }
    void commit(std::unique_ptr<Command> command) {
        std::string why;
        if (changed && command && !ui.state.applyContinuous(std::move(command), &why)) notify(ui, why, true);
        if (seal) ui.state.seal();
    }
};

template <size_t N>
bool combo(const char* label, int* value, const char* const (&items)[N]) {
    return ImGui::Combo(label, value, items, static_cast<int>(N));
}

// A name field; renames through a command when the field is left.
void nameField(EditorUi& ui, EntityRef ref) {
    static EntityRef s_for;
    static char s_buffer[256];
    const std::string current = entityName(ui.state.scene, ref);
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
        if (auto c = makeRename(ui.state, ref, s_buffer, &why)) ui.state.apply(std::move(c));
        else if (!why.empty()) notify(ui, why, true);
    }
}

// Radiance as colour x strength, so brightness and hue are edited separately.
bool colourAndStrength(Edit& e, const char* colourLabel, const char* strengthLabel, glm::vec3* value) {
    float strength = std::max({value->x, value->y, value->z});
    glm::vec3 tint = strength > 0.0f ? *value / strength : glm::vec3(1.0f);
    bool c1 = ImGui::ColorEdit3(colourLabel, &tint.x, ImGuiColorEditFlags_Float);
    e.track(c1);
    bool c2 = ImGui::DragFloat(strengthLabel, &strength, 0.05f, 0.0f, 1e6f, "%.3f", ImGuiSliderFlags_AlwaysClamp);
    e.track(c2);
    if (c1 || c2) *value = glm::max(tint, glm::vec3(0.0f)) * strength;
    return c1 || c2;
}

void transformFields(Edit& e, Transform* t) {
    if (t->matrix) {
        ImGui::TextDisabled("Transform: a matrix (from the file)");
        if (ImGui::Button("Convert to translate / rotate / scale")) {
            *t = transformFromMatrix(*t->matrix);
            e.track(true, true);
        }
        return;
    }
    e.track(ImGui::DragFloat3("Translate", &t->translate.x, 0.01f, 0.0f, 0.0f, "%.3f"));
    e.track(ImGui::DragFloat3("Rotate", &t->rotate.x, 0.5f, 0.0f, 0.0f, "%.1f deg"));
    e.track(ImGui::DragFloat3("Scale", &t->scale.x, 0.005f, 0.0f, 0.0f, "%.3f"));
}

void objectInspector(EditorUi& ui, int index) {
    EditorState& s = ui.state;
    Object o = s.scene.objects[static_cast<size_t>(index)];
    nameField(ui, {EntityKind::Object, index});
    Edit e{ui};
    static const char* const shapes[] = {"sphere", "quad", "box", "mesh"};
    int shape = static_cast<int>(o.shape);
    e.track(combo("Shape", &shape, shapes), true);
    o.shape = static_cast<Shape>(shape);
    if (o.shape == Shape::Mesh) {
        ImGui::TextDisabled("File: %s", o.file.empty() ? "(none)" : o.file.c_str());
        // Another file: imported in the background, applied when ready (mesh_import.h).
        if (s.scene.objects[static_cast<size_t>(index)].shape == Shape::Mesh) {
            ImGui::SameLine();
            if (ImGui::SmallButton("Replace...")) openFileBrowser(ui, FileBrowserState::Mode::MeshFile);
        }
    }
    if (ImGui::BeginCombo("Material", o.material.c_str())) {
        for (const Material& m : s.scene.materials) {
            if (ImGui::Selectable(m.name.c_str(), m.name == o.material)) {
                o.material = m.name;
                e.changed = e.seal = true;
            }
        }
        ImGui::EndCombo();
    }
    ImGui::SeparatorText("Transform");
    transformFields(e, &o.transform);
    // The object's own emission (docs/scene-format.md, objects): replaces the material's, front
    // faces only unless two-sided; the surface still reflects by its material.
    ImGui::SeparatorText("Emission");
    colourAndStrength(e, "Emission colour", "Emission strength", &o.emission);
    if (o.emits()) e.track(ImGui::Checkbox("Two-sided", &o.twoSided), true);
    e.commit(e.changed ? makeSetObject(s, index, o) : nullptr);
    if (const Material* m = s.scene.findMaterial(o.material); m && ImGui::TreeNode("Material parameters")) {
        ImGui::TextDisabled("(edits the shared material '%s')", m->name.c_str());
        const int mi = findEntity(s.scene, EntityKind::Material, m->name).index;
        Material copy = *m;
        Edit me{ui};
        me.track(ImGui::ColorEdit3("Albedo", &copy.albedo.x, ImGuiColorEditFlags_Float));
        me.commit(me.changed ? makeSetMaterial(s, mi, copy) : nullptr);
        ImGui::TreePop();
    }
}

void materialInspector(EditorUi& ui, int index) {
    EditorState& s = ui.state;
    Material m = s.scene.materials[static_cast<size_t>(index)];
    nameField(ui, {EntityKind::Material, index});
    Edit e{ui};
    // In the order of MaterialType (renderer/scene.h); a new type adds a name here and a case below.
    static const char* const types[] = {"diffuse", "oren_nayar", "eon", "mirror", "transmission", "dielectric", "conductor"};
    static_assert(sizeof types / sizeof types[0] == static_cast<size_t>(MaterialType::Conductor) + 1);
    int type = static_cast<int>(m.type);
    e.track(combo("Type", &type, types), true);
    m.type = static_cast<MaterialType>(type);
    const ImGuiColorEditFlags colour = ImGuiColorEditFlags_Float;
    switch (m.type) {
        case MaterialType::Diffuse:
            e.track(ImGui::ColorEdit3("Albedo", &m.albedo.x, colour));
            break;
        case MaterialType::OrenNayar:
            e.track(ImGui::ColorEdit3("Albedo", &m.albedo.x, colour));
            e.track(ImGui::SliderFloat("Sigma", &m.sigma, 0.0f, 1.5707964f, "%.3f rad", ImGuiSliderFlags_AlwaysClamp));
            e.track(ImGui::Checkbox("Energy compensation", &m.energyCompensation), true);
            break;
        case MaterialType::Eon:
            e.track(ImGui::ColorEdit3("Albedo", &m.albedo.x, colour));
            e.track(ImGui::SliderFloat("Roughness", &m.roughness, 0.0f, 1.0f, "%.3f", ImGuiSliderFlags_AlwaysClamp));
            break;
        case MaterialType::Mirror:
            e.track(ImGui::ColorEdit3("Tint", &m.tint.x, colour));
            break;
        case MaterialType::Transmission:
        case MaterialType::Dielectric:
            e.track(ImGui::ColorEdit3("Tint", &m.tint.x, colour));
            e.track(ImGui::DragFloat("IOR", &m.ior, 0.005f, 1.0f, 4.0f, "%.3f", ImGuiSliderFlags_AlwaysClamp));
            e.track(ImGui::SliderFloat("Roughness", &m.roughness, 0.0f, 1.0f, "%.3f", ImGuiSliderFlags_AlwaysClamp));
            break;
        case MaterialType::Conductor: {
            e.track(ImGui::ColorEdit3("Tint", &m.tint.x, colour));
            static const char* const metals[] = {"aluminium", "gold", "copper", "silver", "chromium", "platinum", "perfect", "custom"};
            static_assert(sizeof metals / sizeof metals[0] == static_cast<size_t>(Metal::Custom) + 1);
            int metal = static_cast<int>(m.metal);
            e.track(combo("Metal", &metal, metals), true);
            m.metal = static_cast<Metal>(metal);
            if (m.metal == Metal::Custom) {
                e.track(ImGui::DragFloat3("Eta", &m.eta.x, 0.01f, 1e-3f, 10.0f, "%.3f", ImGuiSliderFlags_AlwaysClamp));
                e.track(ImGui::DragFloat3("k", &m.k.x, 0.01f, 0.0f, 20.0f, "%.3f", ImGuiSliderFlags_AlwaysClamp));
            }
            e.track(ImGui::SliderFloat("Roughness", &m.roughness, 0.0f, 1.0f, "%.3f", ImGuiSliderFlags_AlwaysClamp));
            e.track(ImGui::Checkbox("Multiple scattering", &m.energyCompensation), true);
            break;
        }
    }
    if (!m.albedoTexture.empty() || !m.normalTexture.empty() || !m.roughnessTexture.empty()) {
        ImGui::SeparatorText("Textures");
        if (!m.albedoTexture.empty()) ImGui::TextDisabled("albedo: %s", m.albedoTexture.c_str());
        if (!m.normalTexture.empty()) ImGui::TextDisabled("normal: %s", m.normalTexture.c_str());
        if (!m.roughnessTexture.empty()) ImGui::TextDisabled("roughness: %s", m.roughnessTexture.c_str());
    }
    ImGui::SeparatorText("Emission");
    colourAndStrength(e, "Emission colour", "Emission strength", &m.emission);
    e.commit(e.changed ? makeSetMaterial(s, index, m) : nullptr);
    int users = 0;
    for (const Object& o : s.scene.objects) users += o.material == m.name;
    ImGui::TextDisabled("Used by %d object%s", users, users == 1 ? "" : "s");
}

void lightInspector(EditorUi& ui, int index) {
    EditorState& s = ui.state;
    Light l = s.scene.lights[static_cast<size_t>(index)];
    nameField(ui, {EntityKind::Light, index});
    Edit e{ui};
    static const char* const types[] = {"rect", "sphere", "point", "spot"};
    int type = static_cast<int>(l.type);
    e.track(combo("Type", &type, types), true);
    l.type = static_cast<LightType>(type);
    const bool area = l.type == LightType::Rect || l.type == LightType::Sphere;
    colourAndStrength(e, "Colour", area ? "Radiance" : "Intensity", &l.color);
    switch (l.type) {
        case LightType::Rect:
            ImGui::SeparatorText("Placement and size");
            transformFields(e, &l.transform);
            e.track(ImGui::Checkbox("Two-sided", &l.twoSided), true);
            break;
        case LightType::Sphere:
            e.track(ImGui::DragFloat3("Position", &l.position.x, 0.01f));
            e.track(ImGui::DragFloat("Radius", &l.radius, 0.002f, 1e-4f, 1e4f, "%.4f", ImGuiSliderFlags_AlwaysClamp));
            break;
        case LightType::Point:
            e.track(ImGui::DragFloat3("Position", &l.position.x, 0.01f));
            break;
        case LightType::Spot:
            e.track(ImGui::DragFloat3("Position", &l.position.x, 0.01f));
            e.track(ImGui::DragFloat3("Direction", &l.direction.x, 0.01f));
            e.track(ImGui::DragFloat("Inner angle", &l.innerAngle, 0.2f, 0.0f, 90.0f, "%.1f deg", ImGuiSliderFlags_AlwaysClamp));
            e.track(ImGui::DragFloat("Outer angle", &l.outerAngle, 0.2f, 0.0f, 90.0f, "%.1f deg", ImGuiSliderFlags_AlwaysClamp));
            l.innerAngle = std::min(l.innerAngle, l.outerAngle);
            static const char* const falloffs[] = {"smoothstep (cos)", "linear in angle (Mitsuba)"};
            int falloff = static_cast<int>(l.falloff);
            e.track(combo("Falloff", &falloff, falloffs), true);
            l.falloff = static_cast<SpotFalloff>(falloff);
            break;
    }
    e.commit(e.changed ? makeSetLight(s, index, l) : nullptr);
}

void cameraInspector(EditorUi& ui) {
    EditorState& s = ui.state;
    Camera c = s.scene.camera;
    Edit e{ui};
    e.track(ImGui::DragFloat3("Position", &c.position.x, 0.01f));
    e.track(ImGui::DragFloat3("Look at", &c.lookAt.x, 0.01f));
    e.track(ImGui::DragFloat3("Up", &c.up.x, 0.01f));
    e.track(ImGui::DragFloat("Field of view", &c.fovDegrees, 0.1f, 1.0f, 179.0f, "%.2f deg", ImGuiSliderFlags_AlwaysClamp));
    static const char* const axes[] = {"smaller", "larger", "x", "y"};
    int axis = static_cast<int>(c.fovAxis);
    e.track(combo("Fov axis", &axis, axes), true);
    c.fovAxis = static_cast<FovAxis>(axis);
    e.track(ImGui::DragFloat("Roll", &c.rollDegrees, 0.2f, -180.0f, 180.0f, "%.1f deg"));
    ImGui::SeparatorText("Lens");
    e.track(ImGui::DragFloat("Aperture radius", &c.apertureRadius, 0.001f, 0.0f, 10.0f, "%.4f", ImGuiSliderFlags_AlwaysClamp));
    e.track(ImGui::DragFloat("Focal distance", &c.focalDistance, 0.01f, 0.0f, 1e4f, c.focalDistance > 0.0f ? "%.3f" : "at look-at",
                             ImGuiSliderFlags_AlwaysClamp));
    bool focusOnPoint = c.focusPoint.has_value();
    if (ImGui::Checkbox("Focus on a point", &focusOnPoint)) {
        e.changed = e.seal = true;
        if (focusOnPoint) c.focusPoint = c.lookAt;
        else c.focusPoint.reset();
    }
    if (c.focusPoint) e.track(ImGui::DragFloat3("Focus point", &c.focusPoint->x, 0.01f));
    e.track(ImGui::DragFloat("Squeeze (anamorphic)", &c.squeeze, 0.01f, 0.1f, 10.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp));
    e.track(ImGui::SliderInt("Blades (0: round)", &c.blades, 0, 16));
    if (c.blades == 1 || c.blades == 2) c.blades = 3;
    e.track(ImGui::DragFloat("Blade rotation", &c.bladeRotationDegrees, 0.5f, -180.0f, 180.0f, "%.1f deg"));
    // Reject degenerate cameras instead of letting the renderer divide by zero.
    const bool valid = glm::length(c.lookAt - c.position) > 1e-6f && glm::length(glm::cross(c.lookAt - c.position, c.up)) > 1e-6f;
    e.commit(e.changed && valid ? makeSetCamera(s, c) : nullptr);
    if (ImGui::Button("Frame all (F)")) {
        s.selection = {EntityKind::Camera, -1};
        frameSelection(ui);
    }
}

void renderInspector(EditorUi& ui) {
    EditorState& s = ui.state;
    RenderSettings r = s.scene.render;
    Edit e{ui};
    ImGui::SeparatorText("Image");
    // Resolution: applied when the field is left (a half-typed width would restart everything).
    int size[2] = {r.width, r.height};
    ImGui::InputInt2("Resolution", size);
    if (ImGui::IsItemDeactivatedAfterEdit()) {
        r.width = std::clamp(size[0], 1, 16384);
        r.height = std::clamp(size[1], 1, 16384);
        e.changed = e.seal = true;
    }
    e.track(ImGui::DragInt("Target samples", &r.samples, 1.0f, 1, 1 << 24, "%d", ImGuiSliderFlags_AlwaysClamp));
    ImGui::SeparatorText("Integrator");
    e.track(ImGui::DragInt("Max depth", &r.maxDepth, 0.1f, 0, 1024, "%d", ImGuiSliderFlags_AlwaysClamp));
    int seed = static_cast<int>(r.seed);
    e.track(ImGui::DragInt("Seed", &seed, 1.0f, 0, 1 << 30));
    r.seed = static_cast<std::uint32_t>(std::max(seed, 0));
    static const char* const selections[] = {"power", "uniform", "tree"};  // LightSelection's order
    int sel = static_cast<int>(r.lightSelection);
    e.track(combo("Light selection", &sel, selections), true);
    r.lightSelection = static_cast<LightSelection>(sel);
    static const char* const samplers[] = {"Sobol (Owen-scrambled)", "independent"};  // SamplerType's order
    int smp = static_cast<int>(r.sampler);
    e.track(combo("Sampler", &smp, samplers), true);
    r.sampler = static_cast<SamplerType>(smp);
    static const char* const roulettes[] = {"original", "Mitsuba", "pbrt", "off"};  // RussianRoulette's order
    int rr = static_cast<int>(r.russianRoulette);
    e.track(combo("Russian roulette", &rr, roulettes), true);
    r.russianRoulette = static_cast<RussianRoulette>(rr);
    e.track(ImGui::Checkbox("Glass splitting", &r.glassSplit), true);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("At smooth glass, also trace the reflection or refraction not taken for the light it sees "
                          "directly: less noise in highlights and reflected lights, the same image on average");
    e.commit(e.changed ? makeSetRender(s, r) : nullptr);

    ImGui::SeparatorText("Display (not saved in the scene)");
    static const char* const tones[] = {"ACES filmic", "Reinhard"};
    int tone = static_cast<int>(s.view.toneMap);
    if (combo("Tone mapping", &tone, tones)) s.view.toneMap = static_cast<ToneMap>(tone);
    ImGui::DragFloat("Exposure", &s.view.exposure, 0.02f, -20.0f, 20.0f, "%.2f EV");
    if (ui.denoiser) {
        // Denoising (view state like the tone curve): viewport_denoise.h.
        DenoiseSettings& d = ui.denoiser->settings;
        const bool available = denoiserAvailable();
        ImGui::BeginDisabled(!available);
        ImGui::Checkbox("Denoise (OIDN) at target", &d.autoDenoise);
        if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
            ImGui::SetTooltip(available ? "Denoise with Open Image Denoise when the render reaches its target samples"
                                        : "Open Image Denoise is not in this build");
        if (ImGui::Button("Denoise now (F6)")) denoiseNow(ui);
        ImGui::SameLine();
        bool raw = !d.showDenoised;
        if (ImGui::Checkbox("Show raw", &raw)) d.showDenoised = !raw;
        if (ui.denoiser->holding()) {
            ImGui::SameLine();
            if (ImGui::Button("Resume")) ui.denoiser->resume(ui);
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("Denoise now paused the render at its sample count; continue it");
        }
        ImGui::Checkbox("Prefilter guides", &d.prefilterGuides);
        ImGui::EndDisabled();
        if (const std::string st = ui.denoiser->status(ui); !st.empty()) ImGui::TextDisabled("%s", st.c_str());
    }
    ImGui::Separator();
    if (ImGui::Button("Restart render")) s.markDirty(kDirtySettings);
    ImGui::SameLine();
    if (ImGui::Button("Render to file...")) openFileBrowser(ui, FileBrowserState::Mode::RenderTo);
}

void environmentInspector(EditorUi& ui) {
    EditorState& s = ui.state;
    Environment env = s.scene.environment;
    Edit e{ui};
    static const char* const types[] = {"none", "constant", "sky", "map"};
    int type = static_cast<int>(env.type);
    e.track(combo("Type", &type, types), true);
    env.type = static_cast<EnvironmentType>(type);
    switch (env.type) {
        case EnvironmentType::None: ImGui::TextDisabled("Rays that leave the scene see black."); break;
        case EnvironmentType::Constant: e.track(ImGui::ColorEdit3("Radiance", &env.radiance.x, ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR)); break;
        case EnvironmentType::Sky:
            e.track(ImGui::ColorEdit3("Horizon", &env.horizon.x, ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR));
            e.track(ImGui::ColorEdit3("Zenith", &env.zenith.x, ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR));
            // The named looks (docs/scene-format.md): one click sets horizon, zenith and intensity.
            ImGui::TextUnformatted("Preset:");
            for (const SkyPreset& preset : skyPresets()) {
                ImGui::SameLine();
                if (ImGui::SmallButton(std::string(preset.name).c_str())) {
                    applySkyPreset(preset, env);
                    e.changed = e.seal = true;
                }
            }
            break;
        case EnvironmentType::Map: {
            static char file[512];
            std::strncpy(file, env.file.c_str(), sizeof file - 1);
            file[sizeof file - 1] = '\0';
            if (ImGui::InputText("File", file, sizeof file, ImGuiInputTextFlags_EnterReturnsTrue)) {
                env.file = file;
                e.changed = e.seal = true;
            }
            e.track(ImGui::DragFloat("Rotation", &env.rotation, 0.5f, -360.0f, 360.0f, "%.1f deg"));
            break;
        }
    }
    if (env.type != EnvironmentType::None)
        e.track(ImGui::DragFloat("Intensity", &env.intensity, 0.01f, 0.0f, 1e6f, "%.3f", ImGuiSliderFlags_AlwaysClamp));
    e.commit(e.changed ? makeSetEnvironment(s, env) : nullptr);
}

}  // namespace

void drawInspectorPanel(EditorUi& ui) {
    if (!ImGui::Begin("Inspector")) {
        ImGui::End();
        return;
    }
    ui.state.validateSelection();
    const EntityRef sel = ui.state.selection;
    ImGui::PushItemWidth(-110.0f);
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
