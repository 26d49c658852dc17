// Which reader opens an image file (renderer/image_io.cpp, openByExtension): the one its extension
// names, then the common texture formats' (PNG, JPEG, OpenEXR, Radiance HDR, TIFF, BMP) for a
// file saved under the wrong extension, never OpenImageIO's fallback through every reader it has
// (FITS, DPX, PNM, PSD, ...: 15-60 ms per damaged file, and parsers no scene needs exposed to
// hostile bytes). A PNM file stands for "a format outside the common list": OpenImageIO reads it
// by its own extension, and its old fallback also read it under a PNG name.
#include "renderer/gpu_scene.h"
#include "renderer/image_io.h"
#include "tests/support/meshes.h"

#include <catch2/catch.hpp>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <cstdint>
#include <cstring>
#include <memory>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace caustic;

namespace {

// A 2 x 1 binary PPM: red, then blue.
void writePpm(const std::string& path) {
    std::ofstream f(path, std::ios::binary);
    f << "P6\n2 1\n255\n";
    const unsigned char px[] = {255, 0, 0, 0, 0, 255};
    f.write(reinterpret_cast<const char*>(px), sizeof px);
}

void writePng(const std::string& path) {
    std::string error;
    REQUIRE(writeImage8(path, 2, 1, {255, 0, 0, 0, 0, 255}, {}, &error));
}

ImageData readOk(const std::string& path) {
    ImageData image;
    std::string error;
    INFO(error);
    REQUIRE(readImage(path, &image, &error));
    return image;
}

}  // namespace

TEST_CASE("images: a file is read by the reader its extension names, in either case", "[image]") {
    test::TempDir dir;
    writePng(dir.file("a.png"));
    std::filesystem::copy_file(dir.file("a.png"), dir.file("B.PNG"));
    writePpm(dir.file("c.ppm"));
    for (const char* name : {"a.png", "B.PNG", "c.ppm"}) {
        INFO(name);
        const ImageData image = readOk(dir.file(name));
        CHECK(image.width == 2);
        CHECK(image.height == 1);
        REQUIRE(image.channels >= 3);
        CHECK(image.pixels[0] == Approx(1.0f));                   // red ...
        CHECK(image.pixels[size_t(image.channels) + 2] == Approx(1.0f));  // ... then blue
    }
}

TEST_CASE("images: a PNG saved as .jpg still reads, and a PNM saved as .png is refused, naming the file", "[image]") {
    test::TempDir dir;
    writePng(dir.file("a.png"));
    std::filesystem::copy_file(dir.file("a.png"), dir.file("really-png.jpg"));
    CHECK(readOk(dir.file("really-png.jpg")).width == 2);

    writePpm(dir.file("c.ppm"));
    std::filesystem::copy_file(dir.file("c.ppm"), dir.file("really-ppm.png"));
    ImageData image;
    std::string error;
    CHECK_FALSE(readImage(dir.file("really-ppm.png"), &image, &error));
    CHECK(error.rfind(dir.file("really-ppm.png"), 0) == 0);
    CHECK(error.find("cannot read image") != std::string::npos);
}

TEST_CASE("images: an extension no reader knows, or none, is refused with a message saying so", "[image]") {
    test::TempDir dir;
    writePng(dir.file("a.png"));
    std::filesystem::copy_file(dir.file("a.png"), dir.file("a.texture"));
    std::filesystem::copy_file(dir.file("a.png"), dir.file("noext"));
    ImageData image;
    std::string error;
    CHECK_FALSE(readImage(dir.file("a.texture"), &image, &error));
    CHECK(error == dir.file("a.texture") + ": cannot read image: OpenImageIO has no reader for '.texture' files");
    CHECK_FALSE(readImage(dir.file("noext"), &image, &error));
    CHECK(error == dir.file("noext") + ": cannot read image: the file name has no extension to tell its format");
}

