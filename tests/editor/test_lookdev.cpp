// Lookdev in the editor's model (issue 15): multi-selection, assigning a material to every
// selected object, New material / Make unique, the preset library, artist names, and the preview
// ball's scene.
#include "editor/model/editor_state.h"
#include "editor/model/lookdev.h"
#include "editor/model/viewport_math.h"
#include "renderer/camera.h"
#include "renderer/scene_io.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

using namespace caustic;
using namespace caustic::editor;

namespace {

// Four spheres: a, b and c share "white", d has "red".
EditorState fourSpheres() {
    EditorState st;
    Material white, red;
    white.name = "white";
    red.name = "red";
    red.albedo = {0.8f, 0.1f, 0.1f};
    st.scene.materials = {white, red};
    for (const char* n : {"a", "b", "c", "d"}) {
        Object o;
        o.name = n;
        o.material = std::string(n) == "d" ? "red" : "white";
        o.transform.translate.x = float(st.scene.objects.size()) * 3.0f;
        st.scene.objects.push_back(o);
    }
    st.takeDirty();
    return st;
}

EntityRef obj(int i) { return {EntityKind::Object, i}; }

std::vector<std::string> materialsOf(const EditorState& st) {
    std::vector<std::string> out;
    for (const Object& o : st.scene.objects) out.push_back(o.material);
    return out;
}

}  // namespace

TEST_CASE("Ctrl/Shift+click selects several objects, a plain click or another selection ends it", "[editor][lookdev]") {
    EditorState st = fourSpheres();
    st.select(obj(1));
    st.select(obj(3), EditorState::SelectMode::Toggle);
    st.select(obj(0), EditorState::SelectMode::Toggle);
    CHECK(st.selectedObjects() == std::vector<int>{0, 1, 3});
    CHECK(st.selection == obj(0));   // the last one added is the active one
    CHECK(st.isSelected(obj(3)));
    CHECK_FALSE(st.isSelected(obj(2)));
    // Toggling a selected one removes it; removing the active one makes another active.
    st.select(obj(3), EditorState::SelectMode::Toggle);
    CHECK(st.selectedObjects() == std::vector<int>{0, 1});
    st.select(obj(0), EditorState::SelectMode::Toggle);
    CHECK(st.selectedObjects() == std::vector<int>{1});
    CHECK(st.selection == obj(1));
    st.select(obj(1), EditorState::SelectMode::Toggle);
    CHECK_FALSE(st.selection);
    // A plain click replaces; a direct assignment of the selection (an undo, an insert) ends it.
    st.select(obj(0));
    st.select(obj(2), EditorState::SelectMode::Toggle);
    st.select(obj(3));
    CHECK(st.selectedObjects() == std::vector<int>{3});
    st.select(obj(2), EditorState::SelectMode::Toggle);
    st.selection = obj(1);
    CHECK(st.selectedObjects() == std::vector<int>{1});
    // Only objects take part: Ctrl+click on a light selects it alone.
    st.select(obj(0));
    st.select({EntityKind::Camera, -1}, EditorState::SelectMode::Toggle);
    CHECK(st.selectedObjects().empty());
    CHECK(st.selection == EntityRef{EntityKind::Camera, -1});
    // Deleted objects leave the selection.
    st.select(obj(1));
    st.select(obj(3), EditorState::SelectMode::Toggle);
    st.scene.objects.pop_back();
    st.validateSelection();
    CHECK(st.selectedObjects().empty());   // the active one (3) is gone, so is the selection
}

TEST_CASE("a material is assigned to every selected object in one undo step", "[editor][lookdev]") {
    EditorState st = fourSpheres();
    st.select(obj(0));
    st.select(obj(2), EditorState::SelectMode::Toggle);
    st.select(obj(3), EditorState::SelectMode::Toggle);
    std::string why;
    auto c = makeAssignMaterial(st, st.selectedObjects(), "red", &why);
    REQUIRE(c);
    CHECK(c->name() == "Assign material 'red' to 3 objects");
    REQUIRE(st.apply(std::move(c)));
    CHECK(materialsOf(st) == std::vector<std::string>{"red", "white", "red", "red"});
    CHECK(st.history.undoCount() == 1);
    CHECK((st.takeDirty() & kDirtyGeometry) != 0);
    CHECK(st.selectedObjects() == std::vector<int>{0, 2, 3});   // the selection stays
    REQUIRE(st.undo());
    CHECK(materialsOf(st) == std::vector<std::string>{"white", "white", "white", "red"});
    CHECK(st.selectedObjects() == std::vector<int>{0, 2, 3});
    REQUIRE(st.redo());
    CHECK(materialsOf(st) == std::vector<std::string>{"red", "white", "red", "red"});
    // Refused: nothing to change, a material that does not exist, an object that does not.
    CHECK_FALSE(makeAssignMaterial(st, {0, 3}, "red", &why));
    CHECK(why.find("already") != std::string::npos);
    CHECK_FALSE(makeAssignMaterial(st, {0}, "chrome", &why));
    CHECK(why == "no material named 'chrome'");
    CHECK_FALSE(makeAssignMaterial(st, {9}, "red", &why));
}

