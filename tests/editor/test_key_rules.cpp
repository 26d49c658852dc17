// The key rules of the default key map: Del deletes only where the selection is (the viewport or
// the outliner), and no chord does two things in one place (editor/model/keymap.h, shortcuts.h).
#include "editor/model/keymap.h"
#include "editor/model/shortcuts.h"

#include <catch2/catch.hpp>

#include <set>
#include <string>
#include <utility>

using namespace caustic;
using namespace caustic::editor;

TEST_CASE("Del deletes in the viewport or outliner, never while a field has the keys", "[editor][keys]") {
    CHECK(deleteKeyDeletes({false, false, true}));
    CHECK_FALSE(deleteKeyDeletes({true, false, true}));    // a text field: Del deletes a character
    CHECK_FALSE(deleteKeyDeletes({false, true, true}));    // a slider being dragged
    CHECK_FALSE(deleteKeyDeletes({false, false, false}));  // the inspector (or nothing) focused
}

TEST_CASE("The key map: every action has one binding, no chord does two things in one place", "[editor][keys]") {
    std::set<int> actions;
    std::set<std::pair<int, std::string>> chords;  // (scope, chord)
    for (const KeyBinding& b : keyBindings()) {
        actions.insert(static_cast<int>(b.action));
        INFO(chordText(b.chord));
        CHECK(chords.insert({static_cast<int>(b.scope), chordText(b.chord)}).second);
        CHECK(!b.what.empty());
    }
    CHECK(actions.size() == keyBindings().size());
    CHECK(actions.size() == static_cast<std::size_t>(Action::GizmoLocal) + 1);
    // A viewport key shadowing a global one would do both.
    for (const KeyBinding& v : keyBindings())
        for (const KeyBinding& g : keyBindings())
            if (v.scope == KeyScope::Viewport && g.scope == KeyScope::Global) CHECK(chordText(v.chord) != chordText(g.chord));
    CHECK(chordText({"Z", true, true}) == "Ctrl+Shift+Z");
    CHECK(chordText({"F6", false, false}) == "F6");
}
