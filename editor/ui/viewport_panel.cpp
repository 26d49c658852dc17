// The viewport: the progressive render (fit or 1:1), the lookdev split view, the transform gizmo
// (ImGuizmo, local/world, snapping), click-to-select, and camera navigation (orbit: middle drag
// or Alt+left drag; pan: Shift+middle drag; zoom: wheel; fly: hold the right button and use
// WASD/QE; frame the selection: F). Mouse and keys reach the viewport only when it is hovered
// and ImGui has no text field active.
#include "editor/model/viewport_math.h"
#include "editor/model/focus_overlay.h"
#include "editor/model/keymap.h"
#include "editor/model/modal_transform.h"
#include "editor/ui/editor_ui.h"
#include "editor/ui/mesh_import.h"

#include <imgui.h>
#include <imgui_internal.h>   // IsMouseDragPastThreshold
#include <ImGuizmo.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <optional>
#include <cmath>
#include <cstdio>
#include <functional>

namespace caustic::editor {
namespace {

ImTextureRef textureRef(unsigned id) { return ImTextureRef(static_cast<ImTextureID>(id)); }

void drawToolbar(EditorUi& ui) {
    // Rotate and Scale are greyed out for a selection that cannot take them (point and sphere
    // lights have no rotation or scale, a spot no scale); the gizmo then moves it.
    const GizmoOps ops = gizmoOpsFor(ui.app.state.scene, ui.app.state.selection);
    auto opButton = [&](const char* label, GizmoOp op, const char* tip, bool allowed) {
        const bool active = ui.gizmoOp == op;
        if (active) ImGui::PushStyleColor(ImGuiCol_Button, ImGui::GetStyleColorVec4(ImGuiCol_ButtonActive));
        ImGui::BeginDisabled(!allowed && ui.app.state.selection.kind == EntityKind::Light);
        if (ImGui::Button(label)) ui.gizmoOp = op;
        ImGui::EndDisabled();
        if (active) ImGui::PopStyleColor();
        if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
            ImGui::SetTooltip("%s", allowed || ui.app.state.selection.kind != EntityKind::Light ? tip : "not for this light: it has no rotation or scale (spot: rotate turns its direction)");
        ImGui::SameLine();
    };
    opButton("Move", GizmoOp::Translate, "Translate (W)", true);
    opButton("Rotate", GizmoOp::Rotate, "Rotate (E); a spot light: turns its direction", ops.rotate);
    opButton("Scale", GizmoOp::Scale, "Scale (R)", ops.scale);
    if (ImGui::Button(ui.gizmoLocal ? "Local" : "World")) ui.gizmoLocal = !ui.gizmoLocal;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Gizmo axes: local or world (T)");
    ImGui::SameLine();
    ImGui::Checkbox("Snap", &ui.snap);
    if (ui.snap) {
        ImGui::SameLine();
        ImGui::SetNextItemWidth(60.0f);
        float* step = ui.gizmoOp == GizmoOp::Translate ? &ui.snapTranslate : ui.gizmoOp == GizmoOp::Rotate ? &ui.snapRotate : &ui.snapScale;
        ImGui::DragFloat("##snap", step, 0.01f, 0.001f, 90.0f, "%.3g");
    }
    ImGui::SameLine();
    ImGui::TextDisabled("|");
    ImGui::SameLine();
    if (ImGui::Button(ui.app.state.view.fitToWindow ? "Fit" : "1:1")) ui.app.state.view.fitToWindow = !ui.app.state.view.fitToWindow;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Scale the image to the panel, or show it 1:1");
    ImGui::SameLine();
    if (ImGui::Button("Snapshot") && ui.app.display) {
        ui.app.display->takeSnapshot();
        ui.compare = true;
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Keep the current image to compare with the live render");
    ImGui::SameLine();
    ImGui::BeginDisabled(!ui.app.display || !ui.app.display->hasSnapshot());
    ImGui::Checkbox("Compare", &ui.compare);
    ImGui::EndDisabled();
}

// The gizmo's matrix for the selection, and how to write an edited matrix back (a light takes
// only what it has: lightFromGizmo; an edit that changes nothing records no undo step).
bool selectionMatrix(const EditorUi& ui, glm::mat4* m) {
    const EditorState& s = ui.app.state;
    if (s.selection.kind == EntityKind::Object) {
        *m = s.scene.objects[static_cast<size_t>(s.selection.index)].transform.toMatrix();
        return true;
    }
    if (s.selection.kind == EntityKind::Light) {
        *m = lightGizmoMatrix(s.scene.lights[static_cast<size_t>(s.selection.index)]);
        return true;
    }
    return false;
}

void applyMatrix(EditorUi& ui, const glm::mat4& m) {
    EditorState& s = ui.app.state;
    if (s.selection.kind == EntityKind::Object) {
        Object o = s.scene.objects[static_cast<size_t>(s.selection.index)];
        o.transform = transformFromMatrix(m);
        s.applyContinuous(makeSetObject(s, s.selection.index, o));
    } else if (s.selection.kind == EntityKind::Light) {
        const Light& l = s.scene.lights[static_cast<size_t>(s.selection.index)];
        s.applyContinuous(makeSetLight(s, s.selection.index, lightFromGizmo(l, m)));
    }
}

// One world-space segment over the image, through viewProj (the camera's, as the gizmo uses);
// a segment with an end behind the camera is left out.
void drawWorldLine(ImDrawList* dl, const glm::mat4& viewProj, ImVec2 pos, ImVec2 size, glm::vec3 p, glm::vec3 q,
                   ImU32 colour, float width) {
    const glm::vec4 a = viewProj * glm::vec4(p, 1.0f), b = viewProj * glm::vec4(q, 1.0f);
    if (a.w <= 1e-6f || b.w <= 1e-6f) return;
    auto screen = [&](const glm::vec4& c) {
        return ImVec2(pos.x + (c.x / c.w * 0.5f + 0.5f) * size.x, pos.y + (0.5f - c.y / c.w * 0.5f) * size.y);
    };
    dl->AddLine(screen(a), screen(b), colour, width);
}

// The lights' outlines over the image (lightOutline): every light faint, the selected one bright,
// so lights that are not objects can be seen, picked by eye and placed.
void drawLightOutlines(EditorUi& ui, ImVec2 pos, ImVec2 size) {
    const Scene& scene = ui.app.state.scene;
    if (scene.lights.empty()) return;
    const Camera& cam = ui.app.state.viewCamera();
    const glm::mat4 viewProj = projectionMatrix(cam, scene.render.width, scene.render.height, 0.01f, 1000.0f) * viewMatrix(cam);
    // The outline's size: a tenth of the distance to the look-at point, so it reads at any scale.
    const float outlineSize = 0.1f * glm::length(cam.lookAt - cam.position);
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->PushClipRect(pos, ImVec2(pos.x + size.x, pos.y + size.y), true);
    for (int i = 0; i < int(scene.lights.size()); ++i) {
        const bool selected = ui.app.state.selection.kind == EntityKind::Light && ui.app.state.selection.index == i;
        const ImU32 colour = selected ? IM_COL32(255, 210, 60, 255) : IM_COL32(255, 210, 60, 110);
        for (const std::vector<glm::vec3>& line : lightOutline(scene.lights[size_t(i)], cam, outlineSize)) {
            for (size_t k = 0; k + 1 < line.size(); ++k)
                drawWorldLine(dl, viewProj, pos, size, line[k], line[k + 1], colour, selected ? 2.0f : 1.0f);
        }
    }
    dl->PopClipRect();
}

// With several objects selected, each one's bounding box over the image (the active one
// brighter), so a Ctrl+click's effect shows where it was made.
void drawSelectedBounds(EditorUi& ui, ImVec2 pos, ImVec2 size) {
    const std::vector<int> selected = ui.app.state.selectedObjects();
    if (selected.size() < 2) return;
    const Scene& scene = ui.app.state.scene;
    const Camera& cam = ui.app.state.viewCamera();
    const glm::mat4 viewProj = projectionMatrix(cam, scene.render.width, scene.render.height, 0.01f, 1000.0f) * viewMatrix(cam);
    const MeshBoundsLookup meshBounds = meshBoundsLookup(ui);
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->PushClipRect(pos, ImVec2(pos.x + size.x, pos.y + size.y), true);
    for (int i : selected) {
        // The object's own box under its transform (a turned box is outlined turned): the
        // canonical shape's [-1, 1]^3 (a quad's z = 0), a mesh's imported bounds.
        const Object& o = scene.objects[size_t(i)];
        std::pair<glm::vec3, glm::vec3> local{glm::vec3(-1.0f), glm::vec3(1.0f)};
        if (o.shape == Shape::Quad) local.first.z = local.second.z = 0.0f;
        if (o.shape == Shape::Mesh) {
            const auto mb = meshBounds ? meshBounds(o) : std::nullopt;
            if (!mb) continue;
            local = *mb;
        }
        const glm::mat4 toWorld = o.transform.toMatrix();
        const bool active = ui.app.state.selection == EntityRef{EntityKind::Object, i};
        const ImU32 colour = active ? IM_COL32(255, 150, 40, 255) : IM_COL32(255, 150, 40, 150);
        glm::vec3 corner[8];
        for (int k = 0; k < 8; ++k)
            corner[k] = glm::vec3(toWorld * glm::vec4((k & 1) ? local.second.x : local.first.x, (k & 2) ? local.second.y : local.first.y,
                                                      (k & 4) ? local.second.z : local.first.z, 1.0f));
        for (int k = 0; k < 8; ++k)
            for (int bit : {1, 2, 4})
                if (!(k & bit)) drawWorldLine(dl, viewProj, pos, size, corner[k], corner[k | bit], colour, active ? 2.0f : 1.0f);
    }
    dl->PopClipRect();
}

// The focus-plane overlay: for 1.5 s after any edit of the focus (the inspector's fields, the
// f-stop, Shift+click, an undo), the parts of the scene on the plane of focus are tinted, found
// by CPU ray casts on a grid (focus_overlay.h), with the distance written beside them.
void drawFocusOverlay(EditorUi& ui, ImVec2 pos, ImVec2 size) {
    if (ui.app.state.freeView) return;   // the camera's focus, shown through the camera only
    static Camera s_last;
    static std::uint64_t s_generation = ~std::uint64_t(0);
    const Scene& scene = ui.app.state.scene;
    const double t = ImGui::GetTime();
    if (s_generation == ui.app.state.generation() && focusEdited(s_last, scene.camera)) ui.focusOverlayUntil = t + 1.5;
    s_last = scene.camera;
    s_generation = ui.app.state.generation();
    if (t > ui.focusOverlayUntil) {
        ui.focusOverlayCells = -1;
        return;
    }
    const int cols = 96, rows = std::max(1, int(std::lround(96.0f * size.y / std::max(1.0f, size.x))));
    std::function<std::optional<float>(const Ray&)> meshHit;
    if (ui.app.renderer) {
        const CompiledScene& c = ui.app.renderer->compiled();
        meshHit = [&c](const Ray& r) -> std::optional<float> {
            const RayHit h = intersectVisibleMeshes(c, caustic::Ray{r.origin, r.direction});
            return h.hit() ? std::optional<float>(h.t) : std::nullopt;
        };
    }
    const std::vector<FocusCell> cells = inFocusCells(scene, cols, rows, 0.02f, meshHit);
    ui.focusOverlayCells = int(cells.size());
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->PushClipRect(pos, ImVec2(pos.x + size.x, pos.y + size.y), true);
    const float cw = size.x / float(cols), ch = size.y / float(rows);
    for (const FocusCell& c : cells) {
        const ImVec2 a(pos.x + float(c.x) * cw, pos.y + float(c.y) * ch);
        dl->AddRectFilled(a, ImVec2(a.x + cw, a.y + ch), IM_COL32(60, 255, 120, 90));
    }
    const double aspect = double(scene.render.width) / double(scene.render.height);
    char text[96];
    std::snprintf(text, sizeof text, "plane of focus: %.3g (green: in focus)", focusDistance(scene.camera, aspect));
    dl->AddText(ImVec2(pos.x + 6.0f, pos.y + 22.0f), IM_COL32(60, 255, 120, 255), text);
    dl->PopClipRect();
}

// ---- The Blender key map's modal transforms (modal_transform.h) ----------------------------------

void startModal(EditorUi& ui, ModalKind kind, ImVec2 pos, ImVec2 size) {
    EditorState& s = ui.app.state;
    EditorUi::Modal m;
    m.ref = s.selection;
    if (s.selection.kind == EntityKind::Object) {
        m.start.transform = s.scene.objects[size_t(s.selection.index)].transform;
    } else if (s.selection.kind == EntityKind::Light) {
        m.light = s.scene.lights[size_t(s.selection.index)];
        m.start.transform = Transform{};
        m.start.transform.matrix = lightGizmoMatrix(m.light);
    } else {
        notify(ui, "select an object or a light first", true);
        return;
    }
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    m.start.kind = kind;
    m.start.mouse = {mouse.x - pos.x, mouse.y - pos.y};
    m.start.viewport = {size.x, size.y};
    m.start.camera = s.viewCamera();
    m.start.width = s.scene.render.width;
    m.start.height = s.scene.render.height;
    m.active = true;
    s.seal();
    m.undoAtStart = s.history.undoCount();
    ui.modal = m;
}

void endModal(EditorUi& ui, bool confirm) {
    EditorState& s = ui.app.state;
    s.seal();
    if (!confirm && ui.modal.applied) {
        s.undo();                  // back to where it started, and no redo step left behind
        s.history.discardRedo();
    }
    ui.modal.active = false;
    notify(ui, confirm ? (ui.modal.applied ? "transformed" : "nothing changed") : "transform cancelled");
}

void modalStep(EditorUi& ui, ImVec2 pos) {
    EditorUi::Modal& m = ui.modal;
    EditorState& s = ui.app.state;
    if (!(s.selection == m.ref)) {   // the entity went (an undo, a delete): nothing to transform
        m.active = false;
        return;
    }
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    const Transform t = modalTransform(m.start, m.axis, {mouse.x - pos.x, mouse.y - pos.y});
    std::string why;
    bool ok = true;
    if (m.ref.kind == EntityKind::Object) {
        Object o = s.scene.objects[size_t(m.ref.index)];
        if (o.transform == t) return;
        o.transform = t;
        ok = s.applyContinuous(makeSetObject(s, m.ref.index, o), &why);
    } else {
        const Light l = lightFromGizmo(m.light, t.toMatrix());
        if (l == s.scene.lights[size_t(m.ref.index)]) return;
        ok = s.applyContinuous(makeSetLight(s, m.ref.index, l), &why);
    }
    if (!ok) notify(ui, why, true);
    m.applied = s.history.undoCount() > m.undoAtStart;
}

// The modal transform's keys and clicks (KeyScope::Modal): X Y Z, Enter / left click, Esc / right click.
void modalInput(EditorUi& ui, ImVec2 pos, ImVec2 size) {
    const bool blender = ui.app.keymap == KeymapStyle::Blender;
    for (const KeyBinding& b : keyBindings(ui.app.keymap)) {
        if (b.scope != KeyScope::Modal || !chordPressed(b.chord)) continue;
        auto toggle = [&](ModalAxis a) { ui.modal.axis = ui.modal.axis == a ? ModalAxis::Free : a; };
        switch (b.action) {
            case Action::ConstrainX: toggle(constraintAxis('X', blender)); break;
            case Action::ConstrainY: toggle(constraintAxis('Y', blender)); break;
            case Action::ConstrainZ: toggle(constraintAxis('Z', blender)); break;
            case Action::ModalConfirm: modalStep(ui, pos); endModal(ui, true); return;
            case Action::ModalCancel: endModal(ui, false); return;
            default: break;
        }
    }
    if (ImGui::IsMouseClicked(ImGuiMouseButton_Right)) {
        endModal(ui, false);
        return;
    }
    modalStep(ui, pos);
    if (ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        endModal(ui, true);
        ui.ignoreClickRelease = true;   // the confirming click's release selects nothing
        return;
    }
    static const char* const kinds[] = {"Grab", "Rotate", "Scale"};
    // Named as the keys name them (the Blender map's Z is the scene's Y: up).
    static const char* const axes[] = {"free", "x axis", "y axis", "z axis"};
    static const char* const blenderAxes[] = {"free", "x axis", "z axis (up)", "y axis (depth)"};
    char text[128];
    std::snprintf(text, sizeof text, "%s (%s): X Y Z constrain, click or Enter confirms, Esc or right click cancels",
                  kinds[int(ui.modal.start.kind)], (blender ? blenderAxes : axes)[int(ui.modal.axis)]);
    ImGui::GetWindowDrawList()->AddText(ImVec2(pos.x + 6.0f, pos.y + 40.0f), IM_COL32(255, 220, 120, 255), text);
    (void)size;
}

void drawGizmo(EditorUi& ui, ImVec2 pos, ImVec2 size) {
    glm::mat4 m;
    const bool usingBefore = ui.gizmoWasUsing;
    if (!selectionMatrix(ui, &m)) {
        if (usingBefore) ui.app.state.seal();
        ui.gizmoWasUsing = false;
        return;
    }
    const Camera& cam = ui.app.state.viewCamera();
    const RenderSettings& rs = ui.app.state.scene.render;
    const glm::mat4 view = viewMatrix(cam);
    const glm::mat4 proj = projectionMatrix(cam, rs.width, rs.height, 0.01f, 1000.0f);
    ImGuizmo::SetOrthographic(false);
    ImGuizmo::SetDrawlist();
    ImGuizmo::SetRect(pos.x, pos.y, size.x, size.y);
    // Only what the selection can take: point and sphere lights move, spots move and turn.
    const GizmoOps ops = gizmoOpsFor(ui.app.state.scene, ui.app.state.selection);
    const GizmoOp chosen = (ui.gizmoOp == GizmoOp::Rotate && !ops.rotate) || (ui.gizmoOp == GizmoOp::Scale && !ops.scale)
                               ? GizmoOp::Translate : ui.gizmoOp;
    const ImGuizmo::OPERATION op = chosen == GizmoOp::Translate ? ImGuizmo::TRANSLATE
                                   : chosen == GizmoOp::Rotate  ? ImGuizmo::ROTATE
                                                                : ImGuizmo::SCALE;
    // ImGuizmo scales in local axes only.
    const ImGuizmo::MODE mode = ui.gizmoLocal || chosen == GizmoOp::Scale ? ImGuizmo::LOCAL : ImGuizmo::WORLD;
    const float step = chosen == GizmoOp::Translate ? ui.snapTranslate : chosen == GizmoOp::Rotate ? ui.snapRotate : ui.snapScale;
    const float snap[3] = {step, step, step};
    if (ImGuizmo::Manipulate(glm::value_ptr(view), glm::value_ptr(proj), op, mode, glm::value_ptr(m), nullptr,
                             ui.snap ? snap : nullptr))
        applyMatrix(ui, m);
    const bool usingNow = ImGuizmo::IsUsing();
    if (usingNow) {
        ui.app.session.interacting = true;
        ui.app.session.lastInteraction = ImGui::GetTime();
    }
    if (usingBefore && !usingNow) ui.app.state.seal();   // released: the drag is one undo step
    ui.gizmoWasUsing = usingNow;
}

void navigate(EditorUi& ui, ImVec2 imageSize) {
    ImGuiIO& io = ImGui::GetIO();
    EditorState& s = ui.app.state;
    // The Blender key map navigates its free view; the default one moves the scene camera, or the
    // free view while one is on (View > Free view).
    const bool freeViewMode = ui.app.keymap == KeymapStyle::Blender;
    const Camera& current = s.viewCamera();
    const bool orbitDrag = ImGui::IsMouseDragging(ImGuiMouseButton_Middle, 0.0f) && !io.KeyShift;
    const bool altOrbit = io.KeyAlt && ImGui::IsMouseDragging(ImGuiMouseButton_Left, 0.0f);
    const bool panDrag = ImGui::IsMouseDragging(ImGuiMouseButton_Middle, 0.0f) && io.KeyShift;
    const bool flying = ImGui::IsMouseDown(ImGuiMouseButton_Right);
    const ImVec2 d = io.MouseDelta;
    if ((orbitDrag || altOrbit) && (d.x != 0.0f || d.y != 0.0f)) {
        s.moveView(orbit(current, -d.x * 0.3f, d.y * 0.3f), freeViewMode, true);
        ui.navigating = true;
    } else if (panDrag && (d.x != 0.0f || d.y != 0.0f)) {
        s.moveView(pan(current, d.x / imageSize.y, d.y / imageSize.y), freeViewMode, true);
        ui.navigating = true;
    } else if (flying) {
        // Fly speed: a tenth of the scene's size per second, faster with Shift.
        auto b = sceneBounds(s.scene, meshBoundsLookup(ui));
        const float size = b ? std::max(glm::length(b->second - b->first), 0.1f) : 1.0f;
        const float speed = size * 0.25f * io.DeltaTime * (io.KeyShift ? 4.0f : 1.0f);
        glm::vec3 move(0.0f);
        if (ImGui::IsKeyDown(ImGuiKey_W)) move.z += speed;
        if (ImGui::IsKeyDown(ImGuiKey_S)) move.z -= speed;
        if (ImGui::IsKeyDown(ImGuiKey_D)) move.x += speed;
        if (ImGui::IsKeyDown(ImGuiKey_A)) move.x -= speed;
        if (ImGui::IsKeyDown(ImGuiKey_E)) move.y += speed;
        if (ImGui::IsKeyDown(ImGuiKey_Q)) move.y -= speed;
        Camera c = current;
        if (move != glm::vec3(0.0f)) c = fly(c, move);
        if (d.x != 0.0f || d.y != 0.0f) {
            // Mouse look: orbit the look-at point about the eye (swap the two, orbit, swap back).
            Camera turned = c;
            turned.position = c.lookAt;
            turned.lookAt = c.position;
            turned = orbit(turned, -d.x * 0.2f, -d.y * 0.2f);
            c.lookAt = turned.position;
        }
        if (!(c == current)) {
            s.moveView(c, freeViewMode, true);
            ui.navigating = true;
        }
    }
    if (io.MouseWheel != 0.0f) {
        s.moveView(dolly(current, std::pow(0.85f, io.MouseWheel)), freeViewMode, true);
        ui.lastWheel = ImGui::GetTime();
        ui.app.session.interacting = true;
        ui.app.session.lastInteraction = ImGui::GetTime();
    }
    if (ui.navigating) {
        ui.app.session.interacting = true;
        ui.app.session.lastInteraction = ImGui::GetTime();
    }
}

// What the viewport shows along a ray, as a click picks it: objects and lights (hidden objects
// left out, indices mapped back), meshes through the renderer's own CPU copy of their BVHs (the
// canonical shapes know no triangles; the renderer's objects mapped by session.renderedObjects),
// through the alpha cut-outs as the render shows them. A Picker makes the scene without its
// hidden objects once for many rays (the selection outline casts thousands a frame).
struct Picker {
    EditorUi& ui;
    std::optional<Scene> withoutHiddenScene;   // with hidden objects only
    std::vector<int> shown;                    // its objects' indices in the scene
    explicit Picker(EditorUi& u) : ui(u) {
        if (!ui.app.hidden.empty()) withoutHiddenScene = withoutHidden(ui.app.state.scene, ui.app.hidden, &shown);
    }
    std::optional<PickHit> at(const Ray& ray) const;
};

std::optional<PickHit> pickAt(EditorUi& ui, const Ray& ray) { return Picker(ui).at(ray); }

std::optional<PickHit> Picker::at(const Ray& ray) const {
    std::optional<PickHit> hit = pick(withoutHiddenScene ? *withoutHiddenScene : ui.app.state.scene, ray);
    if (hit && !shown.empty() && hit->ref.kind == EntityKind::Object) hit->ref.index = shown[size_t(hit->ref.index)];
    if (ui.app.renderer) {
        const CompiledScene& c = ui.app.renderer->compiled();
        const RayHit mh = intersectVisibleMeshes(c, caustic::Ray{ray.origin, ray.direction});
        if (mh.hit() && mh.instance < c.instanceObject.size() && (!hit || mh.t < hit->distance)) {
            int object = static_cast<int>(c.instanceObject[mh.instance]);
            const std::vector<int>& map = ui.app.session.renderedObjects;
            if (!map.empty()) object = object < int(map.size()) ? map[size_t(object)] : -1;
            if (object >= 0) hit = PickHit{{EntityKind::Object, object}, mh.t};
        }
    }
    return hit;
}

// The selected objects' outline (selectionOutline), from a grid of picks over the image: about 4
// screen pixels a cell (8 while something is dragged), at most 256 cells across; cast again only
// when the view, the scene, the selection or the size changes.
void drawSelectionOutline(EditorUi& ui, ImVec2 pos, ImVec2 size) {
    const EditorState& s = ui.app.state;
    const std::vector<int> selected = s.selectedObjects();
    if (selected.empty() || size.x < 8.0f || size.y < 8.0f) return;
    struct Cache {
        Camera camera;
        std::uint64_t generation = ~0ull, revision = ~0ull, renderer = ~0ull;
        std::vector<int> selected;
        std::vector<std::string> hidden;
        int w = 0, h = 0;
        std::vector<int> shown;
    };
    static Cache cache;
    const float cellPixels = ui.app.session.interacting ? 8.0f : 4.0f;
    const int w = std::clamp(int(size.x / cellPixels), 8, 256);
    const int h = std::clamp(int(float(w) * size.y / size.x + 0.5f), 4, 256);
    const RenderSettings& rs = s.scene.render;
    const std::uint64_t rendererGeneration = ui.app.session.accumulationGeneration;
    if (!(cache.camera == s.viewCamera()) || cache.generation != s.generation() || cache.revision != s.history.revision() ||
        cache.selected != selected || cache.hidden != ui.app.hidden || cache.w != w || cache.h != h ||
        cache.renderer != rendererGeneration) {
        cache = Cache{s.viewCamera(), s.generation(), s.history.revision(), rendererGeneration, selected, ui.app.hidden, w, h, {}};
        cache.shown.assign(std::size_t(w) * std::size_t(h), -1);
        const LensCamera* lens = ui.app.renderer ? ui.app.renderer->lensCamera() : nullptr;
        const Picker picker(ui);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const glm::vec2 pixel((float(x) + 0.5f) / float(w) * float(rs.width), (float(y) + 0.5f) / float(h) * float(rs.height));
                const auto hit = picker.at(cameraRay(s.viewCamera(), rs.width, rs.height, pixel, lens));
                if (hit && hit->ref.kind == EntityKind::Object) cache.shown[std::size_t(y) * std::size_t(w) + std::size_t(x)] = hit->ref.index;
            }
    }
    const int active = s.selection.kind == EntityKind::Object ? s.selection.index : -1;
    const auto mark = [&](int object) {
        if (object == active) return 2;
        return std::find(selected.begin(), selected.end(), object) != selected.end() ? 1 : 0;
    };
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->PushClipRect(pos, ImVec2(pos.x + size.x, pos.y + size.y), true);
    const float sx = size.x / float(w), sy = size.y / float(h);
    for (const OutlineEdge& e : selectionOutline(cache.shown, w, h, mark))
        dl->AddLine(ImVec2(pos.x + e.a.x * sx, pos.y + e.a.y * sy), ImVec2(pos.x + e.b.x * sx, pos.y + e.b.y * sy),
                    e.mark == 2 ? IM_COL32(255, 170, 50, 255) : IM_COL32(230, 110, 30, 200), e.mark == 2 ? 2.0f : 1.5f);
    dl->PopClipRect();
}

// The renderer refused the model's scene (render_session.h, `behind`): the image is an older
// scene's, and says so over its top edge, with the reason, until an edit makes the scene renderable.
void drawLastGoodBanner(EditorUi& ui, ImVec2 pos, ImVec2 size) {
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const std::string text = "Showing the last good scene: " + ui.app.session.renderError;
    const float wrap = std::max(40.0f, size.x - 12.0f);
    const ImVec2 extent = ImGui::CalcTextSize(text.c_str(), nullptr, false, wrap);
    dl->AddRectFilled(pos, ImVec2(pos.x + size.x, pos.y + extent.y + 8.0f), IM_COL32(120, 20, 20, 220));
    dl->AddText(ImGui::GetFont(), ImGui::GetFontSize(), ImVec2(pos.x + 6.0f, pos.y + 4.0f), IM_COL32(255, 255, 255, 255),
                text.c_str(), nullptr, wrap);
}

}  // namespace

void drawViewportPanel(EditorUi& ui) {
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(4.0f, 4.0f));
    const bool open = ImGui::Begin("Viewport");
    ImGui::PopStyleVar();
    ui.app.session.interacting = false;
    ui.viewportFocused = open && ImGui::IsWindowFocused(ImGuiFocusedFlags_RootAndChildWindows);
    if (!open) {
        ImGui::End();
        return;
    }
    drawToolbar(ui);
    const RenderSettings& rs = ui.app.state.scene.render;
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    if (!ui.app.renderer || !ui.app.display || !ui.app.session.sceneUploaded || ui.app.display->texture() == 0) {
        // The empty state says why and what to do.
        ImGui::Spacing();
        if (!ui.app.renderer) ImGui::TextWrapped("The path tracer is not available: its shaders did not compile. Fix them and press F5 (Render > Reload shaders).");
        else if (!ui.app.session.renderError.empty()) ImGui::TextWrapped("The scene cannot be rendered:\n%s", ui.app.session.renderError.c_str());
        else ImGui::TextDisabled("Preparing the render...");
        ImGui::End();
        return;
    }
    float scale = 1.0f;
    if (ui.app.state.view.fitToWindow) scale = std::max(0.05f, std::min(avail.x / float(rs.width), avail.y / float(rs.height)));
    const ImVec2 size(float(rs.width) * scale, float(rs.height) * scale);
    // The viewport renders at the size it is drawn at, in framebuffer pixels (render_session.h).
    const ImVec2 fb = ImGui::GetIO().DisplayFramebufferScale;
    // A chosen fraction, or the automatic one (render_session.h, chooseViewportScale).
    ui.app.session.autoScaleUsed = ui.app.state.view.viewportScale <= 0.0f;
    const float vs = ui.app.session.autoScaleUsed ? ui.app.session.autoScale : ui.app.state.view.viewportScale;
    ui.app.session.setViewport(int(size.x * fb.x * vs + 0.5f), int(size.y * fb.y * vs + 0.5f), ui.app.state.view.fitToWindow);
    ImVec2 cursor = ImGui::GetCursorPos();
    cursor.x += std::max(0.0f, (avail.x - size.x) * 0.5f);
    cursor.y += std::max(0.0f, (avail.y - size.y) * 0.5f);
    ImGui::SetCursorPos(cursor);
    const ImVec2 pos = ImGui::GetCursorScreenPos();
    ImGui::Image(textureRef(ui.app.display->texture()), size);
    const bool hovered = ImGui::IsItemHovered();
    ui.viewportHovered = hovered;

