#include "renderer/image_io.h"

#include "renderer/file_util.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>

namespace caustic {
namespace {
// The most bytes of pixels one byte of an image file can hold (readChannelImage).
constexpr double kMaxCompressionRatio = 1100.0;

// data: `type` values, channels interleaved; fileType: what the file stores (EXR: half or float).
// The file is encoded in memory (OpenImageIO's IOVecOutput proxy) and then written by
// writeFileAtomically, which checks every write, the fsync and the close: OpenImageIO's PNG and
// Radiance writers do not report a failed fwrite or fclose, so on a full disk they "succeeded"
// with a truncated file that the rename then put over the previous good image.
bool writeAtomically(const std::string& path, int width, int height, OIIO::TypeDesc type, const void* data,
                     const ImageMetadata& metadata, std::string* error,
                     const std::vector<std::string>& channelNames = {"R", "G", "B"},
                     OIIO::TypeDesc fileType = OIIO::TypeDesc::UNKNOWN) {
    try {
        auto out = OIIO::ImageOutput::create(path);
        if (!out) {
            *error = path + ": cannot write this format: " + OIIO::geterror();
            return false;
        }
        if (!out->supports("ioproxy")) {
            *error = path + ": cannot write this format (no in-memory encoder in this OpenImageIO)";
            return false;
        }
        OIIO::ImageSpec spec(width, height, static_cast<int>(channelNames.size()),
                             fileType == OIIO::TypeDesc::UNKNOWN ? type : fileType);
        spec.channelnames = channelNames;
        for (const auto& [key, value] : metadata) spec.attribute(key, value);
        std::vector<unsigned char> encoded;
        OIIO::Filesystem::IOVecOutput memory(encoded);
        OIIO::Filesystem::IOProxy* proxy = &memory;
        spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
        if (!out->open(path, spec)) {
            *error = path + ": cannot write: " + out->geterror();
            return false;
        }
        bool ok = out->write_image(type, data);
        ok = out->close() && ok;
        if (!ok || encoded.empty()) {
            const std::string why = out->geterror();
            *error = path + ": cannot write: encoding failed" + (why.empty() ? std::string() : ": " + why);
            return false;
        }
        return writeFileAtomically(path, reinterpret_cast<const char*>(encoded.data()), encoded.size(), error);
    } catch (const std::bad_alloc&) {
        *error = path + ": cannot write: out of memory";
        return false;
    }
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

bool writeExrLayers(const std::string& path, int width, int height, const std::vector<ImageLayer>& layers, bool half,
                    const ImageMetadata& metadata, std::string* error) {
    const size_t n = static_cast<size_t>(width) * height;
    const size_t channels = layers.size() * 3;
    std::vector<std::string> names;
    std::vector<float> pixels(n * channels);
    for (size_t l = 0; l < layers.size(); ++l) {
        const std::vector<float>& rgb = *layers[l].rgb;
        if (rgb.size() != n * 3) {
            *error = path + ": layer '" + layers[l].name + "' has the wrong size";
            return false;
        }
        for (const char* c : {"R", "G", "B"}) names.push_back(layers[l].name.empty() ? c : layers[l].name + "." + c);
        for (size_t i = 0; i < n; ++i)
            for (size_t c = 0; c < 3; ++c) pixels[i * channels + l * 3 + c] = rgb[i * 3 + c];
    }
    ImageMetadata meta = metadata;
    meta.push_back({"compression", "zip"});
    return writeAtomically(path, width, height, OIIO::TypeDesc::FLOAT, pixels.data(), meta, error, names,
                           half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
}

bool writeExrChannels(const std::string& path, int width, int height, const std::vector<std::string>& names,
                      const std::vector<float>& pixels, const ImageMetadata& metadata, std::string* error) {
    if (pixels.size() != size_t(width) * size_t(height) * names.size()) {
        *error = path + ": " + std::to_string(pixels.size()) + " values for " + std::to_string(names.size()) +
                 " channels of " + std::to_string(width) + "x" + std::to_string(height) + " pixels";
        return false;
    }
    ImageMetadata meta = metadata;
    meta.push_back({"compression", "zip"});
    return writeAtomically(path, width, height, OIIO::TypeDesc::FLOAT, pixels.data(), meta, error, names);
}

namespace {

// Opens an image for reading after the checks every reader needs: a regular file (a FIFO or a
// device such as /dev/zero would make the format probes read forever), a header whose size is
// within the limits (before anything is allocated for the pixels), and a 2D image (read_image
// fills width x height x depth pixels: a volume, TIFF's image depth, or a deep EXR would overrun
// a 2D buffer, and nothing here uses one). Null with *error set otherwise.
//
// Which reader: the one the file's extension names, then (for files saved under the wrong
// extension, common for PNG and JPEG) those of the formats a texture or environment map is
// normally in, each of which refuses a file without its magic number at once. Never
// OpenImageIO's own fallback, which tries every reader it has (about 40: FITS, DPX, PSD, ...) on
// a file its extension's reader refused: 15-60 ms per damaged file (the image fuzzer ran at 13
// inputs a second) and dozens of parsers exposed to hostile bytes that no scene needs.
// A reader may throw instead of failing (OpenImageIO 2.4's BMP reader throws std::length_error
// from open() on a run-length file whose header declares an impossible size: found by fuzz_image),
// which counts as that reader's refusal.
// Nor OpenImageIO's movie reader, which it gives .mp4, .mov, .avi, .mpg and six more extensions:
// it hands the file to FFmpeg's demuxers (libavformat), a large parser for hostile bytes, and
// no texture or environment map is a movie (fuzz_image found FFmpeg leaking on such inputs,
// docs/reliability.md). A movie-named file that is an image of a common format is still read.
std::unique_ptr<OIIO::ImageInput> openWith(const std::string& format, const std::string& path, std::string* why) {
    try {
        auto in = OIIO::ImageInput::create(format, false);
        if (!in) {
            *why = OIIO::geterror();
            return nullptr;
        }
        if (std::string_view(in->format_name()) == "FFmpeg movie") {
            *why = "'." + format + "' names a movie format, which is not read as an image";
            return nullptr;
        }
        OIIO::ImageSpec spec;
        if (!in->open(path, spec)) {
            *why = in->geterror();
            return nullptr;
        }
        return in;
    } catch (const std::exception& e) {
        *why = std::string("the ") + format + " reader failed: " + e.what();
        return nullptr;
    }
}

std::unique_ptr<OIIO::ImageInput> openByExtension(const std::string& path, std::string* error) {
    const std::string ext = OIIO::Strutil::lower(OIIO::Filesystem::extension(path, false));
    if (ext.empty()) {
        *error = path + ": cannot read image: the file name has no extension to tell its format";
        return nullptr;
    }
    std::string why;
    if (auto in = openWith(ext, path, &why)) return in;
    if (!OIIO::ImageInput::create(ext, false)) {
        (void)OIIO::geterror();
        *error = path + ": cannot read image: OpenImageIO has no reader for '." + ext + "' files";
        return nullptr;
    }
    static const char* const kCommonFormats[] = {"png", "jpeg", "openexr", "hdr", "tiff", "bmp"};
    for (const char* format : kCommonFormats) {
        std::string ignored;
        if (auto in = openWith(format, path, &ignored)) return in;
    }
    *error = path + ": cannot read image: " + why;
    return nullptr;
}

// OpenEXR 3.1 (OpenImageIO's EXR reader) allocates, and fills, as many bytes as some attributes
// of the header declare before it reads them: a 1.5 KB part file whose string attribute declared
// 1,879,048,197 bytes made every read of it allocate 1.75 GiB and take 10 s (found by fuzz_part).
// So an OpenEXR file's header (every part's, for a multi-part file) is walked here first, before
// any reader sees it, the way OpenEXR reads it: a channel list up to its empty name and the
// fixed-size types by their size, whatever size the attribute declares; the types whose declared
// size is what OpenEXR allocates (string, stringvector, floatvector, preview, idmanifest and any
// type it does not know) are refused when they declare more bytes than the file has left. A header
// this walk cannot follow (a name without its NUL, a file that ends) is left to OpenEXR, which
// refuses it. Any file is looked at, whatever its extension: a misnamed file reaches the EXR
// reader too (openByExtension). "" when the file is not an OpenEXR file or nothing is wrong.
std::string exrHeaderProblem(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char head[8] = {};
    if (!in.read(reinterpret_cast<char*>(head), sizeof head)) return "";
    if (!(head[0] == 0x76 && head[1] == 0x2f && head[2] == 0x31 && head[3] == 0x01)) return "";
    const bool multiPart = (head[5] & 0x10) != 0;   // version field bit 12
    in.seekg(0, std::ios::end);
    const long long fileSize = static_cast<long long>(in.tellg());
    long long at = 8;
    // A NUL-terminated name of at most 255 bytes (OpenEXR's limit), read from `at`.
    auto readName = [&](std::string* out) {
        char buf[256];
        in.clear();
        in.seekg(at);
        in.read(buf, sizeof buf);
        const void* nul = std::memchr(buf, '\0', static_cast<std::size_t>(in.gcount()));
        if (!nul) return false;
        out->assign(buf, static_cast<std::size_t>(static_cast<const char*>(nul) - buf));
        at += static_cast<long long>(out->size()) + 1;
        return true;
    };
    // Names as a message shows them: printable ASCII, anything else a '?'.
    auto shown = [](std::string t) {
        for (char& c : t)
            if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) c = '?';
        return t;
    };
    // The types OpenEXR reads by a size of their own (Xdr sizes of their fields).
    static const std::pair<const char*, int> kFixed[] = {
        {"box2i", 16}, {"box2f", 16}, {"compression", 1}, {"lineOrder", 1}, {"envmap", 1}, {"deepImageState", 1},
        {"float", 4}, {"double", 8}, {"int", 4}, {"rational", 8}, {"v2i", 8}, {"v2f", 8}, {"v2d", 16}, {"v3i", 12},
        {"v3f", 12}, {"v3d", 24}, {"m33f", 36}, {"m33d", 72}, {"m44f", 64}, {"m44d", 128}, {"chromaticities", 32},
        {"keycode", 28}, {"timecode", 8}, {"tiledesc", 9}};
    for (int part = 0; part < 1 << 16; ++part) {
        std::string name, type;
        for (;;) {   // one header: attributes up to an empty name
            if (!readName(&name)) return "";
            if (name.empty()) break;
            if (!readName(&type)) return "";
            unsigned char size[4];
            in.clear();
            in.seekg(at);
            if (!in.read(reinterpret_cast<char*>(size), 4)) return "";
            at += 4;
            const std::int32_t declared = static_cast<std::int32_t>(std::uint32_t(size[0]) | std::uint32_t(size[1]) << 8 |
                                                                    std::uint32_t(size[2]) << 16 | std::uint32_t(size[3]) << 24);
            if (type == "chlist") {   // channels up to an empty name, each name then 16 bytes
                std::string channel;
                for (;;) {
                    if (!readName(&channel)) return "";
                    if (channel.empty()) break;
                    at += 16;
                }
                continue;
            }
            const auto fixed = std::find_if(std::begin(kFixed), std::end(kFixed),
                                            [&](const auto& f) { return type == f.first; });
            if (fixed != std::end(kFixed)) {
                // OpenEXR sizes its line buffers by the data window when it opens the file, before
                // any size check of caustic's: a window wider or taller than any image caustic reads
                // (fuzz_part's 2,097,155 x 2 pixels took 21 s under the sanitizers) is refused here.
                if (type == "box2i" && name == "dataWindow") {
                    std::int32_t box[4] = {};
                    unsigned char raw[16];
                    in.clear();
                    in.seekg(at);
                    if (!in.read(reinterpret_cast<char*>(raw), 16)) return "";
                    for (int k = 0; k < 4; ++k)
                        box[k] = static_cast<std::int32_t>(std::uint32_t(raw[4 * k]) | std::uint32_t(raw[4 * k + 1]) << 8 |
                                                           std::uint32_t(raw[4 * k + 2]) << 16 |
                                                           std::uint32_t(raw[4 * k + 3]) << 24);
                    const long long width = static_cast<long long>(box[2]) - box[0] + 1;
                    const long long height = static_cast<long long>(box[3]) - box[1] + 1;
                    if (width > kMaxImageDimension || height > kMaxImageDimension ||
                        (width > 0 && height > 0 && width * height > kMaxImagePixels))
                        return path + ": the OpenEXR header's data window is " + std::to_string(width) + " x " +
                               std::to_string(height) + " pixels, more than an image may have (" +
                               std::to_string(kMaxImageDimension) + " a side, " + std::to_string(kMaxImagePixels) +
                               " pixels); the file is damaged or not what it says";
                }
                at += fixed->second;
                continue;
            }
            if (declared < 0 || declared > fileSize - at)
                return path + ": the OpenEXR header declares its attribute '" + shown(name) + "' (" + shown(type) + ") of " +
                       std::to_string(declared) + " bytes, and the file has " + std::to_string(std::max(0LL, fileSize - at)) +
                       " bytes after it; the file is damaged or not what it says";
            at += type == "floatvector" ? declared / 4 * 4 : declared;
        }
        if (!multiPart) return "";
        // A multi-part file's headers end with an empty header (a lone NUL).
        in.clear();
        in.seekg(at);
        char next = 0;
        if (!in.get(next) || next == '\0') return "";
    }
    return "";
}

std::unique_ptr<OIIO::ImageInput> openChecked(const std::string& path, std::string* error) {
    if (!checkRegularFile(path, error)) return nullptr;
    if (std::string why = exrHeaderProblem(path); !why.empty()) {
        *error = why;
        return nullptr;
    }
    auto in = openByExtension(path, error);
    if (!in) return nullptr;
    const OIIO::ImageSpec& spec = in->spec();
    if (std::string why = imageSizeProblem(path, spec.width, spec.height, spec.nchannels); !why.empty()) {
        *error = why;
        return nullptr;
    }
    if (spec.depth > 1 || spec.deep) {
        *error = path + ": " + (spec.deep ? std::string("a deep image") : "a volume image (depth " + std::to_string(spec.depth) + ")") +
                 ", not a 2D image";
        return nullptr;
    }
    // OpenImageIO 2.4's TIFF reader allocates a strip buffer of RowsPerStrip scanlines, however few
    // rows the image has: a damaged 4x3 file declaring 385,875,968 rows per strip made it allocate
    // 4.6 GB (found by tests/fuzz, fuzz_image). More rows per strip than the image has is legal
    // (the TIFF default, 2^32 - 1, means "one strip": OpenImageIO reads it as -1, which passes), so
    // only a strip buffer beyond what the image itself needs at its largest is refused.
    if (const OIIO::ParamValue* rows = spec.find_attribute("tiff:RowsPerStrip"); rows && rows->type() == OIIO::TypeDesc::INT) {
        const long long perStrip = rows->get_int();
        const long long scanline = static_cast<long long>(spec.scanline_bytes());
        if (perStrip > spec.height && perStrip * scanline > kMaxImagePixels * 4 * 4) {
            *error = path + ": the TIFF header declares " + std::to_string(perStrip) + " rows per strip for an image of " +
                     std::to_string(spec.height) + " rows (its reader would allocate " +
                     std::to_string(perStrip * scanline / (1 << 20)) + " MiB); the file is probably damaged";
            return nullptr;
        }
    }
    return in;
}

}  // namespace

bool readChannelImage(const std::string& path, ChannelImage* out, std::string* error, bool pixels) {
    try {
        auto in = openChecked(path, error);
        if (!in) return false;
        const OIIO::ImageSpec& spec = in->spec();
        // What the header declares against what the file can hold: no compression a reader knows
        // (zlib's deflate at most 1032:1; RLE, PIZ, PXR24, B44 far less) packs more than
        // kMaxCompressionRatio bytes of pixels into one byte of file. A larger declared size is a
        // damaged or crafted header, refused before its pixels are allocated.
        std::error_code sizeError;
        const auto fileBytes = std::filesystem::file_size(path, sizeError);
        const double declared = double(spec.width) * double(spec.height) * double(spec.pixel_bytes(true));
        if (!sizeError && declared > kMaxCompressionRatio * (double(fileBytes) + 4096.0)) {
            *error = path + ": its header declares " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                     " pixels of " + std::to_string(spec.nchannels) + " channels (" +
                     std::to_string(static_cast<long long>(declared / (1 << 20))) + " MiB), more than a file of " +
                     std::to_string(fileBytes) + " bytes can hold: the file is damaged or not what it says";
            return false;
        }
        out->width = spec.width;
        out->height = spec.height;
        out->names = spec.channelnames;
        out->metadata.clear();
        for (const OIIO::ParamValue& p : spec.extra_attribs)
            if (p.type() == OIIO::TypeDesc::STRING) out->metadata.push_back({p.name().string(), p.get_string()});
        out->pixels.clear();
        if (!pixels) return true;
        out->pixels.assign(size_t(spec.width) * spec.height * spec.nchannels, 0.0f);
        if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, out->pixels.data())) {
            *error = path + ": cannot decode image (damaged or incomplete?): " + in->geterror();
            out->pixels = {};
            return false;
        }
        in->close();
        return true;
    } catch (const std::bad_alloc&) {
        *error = path + ": out of memory reading the image";
        out->pixels = {};
        return false;
    } catch (const std::exception& e) {  // a reader that throws while decoding (see openWith)
        *error = path + ": cannot decode image: " + e.what();
        out->pixels = {};
        return false;
    }
}

bool readImage(const std::string& path, ImageData* out, std::string* error) {
    try {
        auto in = openChecked(path, error);
        if (!in) return false;
        const OIIO::ImageSpec& spec = in->spec();
        // At most 4 channels are kept (RGBA; what the renderer uses), so a file declaring 64
        // channels costs no more memory than an RGBA one.
        const int channels = std::min(spec.nchannels, kMaxKeptImageChannels);
        out->width = spec.width;
        out->height = spec.height;
        out->channels = channels;
        out->pixels.assign(static_cast<size_t>(spec.width) * spec.height * channels, 0.0f);
        if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, out->pixels.data())) {
            *error = path + ": cannot decode image: " + in->geterror();
            out->pixels = {};
            return false;
        }
        in->close();
        return true;
    } catch (const std::bad_alloc&) {
        *error = path + ": out of memory reading the image (" + std::to_string(out->width) + "x" +
                 std::to_string(out->height) + ")";
        out->pixels = {};
        return false;
    } catch (const std::exception& e) {  // a reader that throws while decoding (see openWith)
        *error = path + ": cannot decode image: " + e.what();
        out->pixels = {};
        return false;
    }
}

}  // namespace caustic
