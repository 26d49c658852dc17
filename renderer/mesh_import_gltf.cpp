// glTF 2.0 material details from the file's own JSON (renderer/mesh_import_gltf.h).
// References: the glTF 2.0 specification (sections 3.9 materials, 3.8 samplers, 4.4 GLB), and the
// Khronos extension documents KHR_texture_transform, KHR_materials_ior, _specular, _clearcoat,
// _sheen, _transmission, _volume and _emissive_strength.
#include "renderer/mesh_import_gltf.h"

#include "renderer/json_depth.h"

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
    if (const Json& e = member(ext, "KHR_materials_volume"); e.is_object()) {
        // Attenuation is Beer-Lambert absorption inside (mapImportedMaterial: the surface's
        // transmission_color / transmission_depth). The thickness (factor and texture) is a
        // rasteriser's stand-in for the geometry a path tracer traces: only whether it is 0
        // (thin-walled) is mapped.
        const float thickness = number(e, "thicknessFactor", 0.0f);
        out.volume = std::isfinite(thickness) && thickness > 0.0f;  // 0: thin-walled, as the extension says
        const float distance = number(e, "attenuationDistance", 0.0f);
        if (std::isfinite(distance) && distance > 0.0f) {
            out.attenuationDistance = distance;
            out.attenuationColor = glm::clamp(colour(e, "attenuationColor", glm::vec3(1.0f)), glm::vec3(0.0f),
                                              glm::vec3(1.0f));
        }
    }
    if (const Json& e = member(ext, "KHR_materials_diffuse_transmission"); e.is_object()) {
        out.diffuseTransmission = unit(number(e, "diffuseTransmissionFactor", 0.0f));
        out.diffuseTransmissionColor = glm::clamp(colour(e, "diffuseTransmissionColorFactor", glm::vec3(1.0f)),
                                                  glm::vec3(0.0f), glm::vec3(1.0f));
        for (const char* t : {"diffuseTransmissionTexture", "diffuseTransmissionColorTexture"})
            if (member(e, t).is_object()) out.ignored.push_back(std::string("KHR_materials_diffuse_transmission ") + t);
    }
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
                                          "KHR_texture_transform",      "KHR_materials_volume",
                                          "KHR_materials_diffuse_transmission"};
    return std::any_of(std::begin(kMapped), std::end(kMapped), [&](const char* k) { return name == k; });
}

namespace {

// The file's JSON: for a .glb its first chunk (then *glb is set and *restOffset is where the
// bytes after that chunk start: the BIN chunk and any others), else the whole file. Of a .glb only
// the header and the JSON chunk are read (its binary chunk may be large). False with *error.
bool readGltfJson(const std::string& path, std::string* text, bool* glb, std::size_t* restOffset, std::string* error) {
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        *error = path + ": cannot read the file";
        return false;
    }
    char head[20] = {};
    f.read(head, 4);
    *glb = f.gcount() == 4 && std::memcmp(head, "glTF", 4) == 0;
    f.clear();
    if (!*glb) {
        if (!readFile(path, text)) {
            *error = path + ": cannot read the file";
            return false;
        }
        return true;
    }
    // GLB: a 12-byte header (magic, version, length), then chunks of (length, type, data); the
    // first is the JSON (glTF 2.0 section 4.4).
    f.seekg(0, std::ios::end);
    const std::uint64_t size = std::uint64_t(f.tellg());
    f.seekg(0);
    if (size < 20 || !f.read(head, 20)) {
        *error = path + ": a GLB file shorter than its header";
        return false;
    }
    const std::string header(head, 20);
    const std::uint32_t length = le32(header, 12), type = le32(header, 16);
    if (type != 0x4E4F534Au || length > size - 20) {
        *error = path + ": the GLB's first chunk is not a complete JSON chunk";
        return false;
    }
    text->resize(length);
    if (!f.read(text->data(), std::streamsize(length))) {
        *error = path + ": cannot read the file";
        return false;
    }
    *restOffset = 20 + std::size_t(length);
    return true;
}

void putLe32(std::string& s, std::uint32_t v) {
    char b[4];
    std::memcpy(b, &v, 4);
    s.append(b, 4);
}

// A non-negative integer at j[key], else `fallback` (absent) or -1 (present and not one).
long long nonNegative(const Json& j, const char* key, long long fallback) {
    const Json& v = member(j, key);
    if (v.is_null()) return fallback;
    return v.is_number_integer() && v.get<long long>() >= 0 ? v.get<long long>() : -1;
}

