#include "renderer/scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include <filesystem>

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

std::span<const SkyPreset> skyPresets() {
    // "original": the original renderer's sky as its issue describes it (a dark teal horizon, a
    // white zenith, scaled down to fill light); its exact numbers are not in this repository, so
    // these are chosen to match that description: the horizon a dark teal (linear 0.1, 0.3, 0.35
    // reads as sRGB (89, 149, 160) before tone mapping), the zenith white, and intensity 0.3, which
    // puts the zenith's radiance at 0.3 and the horizon's at (0.03, 0.09, 0.105).
    static constexpr SkyPreset kPresets[] = {
        {"default", {1.0f, 1.0f, 1.0f}, {0.3f, 0.5f, 1.0f}, 1.0f},
        {"original", {0.1f, 0.3f, 0.35f}, {1.0f, 1.0f, 1.0f}, 0.3f},
    };
    return kPresets;
}

const SkyPreset* findSkyPreset(std::string_view name) {
    for (const SkyPreset& p : skyPresets())
        if (p.name == name) return &p;
    return nullptr;
}

void applySkyPreset(const SkyPreset& preset, Environment& env) {
    env.type = EnvironmentType::Sky;
    env.horizon = preset.horizon;
    env.zenith = preset.zenith;
    env.intensity = preset.intensity;
}

std::string resolvePathIn(const std::string& folder, const std::string& file) {
    const std::filesystem::path path(file);
    if (path.is_relative() && !folder.empty()) return (std::filesystem::path(folder) / path).string();
    return file;
}

std::string sceneFolder(const Scene& scene) {
    return scene.sourcePath.empty() ? std::string() : std::filesystem::path(scene.sourcePath).parent_path().string();
}

std::string resolveScenePath(const Scene& scene, const std::string& file) { return resolvePathIn(sceneFolder(scene), file); }

}  // namespace caustic
