#include "editor/model/editor_state.h"

#include "editor/model/scene_paths.h"
#include "renderer/file_util.h"
#include "renderer/scene_io.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <utility>

namespace fs = std::filesystem;

namespace caustic::editor {

EditorState::EditorState() { newScene(); }

bool EditorState::apply(std::unique_ptr<Command> command, std::string* why) {
    if (!command) return false;
    if (std::string wrong = command->check(); !wrong.empty()) {
        if (why) *why = "edit refused: " + wrong;
        return false;
    }
    if (command->changesNothing()) return true;   // no undo step, nothing dirty (issue 15)
    history.push(std::move(command), *this, false);
    return true;
}

bool EditorState::applyContinuous(std::unique_ptr<Command> command, std::string* why) {
    if (!command) return false;
    if (std::string wrong = command->check(); !wrong.empty()) {
        if (why) *why = "edit refused: " + wrong;
        return false;
    }
    if (command->changesNothing()) return true;   // no undo step, nothing dirty (issue 15)
    history.push(std::move(command), *this, true);
    return true;
}

std::uint32_t dirtyForRenderer(std::uint32_t dirty, std::uint32_t* deferred) {
    if (dirty == kDirtyAll) {   // a new scene: everything, nothing held back
        *deferred = kDirtyNone;
        return dirty;
    }
    if (dirty & kDirtyUnseen) *deferred |= kDirtyGeometry;
    dirty &= ~std::uint32_t(kDirtyTarget | kDirtyUnseen);
    if (dirty != kDirtyNone) dirty |= std::exchange(*deferred, kDirtyNone);
    return dirty;
}

bool EditorState::undo() {
    bool done = history.undo(*this);
    validateSelection();
    return done;
}

bool EditorState::redo() {
    bool done = history.redo(*this);
    validateSelection();
    return done;
}

std::string EditorState::displayName() const {
    return path.empty() ? std::string("untitled") : fs::path(path).filename().string();
}

void EditorState::newScene() {
    scene = Scene{};
    scene.render.width = 512;
    scene.render.height = 384;
    scene.materials.push_back(Material{.name = "default"});
    scene.environment.type = EnvironmentType::Sky;
    selection = {};
    history.clear();
    path.clear();
    m_dirty = kDirtyAll;
    ++m_generation;
}

bool EditorState::open(const std::string& file, std::string* error) {
    SceneLoadResult loaded = loadScene(file);
    if (!loaded) {
        if (error) *error = loaded.error;
        return false;
    }
    adoptOpened(std::move(*loaded.scene), file);
    return true;
}

void EditorState::adoptOpened(Scene opened, const std::string& file) {
    scene = std::move(opened);
    scene.sourcePath = file;
    path = file;
    selection = {};
    history.clear();
    m_dirty = kDirtyAll;
    ++m_generation;
}

bool EditorState::save(std::string* error) {
    if (path.empty()) {
        if (error) *error = "the scene has no file yet: use Save As";
        return false;
    }
    return saveAs(path, error);
}

bool EditorState::saveAs(const std::string& file, std::string* error) {
    // Into another folder, the files the scene names are rebased to stay the same files (and
    // the undo history's with them); in memory too, since they now resolve from the new folder.
    const std::string from = sceneFolderOf(path), to = sceneFolderOf(file);
    Scene saved = scene;
    rebaseScenePaths(saved, from, to);
    saved.sourcePath = file;
    if (!saveScene(saved, file, error)) return false;
    scene = std::move(saved);
    if (from != to) history.rebasePaths(from, to);
    path = file;
    history.markClean();
    return true;
}

void EditorState::adoptRecovered(Scene recovered, const std::string& file) {
    scene = std::move(recovered);
    scene.sourcePath = file;
    path = file;
    selection = {};
    history.clear();
    history.markUnclean();
    m_dirty = kDirtyAll;
    ++m_generation;
}

void EditorState::validateSelection() {
    auto inRange = [](int i, size_t n) { return i >= 0 && static_cast<size_t>(i) < n; };
    switch (selection.kind) {
        case EntityKind::Object: if (!inRange(selection.index, scene.objects.size())) selection = {}; break;
        case EntityKind::Light: if (!inRange(selection.index, scene.lights.size())) selection = {}; break;
        case EntityKind::Material: if (!inRange(selection.index, scene.materials.size())) selection = {}; break;
        default: break;
    }
    std::erase_if(m_otherObjects, [&](int i) { return !inRange(i, scene.objects.size()); });
}

void EditorState::select(EntityRef ref, SelectMode mode) {
    if (mode == SelectMode::Replace || ref.kind != EntityKind::Object || selection.kind != EntityKind::Object) {
        selection = ref;
        m_otherObjects.clear();
        m_otherFor = ref;
        return;
    }
    std::vector<int> all = selectedObjects();
    const auto it = std::find(all.begin(), all.end(), ref.index);
    if (it == all.end()) {
        setSelection(ref, all);   // added, and active
        return;
    }
    all.erase(it);
    if (all.empty()) setSelection({}, {});
    else if (selection == ref) setSelection({EntityKind::Object, all.back()}, all);
    else setSelection(selection, all);
}

std::vector<int> EditorState::selectedObjects() const {
    std::vector<int> out;
    if (selection.kind != EntityKind::Object) return out;
    out.push_back(selection.index);
    if (m_otherFor == selection) out.insert(out.end(), m_otherObjects.begin(), m_otherObjects.end());
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

bool EditorState::isSelected(EntityRef ref) const {
    if (ref == selection) return bool(ref);
    if (ref.kind != EntityKind::Object) return false;
    const std::vector<int> all = selectedObjects();
    return std::find(all.begin(), all.end(), ref.index) != all.end();
}

void EditorState::setSelection(EntityRef active, const std::vector<int>& objects) {
    selection = active;
    m_otherFor = active;
    m_otherObjects.clear();
    if (active.kind != EntityKind::Object) return;
    for (int i : objects)
        if (i != active.index) m_otherObjects.push_back(i);
}

// ---- Command factories ---------------------------------------------------------------------------

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
glm::vec3 spawnPoint(const Scene& scene) { return scene.camera.lookAt; }

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
    o.transform.translate = spawnPoint(s.scene);
    o.transform.scale = glm::vec3(0.25f);
    // A quad faces the camera.
    if (shape == Shape::Quad) o.transform.rotate = glm::vec3(-90.0f, 0.0f, 0.0f);
    return std::make_unique<InsertCommand<Object>>(static_cast<int>(s.scene.objects.size()), std::move(o));
}

std::unique_ptr<Command> makeAddLight(const EditorState& s, LightType type) {
    Light l;
    l.type = type;
    static const char* names[] = {"rect light", "sphere light", "point light", "spot light"};
    l.name = uniqueName(names[static_cast<int>(type)], namesOf(s.scene.lights));
    const glm::vec3 p = spawnPoint(s.scene) + glm::vec3(0.0f, 0.5f, 0.0f);
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

std::unique_ptr<Command> makeImportMesh(const EditorState& s, const std::string& file) {
    Object o;
    o.shape = Shape::Mesh;
    o.name = uniqueName(fs::path(file).stem().string(), namesOf(s.scene.objects));
    o.material = s.scene.materials.empty() ? std::string() : s.scene.materials.front().name;
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

// ---- Config folder, recent files, autosave -------------------------------------------------------

std::string editorConfigDir() {
    if (const char* d = std::getenv("CAUSTIC_EDITOR_HOME"); d && *d) return d;
    if (const char* x = std::getenv("XDG_CONFIG_HOME"); x && *x) return (fs::path(x) / "caustic").string();
    if (const char* h = std::getenv("HOME"); h && *h) return (fs::path(h) / ".config" / "caustic").string();
    return (fs::temp_directory_path() / "caustic").string();
}

void RecentFiles::add(const std::string& file) {
    remove(file);
    m_files.insert(m_files.begin(), file);
    if (m_files.size() > kMax) m_files.resize(kMax);
}

void RecentFiles::remove(const std::string& file) {
    m_files.erase(std::remove(m_files.begin(), m_files.end(), file), m_files.end());
}

bool RecentFiles::load(const std::string& listFile) {
    m_files.clear();
    std::ifstream in(listFile);
    if (!in) return false;
    std::string line;
    while (std::getline(in, line) && m_files.size() < kMax)
        if (!line.empty() && std::find(m_files.begin(), m_files.end(), line) == m_files.end()) m_files.push_back(line);
    return true;
}

bool RecentFiles::save(const std::string& listFile, std::string* error) const {
    std::error_code ec;
    fs::create_directories(fs::path(listFile).parent_path(), ec);
    std::string text;
    for (const std::string& f : m_files) text += f + "\n";
    return writeFileAtomically(listFile, text, error);
}

Autosave Autosave::in(const std::string& dir) {
    return {(fs::path(dir) / "autosave.json").string(), (fs::path(dir) / "autosave.owner").string()};
}

bool Autosave::write(const Scene& scene, const std::string& owner, std::string* error) const {
    std::error_code ec;
    fs::create_directories(fs::path(scenePath).parent_path(), ec);
    // The owner first: a crash between the two writes leaves a scene with a stale owner at worst.
    return writeFileAtomically(ownerPath, owner + "\n", error) && saveScene(scene, scenePath, error);
}

bool Autosave::exists() const { return fs::exists(scenePath); }

std::optional<std::pair<Scene, std::string>> Autosave::read(std::string* error) const {
    SceneLoadResult loaded = loadScene(scenePath);
    if (!loaded) {
        if (error) *error = loaded.error;
        return std::nullopt;
    }
    std::string owner;
    if (std::optional<std::string> text = readTextFile(ownerPath, nullptr)) {
        owner = *text;
        while (!owner.empty() && (owner.back() == '\n' || owner.back() == '\r')) owner.pop_back();
    }
    return std::make_pair(std::move(*loaded.scene), owner);
}

void Autosave::remove() const {
    std::error_code ec;
    fs::remove(scenePath, ec);
    fs::remove(ownerPath, ec);
}

}  // namespace caustic::editor
