// What lights a scene, as the outliner counts and lists it: the scene's lights and its emissive
// objects (an object with its own emission, or whose material emits), so that a scene lit by an
// emissive quad (the Cornell box) does not read "Lights (0)".
#pragma once

#include "renderer/scene.h"

#include <vector>

namespace caustic::editor {

// The object emits light: its own emission, or its material's (by name) is non-zero. A mesh with
// no material of the scene (the model file's own materials) counts only by its own emission: its
// file's materials are known once it is imported.
bool objectEmits(const Scene& scene, const Object& object);
// The indices of the emissive objects, ascending.
std::vector<int> emissiveObjects(const Scene& scene);
// The lights plus the emissive objects.
std::size_t lightSourceCount(const Scene& scene);

}  // namespace caustic::editor
