#include "editor/model/scene_lights.h"

namespace caustic::editor {
namespace {

bool nonZero(glm::vec3 c) { return c.x > 0.0f || c.y > 0.0f || c.z > 0.0f; }

}  // namespace

bool objectEmits(const Scene& scene, const Object& object) {
    if (object.emits()) return true;
    const Material* m = object.material.empty() ? nullptr : scene.findMaterial(object.material);
    return m && nonZero(m->emission);
}

std::vector<int> emissiveObjects(const Scene& scene) {
    std::vector<int> out;
    for (std::size_t i = 0; i < scene.objects.size(); ++i)
        if (objectEmits(scene, scene.objects[i])) out.push_back(static_cast<int>(i));
    return out;
}

std::size_t lightSourceCount(const Scene& scene) { return scene.lights.size() + emissiveObjects(scene).size(); }

}  // namespace caustic::editor
