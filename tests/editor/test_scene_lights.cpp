// What the outliner counts and lists as lights (editor/model/scene_lights.h): the scene's lights
// and its emissive objects, so the Cornell box, lit by an emissive quad, shows its light.
#include "editor/model/scene_lights.h"
#include "tests/editor/cornell_state.h"

#include <catch2/catch.hpp>

using namespace caustic;
using namespace caustic::editor;

TEST_CASE("The Cornell box's emissive ceiling quad counts as its light", "[editor][outliner]") {
    const EditorState s = test::openCornell();
    REQUIRE(s.scene.lights.empty());
    const std::vector<int> emissive = emissiveObjects(s.scene);
    REQUIRE(emissive.size() == 1);
    CHECK(s.scene.objects[size_t(emissive[0])].name == "ceiling light");
    CHECK(lightSourceCount(s.scene) == 1);
}

TEST_CASE("An object emits by its own emission or its material's, not otherwise", "[editor][outliner]") {
    Scene scene;
    Material grey, glow;
    grey.name = "grey";
    glow.name = "glow";
    glow.emission = glm::vec3(0.0f, 2.0f, 0.0f);
    scene.materials = {grey, glow};
    auto object = [](const char* name, const char* material) {
        Object o;
        o.name = name;
        o.material = material;
        return o;
    };
    const Object plain = object("plain", "grey");
    Object own = object("own", "grey");
    own.emission = glm::vec3(1.0f);
    const Object byMaterial = object("by material", "glow");
    Object fileMaterials = object("mesh", "");   // a mesh with the model file's own materials
    fileMaterials.shape = Shape::Mesh;
    scene.objects = {plain, own, byMaterial, fileMaterials};
    Light sun;
    sun.name = "sun";
    scene.lights.push_back(sun);
    CHECK_FALSE(objectEmits(scene, plain));
    CHECK(objectEmits(scene, own));
    CHECK(objectEmits(scene, byMaterial));
    CHECK_FALSE(objectEmits(scene, fileMaterials));
    CHECK(emissiveObjects(scene) == std::vector<int>{1, 2});
    CHECK(lightSourceCount(scene) == 3);
}
