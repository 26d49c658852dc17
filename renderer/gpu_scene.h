// Scene -> the flat arrays the GPU reads (shaders/shared/layout.h). Pure CPU code: no GL, so it
// is unit-tested directly, and the Renderer only uploads what this produces.
#pragma once

#include "renderer/scene.h"
#include "shaders/shared/layout.h"

#include <string>
#include <vector>

namespace caustic {

struct CompiledScene {
    std::vector<gpu::GpuPrimitive> primitives;
    std::vector<gpu::GpuMaterial> materials;
    std::vector<gpu::GpuLight> lights;
    std::vector<float> lightCdf;        // lightCdf[i] = P(index <= i)
    std::vector<float> lightPower;      // the power each light was weighed by (W; see docs)
    int envLightIndex = -1;             // index into lights, -1 when there is no environment
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};  // of all finite geometry
};

// Fails (with a message naming the scene entry, e.g. "objects[2]: ...") only for scenes that
// pass validation but cannot be rendered as given.
bool compileScene(const Scene& scene, CompiledScene* out, std::string* error);

// The per-dispatch constants for an image of the scene's render.width x render.height.
gpu::GpuFrame makeFrame(const Scene& scene, const CompiledScene& compiled, std::uint32_t strategy);

}  // namespace caustic
