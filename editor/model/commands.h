// Editor commands: every edit of the scene is a Command with execute / undo / mergeWith, so
// undo/redo covers every edit and one gizmo or slider drag is one undo step (the steps of a drag
// merge into the first until the stack is sealed, on release). A command reports what it dirtied
// (renderer/dirty.h), and that alone decides what the renderer redoes. No ImGui here.
#pragma once

#include "renderer/dirty.h"
#include "renderer/scene.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace caustic::editor {

class EditorState;

// What can be selected and edited: one entry of a scene list, or one of the singletons.
enum class EntityKind { None, Object, Light, Material, Camera, Render, Environment };

struct EntityRef {
    EntityKind kind = EntityKind::None;
    int index = -1;   // objects, lights, materials; -1 for the singletons
    explicit operator bool() const { return kind != EntityKind::None; }
    bool operator==(const EntityRef&) const = default;
};

const char* entityKindName(EntityKind kind);   // "object", "light", ...

class Command {
public:
    virtual ~Command() = default;
    virtual void execute(EditorState& state) = 0;
    virtual void undo(EditorState& state) = 0;
    // Absorbs `next`, a later step of the same continuous edit (already executed), so that undoing
    // this command undoes both. Returns false when `next` is a different edit.
    virtual bool mergeWith(const Command& next) { (void)next; return false; }
    // What execute or undo changed (renderer/dirty.h).
    virtual std::uint32_t dirty() const = 0;
    virtual std::string name() const = 0;   // "Edit object 'small box'", for the Edit menu
    // What is wrong with the value this command would put into the scene, checked by the scene
    // reader's rules before it executes (renderer/scene_io.h, checkEntity): "" when nothing, else
    // "objects[2].transform.translate[0]: must be a finite 32-bit float, got nan". EditorState
    // refuses a command that reports something, so an edit can never make the scene unsaveable.
    virtual std::string check() const { return {}; }
    // The command would leave the scene as it is (a gizmo turn of a light that has no rotation,
    // a field set to its own value): EditorState records no undo step for it and dirties nothing.
    virtual bool changesNothing() const { return false; }
    // The scene was saved into another folder: the files the command's values name (mesh files,
    // textures, the environment map; editor/model/scene_paths.h) are rebased with it, so undo and
    // redo put back paths that resolve from the new folder.
    virtual void rebasePaths(const std::string& fromFolder, const std::string& toFolder) { (void)fromFolder; (void)toFolder; }
};

// The undo history. push() executes; an unsealed top absorbs the next command if it merges.
// Modified-since-save is tracked with serial numbers: each entry gets a fresh one (also when a
// merge changes it), and markClean() remembers the top's.
class CommandStack {
public:
    void push(std::unique_ptr<Command> command, EditorState& state, bool continuous);
    void seal() { m_sealed = true; }                 // the next push starts a new undo step
    bool undo(EditorState& state);
    bool redo(EditorState& state);
    bool canUndo() const { return !m_done.empty(); }
    bool canRedo() const { return !m_undone.empty(); }
    std::size_t undoCount() const { return m_done.size(); }
    std::size_t redoCount() const { return m_undone.size(); }
    std::string undoName() const { return m_done.empty() ? "" : m_done.back().command->name(); }
    std::string redoName() const { return m_undone.empty() ? "" : m_undone.back().command->name(); }
    void clear();
    void discardRedo() { m_undone.clear(); }   // a cancelled modal transform leaves nothing to redo
    void markClean() { m_clean = topSerial(); }
    void markUnclean() { m_clean = ~std::uint64_t(0); }  // e.g. a recovered autosave
    bool isClean() const { return m_clean == topSerial(); }
    // Identifies the state the history is in: changes with every edit, undo and redo (and comes
    // back with an undo to an earlier state). A background open compares it to tell whether the
    // scene it replaces was edited meanwhile.
    std::uint64_t revision() const { return topSerial(); }
    // Every command's paths (undone ones too), after the scene was saved into another folder.
    void rebasePaths(const std::string& fromFolder, const std::string& toFolder);

private:
    struct Entry { std::unique_ptr<Command> command; std::uint64_t serial; };
    std::uint64_t topSerial() const { return m_done.empty() ? 0 : m_done.back().serial; }
    std::vector<Entry> m_done, m_undone;
    bool m_sealed = true;
    std::uint64_t m_nextSerial = 1, m_clean = 0;
};

