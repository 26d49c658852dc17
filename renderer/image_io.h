// The image module: the only part of caustic that reads or writes image files, through
// OpenImageIO. The renderer core does not link it, so a lean headless binary can exist without
// OpenImageIO's large dependency closure.
#pragma once

#include "renderer/image.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace caustic {

using ImageMetadata = std::vector<std::pair<std::string, std::string>>;

// Writes 8-bit RGB (PNG, by the file's extension). Atomic: a temporary file beside the target is
// renamed over it only when complete, so a failed write never leaves a partial image.
bool writeImage8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb,
                 const ImageMetadata& metadata, std::string* error);

// Writes linear float RGB: Radiance .hdr or OpenEXR .exr (float channels), by extension. Atomic.
bool writeImageFloat(const std::string& path, int width, int height, const std::vector<float>& rgb,
                     const ImageMetadata& metadata, std::string* error);

// Reads any format OpenImageIO knows; errors name the file.
bool readImage(const std::string& path, ImageData* out, std::string* error);

}  // namespace caustic
