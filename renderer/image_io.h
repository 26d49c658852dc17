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

// Any named float channels in one single-part OpenEXR file (ZIP compressed, 32-bit float):
// pixels holds width * height * names.size() floats, interleaved in the order of names. Atomic.
bool writeExrChannels(const std::string& path, int width, int height, const std::vector<std::string>& names,
                      const std::vector<float>& pixels, const ImageMetadata& metadata, std::string* error);

// An image with all its channels by name and its string metadata (what writeExrChannels
// wrote), read as 32-bit float; errors name the file. The image's size is checked against the
// limits of image.h before its pixels are allocated. With pixels = false only the header is read
// (names, size, metadata; out->pixels stays empty).
struct ChannelImage {
    int width = 0, height = 0;
    std::vector<std::string> names;   // as the file orders them (OpenEXR sorts them by name)
    std::vector<float> pixels;        // interleaved, names.size() per pixel, row 0 at the top
    ImageMetadata metadata;           // the string attributes
};
bool readChannelImage(const std::string& path, ChannelImage* out, std::string* error, bool pixels = true);

// Reads any format OpenImageIO knows; errors name the file.
bool readImage(const std::string& path, ImageData* out, std::string* error);

}  // namespace caustic
