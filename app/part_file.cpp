#include "app/part_file.h"

#include "renderer/scene_io.h"

#include <charconv>
#include <cmath>
#include <cinttypes>
#include <cstdio>
#include <map>

namespace caustic {
namespace {

// The channels of a part, in the order the checksum covers them: the accumulation images'
// components as the GPU holds them (film.h's Accumulators).
constexpr const char* kChannels[] = {
    "sum.R",    "sum.G",    "sum.B",    "sum.A",    "sumsq.R",  "sumsq.G",  "sumsq.B",  "albedo.R",
    "albedo.G", "albedo.B", "albedo.A", "normal.R", "normal.G", "normal.B", "normal.A",
};
constexpr int kChannelCount = sizeof kChannels / sizeof kChannels[0];

// Interleaves the sums in kChannels order.
std::vector<float> interleave(const Accumulators& a) {
    const size_t n = size_t(a.width) * a.height;
    std::vector<float> out(n * kChannelCount);
    for (size_t i = 0; i < n; ++i) {
        float* p = &out[i * kChannelCount];
        for (int c = 0; c < 4; ++c) p[c] = a.sum[i][c];
        for (int c = 0; c < 3; ++c) p[4 + c] = a.sumSq[i][c];
        for (int c = 0; c < 4; ++c) p[7 + c] = a.albedo[i][c];
        for (int c = 0; c < 4; ++c) p[11 + c] = a.normal[i][c];
    }
    return out;
}

std::string cropText(const PixelRect& r) {
    return std::to_string(r.x0) + ":" + std::to_string(r.x1) + "," + std::to_string(r.y0) + ":" + std::to_string(r.y1);
}

template <class T>
bool parseNumber(const std::string& s, T* out) {
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), *out);
    return ec == std::errc() && ptr == s.data() + s.size();
}

}  // namespace

std::string fnv1a64Hex(const void* data, std::size_t size) {
    std::uint64_t h = 0xcbf29ce484222325ull;   // FNV-1a's 64-bit offset basis and prime
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016" PRIx64, h);
    return buf;
}

std::string renderIdentityHash(const Scene& scene, const std::string& strategy) {
    Scene s = scene;
    s.render.samples = 0;   // parts of one render differ in samples; the range says which
    const std::string text = sceneToJson(s) + "\nstrategy=" + strategy + "\nversion=" + CAUSTIC_VERSION;
    return fnv1a64Hex(text.data(), text.size());
}

std::string partFileName(const std::string& stem, const PartInfo& i) {
    return stem + ".part-s" + std::to_string(i.sample0) + "-" + std::to_string(i.sample1) + "-x" +
           std::to_string(i.crop.x0) + "-" + std::to_string(i.crop.x1) + "-y" + std::to_string(i.crop.y0) + "-" +
           std::to_string(i.crop.y1) + ".exr";
}

bool writePart(const std::string& path, const Part& part, std::string* error) {
    const PartInfo& i = part.info;
    const std::vector<float> pixels = interleave(part.sums);
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.6f", i.seconds);
    const ImageMetadata meta = {
        {"Software", std::string("caustic ") + CAUSTIC_VERSION},
        {"caustic:part", kPartFormat},
        {"caustic:scene", i.scene},
        {"caustic:render_hash", i.renderHash},
        {"caustic:version", i.version},
        {"caustic:variant", i.variant},
        {"caustic:seed", std::to_string(i.seed)},
        {"caustic:image_size", std::to_string(i.width) + "x" + std::to_string(i.height)},
        {"caustic:sample_range", std::to_string(i.sample0) + ":" + std::to_string(i.sample1)},
        {"caustic:crop", cropText(i.crop)},
        {"caustic:render_seconds", seconds},
        {"caustic:dropped", std::to_string(i.dropped)},
        {"caustic:checksum", fnv1a64Hex(pixels.data(), pixels.size() * sizeof(float))},
    };
    std::vector<std::string> names(std::begin(kChannels), std::end(kChannels));
    return writeExrChannels(path, part.sums.width, part.sums.height, names, pixels, meta, error);
}

