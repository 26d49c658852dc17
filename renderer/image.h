// Pixels in memory, shared by the image module (which reads files) and the renderer core (which
// uploads them). The core never reads files itself: it asks an ImageReader, so it stays free of
// OpenImageIO (the app passes the image module's readImage; tests pass generated pixels).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace caustic {

struct ImageData {
    int width = 0, height = 0, channels = 0;
    std::vector<float> pixels;  // as stored (no colour conversion), row 0 at the top
};

// Limits on images read from files (textures, environment maps), checked from the file's header
// before any pixel memory is allocated: 16384 x 8192 (the largest common environment maps) at
// most, no side over 65536, at most 4 channels are kept.
inline constexpr long long kMaxImageDimension = 65536;
#ifdef CAUSTIC_FUZZ_MAX_IMAGE_PIXELS
inline constexpr long long kMaxImagePixels = CAUSTIC_FUZZ_MAX_IMAGE_PIXELS;  // the fuzz build's (CMakeLists.txt)
#else
inline constexpr long long kMaxImagePixels = 16384LL * 8192;
#endif
inline constexpr int kMaxImageChannels = 64;  // what a file may declare
inline constexpr int kMaxKeptImageChannels = 4;  // what a reader keeps (the first ones: RGBA)

// "" when a file declaring width x height x channels may be read, else why not:
// "<path>: declares 100000x100000 pixels, more than the limit of 134217728 (16384x8192)".
inline std::string imageSizeProblem(const std::string& path, long long width, long long height, long long channels) {
    const auto size = std::to_string(width) + "x" + std::to_string(height);
    if (width <= 0 || height <= 0) return path + ": declares an empty image (" + size + ")";
    if (channels <= 0 || channels > kMaxImageChannels)
        return path + ": declares " + std::to_string(channels) + " channels (at most " +
               std::to_string(kMaxImageChannels) + " are accepted)";
    if (width > kMaxImageDimension || height > kMaxImageDimension || width * height > kMaxImagePixels)
        return path + ": declares " + size + " pixels, more than the limit of " +
               std::to_string(kMaxImagePixels) + (kMaxImagePixels == 16384LL * 8192 ? " pixels (16384x8192) and " : " pixels and ") +
               std::to_string(kMaxImageDimension) + " per side";
    return "";
}

using ImageReader = std::function<bool(const std::string& path, ImageData* out, std::string* error)>;

}  // namespace caustic
