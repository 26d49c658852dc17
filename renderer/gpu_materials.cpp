// Scene materials as the GPU sees them: the conductor presets, convertMaterial, the mapping of
// a model file's materials (glTF metallic-roughness included) and the GGX albedo table.
#include "renderer/gpu_scene.h"

#include "renderer/gpu_materials.h"
#include "renderer/mesh_import.h"
#include "renderer/scene_schema.h"

#include <glm/gtc/packing.hpp>

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

GpuMediumRows gpuMedium(glm::vec3 sigmaA, glm::vec3 sigmaS, float anisotropy) {
    const glm::vec3 most(static_cast<float>(kMaxCoefficient));
    return {glm::vec4(glm::clamp(sigmaA, glm::vec3(0.0f), most), std::clamp(anisotropy, -0.999f, 0.999f)),
            glm::vec4(glm::clamp(sigmaS, glm::vec3(0.0f), most), 0.0f)};
}

// An interior medium in the material's k and eta rows (shared/layout.h: k.rgb sigma_a, eta.rgb
// sigma_s, eta.w g); a vacuum sets nothing.
static void setMedium(gpu::GpuMaterial& g, std::uint32_t& flags, glm::vec3 sigmaA, glm::vec3 sigmaS, float anisotropy) {
    const GpuMediumRows rows = gpuMedium(sigmaA, sigmaS, anisotropy);
    if (rows.vacuum()) return;
    g.k = glm::vec4(glm::vec3(rows.a), 0);
    g.eta = glm::vec4(glm::vec3(rows.s), rows.a.w);
    flags |= MAT_FLAG_MEDIUM;
}

// The interior medium of OpenPBR Surface 1.1's transmission ("Transmission"): extinction sigma_t =
// -ln(transmission_color) / transmission_depth, scattering sigma_s = transmission_scatter / depth,
// absorption sigma_a = sigma_t - sigma_s raised by a grey amount where a channel would be negative
// (the extinction is then sigma_a + sigma_s). Depth 0 (or a white colour without scatter): none,
// the flag stays clear and the interior is clear.
static void setTransmissionMedium(gpu::GpuMaterial& g, std::uint32_t& flags, const Material& m) {
    if (!(m.transmissionDepth > 0.0f)) return;
    const glm::vec3 c = glm::clamp(m.transmissionColor, glm::vec3(1e-6f), glm::vec3(1.0f));
    const glm::vec3 sigmaT = -glm::log(c) / m.transmissionDepth;
    const glm::vec3 sigmaS = glm::max(m.transmissionScatter, glm::vec3(0.0f)) / m.transmissionDepth;
    glm::vec3 sigmaA = sigmaT - sigmaS;
    const float lowest = std::min({sigmaA.x, sigmaA.y, sigmaA.z});
    if (lowest < 0.0f) sigmaA -= lowest;
    setMedium(g, flags, sigmaA, sigmaS, m.scatterAnisotropy);
}

float subsurfaceSingleScatteringAlbedo(float multiple, float g) {
    // van de Hulst's relation for a semi-infinite medium (H. C. van de Hulst, "Multiple Light
    // Scattering", 1980; the similarity parameter s = sqrt((1 - alpha) / (1 - alpha g))):
    //   A = (1 - s)(1 - 0.139 s) / (1 + 1.17 s)
    // solved for s (the root in [0, 1] of 0.139 s^2 - (1.139 + 1.17 A) s + 1 - A = 0), then alpha.
    const double a = std::clamp(double(multiple), 0.0, 1.0);
    const double b = 1.139 + 1.17 * a;
    const double s = (b - std::sqrt(std::max(b * b - 4.0 * 0.139 * (1.0 - a), 0.0))) / (2.0 * 0.139);
    const double s2 = std::clamp(s, 0.0, 1.0) * std::clamp(s, 0.0, 1.0);
    const double gg = std::clamp(double(g), -0.999, 0.999);
    return float((1.0 - s2) / (1.0 - s2 * gg));
}