// OpenImageIO reads .mp4, .mov, .avi, ... with its movie reader, through FFmpeg's demuxers, which
// open a PPM under such a name as a one-frame movie: no image reaches FFmpeg now. An image of a
// common format under a movie's name is read as a misnamed file is.
TEST_CASE("images: a movie's extension does not reach FFmpeg, and a PNG under one still reads", "[image]") {
    test::TempDir dir;
    writePpm(dir.file("frame.mp4"));
    writePng(dir.file("a.png"));
    std::filesystem::copy_file(dir.file("a.png"), dir.file("texture.mov"));
    ImageData image;
    std::string error;
    CHECK_FALSE(readImage(dir.file("frame.mp4"), &image, &error));
    CHECK(error == dir.file("frame.mp4") + ": cannot read image: '.mp4' names a movie format, which is not read as an image");
    const ImageData png = readOk(dir.file("texture.mov"));
    CHECK(png.width == 2);
    CHECK(png.height == 1);
}

// Found by fuzz_image (docs/reliability.md): OpenImageIO 2.4's BMP reader throws std::length_error
// from open() on this run-length file; the CLI died with "unexpected failure:
// vector::_M_default_append", naming no file, and the fuzzer's process with std::terminate.
TEST_CASE("images: a BMP on which OpenImageIO's reader throws is refused with a message naming it", "[image]") {
    const std::string file = CAUSTIC_SOURCE_DIR "/tests/fuzz/seeds/image/rle-length-error.bmp";
    test::TempDir dir;
    std::filesystem::copy_file(file, dir.file("misnamed.png"));
    for (const std::string& path : {file, dir.file("misnamed.png")}) {
        INFO(path);
        ImageData image;
        std::string error;
        CHECK_FALSE(readImage(path, &image, &error));
        CHECK(error.rfind(path + ": cannot read image", 0) == 0);
        CHECK(image.pixels.empty());
    }
}

// Found by fuzz_image (docs/reliability.md): a damaged 4x3 TIFF declaring 385,875,968 rows per
// strip, for which OpenImageIO 2.4's TIFF reader allocates a 4.6 GB strip buffer (a normal build
// overcommits and survives; with overcommit off, a memory limit or the sanitizers it fails). It
// must be refused from its header, naming the file, also when misnamed; a legal TIFF with one
// strip for the whole image (RowsPerStrip at its default, or above the height) still reads.
TEST_CASE("images: a TIFF declaring a strip far larger than its image is refused before its reader allocates",
          "[image]") {
    const std::string file = CAUSTIC_SOURCE_DIR "/tests/fuzz/seeds/image/rows-per-strip.tif";
    test::TempDir dir;
    std::filesystem::copy_file(file, dir.file("misnamed.pfm"));
    for (const std::string& path : {file, dir.file("misnamed.pfm")}) {
        INFO(path);
        ImageData image;
        std::string error;
        CHECK_FALSE(readImage(path, &image, &error));
        CHECK(error == path + ": the TIFF header declares 385875968 rows per strip for an image of 3 rows (its reader "
                              "would allocate 4416 MiB); the file is probably damaged");
        CHECK(image.pixels.empty());
    }
    // One strip of more rows than the image has, within reason: read as before.
    const std::string good = dir.file("one-strip.tif");
    {
        std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(good);
        REQUIRE(out);
        OIIO::ImageSpec spec(4, 3, 3, OIIO::TypeDesc::UINT8);
        spec.attribute("tiff:RowsPerStrip", 64);
        REQUIRE(out->open(good, spec));
        const std::vector<unsigned char> pixels(4 * 3 * 3, 200);
        REQUIRE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
        out->close();
    }
    ImageData image;
    std::string error;
    INFO(error);
    CHECK(readImage(good, &image, &error));
    CHECK(image.width == 4);
    CHECK(image.height == 3);
}

