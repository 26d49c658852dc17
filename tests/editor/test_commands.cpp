// The editor's model without a window: commands, undo/redo, merging of drags, dirty flags,
// selection, names, modified tracking, files (open keeps the scene on error, atomic save,
// autosave, recent files).
#include "editor/model/editor_state.h"
#include "editor/model/editor_config.h"
#include "tests/editor/cornell_state.h"
#include "renderer/scene_io.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

using namespace caustic;
using namespace caustic::editor;
namespace fs = std::filesystem;

namespace {

using test::kCornell;
EditorState cornell() { return test::openCornell(); }

int objectIndex(const EditorState& s, const std::string& name) {
    EntityRef r = findEntity(s.scene, EntityKind::Object, name);
    REQUIRE(r.kind == EntityKind::Object);
    return r.index;
}

struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / ("caustic-editor-test-" + std::to_string(::getpid()) + "-" +
                                            std::to_string(counter()++));
        fs::create_directories(path);
    }
    ~TempDir() { std::error_code ec; fs::remove_all(path, ec); }
    static int& counter() { static int c = 0; return c; }
};

// One step of a drag, as the gizmo makes it: the object's current value, moved.
void dragStep(EditorState& s, int index, glm::vec3 delta) {
    Object o = s.scene.objects[static_cast<size_t>(index)];
    o.transform.translate += delta;
    s.applyContinuous(makeSetObject(s, index, o));
}

}  // namespace

TEST_CASE("an edit command executes, undoes and redoes, and reports what it dirtied", "[editor]") {
    EditorState s = cornell();
    const Scene original = s.scene;
    const int box = objectIndex(s, "small box");
    Object moved = s.scene.objects[static_cast<size_t>(box)];
    moved.transform.translate.x += 0.25f;
    s.apply(makeSetObject(s, box, moved));
    CHECK(s.scene.objects[static_cast<size_t>(box)].transform.translate.x == Approx(original.objects[static_cast<size_t>(box)].transform.translate.x + 0.25f));
    CHECK(s.takeDirty() == kDirtyTransforms);
    CHECK(s.modified());
    CHECK(s.history.undoName() == "Edit object 'small box'");

    REQUIRE(s.undo());
    CHECK(s.scene == original);
    CHECK(s.takeDirty() == kDirtyTransforms);
    CHECK_FALSE(s.modified());
    CHECK(s.selection == EntityRef{EntityKind::Object, box});

    REQUIRE(s.redo());
    CHECK(s.scene.objects[static_cast<size_t>(box)] == moved);
    CHECK_FALSE(s.redo());
}

TEST_CASE("dirty flags name what each kind of edit changed", "[editor]") {
    EditorState s = cornell();
    Material m = s.scene.materials[0];
    m.albedo = glm::vec3(0.5f);
    s.apply(makeSetMaterial(s, 0, m));
    CHECK(s.takeDirty() == kDirtyMaterials);

    Camera c = s.scene.camera;
    c.fovDegrees = 50.0f;
    s.apply(makeSetCamera(s, c));
    CHECK(s.takeDirty() == kDirtyCamera);

    RenderSettings r = s.scene.render;
    r.maxDepth = 3;
    s.apply(makeSetRender(s, r));
    CHECK(s.takeDirty() == kDirtySettings);

    Environment e = s.scene.environment;
    e.type = EnvironmentType::Sky;
    s.apply(makeSetEnvironment(s, e));
    CHECK(s.takeDirty() == kDirtyEnvironment);

    s.apply(makeAddLight(s, LightType::Rect));
    CHECK(s.takeDirty() == kDirtyLights);
    Light l = s.scene.lights[0];
    l.color *= 2.0f;
    s.apply(makeSetLight(s, 0, l));
    CHECK(s.takeDirty() == kDirtyLights);

    // An object's own emission changes the light list.
    const int lamp = findEntity(s.scene, EntityKind::Object, "ceiling light").index;
    REQUIRE(lamp >= 0);
    Object emitter = s.scene.objects[static_cast<size_t>(lamp)];
    emitter.emission *= 2.0f;
    s.apply(makeSetObject(s, lamp, emitter));
    CHECK(s.takeDirty() == kDirtyLights);
    emitter.twoSided = true;
    s.apply(makeSetObject(s, lamp, emitter));
    CHECK(s.takeDirty() == kDirtyLights);

    Object o = s.scene.objects[0];
    o.material = "red";
    s.apply(makeSetObject(s, 0, o));
    CHECK(s.takeDirty() == kDirtyGeometry);

    std::string why;
    s.apply(makeAddObject(s, Shape::Sphere));
    CHECK(s.takeDirty() == kDirtyGeometry);
    s.apply(makeAddLight(s, LightType::Point));
    CHECK(s.takeDirty() == kDirtyLights);

    // A rename changes nothing the renderer sees.
    s.apply(makeRename(s, {EntityKind::Object, 0}, "the floor", &why));
    CHECK(s.takeDirty() == kDirtyNone);
}

