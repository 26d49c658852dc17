// Part files: one part of a split render (caustic --sample-range / --crop), holding what an
// exact merge needs: the accumulation images as sums with their counts, for the part's crop,
// and metadata naming the render they belong to. The format is described in docs/farm.md.
#pragma once

#include "renderer/film.h"
#include "renderer/image_io.h"
#include "renderer/renderer.h"
#include "renderer/scene.h"

#include <cstdint>
#include <string>

namespace caustic {

inline constexpr const char* kPartFormat = "caustic-part-1";

struct PartInfo {
    std::string scene;        // the scene file as named on the command line (for messages)
    std::string renderHash;   // what must agree for parts to merge (renderIdentityHash)
    std::string version;      // the caustic that rendered it
    std::string variant;      // the sweep variant's label, "" for none
    std::uint32_t seed = 0;
    int width = 0, height = 0;               // the whole image
    std::uint32_t sample0 = 0, sample1 = 0;  // sample indices [sample0, sample1)
    PixelRect crop;                          // the part's pixels in the whole image
    double seconds = 0.0;                    // render time
    std::uint64_t dropped = 0;               // NaN/Inf samples dropped
};

struct Part {
    PartInfo info;
    Accumulators sums;   // the crop's size
};

// 64-bit FNV-1a of bytes, as 16 hex digits (a check against damage, not a cryptographic hash).
std::string fnv1a64Hex(const void* data, std::size_t size);

// The hash of everything that decides a render's pixels apart from the seed, the image size and
// the sample range, which the part records separately: the scene as the renderer sees it (after
// --set and the command line's flags; written with sceneToJson, its sample count zeroed), the
// direct-lighting strategy and the program's version.
std::string renderIdentityHash(const Scene& scene, const std::string& strategy);

// "<stem>.part-s<a>-<b>-x<x0>-<x1>-y<y0>-<y1>.exr"
std::string partFileName(const std::string& stem, const PartInfo& info);

// Writes the part atomically (a temporary beside the file, renamed when complete).
bool writePart(const std::string& path, const Part& part, std::string* error);

// Reads a part and checks it: the format tag, every metadata field, the channels, the pixel
// data's size against the crop and its checksum (a damaged or truncated file is refused). With
// pixels = false only the header is read and checked (out->sums stays empty).
bool readPart(const std::string& path, Part* out, std::string* error, bool pixels = true);

}  // namespace caustic
