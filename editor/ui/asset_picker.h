// The file picker of the inspector's file fields (textures, the environment map, a mesh
// object's file): a "..." button beside the field opens a list of the matching files of the
// scene's folder and the assets folder (editor/model/asset_files.h), with a filter; a click picks
// one. The list is read when the picker opens (not every frame).
#pragma once

#include "editor/model/asset_files.h"

#include <optional>

namespace caustic::editor {

struct EditorUi;

// The "..." button and its popup (id unique in the window). Returns the file picked this frame.
std::optional<AssetFile> assetPickerButton(EditorUi& ui, const char* id, AssetKind kind);

// The button's width, to leave room for it beside a field.
float assetPickerButtonWidth();

}  // namespace caustic::editor