// The bytes one element of an accessor takes in its buffer view: glTF 2.0 section 3.6.2.4 (the
// columns of a matrix start on 4-byte boundaries); 0 for an unknown type or component type.
long long elementBytes(const Json& accessor) {
    long long component = 0;
    switch (nonNegative(accessor, "componentType", 0)) {
    case 5120: case 5121: component = 1; break;   // BYTE, UNSIGNED_BYTE
    case 5122: case 5123: component = 2; break;   // SHORT, UNSIGNED_SHORT
    case 5125: case 5126: component = 4; break;   // UNSIGNED_INT, FLOAT
    default: return 0;
    }
    const Json& type = member(accessor, "type");
    const std::string t = type.is_string() ? type.get<std::string>() : "";
    const auto column = [&](long long rows) { return (rows * component + 3) / 4 * 4; };
    if (t == "SCALAR") return component;
    if (t == "VEC2") return 2 * component;
    if (t == "VEC3") return 3 * component;
    if (t == "VEC4") return 4 * component;
    if (t == "MAT2") return 2 * column(2);
    if (t == "MAT3") return 3 * column(3);
    if (t == "MAT4") return 4 * column(4);
    return 0;
}

// "" when every accessor's elements (and sparse indices and values) lie inside their buffer views
// (glTF 2.0 section 3.6.2.4); else which does not, named by JSON path. Assimp 5.2.5 checks buffer views against their
// buffers but not strided accessors against their views, and reads past the buffer: the fuzzer
// found a heap overflow (docs/reliability.md), in a normal build silently garbage data.
std::string accessorOutOfBounds(const Json& root) {
    const Json& accessors = member(root, "accessors");
    const Json& views = member(root, "bufferViews");
    // The length of view v, or -1 (no such view: Assimp reports that).
    const auto viewLength = [&](long long v, long long* stride) -> long long {
        if (!views.is_array() || v < 0 || v >= (long long)views.size()) return -1;
        const Json& view = views[size_t(v)];
        *stride = nonNegative(view, "byteStride", 0);
        return nonNegative(view, "byteLength", -1);
    };
    if (!accessors.is_array()) return "";
    for (size_t a = 0; a < accessors.size(); ++a) {
        const Json& acc = accessors[a];
        const std::string name = "accessors[" + std::to_string(a) + "]";
        const long long n = nonNegative(acc, "count", -1), element = elementBytes(acc);
        if (n < 0 || element == 0) continue;   // Assimp refuses these itself
        const auto fits = [&](const Json& where, long long items, long long itemBytes, bool strided,
                              const std::string& what) -> std::string {
            const long long v = nonNegative(where, "bufferView", -2);
            if (v == -2 || items == 0) return "";
            long long stride = 0;
            const long long length = viewLength(v, &stride);
            const long long offset = nonNegative(where, "byteOffset", 0);
            if (length < 0 || offset < 0 || stride < 0) return "";
            const long long step = strided && stride > 0 ? stride : itemBytes;
            // Each term below 2^62: counts and offsets come from JSON integers, bounded here first.
            if (items > (1LL << 40) || step > (1LL << 20) || offset > (1LL << 40)) return what + " is larger than any buffer";
            const long long end = offset + step * (items - 1) + itemBytes;
            if (end <= length) return "";
            return what + " reads " + std::to_string(end) + " bytes of bufferViews[" + std::to_string(v) + "], which has " +
                   std::to_string(length);
        };
        if (std::string why = fits(acc, n, element, true, name); !why.empty()) return why;
        const Json& sparse = member(acc, "sparse");
        if (sparse.is_object()) {
            const long long k = nonNegative(sparse, "count", -1);
            if (k < 0) continue;
            const long long indexBytes = nonNegative(member(sparse, "indices"), "componentType", 0) == 5121   ? 1
                                         : nonNegative(member(sparse, "indices"), "componentType", 0) == 5123 ? 2
                                                                                                         : 4;
            if (std::string why = fits(member(sparse, "indices"), k, indexBytes, false, name + ".sparse.indices"); !why.empty())
                return why;
            if (std::string why = fits(member(sparse, "values"), k, element, false, name + ".sparse.values"); !why.empty())
                return why;
        }
    }
    return "";
}

// Arrays and objects nested deeper than this are not written back (nlohmann's dump recurses).
constexpr int kMaxRewriteDepth = 64;

}  // namespace

