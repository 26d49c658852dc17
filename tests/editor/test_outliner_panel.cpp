// The outliner's real panel code in a headless Dear ImGui context (no window, no GL): the Cornell
// box, lit by an emissive quad and no light entry, shows "Lights (1)" (the list itself is
// editor/model/scene_lights.h's, tested in test_scene_lights.cpp).
#include "editor/ui/editor_ui.h"
#include "tests/editor/cornell_state.h"

#include <catch2/catch.hpp>
#include <imgui.h>
#include <imgui_internal.h>

using namespace caustic;
using namespace caustic::editor;

TEST_CASE("the outliner counts the Cornell box's emissive quad as its light", "[editor][outliner]") {
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(1280.0f, 800.0f);
    io.IniFilename = nullptr;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
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
    ImGui::DestroyContext();
}
