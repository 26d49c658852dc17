#include "renderer/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace caustic {

namespace {

// Whether the fov angle is along the image's x axis, for an image of aspect ratio width / height.
bool fovAlongX(FovAxis axis, double aspect) {
    return axis == FovAxis::X || (axis == FovAxis::Smaller && aspect <= 1.0) || (axis == FovAxis::Larger && aspect > 1.0);
}

}  // namespace

CameraFrame cameraFrame(const Camera& c, double aspect) {
    CameraFrame f;
    f.position = glm::dvec3(c.position);
    f.forward = glm::normalize(glm::dvec3(c.lookAt) - glm::dvec3(c.position));
    f.right = glm::normalize(glm::cross(f.forward, glm::normalize(glm::dvec3(c.up))));
    f.up = glm::cross(f.right, f.forward);
    if (c.rollDegrees != 0.0f) {  // turns the image counter-clockwise by the roll angle
        const double r = glm::radians(double(c.rollDegrees));
        const glm::dvec3 right = std::cos(r) * f.right + std::sin(r) * f.up;
        f.up = std::cos(r) * f.up - std::sin(r) * f.right;
        f.right = right;
    }
    const double t = std::tan(glm::radians(double(c.fovDegrees)) * 0.5);
    const bool alongX = fovAlongX(c.fovAxis, aspect);
    f.tanX = alongX ? t : t * aspect;
    f.tanY = alongX ? t / aspect : t;
    f.apertureRadius = c.apertureRadius;
    f.focalDistance = c.focalDistance > 0.0f ? double(c.focalDistance)
                                             : glm::length(glm::dvec3(c.lookAt) - glm::dvec3(c.position));
    if (c.focusPoint) f.focalDistance = glm::dot(glm::dvec3(*c.focusPoint) - f.position, f.forward);
    return f;
}

glm::dvec3 CameraFrame::pixelDirection(glm::dvec2 pixel, int width, int height) const {
    const glm::dvec2 ndc(2.0 * pixel.x / double(width) - 1.0, 1.0 - 2.0 * pixel.y / double(height));
    return glm::normalize(planePoint(ndc));
}

double focalLengthMm(const CameraFrame& frame) {
    return 0.5 * kFullFrameWidthMm / std::max(frame.tanX, frame.tanY);
}

double fovForFocalLength(const Camera& camera, double aspect, double mm) {
    // Half the longer side's angle from f; then the fov along the camera's own axis, which spans
    // the longer side, or the shorter one (its tangent scaled by the aspect).
    const double tanLonger = 0.5 * kFullFrameWidthMm / mm;
    const bool xLonger = aspect >= 1.0;
    const bool alongX = camera.fovAxis == FovAxis::X || (camera.fovAxis == FovAxis::Larger && xLonger) ||
                        (camera.fovAxis == FovAxis::Smaller && !xLonger);
    const double tanAlong = alongX == xLonger ? tanLonger : tanLonger / std::max(aspect, 1.0 / aspect);
    return 2.0 * glm::degrees(std::atan(tanAlong));
}

double fNumber(const CameraFrame& frame) {
    if (!(frame.apertureRadius > 0.0)) return std::numeric_limits<double>::infinity();
    return focalLengthMm(frame) / (2.0 * frame.apertureRadius * kMillimetresPerSceneUnit);
}

double apertureRadiusForFNumber(const CameraFrame& frame, double n) {
    return focalLengthMm(frame) / (2.0 * n * kMillimetresPerSceneUnit);
}

std::optional<WorldRay> lensPixelRay(const Camera& camera, const LensCamera& lens, glm::dvec2 pixel, int width, int height) {
    const CameraFrame f = cameraFrame(camera, width, height);
    const glm::dvec2 ndc(2.0 * pixel.x / width - 1.0, 1.0 - 2.0 * pixel.y / height);
    const glm::dvec2 film(-ndc.x * lens.filmHalfWidth, -ndc.y * lens.filmHalfHeight);  // the lens turns the image over
    std::optional<LensRay> ray;
    double weight = 0.0;
    ray = lensCameraRay(lens, film, glm::dvec2(0.5), -1, &weight);
    for (int k = 0; k < 49 && !ray; ++k)
        ray = lensCameraRay(lens, film, glm::dvec2((k % 7 + 0.5) / 7.0, (k / 7 + 0.5) / 7.0), -1, &weight);
    if (!ray) return std::nullopt;
    const double unit = 1.0 / kMillimetresPerSceneUnit;
    WorldRay out;
    out.origin = f.position + unit * (ray->o.x * f.right + ray->o.y * f.up + (lens.filmZ - ray->o.z) * f.forward);
    out.direction = glm::normalize(ray->d.x * f.right + ray->d.y * f.up - ray->d.z * f.forward);
    return out;
}

LensCameraSettings lensCameraSettings(const Camera& camera, int width, int height) {
    const CameraFrame frame = cameraFrame(camera, width, height);
    LensCameraSettings s;
    s.focusDistanceMm = frame.focalDistance * kMillimetresPerSceneUnit;
    s.fNumber = camera.lensFStop;
    const double longer = camera.sensorWidthMm;
    const double aspect = double(width) / double(height);
    s.filmWidthMm = aspect >= 1.0 ? longer : longer * aspect;
    s.filmHeightMm = aspect >= 1.0 ? longer / aspect : longer;
    s.blades = camera.blades;
    s.bladeRotation = glm::radians(double(camera.bladeRotationDegrees));
    s.dispersion = camera.lensDispersion;
    return s;
}

}  // namespace caustic
