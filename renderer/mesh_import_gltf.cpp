// glTF 2.0 material details from the file's own JSON (renderer/mesh_import_gltf.h).
// References: the glTF 2.0 specification (sections 3.9 materials, 3.8 samplers, 4.4 GLB), and the
// Khronos extension documents KHR_texture_transform, KHR_materials_ior, _specular, _clearcoat,
// _sheen, _transmission, _volume and _emissive_strength.
#include "renderer/mesh_import_gltf.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

namespace caustic {

namespace {

using Json = nlohmann::json;

// A number at j[key] (finite), else the fallback.
float number(const Json& j, const char* key, float fallback) {
    if (!j.is_object()) return fallback;
    const auto it = j.find(key);
    if (it == j.end() || !it->is_number()) return fallback;
    const double v = it->get<double>();
    return std::isfinite(v) ? float(v) : fallback;
}

// A vector of N numbers at j[key] (each finite one replaces the fallback's component).
template <int N>
glm::vec<N, float> numbers(const Json& j, const char* key, glm::vec<N, float> fallback) {
    if (!j.is_object()) return fallback;
    const auto it = j.find(key);
    if (it == j.end() || !it->is_array() || it->size() < size_t(N)) return fallback;
    glm::vec<N, float> c = fallback;
    for (int i = 0; i < N; ++i)
        if ((*it)[size_t(i)].is_number()) {
            const double v = (*it)[size_t(i)].get<double>();
            if (std::isfinite(v)) c[i] = float(v);
        }
    return c;
}

glm::vec3 colour(const Json& j, const char* key, glm::vec3 fallback) { return numbers<3>(j, key, fallback); }
glm::vec2 pair(const Json& j, const char* key, glm::vec2 fallback) { return numbers<2>(j, key, fallback); }

const Json& member(const Json& j, const char* key) {
    static const Json null;
    if (!j.is_object()) return null;
    const auto it = j.find(key);
    return it == j.end() ? null : *it;
}

std::uint32_t wrapMode(const Json& sampler, const char* key) {
    const Json& w = member(sampler, key);
    if (!w.is_number_integer()) return kWrapRepeat;
    switch (w.get<long long>()) {
    case 33071: return kWrapClamp;   // CLAMP_TO_EDGE
    case 33648: return kWrapMirror;  // MIRRORED_REPEAT
    default: return kWrapRepeat;     // 10497 REPEAT (and anything else)
    }
}

GltfTextureRef textureRef(const Json& root, const Json& info) {
    GltfTextureRef t;
    if (!info.is_object() || !member(info, "index").is_number_integer()) return t;
    t.present = true;
    t.texCoord = int(number(info, "texCoord", 0.0f));
    const Json& textures = member(root, "textures");
    const long long index = member(info, "index").get<long long>();
    if (textures.is_array() && index >= 0 && size_t(index) < textures.size()) {
        const Json& sampler = member(textures[size_t(index)], "sampler");
        const Json& samplers = member(root, "samplers");
        if (sampler.is_number_integer() && samplers.is_array()) {
            const long long s = sampler.get<long long>();
            if (s >= 0 && size_t(s) < samplers.size()) {
                t.wrapS = wrapMode(samplers[size_t(s)], "wrapS");
                t.wrapT = wrapMode(samplers[size_t(s)], "wrapT");
            }
        }
    }
    const Json& tt = member(member(info, "extensions"), "KHR_texture_transform");
    if (tt.is_object()) {
        t.transformed = true;
        t.offset = pair(tt, "offset", glm::vec2(0.0f));
        t.scale = pair(tt, "scale", glm::vec2(1.0f));
        t.rotation = number(tt, "rotation", 0.0f);
        if (member(tt, "texCoord").is_number_integer()) t.texCoord = int(member(tt, "texCoord").get<long long>());
    }
    return t;
}

float unit(float v) { return std::clamp(v, 0.0f, 1.0f); }

GltfMaterialInfo materialInfo(const Json& root, const Json& m) {
    GltfMaterialInfo out;
    if (member(m, "name").is_string()) out.name = member(m, "name").get<std::string>();
    const Json& pbr = member(m, "pbrMetallicRoughness");
    out.baseColor = textureRef(root, member(pbr, "baseColorTexture"));
    out.metallicRoughness = textureRef(root, member(pbr, "metallicRoughnessTexture"));
    out.normal = textureRef(root, member(m, "normalTexture"));
    out.normalScale = number(member(m, "normalTexture"), "scale", 1.0f);
    out.emissive = textureRef(root, member(m, "emissiveTexture"));
    out.emissiveFactor = glm::max(colour(m, "emissiveFactor", glm::vec3(0.0f)), glm::vec3(0.0f));
    if (member(m, "occlusionTexture").is_object()) out.ignored.push_back("occlusionTexture (a path tracer computes occlusion)");
    const Json& mode = member(m, "alphaMode");
    if (mode.is_string()) {
        const std::string s = mode.get<std::string>();
        out.alphaMode = s == "MASK" ? 1 : s == "BLEND" ? 2 : 0;
    }
    out.alphaCutoff = std::max(0.0f, number(m, "alphaCutoff", 0.5f));
    out.doubleSided = member(m, "doubleSided").is_boolean() && member(m, "doubleSided").get<bool>();
    const Json& ext = member(m, "extensions");
    if (const Json& e = member(ext, "KHR_materials_ior"); e.is_object()) {
        out.hasIor = true;
        out.ior = number(e, "ior", 1.5f);
    }
    if (const Json& e = member(ext, "KHR_materials_specular"); e.is_object()) {
        out.hasSpecular = true;
        out.specular = unit(number(e, "specularFactor", 1.0f));
        out.specularColor = glm::max(colour(e, "specularColorFactor", glm::vec3(1.0f)), glm::vec3(0.0f));
        for (const char* t : {"specularTexture", "specularColorTexture"})
            if (member(e, t).is_object()) out.ignored.push_back(std::string("KHR_materials_specular ") + t);
    }
    if (const Json& e = member(ext, "KHR_materials_clearcoat"); e.is_object()) {
        out.clearcoat = unit(number(e, "clearcoatFactor", 0.0f));
        out.clearcoatRoughness = unit(number(e, "clearcoatRoughnessFactor", 0.0f));
        for (const char* t : {"clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture"})
            if (member(e, t).is_object()) out.ignored.push_back(std::string("KHR_materials_clearcoat ") + t);
    }
    if (const Json& e = member(ext, "KHR_materials_sheen"); e.is_object()) {
        out.sheenColor = glm::clamp(colour(e, "sheenColorFactor", glm::vec3(0.0f)), glm::vec3(0.0f), glm::vec3(1.0f));
        out.sheenRoughness = unit(number(e, "sheenRoughnessFactor", 0.0f));
        for (const char* t : {"sheenColorTexture", "sheenRoughnessTexture"})
            if (member(e, t).is_object()) out.ignored.push_back(std::string("KHR_materials_sheen ") + t);
    }
    if (const Json& e = member(ext, "KHR_materials_transmission"); e.is_object()) {
        out.transmission = unit(number(e, "transmissionFactor", 0.0f));
        if (member(e, "transmissionTexture").is_object()) out.ignored.push_back("KHR_materials_transmission transmissionTexture");
    }
    if (const Json& e = member(ext, "KHR_materials_volume"); e.is_object())
        out.ignored.push_back("KHR_materials_volume (thickness and attenuation: the glass is clear)");
    if (const Json& e = member(ext, "KHR_materials_emissive_strength"); e.is_object())
        out.emissiveStrength = std::max(0.0f, number(e, "emissiveStrength", 1.0f));
    return out;
}

bool readFile(const std::string& path, std::string* bytes) {
    std::ifstream f(path, std::ios::binary);
    if (!f) return false;
    bytes->assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    return !f.bad();
}

std::uint32_t le32(const std::string& s, size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, s.data() + at, 4);
    return v;  // glTF is little-endian, as is every machine caustic runs on
}

}  // namespace

