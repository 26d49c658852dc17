#include "editor/model/command_factories.h"

#include "editor/model/editor_state.h"

#include <algorithm>
#include <filesystem>

namespace fs = std::filesystem;

namespace caustic::editor {

std::unique_ptr<Command> makeSetObject(const EditorState& s, int index, Object after) {
    return std::make_unique<SetCommand<Object>>(index, s.scene.objects.at(static_cast<size_t>(index)), std::move(after));
}
std::unique_ptr<Command> makeSetLight(const EditorState& s, int index, Light after) {
    return std::make_unique<SetCommand<Light>>(index, s.scene.lights.at(static_cast<size_t>(index)), std::move(after));
}
std::unique_ptr<Command> makeSetMaterial(const EditorState& s, int index, Material after) {
    return std::make_unique<SetCommand<Material>>(index, s.scene.materials.at(static_cast<size_t>(index)), std::move(after));
}
std::unique_ptr<Command> makeSetCamera(const EditorState& s, Camera after) {
    return std::make_unique<SetCommand<Camera>>(-1, s.scene.camera, after);
}
std::unique_ptr<Command> makeSetRender(const EditorState& s, RenderSettings after) {
    return std::make_unique<SetCommand<RenderSettings>>(-1, s.scene.render, after);
}
std::unique_ptr<Command> makeSetEnvironment(const EditorState& s, Environment after) {
    return std::make_unique<SetCommand<Environment>>(-1, s.scene.environment, std::move(after));
}

namespace {

template <class T>
std::vector<std::string> namesOf(const std::vector<T>& list) {
    std::vector<std::string> names;
    for (const T& e : list) names.push_back(e.name);
    return names;
}

std::vector<std::string> namesOfKind(const Scene& scene, EntityKind kind) {
    switch (kind) {
        case EntityKind::Object: return namesOf(scene.objects);
        case EntityKind::Light: return namesOf(scene.lights);
        case EntityKind::Material: return namesOf(scene.materials);
        default: return {};
    }
}

const char* shapeName(Shape shape) {
    switch (shape) {
        case Shape::Sphere: return "sphere";
        case Shape::Quad: return "quad";
        case Shape::Box: return "box";
        case Shape::Mesh: return "mesh";
    }
    return "object";
}

// The camera's look-at point, or the origin: where new things appear.
// Where new objects and lights go: the look-at point of the view the viewport shows (the free
// view's where there is one: what the user is looking at, not where the render camera points).
glm::vec3 spawnPoint(const EditorState& s) { return s.viewCamera().lookAt; }

}  // namespace

std::string uniqueName(const std::string& base, const std::vector<std::string>& taken) {
    auto isTaken = [&](const std::string& n) { return std::find(taken.begin(), taken.end(), n) != taken.end(); };
    if (!base.empty() && !isTaken(base)) return base;
    // "box 2" -> stem "box": duplicates of duplicates count on instead of growing "box 2 2".
    std::string stem = base.empty() ? std::string("unnamed") : base;
    if (auto sp = stem.find_last_of(' '); sp != std::string::npos && sp + 1 < stem.size() &&
        std::all_of(stem.begin() + static_cast<long>(sp) + 1, stem.end(), [](char c) { return c >= '0' && c <= '9'; }))
        stem = stem.substr(0, sp);
    for (int i = 2;; ++i) {
        std::string candidate = stem + " " + std::to_string(i);
        if (!isTaken(candidate)) return candidate;
    }
}

std::string entityName(const Scene& scene, EntityRef ref) {
    auto at = [](const auto& list, int i) -> std::string {
        return i >= 0 && static_cast<size_t>(i) < list.size() ? list[static_cast<size_t>(i)].name : std::string();
    };
    switch (ref.kind) {
        case EntityKind::Object: return at(scene.objects, ref.index);
        case EntityKind::Light: return at(scene.lights, ref.index);
        case EntityKind::Material: return at(scene.materials, ref.index);
        case EntityKind::Camera: return "Camera";
        case EntityKind::Render: return "Render settings";
        case EntityKind::Environment: return "Environment";
        case EntityKind::None: return "";
    }
    return "";
}

EntityRef findEntity(const Scene& scene, EntityKind kind, const std::string& name) {
    if (kind == EntityKind::Camera || kind == EntityKind::Render || kind == EntityKind::Environment) return {kind, -1};
    std::vector<std::string> names = namesOfKind(scene, kind);
    for (size_t i = 0; i < names.size(); ++i)
        if (names[i] == name) return {kind, static_cast<int>(i)};
    return {};
}

std::unique_ptr<Command> makeAddObject(const EditorState& s, Shape shape) {
    Object o;
    o.shape = shape;
    o.name = uniqueName(shapeName(shape), namesOf(s.scene.objects));
    o.material = s.scene.materials.empty() ? std::string() : s.scene.materials.front().name;
    o.transform.translate = spawnPoint(s);
    o.transform.scale = glm::vec3(0.25f);
    // A quad faces the camera.
    if (shape == Shape::Quad) o.transform.rotate = glm::vec3(-90.0f, 0.0f, 0.0f);
    return std::make_unique<InsertCommand<Object>>(static_cast<int>(s.scene.objects.size()), std::move(o));
}

std::unique_ptr<Command> makeAddLight(const EditorState& s, LightType type, const MeshBoundsLookup& meshBounds) {
    Light l;
    l.type = type;
    static const char* names[] = {"rect light", "sphere light", "point light", "spot light"};
    l.name = uniqueName(names[static_cast<int>(type)], namesOf(s.scene.lights));
    // Half a unit above the look-at point; while that is inside (or within 0.2 of) an object's
    // bounds, half a unit above the object's top.
    glm::vec3 p = spawnPoint(s) + glm::vec3(0.0f, 0.5f, 0.0f);
    for (bool moved = true; moved;) {
        moved = false;
        for (int i = 0; i < int(s.scene.objects.size()); ++i) {
            const auto b = entityBounds(s.scene, EntityRef{EntityKind::Object, i}, meshBounds);
            if (!b || glm::any(glm::greaterThan(b->first - 0.2f, p)) || glm::any(glm::lessThan(b->second + 0.2f, p))) continue;
            p.y = b->second.y + 0.5f;
            moved = true;
        }
    }
    l.position = p;
    l.transform.translate = p;
    l.transform.rotate = glm::vec3(90.0f, 0.0f, 0.0f);   // a rect light faces down
    l.transform.scale = glm::vec3(0.2f, 0.2f, 1.0f);
    l.color = type == LightType::Point || type == LightType::Spot ? glm::vec3(2.0f) : glm::vec3(10.0f);
    return std::make_unique<InsertCommand<Light>>(static_cast<int>(s.scene.lights.size()), std::move(l));
}

std::unique_ptr<Command> makeAddMaterial(const EditorState& s, const Material* preset) {
    Material m = preset ? *preset : Material{};
    m.name = uniqueName(preset ? preset->name : std::string("material"), namesOf(s.scene.materials));
    return std::make_unique<InsertCommand<Material>>(static_cast<int>(s.scene.materials.size()), std::move(m));
}

std::string meshFileForScene(const EditorState& s, const std::string& file) {
    if (s.path.empty()) return file;
    std::error_code ec;
    fs::path rel = fs::absolute(file, ec).lexically_relative(fs::absolute(s.path, ec).parent_path());
    return !ec && !rel.empty() ? rel.string() : file;
}

bool fileHasOwnMaterials(const std::vector<ImportedMaterial>& imported) {
    return std::any_of(imported.begin(), imported.end(), [](const ImportedMaterial& m) { return m.name != "DefaultMaterial"; });
}

std::unique_ptr<Command> makeImportMesh(const EditorState& s, const std::string& file, bool ownMaterials) {
    Object o;
    o.shape = Shape::Mesh;
    o.name = uniqueName(fs::path(file).stem().string(), namesOf(s.scene.objects));
    o.material = ownMaterials || s.scene.materials.empty() ? std::string() : s.scene.materials.front().name;
    o.file = meshFileForScene(s, file);
    return std::make_unique<InsertCommand<Object>>(static_cast<int>(s.scene.objects.size()), std::move(o), "Import");
}

std::unique_ptr<Command> makeSetMeshFile(const EditorState& s, int index, const std::string& file) {
    if (index < 0 || static_cast<size_t>(index) >= s.scene.objects.size()) return nullptr;
    Object o = s.scene.objects[static_cast<size_t>(index)];
    if (o.shape != Shape::Mesh) return nullptr;
    o.file = meshFileForScene(s, file);
    return makeSetObject(s, index, std::move(o));
}

std::unique_ptr<Command> makeDuplicate(const EditorState& s, EntityRef ref, std::string* why) {
    auto dup = [&](const auto& list) -> std::unique_ptr<Command> {
        using T = std::decay_t<decltype(list[0])>;
        if (ref.index < 0 || static_cast<size_t>(ref.index) >= list.size()) return nullptr;
        T copy = list[static_cast<size_t>(ref.index)];
        copy.name = uniqueName(copy.name, namesOf(list));
        return std::make_unique<InsertCommand<T>>(ref.index + 1, std::move(copy), "Duplicate as");
    };
    std::unique_ptr<Command> c;
    switch (ref.kind) {
        case EntityKind::Object: c = dup(s.scene.objects); break;
        case EntityKind::Light: c = dup(s.scene.lights); break;
        case EntityKind::Material: c = dup(s.scene.materials); break;
        default: break;
    }
    if (!c && why) *why = std::string("cannot duplicate the ") + entityKindName(ref.kind);
    return c;
}

std::unique_ptr<Command> makeDelete(const EditorState& s, EntityRef ref, std::string* why) {
    auto del = [&](const auto& list) -> std::unique_ptr<Command> {
        using T = std::decay_t<decltype(list[0])>;
        if (ref.index < 0 || static_cast<size_t>(ref.index) >= list.size()) return nullptr;
        return std::make_unique<RemoveCommand<T>>(ref.index, list[static_cast<size_t>(ref.index)]);
    };
    switch (ref.kind) {
        case EntityKind::Object: return del(s.scene.objects);
        case EntityKind::Light: return del(s.scene.lights);
        case EntityKind::Material: {
            if (ref.index < 0 || static_cast<size_t>(ref.index) >= s.scene.materials.size()) return nullptr;
            const std::string& name = s.scene.materials[static_cast<size_t>(ref.index)].name;
            for (const Object& o : s.scene.objects) {
                if (o.material == name) {
                    if (why) *why = "material '" + name + "' is used by object '" + o.name + "'";
                    return nullptr;
                }
            }
            return del(s.scene.materials);
        }
        default:
            if (why) *why = std::string("cannot delete the ") + entityKindName(ref.kind);
            return nullptr;
    }
}

std::unique_ptr<Command> makeRename(const EditorState& s, EntityRef ref, const std::string& name, std::string* why) {
    std::string current = entityName(s.scene, ref);
    if (name == current) return nullptr;
    std::vector<std::string> taken = namesOfKind(s.scene, ref.kind);
    if (ref.kind == EntityKind::Material && name.empty()) {
        if (why) *why = "a material needs a name";
        return nullptr;
    }
    if (!name.empty() && std::find(taken.begin(), taken.end(), name) != taken.end()) {
        if (why) *why = std::string("another ") + entityKindName(ref.kind) + " is already called '" + name + "'";
        return nullptr;
    }
    const size_t i = static_cast<size_t>(ref.index);
    switch (ref.kind) {
        case EntityKind::Object: { Object o = s.scene.objects.at(i); o.name = name; return makeSetObject(s, ref.index, o); }
        case EntityKind::Light: { Light l = s.scene.lights.at(i); l.name = name; return makeSetLight(s, ref.index, l); }
        case EntityKind::Material: { Material m = s.scene.materials.at(i); m.name = name; return makeSetMaterial(s, ref.index, m); }
        default:
            if (why) *why = std::string("the ") + entityKindName(ref.kind) + " has no name";
            return nullptr;
    }
}

}  // namespace caustic::editor
