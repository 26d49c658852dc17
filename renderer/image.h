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

using ImageReader = std::function<bool(const std::string& path, ImageData* out, std::string* error)>;

}  // namespace caustic
