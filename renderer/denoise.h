// Denoising with Intel Open Image Denoise (OIDN 2.5): the "RT" filter in HDR mode, guided by the
// albedo and normal AOVs (Film::albedo, Film::normal), optionally with the guides prefiltered
// first ("cleanAux", which OIDN's documentation recommends for the best quality when the guides
// are noisy, as they are behind glass and with depth of field).
// Built with OIDN only when CMake found it (CAUSTIC_HAVE_OIDN); otherwise denoiserAvailable() is
// false and denoise() fails with a message saying so. Not part of the renderer core: a separate
// library (caustic_denoise), so the core stays lean.
#pragma once

#include "renderer/film.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace caustic {

struct DenoiseOptions {
    bool useGuides = true;        // albedo and normal as auxiliary images
    bool prefilterGuides = true;  // denoise the guides first, then run with cleanAux
};

struct DenoiseResult {
    std::vector<glm::vec3> image;  // linear radiance, the film's layout
    std::string device;            // which OIDN device ran, e.g. "CPU" or "CUDA (NVIDIA H100 ...)"
};

// True when this build has Open Image Denoise; the version string ("2.5.1") or a reason.
bool denoiserAvailable();
std::string denoiserVersion();

// Denoises film.mean. Fails (false, *error) without OIDN, or when OIDN reports an error.
bool denoise(const Film& film, const DenoiseOptions& options, DenoiseResult* out, std::string* error);

}  // namespace caustic
