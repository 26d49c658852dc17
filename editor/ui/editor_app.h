// The editor program: `caustic [scene.json]`. Opens a window (GLFW, OpenGL 4.5 core), docks the
// panels, and renders the scene progressively while it is edited.
#pragma once

#include <optional>
#include <string>

namespace caustic::editor {

// Runs until the window is closed (after the unsaved-changes prompt). A script named by
// $CAUSTIC_EDITOR_SCRIPT is replayed (tests, measurements). Returns the process exit code:
// 0, or 1 when the window or GL could not be made or a script step failed.
int runEditor(const std::optional<std::string>& sceneFile);

}  // namespace caustic::editor