std::vector<gpu::GpuMaterial> surfaceParts(const Material& m) {
    std::vector<gpu::GpuMaterial> parts;
    if (m.type != MaterialType::Surface) return parts;
    const float T = std::clamp(m.transmissionWeight, 0.0f, 1.0f), S = std::clamp(m.subsurfaceWeight, 0.0f, 1.0f);
    const float w = T + (1.0f - T) * S;
    if (!(w > 0.0f)) return parts;
    const float ior = std::clamp(m.specularIor, 1.0f, 3.0f);
    const float alpha = m.specularRoughness * m.specularRoughness;
    // The interface: rough where the surface's specular is (or may be, with a roughness texture),
    // except at IOR 1, where nothing bends and the straight-through pair has no half vector.
    const bool rough = (alpha >= kSmoothAlpha || !m.roughnessTexture.empty()) && ior != 1.0f;
    auto interface = [&](std::uint32_t flags) {
        gpu::GpuMaterial g{};
        g.albedo = glm::vec4(1.0f);
        g.params = glm::vec4(alpha, ior, 0, 0);
        g.sheen = glm::vec4(1.0f);  // the crossing tint (surface_parts.glsl)
        g.info = glm::uvec4(rough ? MAT_ROUGH_DIELECTRIC : MAT_DIELECTRIC, flags, 0u,
                            std::uint32_t(std::clamp(m.priority, 0, 1000)));
        return g;
    };
    if (T > 0.0f) {
        gpu::GpuMaterial g;
        if (m.thinWalled) {
            g = gpu::GpuMaterial{};
            g.albedo = glm::vec4(glm::clamp(m.transmissionColor, glm::vec3(0.0f), glm::vec3(1.0f)), 0);
            g.params = glm::vec4(alpha, ior, 0, 0);
            g.sheen = glm::vec4(1.0f);
            g.info = glm::uvec4(MAT_THIN_DIELECTRIC, 0u, 0u, 0u);
        } else {
            std::uint32_t flags = 0;
            g = interface(0);
            setTransmissionMedium(g, flags, m);
            g.info.y = flags;
            if (!(m.transmissionDepth > 0.0f)) g.sheen = glm::vec4(glm::clamp(m.transmissionColor, glm::vec3(0.0f), glm::vec3(1.0f)), 1);
        }
        parts.push_back(g);
    }
    if (S > 0.0f && T < 1.0f) {
        gpu::GpuMaterial g;
        const glm::vec3 colour = glm::clamp(m.subsurfaceColor, glm::vec3(0.0f), glm::vec3(1.0f));
        if (m.thinWalled) {
            // Diffuse transmission: the colour split between the two sides, (1 + g) / 2 of it
            // passing through (half for isotropic scattering), under the specular layer.
            const float through = 0.5f * (1.0f + std::clamp(m.subsurfaceAnisotropy, -1.0f, 1.0f));
            g = gpu::GpuMaterial{};
            g.albedo = glm::vec4(colour * (1.0f - through), 0);
            g.eta = glm::vec4(colour * through, 0);
            // Under the surface's specular layer (its weight, roughness and IOR; bsdf/thin.glsl).
            g.params = glm::vec4(alpha, ior, 0, 0);
            g.k = glm::vec4(std::clamp(m.specularWeight, 0.0f, 1.0f), 0, 0, 0);
            g.sheen = glm::vec4(1.0f);
            g.info = glm::uvec4(MAT_DIFFUSE_TRANSMISSION, 0u, 0u, 0u);
        } else {
            // The walked interior: sigma_t = 1 / mean free path per channel, the single-scattering
            // albedo from the colour (subsurfaceSingleScatteringAlbedo).
            std::uint32_t flags = MAT_FLAG_RANDOM_WALK;
            g = interface(0);
            const glm::vec3 mfp = glm::max(m.subsurfaceRadius * m.subsurfaceRadiusScale, glm::vec3(1e-30f));
            const glm::vec3 sigmaT = 1.0f / mfp;
            glm::vec3 albedo;
            for (int c = 0; c < 3; ++c) albedo[c] = subsurfaceSingleScatteringAlbedo(colour[c], m.subsurfaceAnisotropy);
            setMedium(g, flags, sigmaT * (1.0f - albedo), sigmaT * albedo, m.subsurfaceAnisotropy);
            g.info.y = flags;
        }
        parts.push_back(g);
    }
    // The first part carries the shares (surface_parts.glsl): w and the transmission's share of w.
    parts.front().params.z = w;
    parts.front().params.w = T / w;
    return parts;
}

