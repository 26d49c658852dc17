// Fuzz harness: the part-file reader of `caustic merge` (app/part_file.h readPart: OpenImageIO's
// OpenEXR reader, the header checks of readChannelImage, then the part's metadata, channels,
// checksum and values), on arbitrary file bytes, first the header alone (as merge's memory
// estimate reads it), then with the pixels.
// Properties beyond "no crash, no hang, no leak, no undefined behaviour":
//   - a refusal names the file;
//   - a part whose header is accepted has an image size a render can have (renderer/scene.h
//     kMaxRenderSide a side), a render time that is a number of seconds, a sample range that is
//     not empty, and a crop inside the image;
//   - a part accepted with its pixels has the same header, exactly the crop's pixels of each
//     accumulation image, and only finite values, none negative where a render writes none (all
//     but the normals' sums): what merge adds up.
// Seeds: tests/fuzz/seeds/part/ (make_seeds.py: uncompressed EXR parts, valid and crafted).
#include "app/part_file.h"
#include "renderer/scene.h"
#include "tests/fuzz/fuzz_common.h"

#include <cmath>

using namespace caustic;

namespace {

void checkHeader(const PartInfo& i) {
    FUZZ_CHECK(i.width > 0 && i.height > 0 && i.width <= kMaxRenderSide && i.height <= kMaxRenderSide,
               std::to_string(i.width) + "x" + std::to_string(i.height));
    FUZZ_CHECK(std::isfinite(i.seconds) && i.seconds >= 0.0, std::to_string(i.seconds));
    FUZZ_CHECK(i.sample0 < i.sample1, std::to_string(i.sample0) + ":" + std::to_string(i.sample1));
    FUZZ_CHECK(0 <= i.crop.x0 && i.crop.x0 < i.crop.x1 && i.crop.x1 <= i.width && 0 <= i.crop.y0 &&
                   i.crop.y0 < i.crop.y1 && i.crop.y1 <= i.height,
               "crop outside the image");
}

bool finiteVec(const glm::vec4& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string file = fuzz::ScratchDir::get().write(data, size, ".exr");
    Part header;
    std::string error;
    const bool headerOk = readPart(file, &header, &error, false);
    if (!headerOk) FUZZ_CHECK(error.rfind(file, 0) == 0, "the message does not name the file: " + error);
    else {
        checkHeader(header.info);
        FUZZ_CHECK(header.sums.width == 0 && header.sums.sum.empty(), "pixels read with the header alone");
    }

    Part part;
    error.clear();
    if (!readPart(file, &part, &error, true)) {
        FUZZ_CHECK(error.rfind(file, 0) == 0, "the message does not name the file: " + error);
        return 0;
    }
    FUZZ_CHECK(headerOk, "the pixels read where the header alone was refused");
    const PartInfo& i = part.info;
    checkHeader(i);
    FUZZ_CHECK(i.width == header.info.width && i.height == header.info.height && i.crop.x0 == header.info.crop.x0 &&
                   i.crop.x1 == header.info.crop.x1 && i.crop.y0 == header.info.crop.y0 &&
                   i.crop.y1 == header.info.crop.y1 && i.sample0 == header.info.sample0 &&
                   i.sample1 == header.info.sample1 && i.seed == header.info.seed && i.renderHash == header.info.renderHash,
               "the header reads differently with the pixels");
    const Accumulators& s = part.sums;
    const std::size_t n = std::size_t(i.crop.x1 - i.crop.x0) * std::size_t(i.crop.y1 - i.crop.y0);
    FUZZ_CHECK(s.width == i.crop.x1 - i.crop.x0 && s.height == i.crop.y1 - i.crop.y0,
               std::to_string(s.width) + "x" + std::to_string(s.height));
    FUZZ_CHECK(s.sum.size() == n && s.sumSq.size() == n && s.albedo.size() == n && s.normal.size() == n,
               std::to_string(s.sum.size()) + " pixels for " + std::to_string(n));
    for (std::size_t p = 0; p < n; ++p) {
        FUZZ_CHECK(finiteVec(s.sum[p]) && finiteVec(s.sumSq[p]) && finiteVec(s.albedo[p]) && finiteVec(s.normal[p]),
                   "pixel " + std::to_string(p) + " is not finite");
        for (int c = 0; c < 4; ++c)
            FUZZ_CHECK(s.sum[p][c] >= 0.0f && s.sumSq[p][c] >= 0.0f && s.albedo[p][c] >= 0.0f,
                       "pixel " + std::to_string(p) + " has a negative sum");
        FUZZ_CHECK(s.normal[p].w >= 0.0f, "pixel " + std::to_string(p) + " has a negative normal count");
    }
    return 0;
}
