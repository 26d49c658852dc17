// The files a scene may name, for the inspector's file picker (issue 15): textures, meshes and
// HDR environment maps found in the scene's folder and in the assets folder, filtered by
// extension (lens prescriptions: .lens, docs/lenses.md), each with the path the scene stores (relative to the scene's folder, as every path a
// scene names is: renderer/scene.h). No ImGui, no GL: unit-tested in tests/editor/test_asset_files.cpp.
#pragma once

#include <string>
#include <vector>

namespace caustic::editor {

enum class AssetKind { Texture, Mesh, EnvironmentMap, Lens };

// Whether a file of that name is listed for the kind (by its extension, case-insensitive):
// textures .png .jpg .jpeg .exr .hdr .tga .bmp .tif .tiff; meshes what the importer reads
// (renderer/mesh_import.h); environment maps .hdr .exr; lenses .lens.
bool isAssetFile(AssetKind kind, const std::string& path);

// The assets folder for a scene in `sceneFolder` (absolute): $CAUSTIC_ASSETS_DIR when set, else
// the first of <sceneFolder>/assets and <sceneFolder>/../assets that exists (a project laid out
// as scenes/ beside assets/, as this repository is); "" when none does.
std::string assetsFolderFor(const std::string& sceneFolder);

struct AssetFile {
    std::string root;       // "scene folder" or "assets"
    std::string display;    // the path under its root ("tiles/albedo.png")
    std::string stored;     // what the scene stores: relative to the scene's folder
    std::string absolute;
};

// Files of `kind` under the scene's folder and the assets folder (sub-folders too, at most
// `maxDepth` levels down and `maxFiles` in all; hidden files and folders skipped; a folder that
// cannot be read is skipped), sorted by root, then path; a file under both roots is listed once,
// under the scene's folder. `sceneFolder` as sceneFolderOf gives it.
std::vector<AssetFile> listAssetFiles(AssetKind kind, const std::string& sceneFolder, const std::string& assetsFolder,
                                      int maxDepth = 3, std::size_t maxFiles = 2000);

// `file` (absolute, or relative to the working directory) as a scene in `sceneFolder` stores it:
// relative to the folder (lexically, "../assets/sky.hdr"), or absolute when it is on another
// root.
std::string pathForScene(const std::string& file, const std::string& sceneFolder);

}  // namespace caustic::editor