void linkSurfaceParts(gpu::GpuMaterial& g, const Material& m, std::uint32_t first) {
    g.info.w = first;
    if (m.transmissionWeight > 0.0f) g.info.y |= MAT_FLAG_TRANSMISSION_PART;
    if (m.subsurfaceWeight > 0.0f && m.transmissionWeight < 1.0f) g.info.y |= MAT_FLAG_SUBSURFACE_PART;
}

gpu::GpuMaterial convertMaterial(const Material& m) {
    gpu::GpuMaterial g{};
    g.emission = glm::vec4(m.emission, m.normalScale);  // w: the normal map's scale (material.glsl)
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
        setTransmissionMedium(g, flags, m);
        break;
    case MaterialType::Volume:
        // An index-matched boundary: no surface, only the medium inside (integrator/medium.glsl).
        type = MAT_VOLUME;
        setMedium(g, flags, m.sigmaA, m.sigmaS, m.scatterAnisotropy);
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
    case MaterialType::Surface: {
        // shaders/bsdf/surface.glsl's header says which member holds what; roughnesses become
        // GGX alphas here (perceptual^2; the sheen's Charlie r likewise, as KHR_materials_sheen
        // defines it), the sheen's colour is times its weight.
        type = MAT_SURFACE;
        const float clampedIor = std::clamp(m.specularIor, 1.0f, 3.0f);
        g.albedo = glm::vec4(m.albedo, std::clamp(m.metalness, 0.0f, 1.0f));
        g.params = glm::vec4(m.specularRoughness * m.specularRoughness, clampedIor,
                             std::clamp(m.specularWeight, 0.0f, 1.0f), std::clamp(m.coatWeight, 0.0f, 1.0f));
        g.eta = glm::vec4(m.specularColor, m.coatRoughness * m.coatRoughness);
        g.k = glm::vec4(m.coatColor, std::clamp(m.coatIor, 1.0f, 3.0f));
        g.sheen = glm::vec4(m.sheenColor * std::clamp(m.sheenWeight, 0.0f, 1.0f), m.sheenRoughness * m.sheenRoughness);
        break;
    }
    }
    std::uint32_t cutoff = 0;
    if (m.alphaMode == AlphaMode::Mask) {
        flags |= MAT_FLAG_ALPHA_MASK;
        cutoff = std::bit_cast<std::uint32_t>(std::max(m.alphaCutoff, 0.0f));
    }
    // w: the nesting priority (dielectrics and volumes; integrator/medium.glsl).
    const bool nests = m.type == MaterialType::Dielectric || m.type == MaterialType::Volume;
    g.info = glm::uvec4(type, flags, cutoff, nests ? std::uint32_t(std::clamp(m.priority, 0, 1000)) : 0u);
    return g;
}

std::span<const Material> materialPresets() {
    static const std::vector<Material> presets = [] {
        auto surface = [](const char* name, glm::vec3 base) {
            Material m = materialDefaults(MaterialType::Surface);
            m.name = name;
            m.albedo = base;
            return m;
        };
        Material plastic = surface("plastic", {0.70f, 0.06f, 0.05f});
        plastic.specularRoughness = 0.25f;
        Material wood = surface("varnished wood", {0.30f, 0.14f, 0.06f});
        wood.specularRoughness = 0.7f;  // the raw wood under the varnish
        wood.coatWeight = 1.0f;
        wood.coatRoughness = 0.08f;
        wood.coatIor = 1.5f;
        wood.coatColor = {0.95f, 0.82f, 0.60f};  // an amber varnish
        Material paint = surface("car paint", {0.55f, 0.03f, 0.04f});
        paint.metalness = 1.0f;  // metallic flakes, smoothed into a rough metal
        paint.specularRoughness = 0.45f;
        paint.specularColor = {1.0f, 0.6f, 0.6f};
        paint.coatWeight = 1.0f;
        paint.coatRoughness = 0.03f;
        Material velvet = surface("velvet", {0.20f, 0.02f, 0.06f});
        velvet.specularWeight = 0.2f;
        velvet.specularRoughness = 0.8f;
        velvet.sheenWeight = 1.0f;
        velvet.sheenColor = {0.85f, 0.35f, 0.55f};
        velvet.sheenRoughness = 0.45f;
        return std::vector<Material>{plastic, wood, paint, velvet};
    }();
    return presets;
}

