// The Blender-style key map's modal transforms and views (issue 15; keymap.h KeymapStyle::Blender):
// G / R / S move, turn or scale the selection with the mouse until a click or Enter confirms it
// (one undo step) or Esc / a right click cancels it; X, Y, Z constrain it to a world axis; numpad
// 1 / 3 / 7 (Ctrl: the opposite side) look from the front, right or top; H hides objects in the
// viewport. The maths here, without ImGui: unit-tested in tests/editor/test_blender_keys.cpp.
#pragma once

#include "renderer/scene.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace caustic::editor {

enum class ModalKind { Grab, Rotate, Scale };
enum class ModalAxis { Free, X, Y, Z };

// Where the modal transform started and how the viewport maps the image.
struct ModalStart {
    ModalKind kind = ModalKind::Grab;
    Transform transform;        // the entity's, when it started (a light's, as its gizmo matrix)
    glm::vec2 mouse{0.0f};      // viewport pixels, (0, 0) top-left
    glm::vec2 viewport{1.0f};   // the viewport image's size in pixels
    Camera camera;
    int width = 1, height = 1;  // the render's aspect (the image shown in the viewport)
};

// Where a world point appears in the viewport image (pixels, (0, 0) top-left).
glm::vec2 projectToViewport(const Camera& camera, int width, int height, glm::vec2 viewport, glm::vec3 p);

// The transform for the mouse at `mouse`: Grab moves the start by the mouse's motion on the plane
// through the entity facing the camera (so the entity stays under the cursor), or along one axis
// (the motion's part along it); Rotate turns it about its centre by the angle the mouse swept about
// the entity's image, about the view axis or the world axis; Scale multiplies the scale by the
// ratio of the mouse's distance from the entity's image to where it started, on all axes or one.
Transform modalTransform(const ModalStart& start, ModalAxis axis, glm::vec2 mouse);
// The scene axis a constraint key names. The scene is Y-up; in the Blender key map the keys mean
// Blender's Z-up axes, as its users' hands know them: Z is up (the scene's Y) and Y is depth (the
// scene's Z), so G then Z lifts an object. key: 'X', 'Y' or 'Z'.
ModalAxis constraintAxis(char key, bool blenderKeys);

// Numpad views: the camera looking at its look-at point from `direction` (+z: front, +x: right,
// +y: top, or their opposites), at the same distance, up +y (top and bottom views: -z / +z).
Camera axisView(const Camera& camera, glm::vec3 direction);

// The scene the viewport renders with objects hidden (H): the hidden objects left out;
// *sceneIndex[i] is the edited scene's index of the rendered object i.
Scene withoutHidden(const Scene& scene, const std::vector<std::string>& hidden, std::vector<int>* sceneIndex);

}  // namespace caustic::editor