    ImDrawList* dl = ImGui::GetWindowDrawList();
    if (ui.compare && ui.app.display->hasSnapshot()) {
        // Split view: the snapshot left of the divider, the live render right of it.
        const float split = std::clamp(ui.compareSplit, 0.0f, 1.0f);
        dl->AddImage(textureRef(ui.app.display->snapshotTexture()), pos, ImVec2(pos.x + size.x * split, pos.y + size.y),
                     ImVec2(0.0f, 0.0f), ImVec2(split, 1.0f));
        const float x = pos.x + size.x * split;
        dl->AddLine(ImVec2(x, pos.y), ImVec2(x, pos.y + size.y), IM_COL32(255, 200, 40, 255), 2.0f);
        dl->AddText(ImVec2(pos.x + 6.0f, pos.y + 4.0f), IM_COL32(255, 200, 40, 255), "snapshot");
        dl->AddText(ImVec2(x + 6.0f, pos.y + 4.0f), IM_COL32(255, 200, 40, 255), "live");
        // Ctrl+drag moves the divider.
        if (hovered && ImGui::GetIO().KeyCtrl && ImGui::IsMouseDown(ImGuiMouseButton_Left))
            ui.compareSplit = std::clamp((ImGui::GetIO().MousePos.x - pos.x) / size.x, 0.0f, 1.0f);
    }
    if (ui.app.state.freeView)
        dl->AddText(ImVec2(pos.x + 6.0f, pos.y + 4.0f), IM_COL32(200, 220, 255, 220),
                    ui.app.keymap == KeymapStyle::Blender
                        ? "free view (Numpad 0: through the camera, Ctrl+Alt+Numpad 0: camera to view)"
                        : "free view (View > Free view: through the camera, View > Camera to view)");
    if (ui.app.session.previewDivisor > 1)
        dl->AddText(ImVec2(pos.x + 6.0f, pos.y + size.y - 20.0f), IM_COL32(255, 255, 255, 200), "preview resolution");
    if (ui.app.session.behind) drawLastGoodBanner(ui, pos, size);
    if (ui.app.session.buildingShaders) {   // the viewport's own (the previews say theirs)
        const char* text = "Building shaders...";
        const ImVec2 t = ImGui::CalcTextSize(text);
        const ImVec2 c(pos.x + size.x * 0.5f, pos.y + size.y * 0.5f);
        dl->AddRectFilled(ImVec2(c.x - t.x * 0.5f - 12.0f, c.y - t.y * 0.5f - 8.0f), ImVec2(c.x + t.x * 0.5f + 12.0f, c.y + t.y * 0.5f + 8.0f),
                          IM_COL32(20, 20, 24, 220), 6.0f);
        dl->AddText(ImVec2(c.x - t.x * 0.5f, c.y - t.y * 0.5f), IM_COL32(255, 220, 120, 255), text);
    }

