// The BSDF tables the shaders read (BINDING_BSDF_TABLES), computed on the GPU by the shaders' own
// BSDF code, so that no C++ copy of it exists to drift.
#pragma once

#include <string>
#include <vector>

namespace caustic {

// Every BSDF table, into `buffer` (its storage is replaced; BSDF_TABLE_FLOATS floats, offsets
// BSDF_TABLE_* in shaders/shared/layout.h):
//   - at BSDF_TABLE_GGX, the directional albedo E(mu, alpha) of the F = 1 GGX lobe
//     (height-correlated Smith) for the multiple-scattering compensation of rough conductors:
//     GGX_ALBEDO_TABLE_SIZE^2 floats, mu = i / (N - 1) fastest, alpha = j / (N - 1), computed by
//     shaders/bsdf/ggx_albedo.comp;
//   - the layered surface material's: the dielectric reflection lobe's E(mu, alpha, ior) and its
//     cosine-weighted average, the sheen lobe's E(mu, r), computed by
//     shaders/bsdf/surface_albedo.comp (its header has the axes).
// Needs a current GL context; false with a message if a kernel does not compile.
bool computeBsdfTables(const std::string& shaderDir, unsigned buffer, std::string* error);

// The buffer's floats (tests).
std::vector<float> readFloatBuffer(unsigned buffer);

}  // namespace caustic
