// The viewport's geometry on the CPU: camera rays that match the GPU camera exactly (both come
// from renderer/camera.h's cameraFrame; shaders/integrator/camera.glsl; tested on the GPU), picking against the
// scene's canonical shapes and lights, bounds for "frame selected", camera navigation (orbit,
// pan, dolly, fly, frame), the view/projection matrices for the gizmo, the lights' outlines, and
// the inverse of Transform::toMatrix. Pure functions, unit-tested.
#pragma once

#include "editor/model/commands.h"
#include "renderer/lens.h"
#include "renderer/scene.h"

#include <glm/glm.hpp>

#include <functional>
#include <optional>
#include <utility>
#include <vector>

namespace caustic::editor {

struct Ray {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f, 0.0f, -1.0f};   // normalised
};

// The ray through image position `pixel` (continuous, (0,0) = top-left corner of the image,
// (width, height) = bottom-right) of a width x height render.
// With `lens` (the renderer's prepared lens system, for a camera with one): the ray through the
// lens (renderer/camera.h, lensPixelRay), the pinhole's where none passes.
Ray cameraRay(const Camera& camera, int width, int height, glm::vec2 pixel, const LensCamera* lens = nullptr);

struct PickHit {
    EntityRef ref;
    float distance = 0.0f;
};
// The nearest object or light the ray hits (point and spot lights count as small spheres).
std::optional<PickHit> pick(const Scene& scene, const Ray& ray);

// A mesh object's bounds in its own space (before its transform), when known: the editor answers
// from the renderer's imported copy (its BVH root); nullopt while the file is not imported.
using MeshBoundsLookup = std::function<std::optional<std::pair<glm::vec3, glm::vec3>>(const Object&)>;

// World-space bounds of an entity (objects and lights); nullopt for the singletons, and for a
// mesh whose bounds meshBounds does not know (the 8 corners of its local box, transformed).
std::optional<std::pair<glm::vec3, glm::vec3>> entityBounds(const Scene& scene, EntityRef ref,
                                                            const MeshBoundsLookup& meshBounds = {});
// Bounds of everything in the scene (for framing when nothing is selected).
std::optional<std::pair<glm::vec3, glm::vec3>> sceneBounds(const Scene& scene, const MeshBoundsLookup& meshBounds = {});

// Camera navigation. Angles in degrees; pan offsets in fractions of the view height.
Camera orbit(const Camera& c, float yawDegrees, float pitchDegrees);
Camera pan(const Camera& c, float dx, float dy);
Camera dolly(const Camera& c, float factor);          // distance to the look-at point *= factor
Camera fly(const Camera& c, glm::vec3 localMove);     // x right, y up, z forward, world units
Camera frameBounds(const Camera& c, glm::vec3 lo, glm::vec3 hi, float aspect);

// The camera as matrices for ImGuizmo (OpenGL conventions, column-major).
glm::mat4 viewMatrix(const Camera& c);
glm::mat4 projectionMatrix(const Camera& c, int width, int height, float zNear, float zFar);

// M = T * Rz * Ry * Rx * S back to translate / rotate (degrees) / scale. Shear is dropped; a
// negative determinant becomes a negative x scale. toMatrix(fromMatrix(M)) == M for any M that
// toMatrix can make (up to rounding).
Transform transformFromMatrix(const glm::mat4& m);

// The gizmo on a light (issue 15: rotating a point light showed the rotation, threw it away and
// recorded an empty undo step). What each light can be given by a gizmo: a rect light has a full
// transform (move, rotate, scale); a spot light a position and a direction (move, and rotate,
// which turns the direction); point and sphere lights only a position (move).
struct GizmoOps { bool translate = true, rotate = false, scale = false; };
GizmoOps gizmoOpsFor(const Scene& scene, EntityRef ref);
// The light as the gizmo's matrix: the rect's transform; otherwise a translation to its position,
// and for a spot a rotation whose +z axis is the spot's direction.
glm::mat4 lightGizmoMatrix(const Light& light);
// The light with the gizmo's edited matrix applied, within what gizmoOpsFor allows it (a point
// light takes only the translation; a spot's direction becomes the matrix's +z axis). Returns the
// light unchanged when the matrix changes nothing it has (a spot turned about its own axis).
Light lightFromGizmo(const Light& light, const glm::mat4& m);

// Snaps every component to a multiple of step (no-op for step <= 0).
glm::vec3 snapTo(glm::vec3 v, float step);

// What the viewport draws over a light so it can be seen and placed (world-space polylines, each
// a list of points joined in order): a rect light's outline and its normal (the side it emits
// to), a sphere light's silhouette circle as the camera sees it, a spot light's cone (its apex,
// four edges and the circle where it is `length` long) and a point light's three short axes.
// `size` sets the length of the normal, the spot's cone and the point's axes (scene units).
std::vector<std::vector<glm::vec3>> lightOutline(const Light& light, const Camera& camera, float size);

// The selection's outline over the image (Blender's), from a grid of what the viewport shows:
// `shown` holds, per cell (row-major, w x h, row 0 at the top), the object seen there (-1: none);
// `mark` says of an object whether it is outlined (2: the active one, 1: another selected one,
// 0: not). Returns the cell edges between an outlined object and anything else (another object
// included), in cell units, with the stronger mark of the two sides.
struct OutlineEdge {
    glm::vec2 a, b;
    int mark = 0;
};
std::vector<OutlineEdge> selectionOutline(const std::vector<int>& shown, int w, int h, const std::function<int(int)>& mark);

}  // namespace caustic::editor
