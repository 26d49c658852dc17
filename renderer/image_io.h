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

// One RGB layer of a multi-layer EXR: channels "<name>.R", "<name>.G", "<name>.B" (the layer
// convention Nuke, Blender and OpenImageIO read), or plain "R", "G", "B" when the name is empty.
struct ImageLayer {
    std::string name;
    const std::vector<float>* rgb = nullptr;  // width * height * 3 linear floats, row 0 at the top
};

// Writes the layers into one single-part OpenEXR file (ZIP compressed), as 32-bit float or
// 16-bit half channels. Atomic.
bool writeExrLayers(const std::string& path, int width, int height, const std::vector<ImageLayer>& layers, bool half,
                    const ImageMetadata& metadata, std::string* error);

// Reads any format OpenImageIO knows; errors name the file.
bool readImage(const std::string& path, ImageData* out, std::string* error);

}  // namespace caustic
