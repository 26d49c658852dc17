// Script commands that edit the scene, as the panels do: selection, moves, camera, materials,
// saved views, file picks (docs/editor.md, "Scripts").
#include "editor/script/script_commands.h"

#include "editor/model/asset_files.h"
#include "editor/model/lookdev.h"
#include "editor/model/scene_paths.h"
#include "editor/model/viewport_math.h"
#include "editor/script/script_run.h"
#include "editor/ui/editor_ui.h"
#include "editor/ui/mesh_import.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>

namespace caustic::editor {
namespace {

EntityKind kindFromWord(const std::string& w) {
    if (w == "object") return EntityKind::Object;
    if (w == "light") return EntityKind::Light;
    if (w == "material") return EntityKind::Material;
    if (w == "camera") return EntityKind::Camera;
    if (w == "render") return EntityKind::Render;
    if (w == "environment") return EntityKind::Environment;
    return EntityKind::None;
}

// Moves the selected object or light by d: one step of an edit.
bool moveSelection(EditorUi& ui, glm::vec3 d, bool continuous, std::string* why) {
    EditorState& s = ui.app.state;
    std::unique_ptr<Command> c;
    if (s.selection.kind == EntityKind::Object) {
        Object o = s.scene.objects.at(static_cast<size_t>(s.selection.index));
        o.transform.translate += d;
        c = makeSetObject(s, s.selection.index, o);
    } else if (s.selection.kind == EntityKind::Light) {
        Light l = s.scene.lights.at(static_cast<size_t>(s.selection.index));
        l.transform.translate += d;
        l.position += d;
        c = makeSetLight(s, s.selection.index, l);
    } else {
        *why = "nothing movable is selected";
        return false;
    }
    return continuous ? s.applyContinuous(std::move(c), why) : s.apply(std::move(c), why);
}

// Applies `c` as one edit; a refused one fails the script.
ScriptStep applyEdit(ScriptContext& c, std::unique_ptr<Command> command) {
    std::string why;
    if (!c.app.state.apply(std::move(command), &why)) c.fail(why);
    c.markEdit();
    return ScriptStep::done();
}

ScriptStep select(ScriptContext& c) {
    EditorState& s = c.app.state;
    const EntityKind kind = kindFromWord(c.a[0]);
    if (kind == EntityKind::None) { c.fail("unknown kind '" + c.a[0] + "'"); return ScriptStep::done(); }
    const std::string name = c.a.size() > 1 ? c.a[1] : "";
    const EntityRef ref = findEntity(s.scene, kind, name);
    if (!ref) { c.fail("no " + c.a[0] + " called '" + name + "'"); return ScriptStep::done(); }
    s.select(ref);
    return ScriptStep::done();
}

// As Ctrl+click in the viewport (or Ctrl/Shift+click in the outliner).
ScriptStep selectAdd(ScriptContext& c) {
    EditorState& s = c.app.state;
    const EntityRef ref = findEntity(s.scene, kindFromWord(c.a[0]), c.a[1]);
    if (!ref) { c.fail("no " + c.a[0] + " called '" + c.a[1] + "'"); return ScriptStep::done(); }
    s.select(ref, EditorState::SelectMode::Toggle);
    return ScriptStep::done();
}

ScriptStep translate(ScriptContext& c) {
    std::string why;
    if (!moveSelection(c.ui, {c.num(0), c.num(1), c.num(2)}, false, &why)) c.fail(why);
    c.markEdit();
    return ScriptStep::done();
}

// One step per frame, like a gizmo drag; sealed after the last step, as on release.
ScriptStep drag(ScriptContext& c) {
    ScriptRun& r = c.run;
    if (r.dragStepsLeft == 0) {
        r.dragStepsLeft = std::max(1, static_cast<int>(c.num(3)));
        for (int i = 0; i < 3; ++i) r.drag[i] = c.num(static_cast<size_t>(i)) / float(r.dragStepsLeft);
    }
    std::string why;
    if (!moveSelection(c.ui, {r.drag[0], r.drag[1], r.drag[2]}, true, &why)) { c.fail(why); return ScriptStep::done(); }
    c.markEdit();
    c.app.session.interacting = true;
    c.app.session.lastInteraction = glfwGetTime();
    if (--r.dragStepsLeft > 0) return ScriptStep::again();
    c.app.session.interacting = false;
    c.app.state.seal();
    return ScriptStep::done();
}

ScriptStep orbitCamera(ScriptContext& c) {
    EditorState& s = c.app.state;
    s.apply(makeSetCamera(s, orbit(s.scene.camera, c.num(0), c.num(1))));
    c.markEdit();
    return ScriptStep::done();
}

ScriptStep setSamples(ScriptContext& c) {
    RenderSettings r = c.app.state.scene.render;
    r.samples = static_cast<int>(c.num(0));
    return applyEdit(c, makeSetRender(c.app.state, r));
}

ScriptStep undo(ScriptContext& c) {
    if (!c.app.state.undo()) c.fail("nothing to undo");
    c.markEdit();
    return ScriptStep::done();
}

ScriptStep redo(ScriptContext& c) {
    if (!c.app.state.redo()) c.fail("nothing to redo");
    c.markEdit();
    return ScriptStep::done();
}

ScriptStep addMaterial(ScriptContext& c) { return applyEdit(c, makeAddMaterial(c.app.state)); }

// The inspector's actions on the selected objects (editor/model/lookdev.h).
ScriptStep applyOrFail(ScriptContext& c, std::unique_ptr<Command> command, const std::string& why) {
    std::string refused = why;
    if (!command || !c.app.state.apply(std::move(command), &refused)) c.fail(refused);
    c.markEdit();
    return ScriptStep::done();
}

ScriptStep assignMaterial(ScriptContext& c) {
    EditorState& s = c.app.state;
    std::string why;
    auto command = makeAssignMaterial(s, s.selectedObjects(), c.a[0], &why);
    return applyOrFail(c, std::move(command), why);
}

ScriptStep makeUnique(ScriptContext& c) {
    EditorState& s = c.app.state;
    std::string why;
    auto command = makeMakeUnique(s, s.selectedObjects(), &why);
    return applyOrFail(c, std::move(command), why);
}

ScriptStep newMaterial(ScriptContext& c) {
    EditorState& s = c.app.state;
    const Material* preset = c.a.empty() ? nullptr : findLibraryMaterial(c.a[0]);
    if (!c.a.empty() && !preset) { c.fail("no preset called '" + c.a[0] + "'"); return ScriptStep::done(); }
    std::string why;
    auto command = makeNewMaterialFor(s, s.selectedObjects(), preset, &why);
    return applyOrFail(c, std::move(command), why);
}

ScriptStep applyPreset(ScriptContext& c) {
    EditorState& s = c.app.state;
    const Material* preset = findLibraryMaterial(c.a[0]);
    if (!preset) { c.fail("no preset called '" + c.a[0] + "'"); return ScriptStep::done(); }
    int index = -1;
    if (s.selection.kind == EntityKind::Material) index = s.selection.index;
    else if (s.selection.kind == EntityKind::Object)
        index = findEntity(s.scene, EntityKind::Material, s.scene.objects[size_t(s.selection.index)].material).index;
    if (index < 0) { c.fail("no material is selected"); return ScriptStep::done(); }
    return applyEdit(c, makeApplyPreset(s, index, *preset));
}

ScriptStep setFocus(ScriptContext& c) {
    Camera camera = c.app.state.scene.camera;
    camera.focalDistance = c.num(0);
    camera.focusPoint.reset();
    applyEdit(c, makeSetCamera(c.app.state, camera));
    return ScriptStep::doneAfterFrames(1);   // the overlay is drawn by the next frame's viewport
}

// F: frame the selection (or everything).
ScriptStep frame(ScriptContext& c) {
    frameSelection(c.ui);
    c.markEdit();
    return ScriptStep::done();
}

ScriptStep storeView(ScriptContext& c) {
    storeCameraView(c.ui, c.a[0]);
    return ScriptStep::done();
}

ScriptStep recallView(ScriptContext& c) {
    if (!recallCameraView(c.ui, c.a[0])) c.fail(c.app.lastMessage);
    c.markEdit();
    return ScriptStep::done();
}

// The listing the inspector's "..." shows (asset_files.h), and the path a pick stores (`pick`).
ScriptStep pickerEntry(ScriptContext& c, bool pick) {
    EditorState& s = c.app.state;
    const auto& a = c.a;
    const bool env = a[0] == "environment";
    const AssetKind kind = env ? AssetKind::EnvironmentMap : AssetKind::Texture;
    if (!env && a[0] != "albedo_texture" && a[0] != "normal_texture" && a[0] != "roughness_texture") {
        c.fail("unknown slot '" + a[0] + "'");
        return ScriptStep::done();
    }
    const std::string folder = sceneFolderOf(s.path);
    const std::vector<AssetFile> files = listAssetFiles(kind, folder, assetsFolderFor(folder));
    const AssetFile* found = nullptr;
    for (const AssetFile& f : files)
        if (f.display == a[1]) found = &f;
    if (!found) { c.fail("the picker does not list '" + a[1] + "' (" + std::to_string(files.size()) + " files)"); return ScriptStep::done(); }
    if (!pick) return ScriptStep::done();
    std::string why;
    if (env) {
        Environment e = s.scene.environment;
        e.type = EnvironmentType::Map;
        e.file = found->stored;
        if (!s.apply(makeSetEnvironment(s, e), &why)) c.fail(why);
    } else {
        if (s.selection.kind != EntityKind::Material) { c.fail("no material is selected"); return ScriptStep::done(); }
        Material m = s.scene.materials[size_t(s.selection.index)];
        (a[0] == "albedo_texture" ? m.albedoTexture : a[0] == "normal_texture" ? m.normalTexture : m.roughnessTexture) = found->stored;
        if (!s.apply(makeSetMaterial(s, s.selection.index, m), &why)) c.fail(why);
    }
    c.markEdit();
    return ScriptStep::done();
}

// A texture slot of the selected material set to PATH as typed into its field ("" clears it).
ScriptStep setTexture(ScriptContext& c) {
    EditorState& s = c.app.state;
    if (s.selection.kind != EntityKind::Material) { c.fail("no material is selected"); return ScriptStep::done(); }
    Material m = s.scene.materials[size_t(s.selection.index)];
    const std::string& slot = c.a[0];
    std::string* field = slot == "albedo_texture" ? &m.albedoTexture : slot == "normal_texture" ? &m.normalTexture
                       : slot == "roughness_texture" ? &m.roughnessTexture : slot == "emission_texture" ? &m.emissionTexture : nullptr;
    if (!field) { c.fail("unknown slot '" + slot + "'"); return ScriptStep::done(); }
    *field = c.a[1];
    return applyEdit(c, makeSetMaterial(s, s.selection.index, m));
}

// File > New (the unsaved-changes prompt is not asked: scripts discard).
ScriptStep newScene(ScriptContext& c) {
    c.app.state.newScene();
    c.markEdit();
    return ScriptStep::done();
}

// Add > <type> light, as the outliner's menu does.
ScriptStep addLight(ScriptContext& c) {
    static const std::pair<const char*, LightType> types[] = {
        {"point", LightType::Point}, {"spot", LightType::Spot}, {"rect", LightType::Rect}, {"sphere", LightType::Sphere}};
    for (const auto& [word, type] : types)
        if (c.a[0] == word) return applyEdit(c, makeAddLight(c.app.state, type, meshBoundsLookup(c.ui)));
    c.fail("unknown light type '" + c.a[0] + "' (point, spot, rect, sphere)");
    return ScriptStep::done();
}

// Add > <shape>, as the outliner's menu does.
ScriptStep addObject(ScriptContext& c) {
    static const std::pair<const char*, Shape> shapes[] = {{"sphere", Shape::Sphere}, {"box", Shape::Box}, {"quad", Shape::Quad}};
    for (const auto& [word, shape] : shapes)
        if (c.a[0] == word) return applyEdit(c, makeAddObject(c.app.state, shape));
    c.fail("unknown shape '" + c.a[0] + "' (sphere, box, quad)");
    return ScriptStep::done();
}

ScriptStep pickFile(ScriptContext& c) { return pickerEntry(c, true); }
ScriptStep expectPickerLists(ScriptContext& c) { return pickerEntry(c, false); }

const ScriptCommand kCommands[] = {
    {"select", 1, 2, "", select},                      // select <kind> [name]
    {"select_add", 2, 2, "", selectAdd},               // select_add object NAME: as Ctrl+click (adds, or takes out)
    {"translate", 3, 3, "nnn", translate},             // move the selection by (x y z): one command
    {"drag", 4, 4, "nnnn", drag},                      // drag the selection by (x y z) over N frames: one undo step
    {"orbit", 2, 2, "nn", orbitCamera},                // orbit the camera (yaw pitch degrees)
    {"set_samples", 1, 1, "n", setSamples},            // the render's target samples per pixel
    {"undo", 0, 0, "", undo},
    {"redo", 0, 0, "", redo},
    {"add_material", 0, 0, "", addMaterial},           // Add > Material (a new one, used by nothing)
    {"assign_material", 1, 1, "", assignMaterial},     // give every selected object this material (one undo step)
    {"new_material", 0, 1, "", newMaterial},           // New material [preset] for the selected objects
    {"make_unique", 0, 0, "", makeUnique},             // Make unique: a copy of the selection's shared material
    {"apply_preset", 1, 1, "", applyPreset},           // the selected material (or the object's) takes a library preset
    {"set_focus", 1, 1, "n", setFocus},                // the camera's focal distance (the focus point cleared): one edit
    {"frame", 0, 0, "", frame},                        // frame the selection (F), or everything
    {"store_view", 1, 1, "", storeView},               // store the camera as a saved view NAME
    {"recall_view", 1, 1, "", recallView},             // recall saved view NAME (one undo step)
    // pick_file SLOT NAME: the file picker's entry NAME for a slot (albedo_texture, normal_texture,
    // roughness_texture of the selected material; environment)
    {"pick_file", 2, 2, "", pickFile},
    {"set_texture", 2, 2, "", setTexture},
    {"new_scene", 0, 0, "", newScene},                 // File > New (unsaved changes discarded)
    {"add_light", 1, 1, "", addLight},                 // add_light point|spot|rect|sphere, as Add does
    {"add_object", 1, 1, "", addObject},               // add_object sphere|box|quad, as Add does             // set_texture SLOT PATH: typed into the selected material's field
    {"expect_picker_lists", 2, 2, "", expectPickerLists},   // the picker for SLOT lists NAME
};

}  // namespace

std::span<const ScriptCommand> scriptEditCommands() { return kCommands; }

}  // namespace caustic::editor
