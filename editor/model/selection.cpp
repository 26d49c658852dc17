// EditorState's selection: the active entity and the objects selected with it (editor_state.h).
#include "editor/model/editor_state.h"

#include <algorithm>

namespace caustic::editor {

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

}  // namespace caustic::editor
