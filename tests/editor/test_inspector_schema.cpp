// The inspector against the scene schema, running the real panel code in a headless Dear ImGui
// context (no window, no GL: ImGui builds its frame without rendering it):
//  - for every entity kind and every type of it, the inspector draws a widget for exactly the
//    parameters the schema says apply (none missing, none extra);
//  - each widget offers the loader's range: its bounds are valid values, and they are the range's
//    own ends where the range has them;
//  - drawing every inspector for several frames without input changes nothing: the scene stays
//    equal, no undo step is recorded, and sceneToJson gives the same text (a file loaded and
//    saved with the inspector open is the same file).
#include "editor/ui/editor_ui.h"
#include "editor/ui/param_widgets.h"
#include "editor/ui/viewport_denoise.h"
#include "renderer/scene_io.h"
#include "renderer/scene_schema.h"
#include "tests/editor/headless_imgui.h"
#include "tests/support/scenes.h"

#include <catch2/catch.hpp>
#include <imgui.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

using namespace caustic;
using namespace caustic::editor;

namespace {

struct HeadlessImGui : test::HeadlessImGui {
    // One frame of the inspector; returns what its widgets offered.
    std::vector<WidgetRecord> frame(EditorUi& ui) {
        std::vector<WidgetRecord> trace;
        g_widgetTrace = &trace;
        ImGui::GetIO().DeltaTime = 1.0f / 60.0f;
        ImGui::NewFrame();
        ImGui::SetNextWindowSize(ImVec2(600.0f, 780.0f));
        drawInspectorPanel(ui);
        ImGui::Render();
        g_widgetTrace = nullptr;
        return trace;
    }
};

// The keys the schema applies to `value`.
template <class T>
std::multiset<std::string> expectedKeys(const T& value) {
    std::multiset<std::string> keys;
    for (const Param<T>& p : schemaOf<T>())
        if (appliesTo(p, value)) keys.insert(std::string(p.key));
    return keys;
}

std::multiset<std::string> drawnKeys(const std::vector<WidgetRecord>& trace) {
    std::multiset<std::string> keys;
    for (const WidgetRecord& w : trace) keys.insert(w.key);
    return keys;
}

// Each numeric widget's bounds against the parameter's range.
template <class T>
void checkBounds(const T& value, const std::vector<WidgetRecord>& trace) {
    for (const WidgetRecord& w : trace) {
        const Param<T>* param = nullptr;
        for (const Param<T>& p : schemaOf<T>())
            if (p.key == w.key && appliesTo(p, value)) param = &p;
        REQUIRE(param);
        INFO("key " << w.key << ": widget [" << w.min << ", " << w.max << "], range " << param->range.text());
        const bool numeric = param->kind == ParamKind::Float || param->kind == ParamKind::Int ||
                             param->kind == ParamKind::Vector || param->kind == ParamKind::Colour ||
                             param->kind == ParamKind::OptionalPoint;
        if (!numeric) continue;
        const Range& r = param->range;
        if (!(w.min < w.max)) {  // unbounded widget: only for an unbounded range
            CHECK(!std::isfinite(r.min));
            CHECK(!std::isfinite(r.max));
            continue;
        }
        CHECK(r.contains(w.min));
        CHECK(r.contains(w.max));
        // The widget reaches the range's ends (within one float step for exclusive bounds), or
        // goes on far beyond where the range has none.
        if (std::isfinite(r.min)) CHECK(std::abs(w.min - r.min) <= 1e-6 * std::max(1.0, std::abs(r.min)));
        else CHECK(w.min <= -1e29);
        if (std::isfinite(r.max)) CHECK(std::abs(w.max - r.max) <= 1e-6 * std::max(1.0, std::abs(r.max)));
        else CHECK(w.max >= 1e29);
    }
}

template <class T>
void checkInspector(HeadlessImGui& imgui, EditorUi& ui, EntityRef ref, const T& value) {
    ui.app.state.selection = ref;
    imgui.frame(ui);  // the first frame lays out
    const std::vector<WidgetRecord> trace = imgui.frame(ui);
    INFO("entity kind " << int(ref.kind) << " index " << ref.index);
    CHECK(drawnKeys(trace) == expectedKeys(value));
    checkBounds(value, trace);
}

}  // namespace

TEST_CASE("the inspector draws every schema parameter with the loader's range, and touching nothing changes nothing",
          "[inspector]") {
    HeadlessImGui imgui;
    AppState app;
    EditorUi ui(app);
    ui.app.state.scene = test::everyTypeScene();
    const std::string before = sceneToJson(ui.app.state.scene);
    REQUIRE(!before.empty());
    REQUIRE(parseScene(before, "every-type.json"));  // a valid scene

    const Scene& s = ui.app.state.scene;
    for (int i = 0; i < int(s.materials.size()); ++i)
        checkInspector(imgui, ui, {EntityKind::Material, i}, s.materials[size_t(i)]);
    for (int i = 0; i < int(s.lights.size()); ++i) checkInspector(imgui, ui, {EntityKind::Light, i}, s.lights[size_t(i)]);
    for (int i = 0; i < int(s.objects.size()); ++i)
        checkInspector(imgui, ui, {EntityKind::Object, i}, s.objects[size_t(i)]);
    checkInspector(imgui, ui, {EntityKind::Camera, -1}, s.camera);
    checkInspector(imgui, ui, {EntityKind::Render, -1}, s.render);
    const EnvironmentType environmentBefore = ui.app.state.scene.environment.type;
    for (const EnumChoice& c : enumChoices(EnvironmentType{})) {
        ui.app.state.scene.environment.type = static_cast<EnvironmentType>(c.value);
        checkInspector(imgui, ui, {EntityKind::Environment, -1}, ui.app.state.scene.environment);
    }
    ui.app.state.scene.environment.type = environmentBefore;

    CHECK(ui.app.state.history.revision() == 0);
    CHECK(sceneToJson(ui.app.state.scene) == before);
}

TEST_CASE("every scene of scenes/ is unchanged by the inspector drawn over each of its entities", "[inspector]") {
    HeadlessImGui imgui;
    int scenes = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::string(CAUSTIC_SOURCE_DIR) + "/scenes")) {
        if (entry.path().extension() != ".json") continue;
        const std::string name = entry.path().filename().string();
        const SceneLoadResult loaded = loadScene(entry.path().string());
        INFO(loaded.error);
        REQUIRE(loaded);
        ++scenes;
        AppState app;
    EditorUi ui(app);
        ui.app.state.scene = *loaded.scene;
        const std::string before = sceneToJson(ui.app.state.scene);
        std::vector<EntityRef> refs = {{EntityKind::Camera, -1}, {EntityKind::Render, -1}, {EntityKind::Environment, -1}};
        for (int i = 0; i < int(ui.app.state.scene.materials.size()); ++i) refs.push_back({EntityKind::Material, i});
        for (int i = 0; i < int(ui.app.state.scene.objects.size()); ++i) refs.push_back({EntityKind::Object, i});
        for (int i = 0; i < int(ui.app.state.scene.lights.size()); ++i) refs.push_back({EntityKind::Light, i});
        for (const EntityRef& ref : refs) {
            ui.app.state.selection = ref;
            for (int f = 0; f < 3; ++f) imgui.frame(ui);
        }
        INFO(name);
        CHECK(ui.app.state.history.revision() == 0);
        CHECK(sceneToJson(ui.app.state.scene) == before);
    }
    CHECK(scenes >= 5);
}
