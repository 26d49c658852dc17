// A small reader for Radiance RGBE (.hdr) files, in the renderer core, so that binaries without
// the OpenImageIO image module (caustic-bench, a lean build for the GPU machine) can still load
// environment maps. Reads the "-Y H +X W" orientation, flat and run-length encoded scanlines
// (Greg Ward, "Real Pixels", Graphics Gems II, 1991; the format as Radiance writes it).
#pragma once

#include "renderer/image.h"

#include <string>

namespace caustic {

// Decodes like the reference rgbe.c (Bruce Walter): value = mantissa * 2^(exponent - 136).
bool readRadianceHdr(const std::string& path, ImageData* out, std::string* error);

}  // namespace caustic