// The lean binaries (caustic-bench, the GPU machine's build) read textures and environment maps
// without OpenImageIO (renderer/textures.cpp, readImageWithoutOpenImageIo): what they read must be
// what caustic itself reads, or a benchmark measures another scene.
TEST_CASE("images: the lean reader reads PNG, JPEG and HDR files as OpenImageIO does", "[image]") {
    test::TempDir dir;
    // A JPEG written here (no JPEG in the repository): a horizontal ramp, quality 100.
    const std::string jpeg = dir.file("ramp.jpg");
    {
        std::vector<unsigned char> px(32 * 16 * 3);
        for (size_t i = 0; i < px.size(); ++i) px[i] = static_cast<unsigned char>((i / 3 % 32) * 8 + (i % 3) * 20);
        auto out = OIIO::ImageOutput::create(jpeg);
        REQUIRE(out);
        OIIO::ImageSpec spec(32, 16, 3, OIIO::TypeDesc::UINT8);
        spec.attribute("Compression", "jpeg:100");
        REQUIRE(out->open(jpeg, spec));
        REQUIRE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
        out->close();
    }
    struct Case { std::string path; float tolerance; };
    // PNG: v / 255 against OpenImageIO's v * (1 / 255), a rounding apart.
    for (const Case& c : {Case{CAUSTIC_SOURCE_DIR "/assets/tiles/albedo.png", 1e-6f},
                          Case{CAUSTIC_SOURCE_DIR "/assets/tiles/normal.png", 1e-6f},
                          Case{CAUSTIC_SOURCE_DIR "/assets/sky.hdr", 0.0f},
                          Case{jpeg, 2.5f / 255.0f}}) {
        INFO(c.path);
        ImageData reference, lean;
        std::string error;
        REQUIRE(readImage(c.path, &reference, &error));
        REQUIRE(readImageWithoutOpenImageIo(c.path, &lean, &error));
        REQUIRE(lean.width == reference.width);
        REQUIRE(lean.height == reference.height);
        REQUIRE(lean.channels == reference.channels);
        REQUIRE(lean.pixels.size() == reference.pixels.size());
        float worst = 0.0f;
        for (size_t i = 0; i < lean.pixels.size(); ++i)
            worst = std::max(worst, std::abs(lean.pixels[i] - reference.pixels[i]));
        CHECK(worst <= c.tolerance);
    }
    // Anything else is read as Radiance HDR, whose reader refuses it naming the file.
    const std::string bogus = dir.file("bogus.png");
    std::ofstream(bogus) << "not an image";
    ImageData img;
    std::string error;
    CHECK_FALSE(readImageWithoutOpenImageIo(bogus, &img, &error));
    CHECK(error.find(bogus) != std::string::npos);
}

TEST_CASE("images: a header that declares more pixels than its file can hold is refused before they are read",
          "[image]") {
    // An 8 x 8 EXR of 15 float channels (a part file's), its data and display windows then patched
    // to 16384 x 8192: 8 GiB of pixels declared by a file of a few kilobytes. The reader must
    // refuse it from the header, naming the file and the size, not allocate the pixels.
    test::TempDir dir;
    const std::string path = (dir.path / "patched.exr").string();
    std::vector<std::string> names;
    for (int c = 0; c < 15; ++c) names.push_back("c" + std::to_string(c));
    std::string error;
    REQUIRE(writeExrChannels(path, 8, 8, names, std::vector<float>(8 * 8 * 15, 0.5f), {}, &error));
    ChannelImage image;
    REQUIRE(readChannelImage(path, &image, &error));  // as written, it reads
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    for (const std::string name : {"dataWindow", "displayWindow"}) {
        const std::string attribute = name + std::string(1, '\0') + "box2i" + std::string(1, '\0');
        const size_t at = bytes.find(attribute);
        REQUIRE(at != std::string::npos);
        const std::int32_t box[4] = {0, 0, 16383, 8191};
        std::memcpy(&bytes[at + attribute.size() + 4], box, sizeof box);  // after the value's size
    }
    // The header ends after its attributes (name, type, size, value) with a 0 byte; then comes the
    // offset table, one 64-bit file offset per chunk of 16 lines (ZIP): 1 for 8 lines, 512 for
    // 8192. The table grows to 512 entries, every one pointing at the one chunk there is (which
    // moves by the bytes inserted), so that the header and the table are whole.
    size_t pos = 8;  // magic and version
    while (bytes.at(pos) != '\0') {
        pos = bytes.find('\0', pos) + 1;  // the name
        pos = bytes.find('\0', pos) + 1;  // the type
        std::int32_t size = 0;
        std::memcpy(&size, &bytes.at(pos), 4);
        pos += 4 + size_t(size);
    }
    const size_t table = pos + 1;
    std::uint64_t chunk = 0;
    std::memcpy(&chunk, &bytes.at(table), 8);
    chunk += 511 * 8;
    std::string offsets(512 * 8, '\0');
    for (int k = 0; k < 512; ++k) std::memcpy(&offsets[size_t(k) * 8], &chunk, 8);
    bytes = bytes.substr(0, table) + offsets + bytes.substr(table + 8);
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), std::streamsize(bytes.size()));
    }
    for (const bool pixels : {false, true}) {
        ChannelImage patched;
        error.clear();
        CHECK_FALSE(readChannelImage(path, &patched, &error, pixels));
        INFO(error);
        CHECK(error.rfind(path + ": its header declares 16384x8192 pixels of 15 channels", 0) == 0);
        CHECK(patched.pixels.empty());
    }
}

