// Opening a scene in the background (editor/model/scene_open.h, docs/editor.md "Opening scenes"):
// which mesh files a scene needs, which of them are imported, progress, the first failure naming
// the object and file, and the loader's per-request cancel that a superseded open uses.
#include "editor/model/editor_state.h"
#include "editor/model/scene_open.h"
#include "renderer/gpu_scene.h"
#include "renderer/scene_io.h"
#include "tests/editor/hang_guard.h"
#include "tests/support/meshes.h"

#include <catch2/catch.hpp>

#include <fstream>

using namespace caustic;
using namespace caustic::editor;

namespace {

Object meshObject(const std::string& name, const std::string& file) {
    Object o;
    o.shape = Shape::Mesh;
    o.name = name;
    o.file = file;
    return o;
}

Scene sceneWithMeshes() {
    Scene s;
    s.sourcePath = "/scenes/a/scene.json";
    Object sphere;
    sphere.shape = Shape::Sphere;
    sphere.name = "ball";
    s.objects.push_back(sphere);
    s.objects.push_back(meshObject("knot", "../meshes/knot.obj"));
    s.objects.push_back(meshObject("bunny", "/abs/bunny.ply"));
    s.objects.push_back(meshObject("knot again", "../meshes/./knot.obj"));   // the same file
    return s;
}

MeshLoadResult result(std::uint64_t id, bool ok, const std::string& error = {}) {
    MeshLoadResult r;
    r.id = id;
    if (ok) r.mesh = std::make_shared<MeshCacheEntry>();
    r.error = error;
    r.seconds = 0.5;
    return r;
}

}  // namespace

TEST_CASE("a scene's mesh files are its distinct cache keys, resolved against the scene", "[editor][open]") {
    const auto files = sceneMeshFiles(sceneWithMeshes());
    REQUIRE(files.size() == 2);
    CHECK(files[0].key == "/scenes/meshes/knot.obj");
    CHECK(files[0].objectIndex == 1);
    CHECK(files[0].objectName == "knot");
    CHECK(files[1].key == "/abs/bunny.ply");
    CHECK(files[1].objectIndex == 2);
    CHECK(sceneMeshFiles(Scene{}).empty());
}

TEST_CASE("an open imports only what the renderer does not hold and is ready when all arrive", "[editor][open]") {
    auto heldKnot = [](const std::string& key) { return key == "/scenes/meshes/knot.obj"; };
    PendingOpen open(sceneWithMeshes(), "/scenes/a/scene.json", false, heldKnot);
    REQUIRE(open.toImport() == std::vector<std::string>{"/abs/bunny.ply"});
    CHECK_FALSE(open.ready());
    open.requested(0, 7);
    CHECK(open.ids() == std::vector<std::uint64_t>{7});
    CHECK(open.status() == "opening scene.json: importing 1 of 1 meshes ...");
    CHECK_FALSE(open.take(result(8, true)));   // someone else's request
    CHECK(open.take(result(7, true)));
    CHECK_FALSE(open.take(result(7, true)));   // only once
    CHECK(open.ready());
    CHECK_FALSE(open.failed());
    CHECK(open.ids().empty());
    REQUIRE(open.meshes().size() == 1);
    CHECK(open.meshes()[0].first == "/abs/bunny.ply");
    CHECK(open.seconds() == std::vector<double>{0.5});

    // Nothing to import (all held, or no meshes): ready at once.
    PendingOpen all(sceneWithMeshes(), "/scenes/a/scene.json", false, [](const std::string&) { return true; });
    CHECK(all.toImport().empty());
    CHECK(all.ready());
    PendingOpen none(Scene{}, "x.json", false, nullptr);
    CHECK(none.ready());
}

TEST_CASE("an open counts its progress and fails with the first broken mesh, naming object and file", "[editor][open]") {
    PendingOpen open(sceneWithMeshes(), "/scenes/a/scene.json", false, nullptr);
    REQUIRE(open.toImport().size() == 2);
    open.requested(0, 1);
    open.requested(1, 2);
    CHECK(open.status() == "opening scene.json: importing 1 of 2 meshes ...");
    CHECK(open.take(result(1, false, "/scenes/meshes/knot.obj: no triangles")));
    CHECK(open.failed());
    CHECK(open.error() == "objects[1] ('knot').file: /scenes/meshes/knot.obj: no triangles");
    CHECK(open.status() == "opening scene.json: importing 2 of 2 meshes ...");
    CHECK(open.ids() == std::vector<std::uint64_t>{2});   // what a failed open cancels
    CHECK(open.take(result(2, false, "/abs/bunny.ply: missing")));
    CHECK(open.error() == "objects[1] ('knot').file: /scenes/meshes/knot.obj: no triangles");   // the first
}

TEST_CASE("adopting an opened scene is what open() does, and the history's revision tracks edits", "[editor][open]") {
    const std::string file = std::string(CAUSTIC_SOURCE_DIR) + "/scenes/cornell-box.json";
    EditorState opened, adopted;
    std::string error;
    REQUIRE(opened.open(file, &error));
    const std::uint64_t r0 = adopted.history.revision();
    adopted.apply(makeAddObject(adopted, Shape::Box));
    const std::uint64_t r1 = adopted.history.revision();
    CHECK(r1 != r0);
    adopted.undo();
    CHECK(adopted.history.revision() == r0);
    adopted.redo();
    CHECK(adopted.history.revision() == r1);
    const std::uint64_t generation = adopted.generation();
    SceneLoadResult loaded = loadScene(file);
    REQUIRE(loaded);
    adopted.adoptOpened(std::move(*loaded.scene), file);
    CHECK(adopted.generation() != generation);
    CHECK(adopted.scene == opened.scene);
    CHECK(adopted.scene.sourcePath == file);
    CHECK(adopted.path == file);
    CHECK_FALSE(adopted.modified());
    CHECK(adopted.history.undoCount() == 0);
}

TEST_CASE("the mesh loader cancels single requests and leaves the others", "[editor][open]") {
    test::TempDir dir;
    const std::string big = dir.file("sphere.obj"), small = dir.file("quad.obj");
    test::writeObjSphere(big, 128, 256);   // ~65k triangles: still importing when cancelled
    test::writeObjQuad(small);
    MeshLoader loader;
    const auto a = loader.request(big), b = loader.request(small), c = loader.request(big), d = loader.request(small);
    loader.cancel({a, c});   // the one in progress (or queued) and a queued one
    std::vector<MeshLoadResult> all;
    for (int i = 0; i < 100 && all.size() < 2; ++i) {
        if (!loader.waitIdle(test::kHangGuardSeconds)) FAIL("hung: the mesh loader never went idle");
        for (auto& r : loader.poll()) all.push_back(std::move(r));
    }
    REQUIRE(all.size() == 2);
    CHECK(all[0].id == b);
    CHECK(all[1].id == d);
    CHECK(all[0].ok());
    CHECK(loader.poll().empty());
    CHECK_FALSE(loader.busy());
}
