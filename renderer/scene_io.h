// Scene files: JSON <-> Scene. docs/scene-format.md documents the format; keep the two in step.
// Nothing here throws: every failure (unreadable file, JSON syntax, unknown key, wrong type,
// out-of-range value, dangling reference, out of memory) comes back as a one-line message:
//   "<file>: <json.path>: <what is wrong>"      e.g. "a.json: objects[3].material: unknown material 'blue' (known: white, red)"
//   "<file>:<line>:<column>: JSON syntax error: <explanation>"
//   "<file>: cannot read: <OS reason>"
#pragma once

#include "renderer/scene.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace caustic {

struct SceneLoadResult {
    std::optional<Scene> scene;
    std::string error;         // empty when scene is set
    explicit operator bool() const { return scene.has_value(); }
};

// Reads, parses and validates a scene file; sets Scene::sourcePath to file.
SceneLoadResult loadScene(const std::string& file);

// One `--set path=value`: path in the messages' syntax ("camera.fov", "objects[2].transform.scale",
// "materials[gold].albedo" picks the array element whose "name" is gold); value is JSON ("0.5",
// "[1, 0, 0]", "\"tent\"") or, if it is not valid JSON, a string ("tent").
struct SceneOverride {
    std::string path;
    std::string value;
};
// Parses "path=value"; false with a message if there is no '=' or the path is empty.
bool parseSceneOverride(const std::string& text, SceneOverride* out, std::string* error);
// loadScene with the overrides applied to the JSON before validation, so an override is checked
// exactly like the file itself (messages name the JSON path).
SceneLoadResult loadScene(const std::string& file, const std::vector<SceneOverride>& overrides);

// Parses and validates scene JSON; fileForMessages only prefixes error messages (sourcePath stays
// empty).
SceneLoadResult parseScene(const std::string& jsonText, const std::string& fileForMessages);

// Parses any JSON file of caustic's (a sheet layout, say) as strictly as a scene file: nested at
// most as deep, a syntax error at "<file>:<line>:<column>", a duplicate key or a number out of
// range at its JSON path. False with the message in *error.
bool parseJsonStrict(const std::string& jsonText, const std::string& fileForMessages, nlohmann::json* out,
                     std::string* error);

// The scene as pretty JSON (2-space indent, numeric vectors on one line, trailing newline) in the
// full explicit form: every field of the scene's types is written, so parseScene(sceneToJson(s))
// reproduces s exactly (floats are written with enough digits to round-trip). Fields that do not
// apply (e.g. a point light's radius) and empty object/light names are omitted. Returns an empty
// string only when out of memory.
std::string sceneToJson(const Scene& scene);

// Validates the scene (by parsing sceneToJson's output, so a saved file always loads) and writes it
// atomically (writeFileAtomically): on failure the old file, if any, is untouched and no partial or
// temporary file is left; *error (if non-null) gets the reason.
bool saveScene(const Scene& scene, const std::string& file, std::string* error);

// Checks one entity the way the scene reader checks it in a file (types, ranges, finite numbers,
// e.g. no NaN or infinity in a translation), so an editor can refuse an edit that would make the
// scene unsaveable. "" when valid, else "<path>.<json path>: <what is wrong>", with `path` the
// entity's own place ("objects[3]", "camera"). References between entities (an object's
// material) are not checked here.
std::string checkEntity(const Object& value, const std::string& path);
std::string checkEntity(const Light& value, const std::string& path);
std::string checkEntity(const Material& value, const std::string& path);
std::string checkEntity(const Camera& value, const std::string& path);
std::string checkEntity(const RenderSettings& value, const std::string& path);
std::string checkEntity(const Environment& value, const std::string& path);

}  // namespace caustic