// ---- The edits --------------------------------------------------------------------------------

// Replaces one entity (an object, light, material, the camera, the render settings or the
// environment) by a new value. Renaming a material renames the objects' references to it.
template <class T>
class SetCommand final : public Command {
public:
    SetCommand(int index, T before, T after)
        : m_index(index), m_before(std::move(before)), m_after(std::move(after)) {}
    void execute(EditorState& state) override;
    void undo(EditorState& state) override;
    bool mergeWith(const Command& next) override;
    std::uint32_t dirty() const override;
    std::string name() const override;
    std::string check() const override;
    void rebasePaths(const std::string& fromFolder, const std::string& toFolder) override;
    bool changesNothing() const override { return m_before == m_after; }
    const T& before() const { return m_before; }
    const T& after() const { return m_after; }

private:
    int m_index;
    T m_before, m_after;
    std::uint32_t m_lastDirty = kDirtyNone;  // of the latest step, which is what the renderer redoes
};

// Inserts an object, light or material at index (and selects it); undo removes it.
template <class T>
class InsertCommand final : public Command {
public:
    InsertCommand(int index, T value, std::string verb = "Add")
        : m_index(index), m_value(std::move(value)), m_verb(std::move(verb)) {}
    void execute(EditorState& state) override;
    void undo(EditorState& state) override;
    std::uint32_t dirty() const override;
    std::string name() const override;
    std::string check() const override;
    void rebasePaths(const std::string& fromFolder, const std::string& toFolder) override;

private:
    int m_index;
    T m_value;
    std::string m_verb;
};

// Removes an object, light or material (a material only when nothing uses it); undo restores it
// at the same index and selects it again.
template <class T>
class RemoveCommand final : public Command {
public:
    RemoveCommand(int index, T value) : m_index(index), m_value(std::move(value)) {}
    void execute(EditorState& state) override;
    void undo(EditorState& state) override;
    std::uint32_t dirty() const override;
    std::string name() const override;
    void rebasePaths(const std::string& fromFolder, const std::string& toFolder) override;

private:
    int m_index;
    T m_value;
};

// Several edits as one undo step (assign a material to every selected object; a new material and
// the objects given it): executed in order, undone in reverse. After either, the selection is put
// back as it was when the step was made (`active` and the selected objects), since the steps
// inside each select what they changed.
class CompoundCommand final : public Command {
public:
    CompoundCommand(std::string name, std::vector<std::unique_ptr<Command>> steps, EntityRef active,
                    std::vector<int> selectedObjects)
        : m_name(std::move(name)), m_steps(std::move(steps)), m_active(active), m_selected(std::move(selectedObjects)) {}
    void execute(EditorState& state) override;
    void undo(EditorState& state) override;
    std::uint32_t dirty() const override;
    std::string name() const override { return m_name; }
    std::string check() const override;
    bool changesNothing() const override;
    void rebasePaths(const std::string& fromFolder, const std::string& toFolder) override;

private:
    std::string m_name;
    std::vector<std::unique_ptr<Command>> m_steps;
    EntityRef m_active;
    std::vector<int> m_selected;
};

// What a change of one entity dirties (name-only changes dirty nothing).
std::uint32_t editDirty(const Object& a, const Object& b);
std::uint32_t editDirty(const Light& a, const Light& b);
std::uint32_t editDirty(const Material& a, const Material& b);
std::uint32_t editDirty(const Camera& a, const Camera& b);
std::uint32_t editDirty(const RenderSettings& a, const RenderSettings& b);
std::uint32_t editDirty(const Environment& a, const Environment& b);

}  // namespace caustic::editor
