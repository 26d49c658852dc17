#include "renderer/image_io.h"

#include "renderer/file_util.h"

#include <OpenImageIO/imageio.h>

#include <cstdio>

namespace caustic {
namespace {

bool writeAtomically(const std::string& path, int width, int height, OIIO::TypeDesc type, const void* data,
                     const ImageMetadata& metadata, std::string* error) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) {
        *error = path + ": cannot write this format: " + OIIO::geterror();
        return false;
    }
    OIIO::ImageSpec spec(width, height, 3, type);
    for (const auto& [key, value] : metadata) spec.attribute(key, value);
    const std::string tmp = tempPathBeside(path);
    if (!out->open(tmp, spec)) {
        *error = path + ": cannot write: " + out->geterror();
        std::remove(tmp.c_str());
        return false;
    }
    bool ok = out->write_image(type, data);
    ok = out->close() && ok;
    if (!ok) {
        *error = path + ": write failed: " + out->geterror();
        std::remove(tmp.c_str());
        return false;
    }
    return commitTempFile(tmp, path, error);
}

}  // namespace

bool writeImage8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb,
                 const ImageMetadata& metadata, std::string* error) {
    return writeAtomically(path, width, height, OIIO::TypeDesc::UINT8, rgb.data(), metadata, error);
}

bool writeImageFloat(const std::string& path, int width, int height, const std::vector<float>& rgb,
                     const ImageMetadata& metadata, std::string* error) {
    return writeAtomically(path, width, height, OIIO::TypeDesc::FLOAT, rgb.data(), metadata, error);
}

bool readImage(const std::string& path, ImageData* out, std::string* error) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        *error = path + ": cannot read image: " + OIIO::geterror();
        return false;
    }
    const OIIO::ImageSpec& spec = in->spec();
    out->width = spec.width;
    out->height = spec.height;
    out->channels = spec.nchannels;
    out->pixels.resize(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, out->pixels.data())) {
        *error = path + ": cannot decode image: " + in->geterror();
        return false;
    }
    in->close();
    return true;
}

}  // namespace caustic
