#include "editor/model/modal_transform.h"

#include "editor/model/viewport_math.h"
#include "renderer/camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace caustic::editor {

glm::vec2 projectToViewport(const Camera& camera, int width, int height, glm::vec2 viewport, glm::vec3 p) {
    const glm::vec4 c = projectionMatrix(camera, width, height, 0.01f, 1000.0f) * viewMatrix(camera) * glm::vec4(p, 1.0f);
    if (std::abs(c.w) < 1e-8f) return viewport * 0.5f;
    return {(c.x / c.w * 0.5f + 0.5f) * viewport.x, (0.5f - c.y / c.w * 0.5f) * viewport.y};
}

namespace {

glm::vec3 axisVector(ModalAxis a) {
    switch (a) {
        case ModalAxis::X: return {1.0f, 0.0f, 0.0f};
        case ModalAxis::Y: return {0.0f, 1.0f, 0.0f};
        case ModalAxis::Z: return {0.0f, 0.0f, 1.0f};
        case ModalAxis::Free: break;
    }
    return glm::vec3(0.0f);
}

}  // namespace

Transform modalTransform(const ModalStart& s, ModalAxis axis, glm::vec2 mouse) {
    const CameraFrame f = cameraFrame(s.camera, double(s.width) / double(s.height));
    const glm::vec3 centre = s.transform.matrix ? glm::vec3((*s.transform.matrix)[3]) : s.transform.translate;
    const glm::vec2 screenCentre = projectToViewport(s.camera, s.width, s.height, s.viewport, centre);
    Transform out = s.transform;
    switch (s.kind) {
        case ModalKind::Grab: {
            // World units per viewport pixel at the entity's depth.
            const float depth = std::max(1e-4f, float(glm::dot(glm::dvec3(centre) - f.position, f.forward)));
            const float perPixel = 2.0f * depth * float(f.tanY) / std::max(1.0f, s.viewport.y);
            const glm::vec2 d = mouse - s.mouse;
            glm::vec3 move = perPixel * (d.x * glm::vec3(f.right) - d.y * glm::vec3(f.up));
            if (axis != ModalAxis::Free) {
                // Along the axis: as far as the mouse went along the axis's image.
                const glm::vec3 a = axisVector(axis);
                const glm::vec2 along = projectToViewport(s.camera, s.width, s.height, s.viewport, centre + a) - screenCentre;
                const float len2 = glm::dot(along, along);
                move = len2 > 1e-6f ? a * (glm::dot(d, along) / len2) : glm::vec3(0.0f);
            }
            if (out.matrix) (*out.matrix)[3] += glm::vec4(move, 0.0f);
            else out.translate += move;
            return out;
        }
        case ModalKind::Rotate: {
            const glm::vec2 a0 = s.mouse - screenCentre, a1 = mouse - screenCentre;
            if (glm::length(a0) < 1.0f || glm::length(a1) < 1.0f) return out;
            // Screen angles grow clockwise (y points down); a clockwise sweep turns the entity
            // clockwise as seen from the camera: about the view direction, positively.
            const float angle = std::atan2(a1.y, a1.x) - std::atan2(a0.y, a0.x);
            glm::vec3 about = axis == ModalAxis::Free ? glm::vec3(f.forward) : axisVector(axis);
            // A world axis pointing away from the camera turns the same way on screen as the view axis.
            if (axis != ModalAxis::Free && glm::dot(about, glm::vec3(f.forward)) < 0.0f) about = -about;
            glm::mat4 m = s.transform.toMatrix();
            const glm::vec3 t(m[3]);
            m[3] = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
            // A right-handed rotation by +angle is counter-clockwise seen from the axis's tip, so
            // clockwise seen looking along the axis, as the camera does.
            glm::mat4 r = glm::rotate(glm::mat4(1.0f), angle, about);
            r = glm::translate(glm::mat4(1.0f), t) * r * m;
            if (s.transform.matrix) {
                out.matrix = r;
                return out;
            }
            return transformFromMatrix(r);
        }
        case ModalKind::Scale: {
            const float r0 = glm::length(s.mouse - screenCentre), r1 = glm::length(mouse - screenCentre);
            if (r0 < 1.0f) return out;
            const float k = std::max(1e-3f, r1 / r0);
            if (out.matrix) {
                glm::vec3 scale(k);
                if (axis != ModalAxis::Free) scale = glm::vec3(1.0f) + (k - 1.0f) * axisVector(axis);
                *out.matrix = *out.matrix * glm::scale(glm::mat4(1.0f), scale);
                return out;
            }
            if (axis == ModalAxis::Free) out.scale *= k;
            else out.scale += (k - 1.0f) * axisVector(axis) * out.scale;
            return out;
        }
    }
    return out;
}

ModalAxis constraintAxis(char key, bool blenderKeys) {
    switch (key) {
        case 'X': return ModalAxis::X;
        case 'Y': return blenderKeys ? ModalAxis::Z : ModalAxis::Y;
        case 'Z': return blenderKeys ? ModalAxis::Y : ModalAxis::Z;
        default: return ModalAxis::Free;
    }
}

Camera axisView(const Camera& camera, glm::vec3 direction) {
    Camera c = camera;
    const float distance = glm::length(camera.position - camera.lookAt);
    const glm::vec3 d = glm::normalize(direction);
    c.position = camera.lookAt + distance * d;
    c.up = std::abs(d.y) > 0.9f ? glm::vec3(0.0f, 0.0f, d.y > 0.0f ? -1.0f : 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    c.rollDegrees = 0.0f;
    return c;
}

Scene withoutHidden(const Scene& scene, const std::vector<std::string>& hidden, std::vector<int>* sceneIndex) {
    Scene out = scene;
    if (sceneIndex) sceneIndex->clear();
    out.objects.clear();
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        if (std::find(hidden.begin(), hidden.end(), scene.objects[i].name) != hidden.end()) continue;
        out.objects.push_back(scene.objects[i]);
        if (sceneIndex) sceneIndex->push_back(static_cast<int>(i));
    }
    return out;
}

}  // namespace caustic::editor
