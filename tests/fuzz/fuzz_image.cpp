// Fuzz harness: the image module's reader (renderer/image_io.h readImage: OpenImageIO, for
// textures and environment maps) on arbitrary bytes.
// Input: a file extension on the first line ("png", "exr", "hdr", "jpg", "tga", "bmp", "tif",
// ...), then the file's bytes. Properties: a refusal names the file; an accepted image has a size
// within renderer/image.h's limits, at most 4 channels and exactly width*height*channels
// values.
// Seeds: assets/sky.hdr, textures of Debian's assimp-testmodels and tests/fuzz/seeds/image/.
#include "renderer/image_io.h"
#include "tests/fuzz/fuzz_common.h"

using namespace caustic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view in(reinterpret_cast<const char*>(data), size);
    const auto [ext, body] = fuzz::splitFirstLine(in);
    if (ext.empty() || ext.size() > 8) return 0;
    for (const char c : ext)
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'))) return 0;
    const std::string file = fuzz::ScratchDir::get().write(reinterpret_cast<const std::uint8_t*>(body.data()),
                                                            body.size(), fuzz::dotted(ext));
    ImageData image;
    std::string error;
    if (!readImage(file, &image, &error)) {
        FUZZ_CHECK(error.rfind(file, 0) == 0, "the message does not name the file: " + error);
        return 0;
    }
    FUZZ_CHECK(imageSizeProblem(file, image.width, image.height, image.channels).empty(),
               std::to_string(image.width) + "x" + std::to_string(image.height) + "x" + std::to_string(image.channels));
    // At most RGBA is kept, whatever the file declares (memory stays bounded by the pixel limit).
    FUZZ_CHECK(image.channels <= kMaxKeptImageChannels, std::to_string(image.channels) + " channels kept");
    FUZZ_CHECK(image.pixels.size() ==
                   std::size_t(image.width) * std::size_t(image.height) * std::size_t(image.channels),
               std::to_string(image.pixels.size()));
    return 0;
}