bool readPart(const std::string& path, Part* out, std::string* error, bool withPixels) {
    ChannelImage image;
    if (!readChannelImage(path, &image, error, withPixels)) return false;
    std::map<std::string, std::string> meta(image.metadata.begin(), image.metadata.end());
    auto field = [&](const char* key, std::string* value) {
        const auto it = meta.find(key);
        if (it == meta.end()) {
            *error = path + ": not a caustic part file (no " + key + " in its metadata)";
            return false;
        }
        *value = it->second;
        return true;
    };
    std::string format, size, range, crop, seed, seconds, dropped, checksum;
    if (!field("caustic:part", &format)) return false;
    if (format != kPartFormat) {
        *error = path + ": part format '" + format + "', this caustic reads '" + kPartFormat + "'";
        return false;
    }
    PartInfo& i = out->info;
    if (!field("caustic:scene", &i.scene) || !field("caustic:render_hash", &i.renderHash) ||
        !field("caustic:version", &i.version) || !field("caustic:seed", &seed) || !field("caustic:image_size", &size) ||
        !field("caustic:sample_range", &range) || !field("caustic:crop", &crop) ||
        !field("caustic:render_seconds", &seconds) || !field("caustic:dropped", &dropped) ||
        !field("caustic:checksum", &checksum))
        return false;
    if (auto it = meta.find("caustic:variant"); it != meta.end()) i.variant = it->second;
    auto bad = [&](const char* key, const std::string& value) {
        *error = path + ": metadata " + key + " = '" + value + "' is not valid";
        return false;
    };
    auto split = [](const std::string& s, char sep, std::string* a, std::string* b) {
        const auto at = s.find(sep);
        if (at == std::string::npos) return false;
        *a = s.substr(0, at);
        *b = s.substr(at + 1);
        return true;
    };
    std::string a, b, xs, ys, x0, x1, y0, y1;
    if (!parseNumber(seed, &i.seed)) return bad("caustic:seed", seed);
    // No render is larger than kMaxRenderSide a side (the scene's limit), so no part of one is.
    if (!split(size, 'x', &a, &b) || !parseNumber(a, &i.width) || !parseNumber(b, &i.height) || i.width <= 0 ||
        i.height <= 0 || i.width > kMaxRenderSide || i.height > kMaxRenderSide)
        return bad("caustic:image_size", size);
    if (!split(range, ':', &a, &b) || !parseNumber(a, &i.sample0) || !parseNumber(b, &i.sample1) ||
        i.sample0 >= i.sample1)
        return bad("caustic:sample_range", range);
    if (!split(crop, ',', &xs, &ys) || !split(xs, ':', &x0, &x1) || !split(ys, ':', &y0, &y1) ||
        !parseNumber(x0, &i.crop.x0) || !parseNumber(x1, &i.crop.x1) || !parseNumber(y0, &i.crop.y0) ||
        !parseNumber(y1, &i.crop.y1) || i.crop.x0 < 0 || i.crop.y0 < 0 || i.crop.x0 >= i.crop.x1 ||
        i.crop.y0 >= i.crop.y1 || i.crop.x1 > i.width || i.crop.y1 > i.height)
        return bad("caustic:crop", crop);
    if (!parseNumber(dropped, &i.dropped)) return bad("caustic:dropped", dropped);
    // A number of seconds, as writePart writes it ("0.250000"): not "nan", "inf", negative or text.
    if (!parseNumber(seconds, &i.seconds) || !std::isfinite(i.seconds) || i.seconds < 0.0)
        return bad("caustic:render_seconds", seconds);
    const int w = i.crop.x1 - i.crop.x0, h = i.crop.y1 - i.crop.y0;
    if (image.width != w || image.height != h) {
        *error = path + ": holds " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                 " pixels, its crop " + crop + " is " + std::to_string(w) + "x" + std::to_string(h);
        return false;
    }
    // The channels by name, in the checksum's order.
    const size_t channels = image.names.size();
    int column[kChannelCount];
    for (int c = 0; c < kChannelCount; ++c) {
        column[c] = -1;
        for (size_t k = 0; k < channels; ++k)
            if (image.names[k] == kChannels[c]) column[c] = int(k);
        if (column[c] < 0) {
            *error = path + ": not a caustic part file (no channel " + kChannels[c] + ")";
            return false;
        }
    }
    if (!withPixels) return true;
    const size_t n = size_t(w) * h;
    std::vector<float> pixels(n * kChannelCount);
    for (size_t p = 0; p < n; ++p)
        for (int c = 0; c < kChannelCount; ++c) pixels[p * kChannelCount + c] = image.pixels[p * channels + column[c]];
    if (fnv1a64Hex(pixels.data(), pixels.size() * sizeof(float)) != checksum) {
        *error = path + ": damaged: its pixels do not match the checksum in its metadata";
        return false;
    }
    // Sums caustic writes are finite (a sample that is not is dropped and counted instead), and the
    // counts and sums of squares are not negative: anything else was made by something else.
    for (size_t p = 0; p < n; ++p)
        for (int c = 0; c < kChannelCount; ++c) {
            const float v = pixels[p * kChannelCount + c];
            const bool nonNegative = c <= 10 || c == 14;  // all but the normals' sums
            if (!std::isfinite(v) || (nonNegative && v < 0.0f)) {
                *error = path + ": pixel (" + std::to_string(i.crop.x0 + int(p % size_t(w))) + ", " +
                         std::to_string(i.crop.y0 + int(p / size_t(w))) + ") channel " + kChannels[c] + " is " +
                         std::to_string(v) + ", which no render writes: the part is damaged or not caustic's";
                return false;
            }
        }
    Accumulators& s = out->sums;
    s.width = w;
    s.height = h;
    s.sum.assign(n, glm::vec4(0.0f));
    s.sumSq.assign(n, glm::vec4(0.0f));
    s.albedo.assign(n, glm::vec4(0.0f));
    s.normal.assign(n, glm::vec4(0.0f));
    for (size_t p = 0; p < n; ++p) {
        const float* v = &pixels[p * kChannelCount];
        s.sum[p] = glm::vec4(v[0], v[1], v[2], v[3]);
        s.sumSq[p] = glm::vec4(v[4], v[5], v[6], 0.0f);
        s.albedo[p] = glm::vec4(v[7], v[8], v[9], v[10]);
        s.normal[p] = glm::vec4(v[11], v[12], v[13], v[14]);
    }
    return true;
}

}  // namespace caustic
