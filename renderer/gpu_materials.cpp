// Scene materials as the GPU sees them: the conductor presets, convertMaterial, the mapping of
// a model file's materials (glTF metallic-roughness included) and the GGX albedo table.
#include "renderer/gpu_scene.h"

#include "renderer/gpu_materials.h"
#include "renderer/mesh_import.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <utility>

namespace caustic {

namespace {
constexpr float kPi = std::numbers::pi_v<float>;
}  // namespace

// Complex IOR (eta, k) of the conductor presets at R, G, B. Gold, copper and aluminium are the
// values the materials issue specifies (spectral data integrated to RGB); silver, chromium and
// platinum are from the LabPBR 1.3 material standard's table of hardcoded metals (whose gold and
// copper agree with the values here to 3 digits). "perfect" is F = 1 (a flag, not an IOR).
std::pair<glm::vec3, glm::vec3> conductorPreset(const Material& m) {
    switch (m.metal) {
    case Metal::Gold: return {{0.183f, 0.421f, 1.373f}, {3.424f, 2.346f, 1.770f}};
    case Metal::Copper: return {{0.271f, 0.677f, 1.316f}, {3.609f, 2.625f, 2.292f}};
    case Metal::Aluminium: return {{1.655f, 0.879f, 0.520f}, {9.224f, 6.270f, 4.837f}};
    case Metal::Silver: return {{0.15943f, 0.14512f, 0.13547f}, {3.9291f, 3.1900f, 2.3808f}};
    case Metal::Chromium: return {{3.1071f, 3.1812f, 2.3230f}, {3.3314f, 3.3291f, 3.1350f}};
    case Metal::Platinum: return {{2.3757f, 2.0847f, 1.8453f}, {4.2655f, 3.7153f, 3.1365f}};
    case Metal::Perfect: return {{1.0f, 1.0f, 1.0f}, {0.0f, 0.0f, 0.0f}};
    case Metal::Custom: break;
    }
    return {m.eta, m.k};
}

// Below this GGX alpha the smooth (delta) model is used: the microfacet lobe is then narrower
// than float precision resolves well (pbrt-v4's EffectivelySmooth uses the same threshold).
constexpr float kSmoothAlpha = 1e-3f;

gpu::GpuMaterial convertMaterial(const Material& m) {
    gpu::GpuMaterial g{};
    g.emission = glm::vec4(m.emission, 0);
    g.albedo = glm::vec4(m.tint, 0);
    g.params = glm::vec4(m.roughness, m.ior, 0, 0);
    std::uint32_t type = MAT_DIFFUSE, flags = 0;
    switch (m.type) {
    case MaterialType::Diffuse: g.albedo = glm::vec4(m.albedo, 0); break;
    case MaterialType::OrenNayar:
        type = MAT_OREN_NAYAR;
        g.albedo = glm::vec4(m.albedo, 0);
        g.params.x = m.sigma;
        if (m.energyCompensation) flags |= MAT_FLAG_ENERGY_COMPENSATION;
        break;
    case MaterialType::Eon:
        type = MAT_EON;
        g.albedo = glm::vec4(m.albedo, 0);
        break;
    case MaterialType::Mirror: type = MAT_MIRROR; break;
    case MaterialType::Transmission:
        // Rough: the GGX BTDF alone. At IOR 1 nothing bends, so it stays the delta pass-through
        // (the half vector of a straight-through pair is undefined; pbrt-v4 does the same).
        if ((m.roughness >= kSmoothAlpha || !m.roughnessTexture.empty()) && m.ior != 1.0f) {
            type = MAT_ROUGH_DIELECTRIC;
            flags |= MAT_FLAG_NO_REFLECTION;
        } else {
            type = MAT_TRANSMISSION;
        }
        break;
    case MaterialType::Dielectric:
        // A roughness map can make any point rough, so a textured dielectric is always rough.
        type = m.roughness < kSmoothAlpha && m.roughnessTexture.empty() ? MAT_DIELECTRIC : MAT_ROUGH_DIELECTRIC;
        break;
    case MaterialType::Conductor: {
        type = m.roughness < kSmoothAlpha && m.roughnessTexture.empty() ? MAT_CONDUCTOR : MAT_ROUGH_CONDUCTOR;
        auto [eta, k] = conductorPreset(m);
        g.eta = glm::vec4(eta, 0);
        g.k = glm::vec4(k, 0);
        if (m.metal == Metal::Perfect) flags |= MAT_FLAG_FRESNEL_ONE;
        if (m.energyCompensation) flags |= MAT_FLAG_ENERGY_COMPENSATION;
        break;
    }
    }
    g.info = glm::uvec4(type, flags, 0, 0);
    return g;
}

Material mapImportedMaterial(const ImportedMaterial& in, std::vector<std::string>* unmapped,
                             const MetallicRoughnessMap* mr) {
    Material m;
    m.name = in.name;
    m.emission = glm::max(in.emission, glm::vec3(0.0f));
    const float alpha = std::clamp(in.roughness * in.roughness, 0.0f, 1.0f);  // glTF roughness is perceptual
    const glm::vec3 base = glm::clamp(in.baseColor, glm::vec3(0.0f), glm::vec3(1.0f));
    const std::string who = "material '" + in.name + "': ";
    // A texture not yet read (mr null): map by the factors, and leave the reports to the mapping
    // that reads it. An embedded one ('*N') is never read: the factors it is.
    const bool packed = !in.metallicRoughnessTexture.empty() && in.metallicRoughnessTexture[0] != '*';
    const bool provisional = packed && !mr;
    std::vector<std::string> ignored;
    if (provisional) unmapped = &ignored;
    // Metalness: the factor, or where most of the texture's texels lie (glTF multiplies the two).
    float metallic = in.metallic;
    if (mr) {
        metallic = mr->metalFraction > 0.5f ? 1.0f : 0.0f;
        if (mr->metalMin <= 0.5f && mr->metalMax > 0.5f) {
            char pct[32];
            std::snprintf(pct, sizeof pct, "%.1f%%", 100.0 * double(mr->metalFraction));
            unmapped->push_back(who + "metalness varies over its metallic-roughness texture (" + pct +
                                " of texels above 0.5): mapped as " +
                                (metallic > 0.5f ? "a conductor" : "a non-metal") +
                                " throughout (a per-texel blend needs a layered material)");
        } else {
            metallic = mr->metalMean;  // uniform on one side of 0.5: rounded (and reported) below
        }
    }
    if (in.transmission > 0.5f) {
        m.type = MaterialType::Dielectric;
        m.ior = in.ior;
        m.roughness = alpha;
        m.tint = base;
    } else if (metallic > 0.5f) {
        // Gulbrandsen 2014, "Artist Friendly Metallic Fresnel", JCGT 3(4), eqs. 6-7, with the
        // reflectivity r and the edge tint g both the base colour.
        m.type = MaterialType::Conductor;
        m.metal = Metal::Custom;
        m.roughness = alpha;
        for (int c = 0; c < 3; ++c) {
            const float r = std::clamp(base[c], 0.0f, 0.99f), g = r;
            const float sr = std::sqrt(r);
            const float n = g * (1.0f - r) / (1.0f + r) + (1.0f - g) * (1.0f + sr) / (1.0f - sr);
            const float k2 = (r * (n + 1.0f) * (n + 1.0f) - (n - 1.0f) * (n - 1.0f)) / (1.0f - r);
            m.eta[c] = std::max(n, 1e-3f);
            m.k[c] = std::sqrt(std::max(k2, 0.0f));
        }
        if (metallic < 0.99f) unmapped->push_back(who + "metallic " + std::to_string(metallic) + " rounded to 1");
    } else {
        m.type = MaterialType::Diffuse;
        m.albedo = base;
        if (metallic > 0.01f) unmapped->push_back(who + "metallic " + std::to_string(metallic) + " rounded to 0");
        unmapped->push_back(who + "the specular reflection of a non-metal is not modelled (diffuse only)");
    }
    if (in.transmission > 0.0f && in.transmission <= 0.5f)
        unmapped->push_back(who + "transmission " + std::to_string(in.transmission) + " rounded to 0");
    if (!in.baseColorTexture.empty() && in.baseColorTexture[0] != '*') m.albedoTexture = in.baseColorTexture;
    if (!in.normalTexture.empty() && in.normalTexture[0] != '*') m.normalTexture = in.normalTexture;
    // The texture's roughness becomes a roughness map where the model has a roughness (conductor,
    // dielectric); the path marks the material rough, compileScene wires mr->alpha in its slot.
    if (mr && m.type != MaterialType::Diffuse) m.roughnessTexture = in.metallicRoughnessTexture;
    if (!in.metallicRoughnessTexture.empty() && !packed)
        unmapped->push_back(who + "embedded metallic-roughness texture not read (the factors are used)");
    if (!in.emissionTexture.empty()) unmapped->push_back(who + "emission texture not mapped (the factor is used)");
    if (in.opacity < 1.0f) unmapped->push_back(who + "opacity " + std::to_string(in.opacity) + " not mapped (opaque)");
    return m;
}

bool bakeMetallicRoughness(const ImageData& image, float roughnessFactor, float metallicFactor,
                           MetallicRoughnessMap* out, std::string* error) {
    const int w = image.width, h = image.height, ch = image.channels;
    if (w <= 0 || h <= 0 || ch <= 0 || image.pixels.size() < size_t(w) * size_t(h) * size_t(ch)) {
        *error = "empty or truncated image";
        return false;
    }
    // glTF 2.0 section 3.9.2: G is roughness, B metalness; a grey image has both in its one channel.
    const int g = ch >= 3 ? 1 : 0, b = ch >= 3 ? 2 : 0;
    const float rf = std::clamp(roughnessFactor, 0.0f, 1.0f), mf = std::clamp(metallicFactor, 0.0f, 1.0f);
    MetallicRoughnessMap m;
    m.alpha.width = w;
    m.alpha.height = h;
    m.alpha.channels = 1;
    m.alpha.pixels.resize(size_t(w) * size_t(h));
    m.metalMin = 1.0f;
    m.metalMax = 0.0f;
    double sum = 0.0;
    size_t metal = 0;
    for (size_t i = 0; i < m.alpha.pixels.size(); ++i) {
        const float* px = &image.pixels[i * size_t(ch)];
        if (!std::isfinite(px[g]) || !std::isfinite(px[b])) {
            *error = "non-finite pixel at (" + std::to_string(i % size_t(w)) + ", " + std::to_string(i / size_t(w)) + ")";
            return false;
        }
        const float r = rf * std::clamp(px[g], 0.0f, 1.0f);
        m.alpha.pixels[i] = r * r;
        const float mt = mf * std::clamp(px[b], 0.0f, 1.0f);
        m.metalMin = std::min(m.metalMin, mt);
        m.metalMax = std::max(m.metalMax, mt);
        sum += mt;
        metal += mt > 0.5f ? 1 : 0;
    }
    m.metalMean = float(sum / double(m.alpha.pixels.size()));
    m.metalFraction = float(double(metal) / double(m.alpha.pixels.size()));
    *out = std::move(m);
    return true;
}

}  // namespace caustic