TEST_CASE("the steps of one drag merge into one undo step, sealed on release", "[editor]") {
    EditorState s = cornell();
    const Scene original = s.scene;
    const int box = objectIndex(s, "small box");
    for (int i = 0; i < 10; ++i) dragStep(s, box, glm::vec3(0.01f, 0.0f, 0.0f));
    s.seal();
    CHECK(s.history.undoCount() == 1);
    CHECK(s.takeDirty() == kDirtyTransforms);
    // A second drag after the release is a second step.
    for (int i = 0; i < 5; ++i) dragStep(s, box, glm::vec3(0.0f, 0.01f, 0.0f));
    s.seal();
    CHECK(s.history.undoCount() == 2);
    const glm::vec3 afterFirst = original.objects[static_cast<size_t>(box)].transform.translate + glm::vec3(0.1f, 0.0f, 0.0f);
    REQUIRE(s.undo());
    CHECK(s.scene.objects[static_cast<size_t>(box)].transform.translate.x == Approx(afterFirst.x));
    CHECK(s.scene.objects[static_cast<size_t>(box)].transform.translate.y == Approx(afterFirst.y));
    REQUIRE(s.undo());
    CHECK(s.scene == original);
    CHECK_FALSE(s.modified());
}

TEST_CASE("drags of different things never merge, and a discrete edit never merges", "[editor]") {
    EditorState s = cornell();
    dragStep(s, 0, glm::vec3(0.1f));
    dragStep(s, 1, glm::vec3(0.1f));     // another object: a new step even without a seal
    CHECK(s.history.undoCount() == 2);
    Camera c = s.scene.camera;
    c.fovDegrees += 1.0f;
    s.applyContinuous(makeSetCamera(s, c));   // another kind
    CHECK(s.history.undoCount() == 3);
    s.seal();
    Object o = s.scene.objects[0];
    o.transform.scale *= 2.0f;
    s.apply(makeSetObject(s, 0, o));
    o.transform.scale *= 2.0f;
    s.apply(makeSetObject(s, 0, o));          // discrete edits: one step each
    s.apply(makeSetObject(s, 0, o));          // one that changes nothing: no step (issue 15)
    CHECK(s.history.undoCount() == 5);
}

TEST_CASE("a new edit after undo drops the redo history", "[editor]") {
    EditorState s = cornell();
    dragStep(s, 0, glm::vec3(0.1f));
    s.seal();
    REQUIRE(s.undo());
    CHECK(s.history.canRedo());
    dragStep(s, 1, glm::vec3(0.1f));
    CHECK_FALSE(s.history.canRedo());
}

TEST_CASE("modified tracks the saved state through undo, redo and merges", "[editor]") {
    TempDir dir;
    EditorState s = cornell();
    dragStep(s, 0, glm::vec3(0.1f));
    std::string error;
    REQUIRE(s.saveAs((dir.path / "a.json").string(), &error));
    CHECK_FALSE(s.modified());
    // The drag goes on after the save (not sealed): the scene differs from the file.
    dragStep(s, 0, glm::vec3(0.1f));
    CHECK(s.modified());
    s.seal();
    REQUIRE(s.undo());
    CHECK(s.modified());   // back before the save-time state
    REQUIRE(s.redo());
    CHECK(s.modified());   // the merged step is not what was saved
}

TEST_CASE("add, duplicate and delete select sensibly and undo exactly", "[editor]") {
    EditorState s = cornell();
    const Scene original = s.scene;
    s.apply(makeAddObject(s, Shape::Box));
    CHECK(s.scene.objects.size() == original.objects.size() + 1);
    CHECK(s.scene.objects.back().name == "box");
    CHECK(s.selection == EntityRef{EntityKind::Object, static_cast<int>(original.objects.size())});
    std::string why;
    s.apply(makeDuplicate(s, s.selection, &why));
    CHECK(s.scene.objects.back().name == "box 2");
    s.apply(makeDuplicate(s, s.selection, &why));
    CHECK(s.scene.objects.back().name == "box 3");
    const int small = objectIndex(s, "small box");
    s.apply(makeDelete(s, {EntityKind::Object, small}, &why));
    CHECK(findEntity(s.scene, EntityKind::Object, "small box").kind == EntityKind::None);
    CHECK_FALSE(s.selection);
    REQUIRE(s.undo());
    CHECK(s.selection == EntityRef{EntityKind::Object, small});
    while (s.undo()) {}
    CHECK(s.scene == original);
}