Material mapImportedMaterial(const ImportedMaterial& in, std::vector<std::string>* unmapped,
                             const MetallicRoughnessMap* mr) {
    Material m;
    m.name = in.name;
    m.emission = glm::max(in.emission, glm::vec3(0.0f));
    const glm::vec3 base = glm::clamp(in.baseColor, glm::vec3(0.0f), glm::vec3(1.0f));
    const std::string who = "material '" + in.name + "': ";
    const float roughness = std::clamp(in.roughness, 0.0f, 1.0f);  // perceptual, as glTF's
    // The layered surface, by the glTF-to-OpenPBR correspondence (OpenPBR Surface 1.1, appendix
    // "glTF PBR"): base colour, metalness (per texel with a metallic-roughness texture: mr, wired by
    // compileScene), roughness (perceptual in both), KHR_materials_ior, _specular (factor ->
    // specular_weight, colour -> specular_color), _clearcoat (ior 1.5, as the extension defines;
    // white), _sheen (colour, roughness; weight 1 where the colour is not black), _transmission
    // (transmission_weight), _volume (closed, its attenuation the interior's; without it, or with
    // thickness 0, thin-walled), _diffuse_transmission (thin-walled: the subsurface, all of it
    // passing through).
    m = materialDefaults(MaterialType::Surface);
    m.name = in.name;
    m.emission = glm::max(in.emission, glm::vec3(0.0f));
    m.albedo = base;
    m.metalness = std::clamp(in.metallic, 0.0f, 1.0f);
    m.specularRoughness = roughness;
    m.specularIor = std::clamp(in.ior, 1.0f, 3.0f);
    if (in.ior > 3.0f) unmapped->push_back(who + "ior " + std::to_string(in.ior) + " clamped to 3");
    m.specularWeight = std::clamp(in.specular, 0.0f, 1.0f);
    m.specularColor = glm::clamp(in.specularColor, glm::vec3(0.0f), glm::vec3(1.0f));
    m.coatWeight = std::clamp(in.clearcoat, 0.0f, 1.0f);
    m.coatRoughness = std::clamp(in.clearcoatRoughness, 0.0f, 1.0f);
    m.coatIor = 1.5f;
    m.sheenColor = glm::clamp(in.sheenColor, glm::vec3(0.0f), glm::vec3(1.0f));
    m.sheenWeight = glm::any(glm::greaterThan(m.sheenColor, glm::vec3(0.0f))) ? 1.0f : 0.0f;
    m.sheenRoughness = std::clamp(in.sheenRoughness, 0.0f, 1.0f);
    // The roughness slot holds the baked texture (roughness in R, metalness in G).
    if (!in.metallicRoughnessTexture.empty()) m.roughnessTexture = in.metallicRoughnessTexture;
    (void)mr;
    const bool attenuates =
        in.attenuationDistance > 0.0f && glm::any(glm::lessThan(in.attenuationColor, glm::vec3(1.0f)));
    m.thinWalled = !in.volume && (in.transmission > 0.0f || in.diffuseTransmission > 0.0f);
    m.transmissionWeight = std::clamp(in.transmission, 0.0f, 1.0f);
    if (m.transmissionWeight > 0.0f) {
        // glTF tints the transmission by the base colour (at each refraction: transmission_color at
        // depth 0); KHR_materials_volume's attenuation is OpenPBR's transmission_color at
        // transmission_depth (the distance in the file's world units, taken as scene units: an
        // object's scale does not scale it; a black channel would be an infinite coefficient: at
        // least 1e-4). The two cannot both be the one colour: the attenuation wins, reported.
        m.transmissionColor = base;
        if (in.volume && attenuates) {
            m.transmissionColor = glm::clamp(in.attenuationColor, glm::vec3(1e-4f), glm::vec3(1.0f));
            m.transmissionDepth = in.attenuationDistance;
            if (glm::any(glm::lessThan(base, glm::vec3(1.0f))))
                unmapped->push_back(who + "the base colour's tint of the transmission is not mapped beside "
                                          "KHR_materials_volume's attenuation");
        }
    } else if (attenuates) {
        unmapped->push_back(who + "KHR_materials_volume's attenuation without transmission is not mapped (no light "
                                  "enters the interior)");
    }
    if (in.diffuseTransmission > 0.0f) {
        if (m.thinWalled) {
            m.subsurfaceWeight = std::clamp(in.diffuseTransmission, 0.0f, 1.0f);
            m.subsurfaceColor = glm::clamp(in.diffuseTransmissionColor, glm::vec3(0.0f), glm::vec3(1.0f));
            m.subsurfaceAnisotropy = 0.999f;  // glTF's lobe only transmits: (1 + g) / 2 of it passes
        } else {
            unmapped->push_back(who + "KHR_materials_diffuse_transmission of a closed object (with "
                                      "KHR_materials_volume) is not mapped");
        }
    }
    if (!in.baseColorTexture.empty()) m.albedoTexture = in.baseColorTexture;
    if (!in.normalTexture.empty()) {
        m.normalTexture = in.normalTexture;
        m.normalScale = std::max(in.normalScale, 0.0f);
    }
    // glTF's emissiveTexture: times the emissive factor (x KHR_materials_emissive_strength).
    if (!in.emissionTexture.empty()) m.emissionTexture = in.emissionTexture;
    // alphaMode MASK (and BLEND, approximated by the importer as a mask): a point is cut out where
    // the base colour's alpha, texture alpha x factor alpha, is below the cutoff, i.e. where the
    // texture's alpha is below cutoff / factor (glTF 2.0 section 3.9.5).
    if (in.alphaMode != 0) {
        m.alphaMode = AlphaMode::Mask;
        const float factor = std::clamp(in.opacity, 0.0f, 1.0f);
        // Above 1 every point is cut (alpha <= 1): 2 stands for that, and keeps a tiny factor finite.
        m.alphaCutoff = factor > 0.0f ? std::min(std::max(in.alphaCutoff, 0.0f) / factor, 2.0f) : 2.0f;
    } else if (in.opacity < 1.0f) {
        unmapped->push_back(who + "opacity " + std::to_string(in.opacity) + " not mapped (opaque)");
    }
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
    m.texture.width = w;
    m.texture.height = h;
    m.texture.channels = 3;  // R roughness, G metalness, B unused (addTexture keeps RGB as it is)
    const size_t n = size_t(w) * size_t(h);
    m.texture.pixels.assign(3 * n, 0.0f);
    m.metalMin = 1.0f;
    m.metalMax = 0.0f;
    double sum = 0.0;
    size_t metal = 0;
    for (size_t i = 0; i < n; ++i) {
        const float* px = &image.pixels[i * size_t(ch)];
        if (!std::isfinite(px[g]) || !std::isfinite(px[b])) {
            *error = "non-finite pixel at (" + std::to_string(i % size_t(w)) + ", " + std::to_string(i / size_t(w)) + ")";
            return false;
        }
        m.texture.pixels[3 * i] = rf * std::clamp(px[g], 0.0f, 1.0f);
        const float mt = mf * std::clamp(px[b], 0.0f, 1.0f);
        m.texture.pixels[3 * i + 1] = mt;
        m.metalMin = std::min(m.metalMin, mt);
        m.metalMax = std::max(m.metalMax, mt);
        sum += mt;
        metal += mt > 0.5f ? 1 : 0;
    }
    m.metalMean = float(sum / double(n));
    m.metalFraction = float(double(metal) / double(n));
    *out = std::move(m);
    return true;
}

}  // namespace caustic