TEST_CASE("New material gives the selected objects a fresh material, undo removes it", "[editor][lookdev]") {
    EditorState st = fourSpheres();
    std::string why;
    auto c = makeNewMaterialFor(st, {1, 2}, findLibraryMaterial("gold"), &why);
    REQUIRE(c);
    REQUIRE(st.apply(std::move(c)));
    REQUIRE(st.scene.materials.size() == 3);
    CHECK(st.scene.materials[2].name == "gold");
    CHECK(st.scene.materials[2].type == MaterialType::Conductor);
    CHECK(st.scene.materials[2].metal == Metal::Gold);
    CHECK(materialsOf(st) == std::vector<std::string>{"white", "gold", "gold", "red"});
    CHECK(st.history.undoCount() == 1);
    // Another gets a free name.
    REQUIRE(st.apply(makeNewMaterialFor(st, {0}, findLibraryMaterial("gold"), &why)));
    CHECK(st.scene.materials.back().name == "gold 2");
    REQUIRE(st.undo());
    REQUIRE(st.undo());
    CHECK(st.scene.materials.size() == 2);
    CHECK(materialsOf(st) == std::vector<std::string>{"white", "white", "white", "red"});
    CHECK(sceneToJson(st.scene) == sceneToJson(fourSpheres().scene));
}

TEST_CASE("Make unique copies a shared material for the selection only", "[editor][lookdev]") {
    EditorState st = fourSpheres();
    std::string why;
    auto c = makeMakeUnique(st, {1}, &why);
    REQUIRE(c);
    REQUIRE(st.apply(std::move(c)));
    REQUIRE(st.scene.materials.size() == 3);
    CHECK(st.scene.materials[2].name == "white 2");
    Material copy = st.scene.materials[2];
    copy.name = "white";
    CHECK(copy == st.scene.materials[0]);   // the same parameters
    CHECK(materialsOf(st) == std::vector<std::string>{"white", "white 2", "white", "red"});
    // An edit of the copy reaches only its object: the others keep "white".
    Material edited = st.scene.materials[2];
    edited.albedo = {0.1f, 0.9f, 0.1f};
    REQUIRE(st.apply(makeSetMaterial(st, 2, edited)));
    CHECK(st.scene.materials[0].albedo == glm::vec3(0.8f));
    // Refused where it means nothing: a material only the selection uses, mixed materials.
    CHECK_FALSE(makeMakeUnique(st, {3}, &why));
    CHECK(why.find("unique already") != std::string::npos);
    CHECK_FALSE(makeMakeUnique(st, {0, 3}, &why));
    CHECK(why == "the selected objects have different materials");
    CHECK_FALSE(makeMakeUnique(st, {}, &why));
    // Two selected objects of three users share one new copy.
    REQUIRE(st.undo());
    REQUIRE(st.undo());
    REQUIRE(st.apply(makeMakeUnique(st, {0, 2}, &why)));
    CHECK(materialsOf(st) == std::vector<std::string>{"white 2", "white", "white 2", "red"});
}

TEST_CASE("a preset applied to a material keeps its name and its objects", "[editor][lookdev]") {
    EditorState st = fourSpheres();
    const Material* glass = findLibraryMaterial("rough glass");
    REQUIRE(glass);
    REQUIRE(st.apply(makeApplyPreset(st, 0, *glass)));
    CHECK(st.scene.materials[0].name == "white");
    CHECK(st.scene.materials[0].type == MaterialType::Dielectric);
    CHECK(st.scene.materials[0].roughness > 0.0f);
    CHECK(materialsOf(st) == std::vector<std::string>{"white", "white", "white", "red"});
    REQUIRE(st.undo());
    CHECK(st.scene.materials[0] == fourSpheres().scene.materials[0]);
}