glm::vec2 GltfTextureRef::apply(glm::vec2 uv) const {
    const float c = std::cos(rotation), s = std::sin(rotation);
    const glm::vec2 p = uv * scale;
    return glm::vec2(c * p.x - s * p.y, s * p.x + c * p.y) + offset;
}

bool isMappedGltfExtension(const std::string& name) {
    static const char* const kMapped[] = {"KHR_materials_ior",          "KHR_materials_specular",
                                          "KHR_materials_clearcoat",    "KHR_materials_sheen",
                                          "KHR_materials_transmission", "KHR_materials_emissive_strength",
                                          "KHR_texture_transform",      "KHR_materials_volume"};
    return std::any_of(std::begin(kMapped), std::end(kMapped), [&](const char* k) { return name == k; });
}

bool readGltfInfo(const std::string& path, GltfInfo* out, std::string* error) {
    std::string bytes;
    if (!readFile(path, &bytes)) {
        *error = path + ": cannot read the file";
        return false;
    }
    std::string text;
    if (bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0) {
        // GLB: a 12-byte header (magic, version, length), then chunks of (length, type, data);
        // the first is the JSON (glTF 2.0 section 4.4).
        if (bytes.size() < 20) {
            *error = path + ": a GLB file shorter than its header";
            return false;
        }
        const std::uint32_t length = le32(bytes, 12), type = le32(bytes, 16);
        if (type != 0x4E4F534Au || length > bytes.size() - 20) {
            *error = path + ": the GLB's first chunk is not a complete JSON chunk";
            return false;
        }
        text = bytes.substr(20, length);
    } else {
        text = std::move(bytes);
    }
    const Json root = Json::parse(text, nullptr, false);
    if (root.is_discarded() || !root.is_object()) {
        *error = path + ": its JSON does not parse";
        return false;
    }
    GltfInfo info;
    if (const Json& used = member(root, "extensionsUsed"); used.is_array())
        for (const Json& e : used)
            if (e.is_string()) info.extensionsUsed.push_back(e.get<std::string>());
    if (const Json& materials = member(root, "materials"); materials.is_array())
        for (const Json& m : materials) info.materials.push_back(materialInfo(root, m));
    *out = std::move(info);
    return true;
}

}  // namespace caustic
