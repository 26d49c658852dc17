// The camera's frame, computed in one place: the basis (with roll), the image plane's extents
// (fov along its axis) and the lens (aperture, distance of the plane of focus) that a Camera
// means for an image of width x height. The renderer rounds it into GpuFrame (makeFrame,
// renderer/gpu_scene.cpp; shaders/integrator/camera.glsl shoots the rays), the editor picks,
// focuses, pans and draws its gizmo with it (editor/model/viewport_math.cpp), and the tests'
// reference tracer shoots its rays with it, so the three cannot disagree (issue 14: the editor's
// copy had ignored roll).
//
// In double: an up or view vector as short as 1e-30 (its squared length underflows a float) or a
// view between points near +-3e38 (their difference overflows) would normalise to NaN in float.
#pragma once

#include "renderer/lens.h"
#include "renderer/scene.h"

#include <glm/glm.hpp>

namespace caustic {

struct CameraFrame {
    glm::dvec3 position{0.0};
    glm::dvec3 forward{0.0, 0.0, -1.0};  // unit view direction
    glm::dvec3 right{1.0, 0.0, 0.0};     // unit, the image's +x (after roll)
    glm::dvec3 up{0.0, 1.0, 0.0};        // unit, the image's +y, up on screen (after roll)
    double tanX = 1.0;                   // half extents of the image plane at distance 1
    double tanY = 1.0;
    double apertureRadius = 0.0;         // 0: a pinhole
    double focalDistance = 1.0;          // of the plane of focus, along forward

    // The point of the image plane at distance 1 for normalised device coordinates ndc in
    // [-1, 1]^2 (+x right, +y up), not normalised.
    glm::dvec3 planePoint(glm::dvec2 ndc) const { return forward + ndc.x * tanX * right + ndc.y * tanY * up; }
    // The pinhole ray's unit direction through image position `pixel` (continuous: (0, 0) is the
    // top-left corner of the image, (width, height) the bottom-right), as the shader computes it.
    glm::dvec3 pixelDirection(glm::dvec2 pixel, int width, int height) const;
    // Where a ray of unit direction `dir` from the camera meets the plane of focus: every lens
    // ray of that pixel passes through it (shaders/integrator/camera.glsl).
    glm::dvec3 focusOn(glm::dvec3 dir) const { return position + dir * (focalDistance / glm::dot(dir, forward)); }
};

// The frame of `camera` for an image of aspect ratio width / height. The camera is assumed valid
// (scene_io.cpp's rules: position != lookAt, up not parallel to the view, fov in (0, 180)).
CameraFrame cameraFrame(const Camera& camera, double aspect);
inline CameraFrame cameraFrame(const Camera& camera, int width, int height) {
    return cameraFrame(camera, double(width) / double(height));
}

// Photographic terms for the thin lens, as a full-frame ("35 mm") camera would name them, with
// scene units taken as metres (docs/scene-format.md, camera): the focal length in mm of a 36 x 24
// mm sensor whose longer side (36 mm) spans the image's longer side (as Blender's sensor fit
// "auto"), and the f-number N = f / (2 r), r the aperture radius. They are views of fov and
// aperture_radius, not parameters of their own.
inline constexpr double kFullFrameWidthMm = 36.0;
inline constexpr double kMillimetresPerSceneUnit = 1000.0;
// The focal length (mm) that gives `frame`'s field of view across the longer image side.
double focalLengthMm(const CameraFrame& frame);
// The fov (degrees, along camera.fovAxis) that gives focal length `mm` for this image aspect.
double fovForFocalLength(const Camera& camera, double aspect, double mm);
// N = f / (2 r); +infinity for a pinhole.
double fNumber(const CameraFrame& frame);
// The aperture radius (scene units) of f-number n at the frame's focal length.
double apertureRadiusForFNumber(const CameraFrame& frame, double n);

// What a camera with a lens system (Camera::lens) asks of it for an image of width x height: the
// focus distance (cameraFrame's, in mm from the film), the stop, the film (sensorWidthMm along
// the image's longer side), the blades and dispersion.
LensCameraSettings lensCameraSettings(const Camera& camera, int width, int height);

// The ray of a lens-system camera (prepared for this camera: Renderer::lensCamera) through image
// position `pixel` (as pixelDirection's), in the world: through the middle of that film point's
// exit-pupil bound, or the first ray of a 7 x 7 grid over the bound that passes. Every ray of an
// in-focus point meets it there, so picking and Shift+click focus work through the lens as the
// shader renders it (integrator/lens_camera.glsl). Empty where no ray passes.
struct WorldRay {
    glm::dvec3 origin, direction;
};
std::optional<WorldRay> lensPixelRay(const Camera& camera, const LensCamera& lens, glm::dvec2 pixel, int width, int height);

}  // namespace caustic