TEST_CASE("the preset library has the usual looks, each valid and uniquely named", "[editor][lookdev]") {
    std::set<std::string> names;
    for (const LibraryMaterial& l : materialLibrary()) {
        INFO(l.material.name);
        CHECK(checkEntity(l.material, "materials[0]").empty());   // the loader would take it
        CHECK(names.insert(l.material.name).second);
        CHECK_FALSE(l.group.empty());
    }
    for (const char* n : {"gold", "copper", "aluminium", "silver", "glass", "rough glass", "plastic", "rough plastic",
                          "matte white", "mirror", "velvet", "car paint", "jade", "marble", "wax", "skin", "milk"}) {
        INFO(n);
        CHECK(findLibraryMaterial(n));
    }
    CHECK(findLibraryMaterial("copper")->metal == Metal::Copper);
    CHECK(findLibraryMaterial("rough plastic")->type == MaterialType::Surface);
    CHECK(findLibraryMaterial("rough plastic")->specularRoughness > findLibraryMaterial("plastic")->specularRoughness);
    CHECK(findLibraryMaterial("glass")->roughness == 0.0f);
    CHECK_FALSE(findLibraryMaterial("unobtainium"));
}

TEST_CASE("every material model has an artist's name", "[editor][lookdev]") {
    std::set<std::string> seen;
    for (MaterialType t : {MaterialType::Diffuse, MaterialType::OrenNayar, MaterialType::Eon, MaterialType::Mirror,
                           MaterialType::Transmission, MaterialType::Dielectric, MaterialType::Conductor,
                           MaterialType::Surface}) {
        const std::string name(materialTypeArtistName(t));
        CHECK(name != "?");
        CHECK(seen.insert(name).second);
    }
    CHECK(materialTypeArtistName(MaterialType::Conductor).find("Metal") != std::string_view::npos);
    CHECK(materialTypeArtistName(MaterialType::Dielectric).find("Glass") != std::string_view::npos);
}

TEST_CASE("the preview ball's scene: the material on a sphere over a checker floor", "[editor][lookdev]") {
    EditorState st = fourSpheres();
    st.scene.sourcePath = "/some/folder/scene.json";
    Material gold = *findLibraryMaterial("gold");
    gold.albedoTexture = "tex/scratches.png";
    st.scene.environment.type = EnvironmentType::Map;
    st.scene.environment.file = "../assets/sky.hdr";
    const Scene p = makePreviewScene(st.scene, gold, PreviewLighting::Scene, 96, 32);
    CHECK(p.render.width == 96);
    CHECK(p.render.height == 96);
    CHECK(p.render.samples == 32);
    CHECK(p.sourcePath == st.scene.sourcePath);   // the material's and the map's files resolve from the scene
    const Material* ball = p.findMaterial(kPreviewMaterialName);
    REQUIRE(ball);
    Material expected = gold;
    expected.name = kPreviewMaterialName;
    CHECK(*ball == expected);
    REQUIRE(!p.objects.empty());
    CHECK(p.objects[0].shape == Shape::Sphere);
    CHECK(p.objects[0].material == kPreviewMaterialName);
    int light = 0, dark = 0;
    for (size_t i = 1; i < p.objects.size(); ++i) {
        CHECK(p.objects[i].shape == Shape::Quad);
        light += p.objects[i].material == "preview checker light";
        dark += p.objects[i].material == "preview checker dark";
    }
    CHECK(light == dark);
    CHECK(light > 8);
    CHECK(p.environment == st.scene.environment);   // the scene's environment
    CHECK(p.lights.empty());
    // The studio, and a scene without an environment, get the key light.
    const Scene studio = makePreviewScene(st.scene, gold, PreviewLighting::Studio);
    CHECK(studio.lights.size() == 1);
    CHECK(studio.environment.type == EnvironmentType::Constant);
    st.scene.environment = {};
    CHECK(makePreviewScene(st.scene, gold, PreviewLighting::Scene).lights.size() == 1);
    // The preview scene is one the loader takes (so the renderer can compile it).
    const SceneLoadResult reread = parseScene(sceneToJson(studio), "preview");
    CHECK(reread.error.empty());
}

#include "editor/model/focus_overlay.h"

