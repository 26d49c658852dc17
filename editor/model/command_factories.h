// The edits of the editor, built from the current scene (the usual way to make a command for
// EditorState::apply), and the names they give: unique names, entity names, lookup by name.
#pragma once

#include "editor/model/commands.h"
#include "editor/model/viewport_math.h"
#include "renderer/mesh.h"
#include "renderer/scene.h"

#include <memory>
#include <string>
#include <vector>

namespace caustic::editor {

class EditorState;

std::unique_ptr<Command> makeSetObject(const EditorState& s, int index, Object after);
std::unique_ptr<Command> makeSetLight(const EditorState& s, int index, Light after);
std::unique_ptr<Command> makeSetMaterial(const EditorState& s, int index, Material after);
std::unique_ptr<Command> makeSetCamera(const EditorState& s, Camera after);
std::unique_ptr<Command> makeSetRender(const EditorState& s, RenderSettings after);
std::unique_ptr<Command> makeSetEnvironment(const EditorState& s, Environment after);

// Adds a primitive, light or material with a unique name in front of the camera's look-at point.
std::unique_ptr<Command> makeAddObject(const EditorState& s, Shape shape);
// A light above the camera's look-at point, raised clear of the objects there (their bounds;
// meshes' through meshBounds when given).
std::unique_ptr<Command> makeAddLight(const EditorState& s, LightType type, const MeshBoundsLookup& meshBounds = {});
// preset: a material to copy (renderer/gpu_materials.h materialPresets), named after it.
std::unique_ptr<Command> makeAddMaterial(const EditorState& s, const Material* preset = nullptr);
// A mesh object for a model file (check the file first: the renderer would refuse a broken one).
// The path is stored relative to the scene's folder when the scene has a file. ownMaterials (the
// file has materials of its own: fileHasOwnMaterials): the object keeps them (material ""), as
// Blender's import does; else it gets the scene's first material, if any.
std::unique_ptr<Command> makeImportMesh(const EditorState& s, const std::string& file, bool ownMaterials = true);
// Whether an imported model file brings materials of its own: any but the one Assimp makes up for
// a file without any ("DefaultMaterial": OBJ without .mtl, PLY, STL, OFF).
bool fileHasOwnMaterials(const std::vector<ImportedMaterial>& imported);
// Object `index` (a mesh) with another model file; null when index is not a mesh object.
std::unique_ptr<Command> makeSetMeshFile(const EditorState& s, int index, const std::string& file);
// A model file's path as a mesh object of this scene stores it: relative to the scene's folder
// when the scene has a file, else as given.
std::string meshFileForScene(const EditorState& s, const std::string& file);
// Duplicates / deletes the entity `ref` (objects, lights, materials). Returns null with *why set
// when it cannot (e.g. deleting a material that objects use).
std::unique_ptr<Command> makeDuplicate(const EditorState& s, EntityRef ref, std::string* why);
std::unique_ptr<Command> makeDelete(const EditorState& s, EntityRef ref, std::string* why);
// Renames (names must stay unique among their kind; a material rename follows its users).
std::unique_ptr<Command> makeRename(const EditorState& s, EntityRef ref, const std::string& name, std::string* why);

// "box" -> "box", or "box 2", "box 3" ... whichever is free among `taken`.
std::string uniqueName(const std::string& base, const std::vector<std::string>& taken);
std::string entityName(const Scene& scene, EntityRef ref);
// Finds an entity by kind and name (the singletons ignore the name).
EntityRef findEntity(const Scene& scene, EntityKind kind, const std::string& name);

}  // namespace caustic::editor
