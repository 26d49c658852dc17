// Textures: decoding to linear, mip chains, and their place in CompiledScene (addTexture).
#include "renderer/gpu_scene.h"
#include "renderer/file_util.h"
#include "renderer/hdr_file.h"

#include <glm/gtc/packing.hpp>

#include <jpeglib.h>
#include <png.h>

#include <csetjmp>
#include <cstdlib>
#include <cstring>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <utility>

namespace caustic {
namespace {

float srgbToLinear(float c) {
    // IEC 61966-2-1 (the sRGB standard's decoding curve).
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// libjpeg reports errors through error_exit, which must not return: jump back to the decoder.
struct JpegError {
    jpeg_error_mgr mgr;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
};

void jpegErrorExit(j_common_ptr cinfo) {
    auto* e = reinterpret_cast<JpegError*>(cinfo->err);
    (*cinfo->err->format_message)(cinfo, e->message);
    std::longjmp(e->jump, 1);
}

void jpegSilence(j_common_ptr, int) {}

bool decodeJpeg(const std::string& bytes, const std::string& what, ImageData* out, std::string* error) {
    jpeg_decompress_struct cinfo{};
    JpegError err{};
    cinfo.err = jpeg_std_error(&err.mgr);
    err.mgr.error_exit = jpegErrorExit;
    err.mgr.emit_message = jpegSilence;
    // Locals that live across setjmp are volatile or set before it (C's rule for longjmp).
    std::vector<unsigned char> rows;
    if (setjmp(err.jump)) {
        jpeg_destroy_decompress(&cinfo);
        *error = what + ": not a readable JPEG (" + err.message + ")";
        return false;
    }
    jpeg_create_decompress(&cinfo);
    jpeg_mem_src(&cinfo, reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<unsigned long>(bytes.size()));
    jpeg_read_header(&cinfo, TRUE);
    const std::string size = imageSizeProblem(what, cinfo.image_width, cinfo.image_height, cinfo.num_components);
    if (!size.empty()) {
        jpeg_destroy_decompress(&cinfo);
        *error = size;
        return false;
    }
    cinfo.out_color_space = cinfo.num_components == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_start_decompress(&cinfo);
    const int w = int(cinfo.output_width), h = int(cinfo.output_height), ch = int(cinfo.output_components);
    rows.resize(size_t(w) * size_t(h) * size_t(ch));
    while (cinfo.output_scanline < cinfo.output_height) {
        unsigned char* row = rows.data() + size_t(cinfo.output_scanline) * size_t(w) * size_t(ch);
        jpeg_read_scanlines(&cinfo, &row, 1);
    }
    jpeg_finish_decompress(&cinfo);
    jpeg_destroy_decompress(&cinfo);
    out->width = w;
    out->height = h;
    out->channels = ch;
    out->pixels.resize(rows.size());
    for (size_t i = 0; i < rows.size(); ++i) out->pixels[i] = float(rows[i]) / 255.0f;
    return true;
}

bool decodePng(const std::string& bytes, const std::string& what, ImageData* out, std::string* error) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size())) {
        *error = what + ": not a readable PNG (" + image.message + ")";
        return false;
    }
    const bool alpha = (image.format & PNG_FORMAT_FLAG_ALPHA) != 0, colour = (image.format & PNG_FORMAT_FLAG_COLOR) != 0;
    const int ch = (colour ? 3 : 1) + (alpha ? 1 : 0);
    const std::string size = imageSizeProblem(what, image.width, image.height, ch);
    if (!size.empty()) {
        png_image_free(&image);
        *error = size;
        return false;
    }
    // 16 bits per channel where the file has them (linear "LINEAR" formats would convert gamma:
    // read the stored values as 8 or 16-bit integers without any conversion instead).
    const bool sixteen = (image.format & PNG_FORMAT_FLAG_LINEAR) != 0;
    image.format = (colour ? PNG_FORMAT_FLAG_COLOR : 0u) | (alpha ? PNG_FORMAT_FLAG_ALPHA : 0u);
    if (sixteen) image.format |= PNG_FORMAT_FLAG_LINEAR;
    const size_t count = size_t(image.width) * size_t(image.height) * size_t(ch);
    std::vector<unsigned char> raw(count * (sixteen ? 2 : 1));
    if (!png_image_finish_read(&image, nullptr, raw.data(), 0, nullptr)) {
        *error = what + ": not a readable PNG (" + image.message + ")";
        png_image_free(&image);
        return false;
    }
    out->width = int(image.width);
    out->height = int(image.height);
    out->channels = ch;
    out->pixels.resize(count);
    for (size_t i = 0; i < count; ++i) {
        if (sixteen) {
            std::uint16_t v;
            std::memcpy(&v, raw.data() + 2 * i, 2);
            out->pixels[i] = float(v) / 65535.0f;
        } else {
            out->pixels[i] = float(raw[i]) / 255.0f;
        }
    }
    return true;
}

}  // namespace

