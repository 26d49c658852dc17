#include "app/outputs.h"

#include "renderer/denoise.h"
#include "renderer/tonemap.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace caustic {
namespace {

// The AOVs as images: albedo as it is (linear reflectance); the normal remapped from [-1, 1] to
// [0, 1] (files without negative values: PNG, Radiance) or as it is (EXR).
std::vector<float> flatten(const std::vector<glm::vec3>& v, bool remapSigned = false) {
    std::vector<float> out(v.size() * 3);
    for (size_t i = 0; i < v.size(); ++i)
        for (int c = 0; c < 3; ++c) out[i * 3 + c] = remapSigned ? v[i][c] * 0.5f + 0.5f : v[i][c];
    return out;
}

// 8-bit with no tone curve: linear values in [0, 1], sRGB-encoded (albedo) or stored as they are
// (the remapped normal, which is data, not colour).
std::vector<std::uint8_t> to8Bit(const std::vector<float>& v, bool srgb) {
    std::vector<std::uint8_t> out(v.size());
    for (size_t i = 0; i < v.size(); ++i) {
        const float x = std::clamp(v[i], 0.0f, 1.0f);
        out[i] = static_cast<std::uint8_t>(std::lround((srgb ? srgbEncode(x) : x) * 255.0f));
    }
    return out;
}

}  // namespace

std::string outputsNotAvailable(const CliOptions& o) {
    std::string error;
    if (o.oidn && !denoiserAvailable()) {
        denoise(Film{}, {}, nullptr, &error);
        return "--oidn: " + error;
    }
    return "";
}

bool writeOutputs(const CliOptions& o, const std::string& base, const Film& raw, ImageMetadata meta,
                  std::vector<std::uint8_t>* srgbOut, std::string* error) {
    auto wrote = [](const std::string& path) { std::cout << path << std::endl; };
    const ToneMap toneMap = o.reinhard ? ToneMap::Reinhard : ToneMap::Aces;
    const bool png = o.png || (!o.hdr && !o.exr);
    Film film = raw;  // what the files show: the denoised image with --oidn
    if (o.oidn) {
        DenoiseOptions dopt;
        dopt.useGuides = o.oidnGuides != "none";
        dopt.prefilterGuides = o.oidnGuides == "prefilter";
        DenoiseResult denoised;
        const auto t0 = std::chrono::steady_clock::now();
        if (!denoise(raw, dopt, &denoised, error)) { *error = "--oidn: " + *error; return false; }
        const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        film.mean = std::move(denoised.image);
        const std::string denoiser =
            "Open Image Denoise " + denoiserVersion() + ", filter RT, hdr, guides " +
            (dopt.useGuides ? (dopt.prefilterGuides ? "albedo+normal prefiltered" : "albedo+normal") : "none") +
            ", device " + denoised.device;
        std::fprintf(stderr, "caustic: denoised in %.2f s: %s\n", dt, denoiser.c_str());
        meta.push_back({"caustic:denoiser", denoiser});
    }
    std::vector<std::uint8_t> srgb = toSrgb8(film, toneMap, o.exposure);
    // AOV files carry the same metadata plus what they are.
    auto aovMeta = [&](const char* pass) {
        ImageMetadata m = meta;
        m.push_back({"caustic:pass", pass});
        return m;
    };
    const std::vector<float> albedo = o.aovs ? flatten(raw.albedo) : std::vector<float>{};
    const std::vector<float> normal01 = o.aovs ? flatten(raw.normal, true) : std::vector<float>{};
    if (png) {
        if (!writeImage8(base + ".png", film.width, film.height, srgb, meta, error)) return false;
        wrote(base + ".png");
        if (o.aovs) {
            if (!writeImage8(base + "-albedo.png", film.width, film.height, to8Bit(albedo, true), aovMeta("albedo"), error))
                return false;
            wrote(base + "-albedo.png");
            if (!writeImage8(base + "-normal.png", film.width, film.height, to8Bit(normal01, false), aovMeta("normal"), error))
                return false;
            wrote(base + "-normal.png");
        }
    }
    const std::vector<float> linear = toLinearRgb(film);
    if (o.hdr) {
        if (!writeImageFloat(base + ".hdr", film.width, film.height, linear, meta, error)) return false;
        wrote(base + ".hdr");
        if (o.aovs) {
            if (!writeImageFloat(base + "-albedo.hdr", film.width, film.height, albedo, aovMeta("albedo"), error))
                return false;
            wrote(base + "-albedo.hdr");
            if (!writeImageFloat(base + "-normal.hdr", film.width, film.height, normal01, aovMeta("normal"), error))
                return false;
            wrote(base + "-normal.hdr");
        }
    }
    if (o.exr) {
        // One file: R, G, B hold the final image (what viewers without layer support show);
        // with --aovs the named layers raw, denoised (with --oidn), albedo and normal follow
        // (the normal as it is, in [-1, 1]).
        std::vector<ImageLayer> layers = {{"", &linear}};
        std::vector<float> rawRgb, normal;
        if (o.aovs) {
            rawRgb = toLinearRgb(raw);
            normal = flatten(raw.normal);
            layers.push_back({"raw", &rawRgb});
            if (o.oidn) layers.push_back({"denoised", &linear});
            layers.push_back({"albedo", &albedo});
            layers.push_back({"normal", &normal});
        }
        if (!writeExrLayers(base + ".exr", film.width, film.height, layers, o.half, meta, error)) return false;
        wrote(base + ".exr");
    }
    if (srgbOut) *srgbOut = std::move(srgb);
    return true;
}

}  // namespace caustic
