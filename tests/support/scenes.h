// Test scenes shared by the schema tests (tests/cpu/test_scene_schema.cpp) and the inspector test
// (tests/editor/test_inspector_schema.cpp).
#pragma once

#include "renderer/scene.h"
#include "renderer/scene_schema.h"

#include <string>

namespace caustic::test {

// A valid scene with one entity of every type: a material of every type (and a custom conductor),
// an object of every shape (and one with its own emission), a light of every type, a camera with
// a focus point and an aperture, a sky. The mesh names a file that the loader does not open.
inline Scene everyTypeScene() {
    Scene s;
    for (const EnumChoice& c : enumChoices(MaterialType{})) {
        Material m = materialDefaults(static_cast<MaterialType>(c.value));
        m.name = std::string(c.name);
        s.materials.push_back(m);
    }
    Material custom = materialDefaults(MaterialType::Conductor);
    custom.name = "custom-metal";
    custom.metal = Metal::Custom;
    custom.eta = glm::vec3(0.2f, 0.9f, 1.1f);
    custom.k = glm::vec3(3.0f, 2.5f, 2.0f);
    s.materials.push_back(custom);
    for (const EnumChoice& c : enumChoices(Shape{})) {
        Object o;
        o.name = "o-" + std::string(c.name);
        o.shape = static_cast<Shape>(c.value);
        o.material = "diffuse";
        if (o.shape == Shape::Mesh) o.file = "no-such-mesh.obj";
        s.objects.push_back(o);
    }
    Object glowing;
    glowing.name = "glowing";
    glowing.material = "diffuse";
    glowing.emission = glm::vec3(2.0f, 1.0f, 0.5f);
    s.objects.push_back(glowing);
    for (const EnumChoice& c : enumChoices(LightType{})) {
        Light l;
        l.name = "l-" + std::string(c.name);
        l.type = static_cast<LightType>(c.value);
        s.lights.push_back(l);
    }
    s.camera.focusPoint = glm::vec3(0.0f, 0.0f, 1.0f);
    s.camera.apertureRadius = 0.05f;
    s.environment.type = EnvironmentType::Sky;
    return s;
}

}  // namespace caustic::test
