// The editor's background mesh import (editor/model/mesh_loader.h): a file is imported and its BVH
// built on a worker thread, with the same result as the synchronous import the renderer does; a
// broken file yields the importer's message; cancel and destruction never hang or crash.
#include "editor/model/editor_state.h"
#include "editor/model/mesh_loader.h"
#include "renderer/gpu_scene.h"
#include "tests/editor/hang_guard.h"
#include "tests/support/meshes.h"

#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

using namespace caustic;
using namespace caustic::editor;

namespace {

// Waits for the worker and collects every result (the loader never blocks in poll()).
std::vector<MeshLoadResult> drain(MeshLoader& loader, std::size_t expected) {
    std::vector<MeshLoadResult> all;
    for (int i = 0; i < 600 && all.size() < expected; ++i) {
        if (!loader.waitIdle(test::kHangGuardSeconds)) FAIL("hung: the mesh loader never went idle");
        for (auto& r : loader.poll()) all.push_back(std::move(r));
    }
    return all;
}

}  // namespace

TEST_CASE("the mesh loader imports off the calling thread, as the synchronous import does", "[editor][mesh]") {
    test::TempDir dir;
    const std::string file = dir.file("torus.obj");
    test::writeObjTorus(file, 1.0, 0.3, 48, 24);

    MeshLoader loader;
    CHECK_FALSE(loader.busy());
    const std::uint64_t id = loader.request(file);
    CHECK(id >= 1);
    CHECK(loader.busy());
    const auto results = drain(loader, 1);
    REQUIRE(results.size() == 1);
    const MeshLoadResult& r = results[0];
    CHECK(r.id == id);
    CHECK(r.file == file);
    REQUIRE(r.ok());
    CHECK(r.error.empty());
    CHECK(r.thread != std::this_thread::get_id());
    CHECK(r.seconds > 0.0);
    CHECK_FALSE(loader.busy());
    CHECK(loader.pending().empty());

    MeshCacheEntry sync;
    std::string error;
    REQUIRE(prepareMesh(file, &sync, &error));
    const MeshCacheEntry& bg = *r.mesh;
    CHECK(bg.blas.triangles.size() == 48u * 24u * 2u);
    CHECK(bg.positions == sync.positions);
    CHECK(bg.blas.triangles == sync.blas.triangles);
    CHECK(bg.blas.triangleIds == sync.blas.triangleIds);
    REQUIRE(bg.blas.bvh.nodes.size() == sync.blas.bvh.nodes.size());
    CHECK(std::memcmp(bg.blas.bvh.nodes.data(), sync.blas.bvh.nodes.data(), bg.blas.bvh.nodes.size() * sizeof(BvhNode)) == 0);
    CHECK(bg.triangleSlot == sync.triangleSlot);
    CHECK(bg.vertices.size() == sync.vertices.size());
    CHECK(bg.stamp == sync.stamp);
    CHECK(bg.stamp == std::filesystem::last_write_time(file));
}

TEST_CASE("the mesh loader reports a broken file with the importer's message, in request order", "[editor][mesh]") {
    test::TempDir dir;
    const std::string good = dir.file("quad.obj"), broken = dir.file("broken.obj"), missing = dir.file("missing.obj");
    test::writeObjQuad(good);
    {
        std::ofstream f(broken);
        f << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";   // an index past the vertices: no usable triangle
    }
    MeshLoader loader;
    const auto a = loader.request(broken), b = loader.request(good), c = loader.request(missing);
    const auto results = drain(loader, 3);
    REQUIRE(results.size() == 3);
    CHECK(results[0].id == a);
    CHECK(results[1].id == b);
    CHECK(results[2].id == c);
    CHECK_FALSE(results[0].ok());
    CHECK_THAT(results[0].error, Catch::Contains("broken.obj"));
    CHECK(results[1].ok());
    CHECK_FALSE(results[2].ok());
    CHECK_THAT(results[2].error, Catch::Contains("missing.obj"));
}

