// Issue 15's editor bugs, in the model: the Del key's focus rule.
#include "editor/model/shortcuts.h"

#include <catch2/catch.hpp>

using namespace caustic;
using namespace caustic::editor;

TEST_CASE("Del deletes in the viewport or outliner, never while a field has the keys", "[editor][keys]") {
    CHECK(deleteKeyDeletes({false, false, true}));
    CHECK_FALSE(deleteKeyDeletes({true, false, true}));    // a text field: Del deletes a character
    CHECK_FALSE(deleteKeyDeletes({false, true, true}));    // a slider being dragged
    CHECK_FALSE(deleteKeyDeletes({false, false, false}));  // the inspector (or nothing) focused
}
