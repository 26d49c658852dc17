// The inspector's file picker's listing (editor/model/asset_files.h): the scene's folder and the
// assets folder, filtered by the kind's extensions, with the paths the scene stores.
#include "editor/model/asset_files.h"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <string>

namespace fs = std::filesystem;
using namespace caustic::editor;

namespace {

void touchFile(const fs::path& p) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << "x";
}

std::vector<std::string> stored(const std::vector<AssetFile>& files) {
    std::vector<std::string> out;
    for (const AssetFile& f : files) out.push_back(f.root + ":" + f.display + "=" + f.stored);
    return out;
}

}  // namespace

TEST_CASE("the file picker lists the scene's and the assets folder's files of a kind, relative to the scene",
          "[editor][files]") {
    unsetenv("CAUSTIC_ASSETS_DIR");
    const fs::path root = fs::temp_directory_path() / ("caustic-assets-" + std::to_string(::getpid()));
    fs::remove_all(root);
    // project/scenes/ beside project/assets/, as this repository is laid out.
    touchFile(root / "scenes" / "scene.json");
    touchFile(root / "scenes" / "local.PNG");
    touchFile(root / "scenes" / "maps" / "wood.jpg");
    touchFile(root / "scenes" / ".hidden" / "secret.png");
    touchFile(root / "scenes" / "a" / "b" / "c" / "too-deep.png");
    touchFile(root / "assets" / "sky.hdr");
    touchFile(root / "assets" / "tiles" / "albedo.png");
    touchFile(root / "assets" / "tiles" / "torus.obj");
    touchFile(root / "assets" / "notes.txt");
    touchFile(root / "assets" / "lenses" / "dgauss.lens");
    const std::string scenes = (root / "scenes").string();

    CHECK(assetsFolderFor(scenes) == (root / "assets").string());
    CHECK(stored(listAssetFiles(AssetKind::Texture, scenes, assetsFolderFor(scenes))) ==
          std::vector<std::string>{"scene folder:local.PNG=local.PNG", "scene folder:maps/wood.jpg=maps/wood.jpg",
                                   "assets:sky.hdr=../assets/sky.hdr", "assets:tiles/albedo.png=../assets/tiles/albedo.png"});
    CHECK(stored(listAssetFiles(AssetKind::EnvironmentMap, scenes, assetsFolderFor(scenes))) ==
          std::vector<std::string>{"assets:sky.hdr=../assets/sky.hdr"});
    CHECK(stored(listAssetFiles(AssetKind::Lens, scenes, assetsFolderFor(scenes))) ==
          std::vector<std::string>{"assets:lenses/dgauss.lens=../assets/lenses/dgauss.lens"});
    CHECK(stored(listAssetFiles(AssetKind::Mesh, scenes, assetsFolderFor(scenes))) ==
          std::vector<std::string>{"assets:tiles/torus.obj=../assets/tiles/torus.obj"});
    // Deeper folders when asked; a file under both roots is listed once (the scene's folder's).
    CHECK(listAssetFiles(AssetKind::Texture, scenes, "", 4).size() == 3);
    CHECK(listAssetFiles(AssetKind::Texture, (root).string(), (root / "assets").string()).size() == 4);
    // The assets folder inside the scene's folder wins; $CAUSTIC_ASSETS_DIR over both.
    touchFile(root / "scenes" / "assets" / "x.png");
    CHECK(assetsFolderFor(scenes) == (root / "scenes" / "assets").string());
    setenv("CAUSTIC_ASSETS_DIR", (root / "assets" / "tiles").string().c_str(), 1);
    CHECK(assetsFolderFor(scenes) == (root / "assets" / "tiles").string());
    unsetenv("CAUSTIC_ASSETS_DIR");
    // No folder at all, or an unreadable one: nothing, no throw.
    CHECK(listAssetFiles(AssetKind::Texture, (root / "nowhere").string(), "").empty());
    CHECK(pathForScene((root / "assets" / "sky.hdr").string(), scenes) == "../assets/sky.hdr");
    CHECK(pathForScene((root / "scenes" / "local.PNG").string(), scenes) == "local.PNG");
    fs::remove_all(root);
}

TEST_CASE("asset kinds by extension", "[editor][files]") {
    CHECK(isAssetFile(AssetKind::Texture, "a/b.JPEG"));
    CHECK(isAssetFile(AssetKind::Texture, "x.exr"));
    CHECK_FALSE(isAssetFile(AssetKind::Texture, "x.json"));
    CHECK_FALSE(isAssetFile(AssetKind::Texture, "png"));
    CHECK(isAssetFile(AssetKind::EnvironmentMap, "sky.HDR"));
    CHECK_FALSE(isAssetFile(AssetKind::EnvironmentMap, "sky.png"));
    CHECK(isAssetFile(AssetKind::Mesh, "m.obj"));
    CHECK(isAssetFile(AssetKind::Mesh, "m.gltf"));
    CHECK_FALSE(isAssetFile(AssetKind::Mesh, "m.png"));
}

#include "editor/model/camera_views.h"

TEST_CASE("saved camera views: stored by scene file, kept across sessions, carried by Save As", "[editor][camera]") {
    const fs::path root = fs::temp_directory_path() / ("caustic-views-" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root);
    const std::string file = (root / "views.json").string();
    const std::string a = (root / "a.json").string(), b = (root / "sub" / "b.json").string();
    caustic::Camera wide, close;
    close.position = {1.0f, 2.0f, 3.0f};
    close.focusPoint = glm::vec3(0.5f, 0.0f, 0.0f);
    close.apertureRadius = 0.05f;
    close.blades = 6;
    CameraViews v;
    std::string error;
    REQUIRE(v.load(file, &error));   // no file yet: no views
    CHECK(v.nextName(a) == "view 1");
    v.store(a, "wide", wide);
    v.store(a, "close", wide);
    v.store(a, "close", close);      // replaces
    CHECK(v.of(a).size() == 2);
    CHECK(v.find(a, "close")->camera == close);
    CHECK(v.of(b).empty());
    CHECK(v.of((root / "." / "a.json").string()).size() == 2);   // the same file however it is written
    REQUIRE(v.save(file, &error));
    CameraViews again;
    REQUIRE(again.load(file, &error));
    CHECK(again.of(a) == v.of(a));
    again.carry(a, b);
    CHECK(again.of(b) == v.of(a));
    CHECK(again.remove(a, "wide"));
    CHECK_FALSE(again.remove(a, "wide"));
    CHECK(again.of(a).size() == 1);
    CHECK(again.of(b).size() == 2);
    // A broken file is reported and changes nothing; a camera the reader would refuse is skipped.
    { std::ofstream(file) << "{ not json"; }
    CHECK_FALSE(again.load(file, &error));
    CHECK(error.find("views.json") != std::string::npos);
    CHECK(again.of(b).size() == 2);
    { std::ofstream(file) << R"({"scenes": {")" << a << R"(": [{"name": "bad", "camera": {"position": [0,0,0], "look_at": [0,0,0], "up": [0,1,0], "fov": 40}}, {"name": "ok", "camera": {"position": [0,0,5], "look_at": [0,0,0], "up": [0,1,0], "fov": 40}}]}})"; }
    CameraViews third;
    REQUIRE(third.load(file, &error));
    REQUIRE(third.of(a).size() == 1);
    CHECK(third.of(a)[0].name == "ok");
    fs::remove_all(root);
}