TEST_CASE("images: an OpenEXR attribute declaring more bytes than the file holds is refused before its reader allocates",
          "[image]") {
    // fuzz_part's file: a 1.5 KB part whose string attribute 'caustic:version' declares
    // 1,879,048,197 bytes (and whose channel list is misnamed). OpenEXR allocated and zeroed
    // 1.75 GiB for it, and took 10 s, before it failed; the header walk refuses it first, as a
    // texture, an environment map or a part.
    const std::string file = CAUSTIC_SOURCE_DIR "/tests/fuzz/seeds/part/attribute-size.exr";
    test::TempDir dir;
    std::filesystem::copy_file(file, dir.file("misnamed.png"));
    for (const std::string& path : {file, dir.file("misnamed.png")}) {
        INFO(path);
        const std::string expected = path + ": the OpenEXR header declares its attribute 'caustic:version' (string) of "
                                            "1879048197 bytes, and the file has 457 bytes after it; the file is "
                                            "damaged or not what it says";
        ImageData image;
        std::string error;
        CHECK_FALSE(readImage(path, &image, &error));
        CHECK(error == expected);
        ChannelImage channels;
        CHECK_FALSE(readChannelImage(path, &channels, &error, false));
        CHECK(error == expected);
    }
    // Long string attributes that the file does hold still read: a part's metadata of 100 KB.
    const std::string good = dir.file("long-metadata.exr");
    std::string error;
    REQUIRE(writeExrChannels(good, 2, 1, {"R", "G", "B"}, std::vector<float>(6, 0.25f),
                             {{"caustic:scene", std::string(100000, 's')}, {"note", "x"}}, &error));
    ChannelImage image;
    INFO(error);
    REQUIRE(readChannelImage(good, &image, &error));
    const auto scene = std::find_if(image.metadata.begin(), image.metadata.end(),
                                    [](const auto& kv) { return kv.first == "caustic:scene"; });
    REQUIRE(scene != image.metadata.end());
    CHECK(scene->second == std::string(100000, 's'));
}

TEST_CASE("images: an OpenEXR data window wider than any image is refused before its reader opens it", "[image]") {
    // fuzz_part's slow input: a header whose data window is 2,097,155 x 2 pixels. OpenEXR sizes
    // its line buffers by the window when it opens the file (21 s under the sanitizers), before
    // any check of caustic's; the header walk refuses it first. Made here from a valid 2 x 1 file
    // whose dataWindow box2i is rewritten.
    test::TempDir dir;
    const std::string path = dir.file("wide.exr");
    std::string error;
    REQUIRE(writeExrChannels(path, 2, 1, {"R", "G", "B"}, std::vector<float>(6, 0.5f), {}, &error));
    ChannelImage ok;
    REQUIRE(readChannelImage(path, &ok, &error));  // the file as written reads
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    const std::string key = std::string("dataWindow") + '\0' + "box2i" + '\0';
    const size_t at = bytes.find(key);
    REQUIRE(at != std::string::npos);
    const size_t box = at + key.size() + 4;  // after the attribute's size
    auto put = [&](size_t offset, std::int32_t v) {
        for (int k = 0; k < 4; ++k) bytes[offset + k] = char((std::uint32_t(v) >> (8 * k)) & 0xff);
    };
    put(box + 0, 0);
    put(box + 4, 0);
    put(box + 8, 2097154);
    put(box + 12, 1);
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), std::streamsize(bytes.size()));
    }
    const std::string expected = path + ": the OpenEXR header's data window is 2097155 x 2 pixels, more than an image "
                                        "may have (65536 a side, " + std::to_string(kMaxImagePixels) +
                                 " pixels); the file is damaged or not what it says";
    ImageData image;
    CHECK_FALSE(readImage(path, &image, &error));
    CHECK(error == expected);
    ChannelImage channels;
    CHECK_FALSE(readChannelImage(path, &channels, &error, false));
    CHECK(error == expected);
}