TEST_CASE("the mesh loader cancels and joins cleanly", "[editor][mesh]") {
    test::TempDir dir;
    const std::string file = dir.file("sphere.obj");
    test::writeObjSphere(file, 128, 256);   // ~65k triangles: still importing when cancelled
    {
        MeshLoader loader;
        loader.request(file);
        loader.request(file);
        loader.cancel();
        if (!loader.waitIdle(test::kHangGuardSeconds)) FAIL("hung: the mesh loader never went idle");
        CHECK(loader.poll().empty());         // neither the cancelled import nor the queued one
        CHECK_FALSE(loader.busy());
        // It still works after a cancel.
        loader.request(file);
        CHECK(drain(loader, 1).size() == 1);
    }
    {
        MeshLoader loader;
        loader.request(file);
        loader.request(file);
    }   // destroyed while importing: joins without a result and without hanging
    SUCCEED();
}

TEST_CASE("a mesh file change is one edit, stored relative to the scene, and scenes are told apart", "[editor][mesh]") {
    EditorState s;
    const std::uint64_t untitled = s.generation();
    s.path = "/models/scenes/a.json";
    s.scene.sourcePath = s.path;
    CHECK(meshFileForScene(s, "/models/meshes/knot.obj") == "../meshes/knot.obj");
    s.apply(makeImportMesh(s, "/models/meshes/knot.obj"));
    REQUIRE(s.scene.objects.size() == 1);
    CHECK(s.scene.objects[0].file == "../meshes/knot.obj");
    // The renderer's cache key for it: resolved against the scene's folder.
    CHECK(meshCacheKey(s.scene, s.scene.objects[0].file) == "/models/meshes/knot.obj");
    auto c = makeSetMeshFile(s, 0, "/models/scenes/ball.obj");
    REQUIRE(c);
    CHECK((c->dirty() & kDirtyGeometry) != 0);
    s.apply(std::move(c));
    CHECK(s.scene.objects[0].file == "ball.obj");
    CHECK(s.history.undoCount() == 2);
    s.undo();
    CHECK(s.scene.objects[0].file == "../meshes/knot.obj");
    s.apply(makeAddObject(s, Shape::Sphere));
    CHECK_FALSE(makeSetMeshFile(s, 1, "/models/scenes/ball.obj"));   // not a mesh
    CHECK_FALSE(makeSetMeshFile(s, 7, "/models/scenes/ball.obj"));   // no such object
    CHECK(s.generation() == untitled);
    s.newScene();
    CHECK(s.generation() != untitled);
}

TEST_CASE("an imported model keeps its own materials, and a file without any gets the scene's first", "[editor][mesh]") {
    const std::string data = std::string(CAUSTIC_SOURCE_DIR) + "/tests/data/gltf/";
    const std::string knot = std::string(CAUSTIC_SOURCE_DIR) + "/assets/knot.obj";
    MeshCacheEntry glb, obj;
    std::string error;
    REQUIRE(prepareMesh(data + "leaf.glb", &glb, &error));
    REQUIRE(prepareMesh(knot, &obj, &error));
    CHECK(fileHasOwnMaterials(glb.imported));
    CHECK_FALSE(fileHasOwnMaterials(obj.imported));   // Assimp's DefaultMaterial only

    EditorState s;
    REQUIRE(!s.scene.materials.empty());
    const std::string first = s.scene.materials.front().name;
    REQUIRE(s.apply(makeImportMesh(s, data + "leaf.glb", fileHasOwnMaterials(glb.imported))));
    CHECK(s.scene.objects.back().material.empty());   // the file's own (the inspector lists them)
    REQUIRE(s.apply(makeImportMesh(s, knot, fileHasOwnMaterials(obj.imported))));
    CHECK(s.scene.objects.back().material == first);
    // The scene with the file's materials compiles with the file's material table.
    s.scene.sourcePath.clear();
    CompiledScene compiled;
    REQUIRE(compileScene(s.scene, readImageWithoutOpenImageIo, &compiled, &error));
    CHECK(compiled.materials.size() >= 1 + glb.materials.size());
}