TEST_CASE("the focus overlay marks what lies on the plane of focus", "[editor][camera]") {
    Scene scene;
    scene.render.width = 200;
    scene.render.height = 100;
    scene.camera.position = {0.0f, 0.0f, 5.0f};
    scene.camera.lookAt = {0.0f, 0.0f, 0.0f};
    Object ball;
    ball.name = "ball";   // the unit sphere: its front at depth 4
    scene.objects.push_back(ball);
    scene.camera.focalDistance = 4.0f;
    const auto near = inFocusCells(scene, 40, 20, 0.03f);
    REQUIRE_FALSE(near.empty());
    for (const FocusCell& c : near) {   // all near the image's centre, where the ball's front is
        CHECK(std::abs(c.x - 20) <= 6);
        CHECK(std::abs(c.y - 10) <= 6);
    }
    CHECK(std::find(near.begin(), near.end(), FocusCell{20, 10}) != near.end());
    // Focused behind the ball: nothing is on the plane.
    scene.camera.focalDistance = 8.0f;
    CHECK(inFocusCells(scene, 40, 20, 0.03f).empty());
    // A hit the shapes lack (a mesh, from the editor) counts.
    CHECK_FALSE(inFocusCells(scene, 40, 20, 0.03f, [](const caustic::editor::Ray& r) {
                    return std::optional<float>(8.0f / r.direction.z * -1.0f);
                }).empty());
    // The focus point overrides the distance; 0 means the look-at point's.
    scene.camera.focusPoint = glm::vec3(0.0f, 0.0f, 1.0f);
    CHECK(focusDistance(scene.camera, 2.0) == Approx(4.0));
    scene.camera.focusPoint.reset();
    scene.camera.focalDistance = 0.0f;
    CHECK(focusDistance(scene.camera, 2.0) == Approx(5.0));
    Camera moved = scene.camera;
    CHECK_FALSE(focusEdited(scene.camera, moved));
    moved.apertureRadius = 0.1f;
    CHECK(focusEdited(scene.camera, moved));
    moved = scene.camera;
    moved.position.x = 1.0f;
    CHECK_FALSE(focusEdited(scene.camera, moved));   // a move is no focus edit
}

TEST_CASE("the bokeh preview's scene: points across the frame behind the focus, seen by the edited camera",
          "[editor][lookdev][camera]") {
    EditorState st = fourSpheres();
    st.scene.sourcePath = "/some/folder/scene.json";
    st.scene.render.width = 300;
    st.scene.render.height = 200;
    st.scene.camera.apertureRadius = 0.05f;
    st.scene.camera.blades = 6;
    st.scene.camera.focalDistance = 2.0f;
    const Scene p = makeBokehPreviewScene(st.scene, nullptr, 120, 16);
    CHECK(p.camera == st.scene.camera);          // the lens as edited: aperture, blades, focus
    CHECK(p.sourcePath == st.scene.sourcePath);  // a lens file or aperture image resolves from the scene
    CHECK(p.render.width == 120);
    CHECK(p.render.height == 80);                // the edited image's aspect
    CHECK(p.render.samples == 16);
    REQUIRE(p.objects.size() == std::size_t(kBokehPreviewColumns * kBokehPreviewRows));
    REQUIRE(p.materials.size() == 1);
    CHECK(p.materials[0].emission.x > 1.0f);     // bright enough to show through the blur
    CHECK(p.lights.empty());
    CHECK(p.environment.type == EnvironmentType::None);
    const CameraFrame frame = cameraFrame(p.camera, p.render.width, p.render.height);
    for (int j = 0; j < kBokehPreviewRows; ++j)
        for (int i = 0; i < kBokehPreviewColumns; ++i) {
            const Object& o = p.objects[std::size_t(j * kBokehPreviewColumns + i)];
            // Ten times the focus distance away along the view, under its grid position.
            CHECK(glm::dot(glm::dvec3(o.transform.translate) - frame.position, frame.forward) ==
                  Approx(10.0 * frame.focalDistance).epsilon(1e-5));
            const glm::vec2 pixel(120.0f * (0.08f + 0.84f * float(i) / float(kBokehPreviewColumns - 1)),
                                  80.0f * (0.08f + 0.84f * float(j) / float(kBokehPreviewRows - 1)));
            const auto hit = pick(p, cameraRay(p.camera, p.render.width, p.render.height, pixel));
            REQUIRE(hit.has_value());
            CHECK(hit->ref.index == j * kBokehPreviewColumns + i);
        }
}
