// What the GL implementation can hold, checked before a scene is uploaded (issue 12): a texture
// larger than GL_MAX_TEXTURE_SIZE or a storage buffer larger than GL_MAX_SHADER_STORAGE_BLOCK_SIZE
// fails inside the driver with a GL error that nothing reported (an environment map 16385 pixels
// wide rendered black on llvmpipe, whose texture limit is 16384). The check is a pure function of
// the compiled scene and the limits, so tests can inject small limits instead of building giant
// scenes. GL errors after the uploads are checked too (renderer.cpp, glErrorsSince).
#pragma once

#include "renderer/gpu_scene.h"
#include "renderer/scene.h"

#include <cstdint>
#include <string>

namespace caustic {

struct GpuLimits {
    std::int64_t maxTextureSize = 0;          // GL_MAX_TEXTURE_SIZE: texels per side
    std::int64_t maxStorageBlockSize = 0;     // GL_MAX_SHADER_STORAGE_BLOCK_SIZE: bytes per buffer
    // GL_MAX_TEXTURE_BUFFER_SIZE: texels per buffer texture, where the integrator reads the scene
    // through buffer textures (CAUSTIC_FETCH_TEXELS); 0 where it does not (nothing to check).
    std::int64_t maxTextureBufferTexels = 0;
};

// Queries the current GL context's limits (needs a current context); maxTextureBufferTexels only
// when `texelFetching` (the integrator's defines have CAUSTIC_FETCH_TEXELS).
GpuLimits queryGpuLimits(bool texelFetching);

// Empty when the compiled scene fits; otherwise why not, naming the JSON path and file (an
// environment map too wide or tall), the render size, or the buffer that is too large and its
// size against the limit.
std::string gpuLimitProblem(const Scene& scene, const CompiledScene& compiled, const GpuLimits& limits);

}  // namespace caustic
