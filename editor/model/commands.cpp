#include "editor/model/commands.h"

#include "editor/model/editor_state.h"
#include "editor/model/scene_paths.h"
#include "renderer/scene_io.h"

#include <type_traits>

namespace caustic::editor {
namespace {

// The list or singleton of the scene that holds a T, and how an edit of it is named.
template <class T> constexpr bool kIsList = std::is_same_v<T, Object> || std::is_same_v<T, Light> || std::is_same_v<T, Material>;

// key: the entity's JSON key in a scene file (for the place named in check()'s messages).
template <class T> struct Access;
template <> struct Access<Object> {
    static constexpr EntityKind kind = EntityKind::Object;
    static std::vector<Object>& list(Scene& s) { return s.objects; }
    static constexpr const char* noun = "object";
    static constexpr const char* key = "objects";
};
template <> struct Access<Light> {
    static constexpr EntityKind kind = EntityKind::Light;
    static std::vector<Light>& list(Scene& s) { return s.lights; }
    static constexpr const char* noun = "light";
    static constexpr const char* key = "lights";
};
template <> struct Access<Material> {
    static constexpr EntityKind kind = EntityKind::Material;
    static std::vector<Material>& list(Scene& s) { return s.materials; }
    static constexpr const char* noun = "material";
    static constexpr const char* key = "materials";
};
template <> struct Access<Camera> {
    static constexpr EntityKind kind = EntityKind::Camera;
    static Camera& single(Scene& s) { return s.camera; }
    static constexpr const char* noun = "camera";
    static constexpr const char* key = "camera";
};
template <> struct Access<RenderSettings> {
    static constexpr EntityKind kind = EntityKind::Render;
    static RenderSettings& single(Scene& s) { return s.render; }
    static constexpr const char* noun = "render settings";
    static constexpr const char* key = "render";
};
template <> struct Access<Environment> {
    static constexpr EntityKind kind = EntityKind::Environment;
    static Environment& single(Scene& s) { return s.environment; }
    static constexpr const char* noun = "environment";
    static constexpr const char* key = "environment";
};

// "objects[2]", "camera": where the entity sits in a scene file.
template <class T>
std::string placeOf(int index) {
    if constexpr (kIsList<T>) return std::string(Access<T>::key) + "[" + std::to_string(index) + "]";
    else { (void)index; return Access<T>::key; }
}


template <class T>
void assign(Scene& scene, int index, const T& from, const T& to) {
    if constexpr (kIsList<T>) {
        Access<T>::list(scene)[static_cast<size_t>(index)] = to;
        if constexpr (std::is_same_v<T, Material>) {
            if (from.name != to.name)
                for (Object& o : scene.objects)
                    if (o.material == from.name) o.material = to.name;
        }
    } else {
        (void)index;
        (void)from;
        Access<T>::single(scene) = to;
    }
}

template <class T>
std::string describe(const T& value) {
    if constexpr (kIsList<T>) return std::string(Access<T>::noun) + " '" + value.name + "'";
    else { (void)value; return Access<T>::noun; }
}

std::uint32_t listChangeDirty(EntityKind kind) {
    switch (kind) {
        case EntityKind::Object: return kDirtyGeometry;
        case EntityKind::Light: return kDirtyLights;
        case EntityKind::Material: return kDirtyMaterials;
        default: return kDirtyAll;
    }
}

bool sameFiles(const Material& a, const Material& b) {
    return a.albedoTexture == b.albedoTexture && a.normalTexture == b.normalTexture &&
           a.roughnessTexture == b.roughnessTexture && a.emissionTexture == b.emissionTexture;
}

// A material edit that no object sees (its name, before or after, is nobody's material) changes
// nothing on screen: kDirtyUnseen instead of a re-upload and restart. Unless it changes a texture
// file: the renderer reads every material's textures, used or not (as batch mode does), so such
// an edit can make the scene unrenderable, or renderable again, and must be tried at once.
std::uint32_t materialDirty(const Scene& scene, const Material& a, const Material& b, std::uint32_t d) {
    if (!(d & kDirtyMaterials) || !sameFiles(a, b)) return d;
    for (const Object& o : scene.objects)
        if (o.material == a.name || o.material == b.name) return d;
    return (d & ~std::uint32_t(kDirtyMaterials)) | kDirtyUnseen;
}

}  // namespace

const char* entityKindName(EntityKind kind) {
    switch (kind) {
        case EntityKind::None: return "none";
        case EntityKind::Object: return "object";
        case EntityKind::Light: return "light";
        case EntityKind::Material: return "material";
        case EntityKind::Camera: return "camera";
        case EntityKind::Render: return "render";
        case EntityKind::Environment: return "environment";
    }
    return "?";
}

// ---- CommandStack ------------------------------------------------------------------------------

void CommandStack::push(std::unique_ptr<Command> command, EditorState& state, bool continuous) {
    command->execute(state);
    m_undone.clear();
    if (continuous && !m_sealed && !m_done.empty() && m_done.back().command->mergeWith(*command)) {
        // The merged step changed the scene: it is a new state, even if the top was saved.
        m_done.back().serial = m_nextSerial++;
        return;
    }
    m_done.push_back({std::move(command), m_nextSerial++});
    m_sealed = !continuous;
}

bool CommandStack::undo(EditorState& state) {
    if (m_done.empty()) return false;
    Entry e = std::move(m_done.back());
    m_done.pop_back();
    e.command->undo(state);
    m_undone.push_back(std::move(e));
    m_sealed = true;
    return true;
}

bool CommandStack::redo(EditorState& state) {
    if (m_undone.empty()) return false;
    Entry e = std::move(m_undone.back());
    m_undone.pop_back();
    e.command->execute(state);
    m_done.push_back(std::move(e));
    m_sealed = true;
    return true;
}

void CommandStack::rebasePaths(const std::string& fromFolder, const std::string& toFolder) {
    for (Entry& e : m_done) e.command->rebasePaths(fromFolder, toFolder);
    for (Entry& e : m_undone) e.command->rebasePaths(fromFolder, toFolder);
}

void CommandStack::clear() {
    m_done.clear();
    m_undone.clear();
    m_sealed = true;
    m_clean = 0;
}

// ---- Dirty flags of single edits ---------------------------------------------------------------

std::uint32_t editDirty(const Object& a, const Object& b) {
    std::uint32_t d = kDirtyNone;
    if (a.transform != b.transform) d |= kDirtyTransforms;
    if (a.shape != b.shape || a.material != b.material || a.file != b.file) d |= kDirtyGeometry;
    if (a.emission != b.emission || a.twoSided != b.twoSided) d |= kDirtyLights;  // the light list changes
    return d;
}
std::uint32_t editDirty(const Light& a, const Light& b) {
    Light an = a, bn = b;
    an.name = bn.name = "";
    if (an == bn) return kDirtyNone;
    return a.transform != b.transform || a.position != b.position ? kDirtyLights | kDirtyTransforms : kDirtyLights;
}
std::uint32_t editDirty(const Material& a, const Material& b) {
    Material an = a, bn = b;
    an.name = bn.name = "";
    return an == bn ? kDirtyNone : kDirtyMaterials;
}
std::uint32_t editDirty(const Camera& a, const Camera& b) { return a == b ? kDirtyNone : kDirtyCamera; }
std::uint32_t editDirty(const RenderSettings& a, const RenderSettings& b) {
    if (a == b) return kDirtyNone;
    RenderSettings an = a, bn = b;
    an.samples = bn.samples = 0;
    // The target alone: the accumulated samples stay valid (same pixels, seed and sample indices).
    return an == bn ? kDirtyTarget : kDirtySettings;
}
std::uint32_t editDirty(const Environment& a, const Environment& b) { return a == b ? kDirtyNone : kDirtyEnvironment; }

// ---- SetCommand ----------------------------------------------------------------------------------

template <class T>
void SetCommand<T>::execute(EditorState& state) {
    assign(state.scene, m_index, m_before, m_after);
    m_lastDirty = editDirty(m_before, m_after);
    if constexpr (std::is_same_v<T, Material>) m_lastDirty = materialDirty(state.scene, m_before, m_after, m_lastDirty);
    state.markDirty(m_lastDirty);
}

template <class T>
void SetCommand<T>::undo(EditorState& state) {
    assign(state.scene, m_index, m_after, m_before);
    std::uint32_t d = editDirty(m_after, m_before);
    if constexpr (std::is_same_v<T, Material>) d = materialDirty(state.scene, m_after, m_before, d);
    state.markDirty(d);
    if constexpr (kIsList<T>) state.selection = {Access<T>::kind, m_index};  // show what changed back
}

template <class T>
bool SetCommand<T>::mergeWith(const Command& next) {
    const auto* n = dynamic_cast<const SetCommand<T>*>(&next);
    if (!n || n->m_index != m_index) return false;
    // Only the same entity, and (for list entries) while it keeps the name it had during the
    // drag: a rename between two drags is its own step.
    if constexpr (kIsList<T>) {
        if (n->m_before.name != m_after.name) return false;
    }
    m_after = n->m_after;
    m_lastDirty = n->m_lastDirty;
    return true;
}

template <class T>
std::uint32_t SetCommand<T>::dirty() const { return editDirty(m_before, m_after); }

template <class T>
std::string SetCommand<T>::check() const { return checkEntity(m_after, placeOf<T>(m_index)); }

template <class T>
void SetCommand<T>::rebasePaths(const std::string& from, const std::string& to) {
    editor::rebasePaths(m_before, from, to);
    editor::rebasePaths(m_after, from, to);
}

template <class T>
std::string SetCommand<T>::name() const {
    if constexpr (kIsList<T>) {
        if (m_before.name != m_after.name) return "Rename " + describe(m_before) + " to '" + m_after.name + "'";
    }
    return "Edit " + describe(m_after);
}

// ---- InsertCommand / RemoveCommand ---------------------------------------------------------------

// Adding or removing a material shifts the table's indices, so once it reaches the renderer it is
// a full recompile (kDirtyUnseen is handed over as one); until then nothing on screen changed.
template <class T>
std::uint32_t listEditDirty(const Scene& scene, const T& value) {
    if constexpr (std::is_same_v<T, Material>)
        return sameFiles(value, Material{}) ? materialDirty(scene, value, value, kDirtyMaterials) : kDirtyMaterials;
    else { (void)scene; (void)value; return listChangeDirty(Access<T>::kind); }
}

template <class T>
void InsertCommand<T>::execute(EditorState& state) {
    auto& list = Access<T>::list(state.scene);
    list.insert(list.begin() + m_index, m_value);
    state.markDirty(listEditDirty(state.scene, m_value));
    state.selection = {Access<T>::kind, m_index};
}

template <class T>
void InsertCommand<T>::undo(EditorState& state) {
    auto& list = Access<T>::list(state.scene);
    list.erase(list.begin() + m_index);
    state.markDirty(listEditDirty(state.scene, m_value));
    state.selection = {};
}

template <class T>
std::uint32_t InsertCommand<T>::dirty() const { return listChangeDirty(Access<T>::kind); }

template <class T>
std::string InsertCommand<T>::check() const { return checkEntity(m_value, placeOf<T>(m_index)); }

template <class T>
void InsertCommand<T>::rebasePaths(const std::string& from, const std::string& to) { editor::rebasePaths(m_value, from, to); }

template <class T>
std::string InsertCommand<T>::name() const { return m_verb + " " + describe(m_value); }

template <class T>
void RemoveCommand<T>::execute(EditorState& state) {
    auto& list = Access<T>::list(state.scene);
    list.erase(list.begin() + m_index);
    state.markDirty(listEditDirty(state.scene, m_value));
    state.selection = {};
}

template <class T>
void RemoveCommand<T>::undo(EditorState& state) {
    auto& list = Access<T>::list(state.scene);
    list.insert(list.begin() + m_index, m_value);
    state.markDirty(listEditDirty(state.scene, m_value));
    state.selection = {Access<T>::kind, m_index};
}

template <class T>
std::uint32_t RemoveCommand<T>::dirty() const { return listChangeDirty(Access<T>::kind); }

template <class T>
void RemoveCommand<T>::rebasePaths(const std::string& from, const std::string& to) { editor::rebasePaths(m_value, from, to); }

template <class T>
std::string RemoveCommand<T>::name() const { return "Delete " + describe(m_value); }

// ---- CompoundCommand ------------------------------------------------------------------------------

void CompoundCommand::execute(EditorState& state) {
    for (auto& c : m_steps) c->execute(state);
    state.setSelection(m_active, m_selected);
}

void CompoundCommand::undo(EditorState& state) {
    for (auto it = m_steps.rbegin(); it != m_steps.rend(); ++it) (*it)->undo(state);
    state.setSelection(m_active, m_selected);
}

std::uint32_t CompoundCommand::dirty() const {
    std::uint32_t d = kDirtyNone;
    for (const auto& c : m_steps) d |= c->dirty();
    return d;
}

std::string CompoundCommand::check() const {
    for (const auto& c : m_steps)
        if (std::string why = c->check(); !why.empty()) return why;
    return {};
}

bool CompoundCommand::changesNothing() const {
    for (const auto& c : m_steps)
        if (!c->changesNothing()) return false;
    return true;
}

void CompoundCommand::rebasePaths(const std::string& from, const std::string& to) {
    for (auto& c : m_steps) c->rebasePaths(from, to);
}

template class SetCommand<Object>;
template class SetCommand<Light>;
template class SetCommand<Material>;
template class SetCommand<Camera>;
template class SetCommand<RenderSettings>;
template class SetCommand<Environment>;
template class InsertCommand<Object>;
template class InsertCommand<Light>;
template class InsertCommand<Material>;
template class RemoveCommand<Object>;
template class RemoveCommand<Light>;
template class RemoveCommand<Material>;

}  // namespace caustic::editor
