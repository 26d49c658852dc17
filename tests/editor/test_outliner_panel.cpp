// The outliner's real panel code in a headless Dear ImGui context (no window, no GL): the Cornell
// box, lit by an emissive quad and no light entry, shows "Lights (1)" (the list itself is
// editor/model/scene_lights.h's, tested in test_scene_lights.cpp).
#include "editor/ui/editor_ui.h"
#include "tests/editor/cornell_state.h"
#include "tests/editor/headless_imgui.h"

#include <catch2/catch.hpp>
#include <imgui.h>
#include <imgui_internal.h>

using namespace caustic;
using namespace caustic::editor;

TEST_CASE("the outliner counts the Cornell box's emissive quad as its light", "[editor][outliner]") {
    const test::HeadlessImGui imgui;
    {
        AppState app;
        app.state = test::openCornell();
        EditorUi ui(app);
        for (int frame = 0; frame < 2; ++frame) {
            ImGui::GetIO().DeltaTime = 1.0f / 60.0f;
            ImGui::NewFrame();
            drawOutlinerPanel(ui);
            ImGui::Render();
        }
        ImGuiWindow* outliner = ImGui::FindWindowByName("Outliner");
        REQUIRE(outliner);
        // A section header drawn open records its state under its label's ID.
        auto headerDrawn = [&](const char* label) { return outliner->DC.StateStorage->GetInt(outliner->GetID(label), -1) == 1; };
        CHECK(headerDrawn("Lights (1)"));
        CHECK_FALSE(headerDrawn("Lights (0)"));
    }
}