GltfForAssimp prepareGltfForAssimp(const std::string& path) {
    GltfForAssimp out;
    std::string text;
    bool glb = false;
    std::size_t restOffset = 0;
    if (!readGltfJson(path, &text, &glb, &restOffset, &out.error)) return out;
    Json root;
    try {
        root = Json::parse(text);
    } catch (const Json::exception& e) {
        // what(): "[json.exception.parse_error.101] parse error at line 3, column 7: ..."
        std::string what = e.what();
        if (const std::size_t close = what.find("] "); what.rfind("[json.exception", 0) == 0 && close != std::string::npos)
            what = what.substr(close + 2);
        // nlohmann quotes what it last read, raw: bytes outside printable ASCII become \xNN.
        std::string printable;
        for (const char c : what) {
            const unsigned char u = static_cast<unsigned char>(c);
            if (u >= 0x20 && u < 0x7f) {
                printable += c;
            } else {
                static const char* const kHex = "0123456789ABCDEF";
                printable += {'\\', 'x', kHex[u >> 4], kHex[u & 15u]};
            }
        }
        out.error = path + ": its JSON is not valid (glTF is UTF-8 JSON, RFC 8259): " + printable;
        return out;
    }
    if (!root.is_object()) {
        out.error = path + ": its JSON is not an object, so not glTF";
        return out;
    }
    if (const Json& used = member(root, "extensionsUsed"); used.is_array())
        for (const Json& e : used)
            if (e.is_string()) out.info.extensionsUsed.push_back(e.get<std::string>());
    if (const Json& materials = member(root, "materials"); materials.is_array())
        for (const Json& m : materials) out.info.materials.push_back(materialInfo(root, m));
    // glTF 1.0 (Assimp has a separate reader for it) is left as it is.
    if (const Json& version = member(member(root, "asset"), "version");
        version.is_string() && version.get<std::string>().rfind("2", 0) != 0)
        return out;
    if (std::string why = accessorOutOfBounds(root); !why.empty()) {
        out.error = path + ": " + why;
        return out;
    }
    // A skin without inverseBindMatrices is valid glTF 2.0 (section 5.28: each matrix is then the
    // identity), but Assimp 5.2.5 dereferences the missing accessor and crashes (found by the
    // mesh fuzzer, docs/reliability.md). caustic ignores skinning (meshes in bind pose), so the
    // nodes' references to such skins are dropped in the bytes Assimp reads.
    const Json& skins = member(root, "skins");
    const auto nodes = root.find("nodes");
    std::vector<long long> dropped;
    if (skins.is_array() && nodes != root.end() && nodes->is_array())
        for (Json& node : *nodes) {
            const Json& skin = member(node, "skin");
            if (!skin.is_number_integer()) continue;
            const long long k = skin.get<long long>();
            if (k < 0 || k >= (long long)skins.size() || !skins[size_t(k)].is_object() ||
                skins[size_t(k)].contains("inverseBindMatrices"))
                continue;
            node.erase("skin");
            if (std::find(dropped.begin(), dropped.end(), k) == dropped.end()) dropped.push_back(k);
        }
    if (dropped.empty() || jsonTooDeepAt(text, kMaxRewriteDepth) != std::string_view::npos) return out;
    std::string list;
    for (const long long k : dropped) list += (list.empty() ? "" : ", ") + std::to_string(k);
    out.warnings.push_back(path + ": skin" + (dropped.size() > 1 ? "s " : " ") + list +
                           " without inverseBindMatrices left out (Assimp 5.2.5 cannot read such a skin; "
                           "skinning is ignored: meshes in bind pose)");
    std::string json = root.dump();
    if (!glb) {
        out.replacement = std::move(json);
        return out;
    }
    std::string rest;   // the chunks after the JSON, as they are
    if (!readFile(path, &rest) || rest.size() < restOffset) {
        out.error = path + ": cannot read the file";
        return out;
    }
    rest.erase(0, restOffset);
    while (json.size() % 4 != 0) json.push_back(' ');  // chunks are 4-byte aligned, JSON padded with spaces
    std::string bytes = "glTF";
    putLe32(bytes, 2);
    putLe32(bytes, std::uint32_t(12 + 8 + json.size() + rest.size()));
    putLe32(bytes, std::uint32_t(json.size()));
    putLe32(bytes, 0x4E4F534Au);
    bytes += json;
    bytes += rest;
    out.replacement = std::move(bytes);
    return out;
}

}  // namespace caustic
