// The inspector's widgets, drawn from the scene schema (renderer/scene_schema.h): one widget per
// parameter that applies to the value, with the schema's label, unit and range, so the inspector
// offers exactly what a file may hold. A widget never rewrites a value the user did not touch (a
// file's value is always inside the range the loader checked); a value the user types outside
// the range is brought to its nearest valid value.
#pragma once

#include "editor/model/commands.h"
#include "renderer/scene_schema.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace caustic::editor {

struct EditorUi;

// Tracks the widgets of one inspector section: whether any changed the copy and whether the
// edit is complete (a released drag, a typed value, a combo or checkbox). One drag is one undo
// step: the command applies continuously and is sealed on release.
struct Edit {
    EditorUi& ui;
    bool changed = false, seal = false;
    void track(bool c, bool discrete = false);
    void commit(std::unique_ptr<Command> command);
};

// What a widget offered, for tests (tests/editor/test_inspector_schema.cpp): the key it edits
// and its bounds (min > max: unbounded). Null in the editor.
struct WidgetRecord {
    std::string key;
    ParamKind kind;
    double min, max;
};
extern std::vector<WidgetRecord>* g_widgetTrace;
void traceWidget(std::string_view key, ParamKind kind, double min = 1.0, double max = 0.0);

// Draws a widget for every parameter of `value` that applies to it, in the schema's order.
// `special` draws the parameters whose meaning goes beyond their value (a name is renamed through
// a command, a reference offers the scene's materials); it returns false to fall back to the
// generic widget.
template <class T>
void drawParams(Edit& e, T& value, const std::function<bool(const Param<T>&, T&)>& special = {});

// Radiance as colour x strength, so brightness and hue are edited separately.
bool colourAndStrength(Edit& e, const char* colourLabel, const char* strengthLabel, glm::vec3* value,
                       double maxStrength);
void transformWidgets(Edit& e, Transform* t);

}  // namespace caustic::editor
