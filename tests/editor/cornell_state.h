// The editor model tests' starting point: the Cornell box open in an EditorState (no window).
#pragma once

#include "editor/model/editor_state.h"

#include <catch2/catch.hpp>

#include <string>

namespace caustic::test {

inline const std::string kCornell = std::string(CAUSTIC_SOURCE_DIR) + "/scenes/cornell-box.json";

// scenes/cornell-box.json opened; with takeDirty, the dirty flags of the open itself taken, so
// that a test sees only what its own edits mark.
inline editor::EditorState openCornell(bool takeDirty = true) {
    editor::EditorState s;
    std::string error;
    REQUIRE(s.open(kCornell, &error));
    if (takeDirty) s.takeDirty();
    return s;
}

}  // namespace caustic::test