TEST_CASE("a material in use cannot be deleted, renaming it renames its users' references", "[editor]") {
    EditorState s = cornell();
    const EntityRef white = findEntity(s.scene, EntityKind::Material, "white");
    std::string why;
    CHECK(makeDelete(s, white, &why) == nullptr);
    CHECK(why.find("used by object") != std::string::npos);
    auto rename = makeRename(s, white, "ivory", &why);
    REQUIRE(rename);
    s.apply(std::move(rename));
    CHECK(s.scene.findMaterial("ivory"));
    CHECK(s.scene.objects[0].material == "ivory");
    // Still a valid scene: it saves and loads.
    SceneLoadResult back = parseScene(sceneToJson(s.scene), "x.json");
    REQUIRE(back);
    REQUIRE(s.undo());
    CHECK(s.scene.objects[0].material == "white");
    CHECK(makeRename(s, white, "red", &why) == nullptr);
    CHECK(why == "another material is already called 'red'");
    s.apply(makeAddMaterial(s));
    CHECK(s.scene.materials.back().name == "material");
    CHECK(makeDelete(s, s.selection, &why) != nullptr);
}

TEST_CASE("unique names count on from a numbered name", "[editor]") {
    CHECK(uniqueName("box", {}) == "box");
    CHECK(uniqueName("box", {"box"}) == "box 2");
    CHECK(uniqueName("box 2", {"box", "box 2"}) == "box 3");
    CHECK(uniqueName("", {}) == "unnamed 2");
}

TEST_CASE("opening a broken scene keeps the current one and reports file and JSON path", "[editor]") {
    TempDir dir;
    EditorState s = cornell();
    dragStep(s, 0, glm::vec3(0.1f));
    const Scene before = s.scene;
    const std::string bad = (dir.path / "bad.json").string();
    {
        std::ofstream out(bad);
        out << R"({"version": 1, "objects": [{"shape": "sphere", "material": "nope"}]})";
    }
    std::string error;
    CHECK_FALSE(s.open(bad, &error));
    CHECK(error.find("bad.json") != std::string::npos);
    CHECK(error.find("objects[0].material") != std::string::npos);
    CHECK(s.scene == before);
    CHECK(s.path == kCornell);
    CHECK(s.history.undoCount() == 1);
    CHECK_FALSE(s.open((dir.path / "missing.json").string(), &error));
    CHECK(error.find("cannot read") != std::string::npos);
}

TEST_CASE("save writes a scene that loads back equal, a failed save keeps the old file", "[editor]") {
    TempDir dir;
    EditorState s = cornell();
    dragStep(s, 2, glm::vec3(0.0f, 0.2f, 0.0f));
    std::string error;
    const std::string file = (dir.path / "copy.json").string();
    REQUIRE(s.saveAs(file, &error));
    CHECK(s.path == file);
    SceneLoadResult back = loadScene(file);
    REQUIRE(back);
    CHECK(*back.scene == s.scene);
    // An unwritable target: the error names it, the old file is untouched.
    fs::create_directories(dir.path / "dir.json");
    CHECK_FALSE(s.saveAs((dir.path / "dir.json").string(), &error));
    CHECK_FALSE(error.empty());
    CHECK(s.path == file);
}

TEST_CASE("an untitled scene needs Save As", "[editor]") {
    EditorState s;
    CHECK(s.path.empty());
    CHECK(s.displayName() == "untitled");
    std::string error;
    CHECK_FALSE(s.save(&error));
    CHECK(error.find("Save As") != std::string::npos);
}

TEST_CASE("the autosave round-trips the scene and its owner and is offered back", "[editor]") {
    TempDir dir;
    EditorState s = cornell();
    dragStep(s, 0, glm::vec3(0.3f));
    Autosave a = Autosave::in((dir.path / "cfg").string());
    CHECK_FALSE(a.exists());
    std::string error;
    REQUIRE(a.write(s.scene, s.path, &error));
    REQUIRE(a.exists());
    auto recovered = a.read(&error);
    REQUIRE(recovered);
    CHECK(recovered->first == s.scene);
    CHECK(recovered->second == kCornell);
    EditorState t;
    t.adoptRecovered(recovered->first, recovered->second);
    CHECK(t.modified());
    CHECK(t.path == kCornell);
    CHECK(t.scene == s.scene);
    a.remove();
    CHECK_FALSE(a.exists());
}

namespace {
std::string fileText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}
}  // namespace