bool rawTexelImage(const EmbeddedImage& e, const std::string& what, ImageData* out, std::string* error) {
    if (std::string problem = imageSizeProblem(what, e.width, e.height, 4); !problem.empty()) {
        *error = problem;
        return false;
    }
    const std::size_t count = std::size_t(e.width) * std::size_t(e.height) * 4;
    if (e.bytes.size() != count) {
        *error = what + ": " + std::to_string(e.bytes.size()) + " bytes of raw texels for " + std::to_string(e.width) +
                 "x" + std::to_string(e.height) + " (" + std::to_string(count) + " expected)";
        return false;
    }
    out->width = e.width;
    out->height = e.height;
    out->channels = 4;
    out->pixels.resize(count);
    for (std::size_t i = 0; i < count; ++i) out->pixels[i] = float(static_cast<unsigned char>(e.bytes[i])) / 255.0f;
    return true;
}

bool decodeImageBytes(const std::string& bytes, const std::string& what, ImageData* out, std::string* error) {
    const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
    if (bytes.size() >= 8 && std::memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0) return decodePng(bytes, what, out, error);
    if (bytes.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return decodeJpeg(bytes, what, out, error);
    *error = what + ": an embedded image that is neither PNG nor JPEG (the two formats glTF 2.0 allows)";
    return false;
}

bool readImageWithoutOpenImageIo(const std::string& path, ImageData* out, std::string* error) {
    if (!checkRegularFile(path, error)) return false;
    char head[8] = {};
    {
        std::FILE* f = std::fopen(path.c_str(), "rb");
        if (!f) {
            *error = path + ": cannot read image";
            return false;
        }
        const size_t n = std::fread(head, 1, sizeof head, f);
        std::fclose(f);
        const auto* b = reinterpret_cast<const unsigned char*>(head);
        const bool png = n == 8 && std::memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0;
        const bool jpeg = n >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF;
        if (!png && !jpeg) return readRadianceHdr(path, out, error);
    }
    const std::optional<std::string> bytes = readTextFile(path, error);
    return bytes && decodeImageBytes(*bytes, path, out, error);
}

std::uint32_t FileTextures::wrap(const std::string& slotKey) const {
    const TextureSlot slot = slotKey == "albedo_texture"      ? TextureSlot::BaseColor
                             : slotKey == "roughness_texture" ? TextureSlot::MetallicRoughness
                             : slotKey == "normal_texture"    ? TextureSlot::Normal
                                                              : TextureSlot::Emission;
    ImportedMaterial m;
    m.wrap = wraps;
    return m.textureWrap(slot, 0) | m.textureWrap(slot, 1) << 2;
}

bool readTextureImage(const ImageReader& reader, const FileTextures* files, const std::string& path, ImageData* out,
                      std::string* error) {
    if (files && !path.empty() && path[0] == '*') {
        const std::string what = files->file + " (embedded image " + path.substr(1) + ")";
        size_t index = 0;
        const char* digits = path.c_str() + 1;
        char* end = nullptr;
        const unsigned long long n = std::strtoull(digits, &end, 10);
        index = size_t(n);
        if (end == digits || *end != '\0' || !files->embedded || index >= files->embedded->size()) {
            *error = what + ": the file has no such embedded image";
            return false;
        }
        const EmbeddedImage& e = (*files->embedded)[index];
        if (e.raw()) return rawTexelImage(e, what, out, error);
        if (e.bytes.empty()) {
            *error = what + ": the file gives no data for it";
            return false;
        }
        return decodeImageBytes(e.bytes, what, out, error);
    }
    if (!reader) {
        *error = path + ": this build cannot read images";
        return false;
    }
    if (!reader(path, out, error)) {
        // The reader's message names the file; make sure it does even if it did not.
        if (error->find(path) == std::string::npos) *error = path + ": " + *error;
        return false;
    }
    return true;
}

namespace {
constexpr float kMaxHalf = 65504.0f;  // the largest finite 16-bit half float
}  // namespace

bool addTexture(const ImageData& image, TextureEncoding encoding, CompiledScene* out, std::string* error,
                std::uint32_t wrap) {
    const int w = image.width, h = image.height, ch = image.channels;
    if (w <= 0 || h <= 0 || ch <= 0 || image.pixels.size() < size_t(w) * size_t(h) * size_t(ch)) {
        *error = "empty or truncated image";
        return false;
    }
    const size_t total = size_t(out->texels.size()) + size_t(w) * size_t(h) * 2;  // a mip chain is < 4/3 of level 0
    if (total > size_t(1) << 31) {
        *error = "too many texels in all (" + std::to_string(total) + "; at most 2^31)";
        return false;
    }
    // Level 0 in linear floats; grey and grey+alpha images are expanded to RGBA.
    std::vector<glm::vec4> level(size_t(w) * size_t(h));
    for (size_t i = 0; i < level.size(); ++i) {
        const float* px = &image.pixels[i * size_t(ch)];
        glm::vec4 c = ch >= 3 ? glm::vec4(px[0], px[1], px[2], ch >= 4 ? px[3] : 1.0f)
                              : glm::vec4(px[0], px[0], px[0], ch == 2 ? px[1] : 1.0f);
        for (int k = 0; k < 4; ++k)
            if (!std::isfinite(c[k])) {
                *error = "non-finite pixel at (" + std::to_string(i % size_t(w)) + ", " + std::to_string(i / size_t(w)) + ")";
                return false;
            }
        if (encoding == TextureEncoding::Srgb) c = glm::vec4(srgbToLinear(c.r), srgbToLinear(c.g), srgbToLinear(c.b), c.a);
        // The GPU stores texels as 16-bit halves: a value beyond the largest (65,504) would become
        // infinite there (an albedo texel black, an emission texel lost), so it is refused here.
        for (int k = 0; k < 4; ++k)
            if (std::abs(c[k]) > kMaxHalf) {
                *error = "pixel (" + std::to_string(i % size_t(w)) + ", " + std::to_string(i / size_t(w)) + ") holds " +
                         std::to_string(c[k]) + ", beyond 65504, the largest value a texture stores (16-bit half "
                         "floats); scale the image down (an emission texture's scale can go into the material's "
                         "emission)";
                return false;
            }
        if (encoding == TextureEncoding::LinearReflectance)
            c = glm::vec4(glm::clamp(glm::vec3(c), glm::vec3(0.0f), glm::vec3(1.0f)), c.a);
        level[i] = c;
    }
    gpu::GpuTexture t{};
    t.info = glm::uvec4(static_cast<std::uint32_t>(out->texels.size()), w, h, 0);
    // The mip chain by 2x2 box filtering in linear space (odd sizes clamp the last row/column).
    int lw = w, lh = h;
    for (;;) {
        for (const glm::vec4& c : level)
            out->texels.emplace_back(glm::packHalf2x16(glm::vec2(c.r, c.g)), glm::packHalf2x16(glm::vec2(c.b, c.a)));
        ++t.info.w;  // the level count (the low 8 bits)
        if (lw == 1 && lh == 1) break;
        const int nw = std::max(1, lw / 2), nh = std::max(1, lh / 2);
        std::vector<glm::vec4> next(size_t(nw) * size_t(nh));
        for (int y = 0; y < nh; ++y)
            for (int x = 0; x < nw; ++x) {
                const int x0 = std::min(2 * x, lw - 1), x1 = std::min(2 * x + 1, lw - 1);
                const int y0 = std::min(2 * y, lh - 1), y1 = std::min(2 * y + 1, lh - 1);
                next[size_t(y) * size_t(nw) + size_t(x)] =
                    0.25f * (level[size_t(y0) * size_t(lw) + size_t(x0)] + level[size_t(y0) * size_t(lw) + size_t(x1)] +
                             level[size_t(y1) * size_t(lw) + size_t(x0)] + level[size_t(y1) * size_t(lw) + size_t(x1)]);
            }
        level = std::move(next);
        lw = nw;
        lh = nh;
    }
    t.info.w |= (wrap & 15u) << 8;  // TEXTURE_WRAP_* of u (bits 8-9) and v (10-11)
    out->textures.push_back(t);
    return true;
}

namespace {

// One texel coordinate of an axis of n texels, wrapped by mode (bsdf/texture.glsl textureWrapCoord).
int wrapCoord(int x, int n, std::uint32_t mode) {
    if (mode == TEXTURE_WRAP_CLAMP) return std::clamp(x, 0, n - 1);
    if (mode == TEXTURE_WRAP_MIRROR) {
        const int p = ((x % (2 * n)) + 2 * n) % (2 * n);
        return p < n ? p : 2 * n - 1 - p;
    }
    return ((x % n) + n) % n;
}

}  // namespace

glm::vec4 sampleTextureLevel0(const CompiledScene& c, std::uint32_t index, glm::vec2 uv) {
    if (index >= c.textures.size()) return glm::vec4(1.0f);
    const glm::uvec4 info = c.textures[index].info;
    const int w = int(info.y), h = int(info.z);
    const std::uint32_t wrapU = (info.w >> 8) & 3u, wrapV = (info.w >> 10) & 3u;
    if (w <= 0 || h <= 0 || size_t(info.x) + size_t(w) * size_t(h) > c.texels.size()) return glm::vec4(1.0f);
    const auto texel = [&](int x, int y) {
        const int px = wrapCoord(x, w, wrapU), py = wrapCoord(y, h, wrapV);
        const glm::uvec2 t = c.texels[info.x + size_t(py) * size_t(w) + size_t(px)];
        return glm::vec4(glm::unpackHalf2x16(t.x), glm::unpackHalf2x16(t.y));
    };
    // As textureBilinear: v up (the image's top row is v = 1), texel centres at half integers,
    // the integer corner reduced by the wrap's period so the modulo stays exact far from [0, 1].
    const glm::vec2 x = glm::vec2(uv.x, 1.0f - uv.y) * glm::vec2(float(w), float(h)) - 0.5f;
    const glm::vec2 x0 = glm::floor(x), t = x - x0;
    const glm::vec2 n = glm::vec2(float(w), float(h));
    const glm::vec2 period = glm::vec2(wrapU == TEXTURE_WRAP_MIRROR ? 2.0f : 1.0f, wrapV == TEXTURE_WRAP_MIRROR ? 2.0f : 1.0f) * n;
    const glm::vec2 reduced = x0 - period * glm::floor(x0 / period);   // GLSL mod
    const int i = int(wrapU == TEXTURE_WRAP_CLAMP ? std::clamp(x0.x, -1.0f, n.x) : reduced.x);
    const int j = int(wrapV == TEXTURE_WRAP_CLAMP ? std::clamp(x0.y, -1.0f, n.y) : reduced.y);
    const glm::vec4 a = texel(i, j), b = texel(i + 1, j), cc = texel(i, j + 1), d = texel(i + 1, j + 1);
    return glm::mix(glm::mix(a, b, t.x), glm::mix(cc, d, t.x), t.y);
}

bool alphaMaskKeeps(const CompiledScene& c, std::uint32_t instance, std::uint32_t slot, float u, float v) {
    if (instance >= c.instances.size()) return true;
    const gpu::GpuInstance& inst = c.instances[instance];
    if ((inst.flags & PRIM_FLAG_ALPHA_MASK) == 0u) return true;
    const std::size_t k = std::size_t(inst.firstTriangle) + slot;
    if (k >= c.triangles.size()) return true;
    const gpu::GpuTriangle& tri = c.triangles[k];
    // geometry/surface.glsl triangleMaterial and triangleUv.
    const std::uint32_t material = inst.material + (inst.fileMaterials != 0u ? std::bit_cast<std::uint32_t>(tri.p0.w) : 0u);
    if (material >= c.materials.size()) return true;
    const gpu::GpuMaterial& m = c.materials[material];
    if ((m.info.y & MAT_FLAG_ALPHA_MASK) == 0u) return true;
    float alpha = 1.0f;
    if (m.textures.x != 0u) {
        const auto uvOf = [&](std::uint32_t vertex) {
            return vertex < c.vertices.size() ? glm::vec2(c.vertices[vertex].normalU.w, c.vertices[vertex].tangentV.w)
                                              : glm::vec2(0.0f);
        };
        const glm::vec2 uv = (1.0f - u - v) * uvOf(tri.v.x) + u * uvOf(tri.v.y) + v * uvOf(tri.v.z);
        alpha = sampleTextureLevel0(c, m.textures.x - 1u, uv).a;
    }
    return alpha >= std::bit_cast<float>(m.info.z);
}

RayHit intersectVisibleMeshes(const CompiledScene& c, const Ray& ray) {
    return intersectScene(c.meshBvh, c.meshPositions, ray, std::numeric_limits<float>::infinity(),
                          [&c](std::uint32_t instance, std::uint32_t slot, float u, float v) {
                              return alphaMaskKeeps(c, instance, slot, u, v);
                          });
}

}  // namespace caustic
