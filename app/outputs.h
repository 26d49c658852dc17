// The files a render ends in, shared by a render (caustic --scene) and a merge (caustic merge):
// denoising with --oidn, then PNG / HDR / EXR and the AOVs as the options ask.
#pragma once

#include "app/cli.h"
#include "renderer/film.h"
#include "renderer/image_io.h"

#include <cstdint>
#include <string>
#include <vector>

namespace caustic {

// "" when every feature the options ask for is in this build, else why not ("--oidn: ...").
std::string outputsNotAvailable(const CliOptions& o);

// Writes <base>.png / .hdr / .exr (and the AOV files) from the raw film, denoised first with
// --oidn (its description added to meta as caustic:denoiser). Each file's path is printed on
// stdout as soon as it is complete. srgb (if not null) gets the 8-bit image the PNG shows.
bool writeOutputs(const CliOptions& o, const std::string& base, const Film& raw, ImageMetadata meta,
                  std::vector<std::uint8_t>* srgb, std::string* error);

}  // namespace caustic