TEST_CASE("a corrupt autosave is reported, named and kept aside, not offered back or deleted", "[editor]") {
    TempDir dir;
    const fs::path cfg = dir.path / "cfg";
    Autosave a = Autosave::in(cfg.string());
    std::string error;
    REQUIRE(a.write(cornell().scene, kCornell, &error));
    // Cut short, as a crash in the middle of a copy or a full disk leaves a file.
    const std::string whole = fileText(a.scenePath);
    const std::string cut = whole.substr(0, whole.size() / 2);
    std::ofstream(a.scenePath, std::ios::binary | std::ios::trunc) << cut;

    Autosave::Found found = a.recover();
    CHECK_FALSE(found.recovered);
    INFO(found.message);
    // The message names the file and what is wrong with it (the parser's line and column).
    CHECK(found.message.find(a.scenePath + " could not be read") != std::string::npos);
    CHECK(found.message.find(a.scenePath + ":") != std::string::npos);
    const fs::path kept = cfg / "autosave.unreadable-1.json";
    CHECK(found.keptAs == kept.string());
    CHECK(found.message.find("kept as " + kept.string()) != std::string::npos);
    // The user's bytes are kept, out of the way of the next autosave and of the clean exit.
    CHECK(fileText(kept) == cut);
    CHECK(fileText(cfg / "autosave.unreadable-1.owner") == std::string(kCornell) + "\n");
    CHECK_FALSE(a.exists());
    CHECK_FALSE(a.frozen);
    REQUIRE(a.write(cornell().scene, kCornell, &error));
    a.remove();
    CHECK(fileText(kept) == cut);

    // A second unreadable autosave does not replace the first.
    std::ofstream(a.scenePath, std::ios::binary) << "{\"version\": 1, \"camera\": ";
    found = a.recover();
    CHECK_FALSE(found.recovered);
    CHECK(found.keptAs == (cfg / "autosave.unreadable-2.json").string());
    CHECK(fileText(kept) == cut);
    CHECK_FALSE(fs::exists(cfg / "autosave.unreadable-2.owner"));   // it had none

    // One that cannot be moved aside (every name taken) stays, and the session leaves it alone.
    for (int n = 1; n <= 1000; ++n) std::ofstream(cfg / ("autosave.unreadable-" + std::to_string(n) + ".json"));
    std::ofstream(a.scenePath, std::ios::binary) << "not json";
    found = a.recover();
    CHECK_FALSE(found.recovered);
    CHECK(found.keptAs.empty());
    CHECK(found.message.find(a.scenePath + " could not be read") != std::string::npos);
    CHECK(found.message.find("stays where it is") != std::string::npos);
    CHECK(a.frozen);
    a.remove();
    CHECK(fileText(a.scenePath) == "not json");
}

TEST_CASE("recent files: most recent first, no duplicates, at most ten, persisted", "[editor]") {
    TempDir dir;
    RecentFiles r;
    for (int i = 0; i < 12; ++i) r.add("f" + std::to_string(i) + ".json");
    r.add("f5.json");
    REQUIRE(r.files().size() == RecentFiles::kMax);
    CHECK(r.files()[0] == "f5.json");
    CHECK(r.files()[1] == "f11.json");
    std::string error;
    const std::string list = (dir.path / "sub" / "recent.txt").string();
    REQUIRE(r.save(list, &error));
    RecentFiles back;
    REQUIRE(back.load(list));
    CHECK(back.files() == r.files());
    RecentFiles none;
    CHECK_FALSE(none.load((dir.path / "missing.txt").string()));
    CHECK(none.files().empty());
}

TEST_CASE("the selection is dropped when its entity disappears", "[editor]") {
    EditorState s = cornell();
    s.selection = {EntityKind::Object, static_cast<int>(s.scene.objects.size()) - 1};
    s.scene.objects.pop_back();
    s.validateSelection();
    CHECK_FALSE(s.selection);
}

TEST_CASE("importing a mesh adds a mesh object whose file is relative to the scene", "[editor]") {
    EditorState s = cornell();
    const std::string file = std::string(CAUSTIC_SOURCE_DIR) + "/scenes/models/bunny.obj";
    s.apply(makeImportMesh(s, file));
    const Object& o = s.scene.objects.back();
    CHECK(o.shape == Shape::Mesh);
    CHECK(o.name == "bunny");
    CHECK(o.file == "models/bunny.obj");
    CHECK(s.takeDirty() == kDirtyGeometry);
    Object changed = o;
    changed.file = "models/other.obj";
    s.apply(makeSetObject(s, static_cast<int>(s.scene.objects.size()) - 1, changed));
    CHECK(s.takeDirty() == kDirtyGeometry);
}