    drawLightOutlines(ui, pos, size);
    drawSelectedBounds(ui, pos, size);
    drawSelectionOutline(ui, pos, size);
    drawFocusOverlay(ui, pos, size);
    if (!ui.modal.active) drawGizmo(ui, pos, size);   // G / R / S drive the selection meanwhile

    ImGuiIO& io = ImGui::GetIO();
    ui.viewportImage[0] = pos.x;
    ui.viewportImage[1] = pos.y;
    ui.viewportImage[2] = size.x;
    ui.viewportImage[3] = size.y;
    if (ui.modal.active) {
        // G / R / S: the mouse drives the transform; nothing else takes clicks meanwhile.
        modalInput(ui, pos, size);
        ImGui::End();
        return;
    }
    const bool gizmoBusy = ImGuizmo::IsOver() || ImGuizmo::IsUsing();
    // Clicks (not drags) select what is under the cursor; Shift+click focuses the lens there.
    // Ctrl+click adds an object to the selection or takes it out (not with compare on, where
    // Ctrl+drag moves the divider).
    // The release of the click that confirmed a G / R / S move is not a pick.
    const bool confirmRelease = ui.ignoreClickRelease && ImGui::IsMouseReleased(ImGuiMouseButton_Left);
    if (confirmRelease || !ImGui::IsMouseDown(ImGuiMouseButton_Left)) ui.ignoreClickRelease = false;
    if (hovered && !gizmoBusy && !confirmRelease && !io.KeyAlt && !(io.KeyCtrl && ui.compare) && ImGui::IsMouseReleased(ImGuiMouseButton_Left) &&
        !ImGui::IsMouseDragPastThreshold(ImGuiMouseButton_Left)) {
        const glm::vec2 pixel((io.MousePos.x - pos.x) / scale, (io.MousePos.y - pos.y) / scale);
        // Through the lens system where the camera has one (the renderer's, as it renders).
        const Ray ray = cameraRay(ui.app.state.viewCamera(), rs.width, rs.height, pixel,
                                  ui.app.renderer ? ui.app.renderer->lensCamera() : nullptr);
        const std::optional<PickHit> hit = pickAt(ui, ray);
        if (io.KeyShift) {
            if (hit) {
                Camera cam = ui.app.state.scene.camera;
                cam.focusPoint = ray.origin + hit->distance * ray.direction;
                ui.app.state.apply(makeSetCamera(ui.app.state, cam));
            }
        } else if (io.KeyCtrl) {
            if (hit) ui.app.state.select(hit->ref, EditorState::SelectMode::Toggle);
        } else {
            ui.app.state.select(hit ? hit->ref : EntityRef{});
        }
    }
    if (hovered && !gizmoBusy) navigate(ui, size);
    if (ui.navigating && !ImGui::IsMouseDown(ImGuiMouseButton_Middle) && !ImGui::IsMouseDown(ImGuiMouseButton_Left) &&
        !ImGui::IsMouseDown(ImGuiMouseButton_Right)) {
        ui.app.state.seal();
        ui.navigating = false;
    }
    if ((hovered || ImGui::IsWindowFocused()) && !io.WantTextInput && !ImGui::IsMouseDown(ImGuiMouseButton_Right)) {
        // The viewport's keys (editor/model/keymap.h, scope Viewport; chords match their
        // modifiers exactly).
        EditorState& s = ui.app.state;
        // The numpad views move the free view (the Blender key map's only).
        auto view = [&](glm::vec3 from) { s.moveView(axisView(s.viewCamera(), from), true, false); };
        for (const KeyBinding& b : keyBindings(ui.app.keymap)) {
            if (b.scope != KeyScope::Viewport || !chordPressed(b.chord)) continue;
            switch (b.action) {
                case Action::ModalGrab: startModal(ui, ModalKind::Grab, pos, size); break;
                case Action::ModalRotate: startModal(ui, ModalKind::Rotate, pos, size); break;
                case Action::ModalScale: startModal(ui, ModalKind::Scale, pos, size); break;
                case Action::DuplicateMove: {
                    std::string why;
                    if (!s.selection || s.selection.index < 0) break;
                    if (auto c = makeDuplicate(s, s.selection, &why); c && s.apply(std::move(c), &why))
                        startModal(ui, ModalKind::Grab, pos, size);   // the copy is selected
                    else notify(ui, why, true);
                    break;
                }
                case Action::Hide:
                    for (int i : s.selectedObjects()) {
                        const std::string& name = s.scene.objects[size_t(i)].name;
                        if (std::find(ui.app.hidden.begin(), ui.app.hidden.end(), name) == ui.app.hidden.end()) ui.app.hidden.push_back(name);
                    }
                    if (!s.selectedObjects().empty()) s.select({});
                    break;
                case Action::UnhideAll: ui.app.hidden.clear(); break;
                case Action::ViewFront: view({0.0f, 0.0f, 1.0f}); break;
                case Action::ViewBack: view({0.0f, 0.0f, -1.0f}); break;
                case Action::ViewRight: view({1.0f, 0.0f, 0.0f}); break;
                case Action::ViewLeft: view({-1.0f, 0.0f, 0.0f}); break;
                case Action::ViewTop: view({0.0f, 1.0f, 0.0f}); break;
                case Action::ViewBottom: view({0.0f, -1.0f, 0.0f}); break;
                case Action::CameraView: s.toggleCameraView(); break;
                case Action::CameraToView: {
                    std::string why;
                    if (!s.cameraToView(&why)) notify(ui, why, true);
                    break;
                }
                case Action::FrameSelection: frameSelection(ui); break;
                case Action::GizmoTranslate: ui.gizmoOp = GizmoOp::Translate; break;
                case Action::GizmoRotate: ui.gizmoOp = GizmoOp::Rotate; break;
                case Action::GizmoScale: ui.gizmoOp = GizmoOp::Scale; break;
                case Action::GizmoLocal: ui.gizmoLocal = !ui.gizmoLocal; break;
                default: break;
            }
        }
    }
    ImGui::End();
}

}  // namespace caustic::editor
