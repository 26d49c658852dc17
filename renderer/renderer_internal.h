// What the renderer's source files share (renderer.cpp, renderer_programs.cpp,
// renderer_dispatch.cpp); not for other code.
#pragma once

#include "shaders/shared/layout.h"

#include <vector>

namespace caustic {

// The primitives as the ray tests read them (shaders/scene/buffers.glsl, primitiveHits): spheres
// unchanged, quads in plane form (renderer.cpp).
std::vector<gpu::GpuPrimitive> primitiveHitRecords(const std::vector<gpu::GpuPrimitive>& primitives);

}  // namespace caustic
