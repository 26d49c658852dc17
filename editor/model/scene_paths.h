// The files a scene names (environment map, mesh files, textures) are relative to the scene
// file's folder (renderer/scene.h). Saving the scene into another folder must rebase them, or the
// saved file names files that are not there ("cannot read image" in batch mode and at the next
// edit). No ImGui, no GL: unit-tested in tests/editor/test_scene_paths.cpp.
#pragma once

#include "renderer/scene.h"

#include <string>

namespace caustic::editor {

// The folder a scene file's relative paths are relative to: the file's folder, made absolute and
// normalised; for "" (an untitled scene) the working directory, which is what they resolve
// against then.
std::string sceneFolderOf(const std::string& sceneFile);

// `file` as seen from `toFolder` instead of `fromFolder` (both as sceneFolderOf gives them):
// "" and absolute paths stay as they are; a relative one stays relative ("../assets/sky.hdr"
// from scenes/ is "../../assets/sky.hdr" from scenes/sub/), lexically, so a path through a
// symbolic link is rebased as written. Unchanged when the folders are the same.
std::string rebasePath(const std::string& file, const std::string& fromFolder, const std::string& toFolder);

// Every path an entity names: an object's mesh file, a material's textures, the environment map.
// (Other entities name no files: the overloads for them do nothing.)
void rebasePaths(Object& o, const std::string& fromFolder, const std::string& toFolder);
void rebasePaths(Material& m, const std::string& fromFolder, const std::string& toFolder);
void rebasePaths(Environment& e, const std::string& fromFolder, const std::string& toFolder);
template <class T>
void rebasePaths(T&, const std::string&, const std::string&) {}
void rebaseScenePaths(Scene& scene, const std::string& fromFolder, const std::string& toFolder);

// The name Save As proposes in `folder` for the scene at `currentFile` ("" when untitled): never
// an existing file, so that pressing Save at once cannot overwrite anything: "scene.json" when
// untitled, else "<stem>-2.json" (or -3, ...), the first that does not exist there.
std::string suggestSaveAsName(const std::string& folder, const std::string& currentFile);

}  // namespace caustic::editor
