// The scene's materials as the GPU sees them (renderer/gpu_materials.cpp), for the scene compiler
// (renderer/gpu_scene.cpp). The public side (mapImportedMaterial, bakeMetallicRoughness) is
// declared in renderer/gpu_scene.h; the GGX albedo table is renderer/bsdf_tables.h.
#pragma once

#include "renderer/scene.h"
#include "shaders/shared/layout.h"

#include <glm/glm.hpp>

#include <span>
#include <utility>
#include <vector>

namespace caustic {

// Complex IOR (eta, k) at R, G, B of a conductor: its preset's values, or its own for Custom.
std::pair<glm::vec3, glm::vec3> conductorPreset(const Material& m);

// The GPU material for a scene material (textures are filled in by the caller).
gpu::GpuMaterial convertMaterial(const Material& m);

// The parts of a surface with transmission or subsurface (integrator/surface_parts.glsl), in the
// order they are stored: the transmission's, then the subsurface's; none without either. And the
// surface's link to them, stored from index `first`.
std::vector<gpu::GpuMaterial> surfaceParts(const Material& m);
void linkSurfaceParts(gpu::GpuMaterial& g, const Material& m, std::uint32_t first);

// The single-scattering albedo of a medium of Henyey-Greenstein g whose semi-infinite slab shows
// the multiple-scattering albedo `multiple` (the inverse of van de Hulst's relation; the surface's
// subsurface_color to its interior).
float subsurfaceSingleScatteringAlbedo(float multiple, float g);

// A medium as the shaders read it (shared/layout.h: a material's k and eta rows, GpuFrame's
// mediumA and mediumS): sigma_a in a.rgb, sigma_s in s.rgb, each channel in [0, kMaxCoefficient]
// (a transmission_depth of 1e-38 would make it infinite), the Henyey-Greenstein g in a.w, clamped
// to [-0.999, 0.999] (at +-1 the phase function is a delta the sampler cannot represent).
struct GpuMediumRows {
    glm::vec4 a, s;
    bool vacuum() const { return glm::vec3(a) == glm::vec3(0.0f) && glm::vec3(s) == glm::vec3(0.0f); }
};
GpuMediumRows gpuMedium(glm::vec3 sigmaA, glm::vec3 sigmaS, float anisotropy);

// Named layered ("surface") materials for the editor's "Add > Material preset" menu and the
// lookdev scene: plastic, varnished wood, car paint (a metal base under a clear coat), velvet
// (sheen); each Material's name is the preset's. docs/materials.md lists their values.
std::span<const Material> materialPresets();

}  // namespace caustic
