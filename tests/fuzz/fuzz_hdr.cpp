// Fuzz harness: the core's Radiance RGBE reader (renderer/hdr_file.h readRadianceHdr), which
// binaries without OpenImageIO use for environment maps. Properties: a refusal names the file; an
// accepted image has a size within the limits of renderer/image.h, 3 channels, exactly
// width*height*3 finite, non-negative values.
// Seeds: assets/sky.hdr and tests/fuzz/seeds/hdr/ (tests/fuzz/make_seeds.py).
#include "renderer/hdr_file.h"
#include "tests/fuzz/fuzz_common.h"

#include <cmath>

using namespace caustic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string file = fuzz::ScratchDir::get().write(data, size, ".hdr");
    ImageData image;
    std::string error;
    if (!readRadianceHdr(file, &image, &error)) {
        FUZZ_CHECK(error.rfind(file, 0) == 0, "the message does not name the file: " + error);
        return 0;
    }
    FUZZ_CHECK(imageSizeProblem(file, image.width, image.height, image.channels).empty(),
               std::to_string(image.width) + "x" + std::to_string(image.height));
    FUZZ_CHECK(image.channels == 3, std::to_string(image.channels));
    FUZZ_CHECK(image.pixels.size() == std::size_t(image.width) * std::size_t(image.height) * 3,
               std::to_string(image.pixels.size()));
    for (const float v : image.pixels) FUZZ_CHECK(std::isfinite(v) && v >= 0.0f, std::to_string(v));
    return 0;
}
