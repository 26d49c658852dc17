// The focus-plane overlay (issue 15): while the focus distance (or the focus point, or the
// aperture) is being adjusted, the viewport marks where the scene lies on the plane of focus, so
// the artist sees what will be sharp before depth of field converges. No ImGui, no GL: the cells
// are found by CPU ray casts against the scene's shapes (viewport_math.h pick) plus, from the
// editor, the renderer's mesh BVHs.
#pragma once

#include "editor/model/viewport_math.h"
#include "renderer/scene.h"

#include <functional>
#include <optional>
#include <vector>

namespace caustic::editor {

// The distance of the plane of focus along the view direction, as the renderer computes it
// (renderer/camera.h cameraFrame: the focus point's, else focal_distance, else the look-at
// point's), for an image of this aspect.
double focusDistance(const Camera& camera, double aspect);

// An edit of the camera that moves the plane of focus or changes the aperture (what the overlay
// shows while it is adjusted).
bool focusEdited(const Camera& before, const Camera& after);

struct FocusCell {
    int x = 0, y = 0;   // in a cols x rows grid over the image, (0, 0) top-left
    bool operator==(const FocusCell&) const = default;
};

// The cells whose centre ray meets the scene within `band` x the focus distance of the plane of
// focus (in depth along the view direction). `extraHit` may add hits the shapes do not have
// (meshes): the distance along the ray, or nullopt.
std::vector<FocusCell> inFocusCells(const Scene& scene, int cols, int rows, float band,
                                    const std::function<std::optional<float>(const Ray&)>& extraHit = {});

}  // namespace caustic::editor
