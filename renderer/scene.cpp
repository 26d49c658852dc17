#include "renderer/scene.h"

#include <glm/gtc/matrix_transform.hpp>

namespace caustic {

glm::mat4 Transform::toMatrix() const {
    if (matrix) return *matrix;
    // M = T * Rz * Ry * Rx * S; glm::rotate(m, a, axis) returns m * R(a, axis), and R is
    // right-handed (counter-clockwise looking down the axis towards the origin).
    glm::mat4 m = glm::translate(glm::mat4(1.0f), translate);
    m = glm::rotate(m, glm::radians(rotate.z), glm::vec3(0.0f, 0.0f, 1.0f));
    m = glm::rotate(m, glm::radians(rotate.y), glm::vec3(0.0f, 1.0f, 0.0f));
    m = glm::rotate(m, glm::radians(rotate.x), glm::vec3(1.0f, 0.0f, 0.0f));
    return glm::scale(m, scale);
}

const Material* Scene::findMaterial(const std::string& name) const {
    for (const Material& material : materials) {
        if (material.name == name) return &material;
    }
    return nullptr;
}

}  // namespace caustic
