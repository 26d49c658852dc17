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
    const std::string scenes = (root / "scenes").string();

    CHECK(assetsFolderFor(scenes) == (root / "assets").string());
    CHECK(stored(listAssetFiles(AssetKind::Texture, scenes, assetsFolderFor(scenes))) ==
          std::vector<std::string>{"scene folder:local.PNG=local.PNG", "scene folder:maps/wood.jpg=maps/wood.jpg",
                                   "assets:sky.hdr=../assets/sky.hdr", "assets:tiles/albedo.png=../assets/tiles/albedo.png"});
    CHECK(stored(listAssetFiles(AssetKind::EnvironmentMap, scenes, assetsFolderFor(scenes))) ==
          std::vector<std::string>{"assets:sky.hdr=../assets/sky.hdr"});
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
