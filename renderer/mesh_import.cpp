#include "renderer/mesh_import.h"
#include "renderer/image.h"
#include "renderer/mesh_import_gltf.h"

#include <assimp/GltfMaterial.h>
#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <map>
#include <new>
#include <stdexcept>
#include <system_error>

// Debian's Assimp 5.2.5 is built with its internal assertions on (its defs.h defines
// ASSIMP_BUILD_DEBUG whenever NDEBUG is not defined), and a failed one calls
// Assimp::aiAssertViolation, which prints and aborts the process: a corrupt PLY file
// (TriangulateProcess.cpp:238, found by tests/fuzz) killed the CLI and the editor. The library
// calls that function through its PLT, so this definition in the program is the one bound: the
// failed assertion becomes an exception, which Importer::ReadFile (or importMeshFile below)
// catches, and the file is refused with a message. Assimp versions without the assertions never
// call it.
namespace Assimp {
void aiAssertViolation(const char* failedExpression, const char* file, int line) {
    throw std::runtime_error(std::string("Assimp's internal check '") + failedExpression + "' failed (" + file + ":" +
                             std::to_string(line) + "): the file is inconsistent");
}
}  // namespace Assimp

namespace caustic {

namespace {

namespace fs = std::filesystem;

// Node hierarchies deeper than this are treated as broken (a cycle, or a hostile file).
constexpr int kMaxNodeDepth = 256;
// Flattening duplicates meshes used by several nodes; beyond this many triangles in total the
// file is refused rather than exhausting memory.
constexpr std::size_t kMaxTotalTriangles = std::size_t(1) << 28;

glm::mat4 toGlm(const aiMatrix4x4& m) {
    // Assimp matrices are row-major (a1..a4 is the first row); glm is column-major.
    return glm::mat4(m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4,
                     m.b4, m.c4, m.d4);
}

bool finiteMat(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

// A material's texture: "*N" for the file's embedded image N, else a path beside the model. A
// name that matches an embedded image's name (Half-Life MDL skins: "Material.bmp"; FBX with
// embedded media) is that image, as Assimp's aiScene::GetEmbeddedTexture resolves it.
std::string texturePath(const aiMaterial* mat, aiTextureType type, const fs::path& dir, const aiScene* scene) {
    aiString s;
    if (mat->GetTextureCount(type) == 0 || mat->GetTexture(type, 0, &s) != AI_SUCCESS) return {};
    std::string p = s.C_Str();
    if (p.empty()) return {};
    if (p[0] == '*') return p;
    if (scene->mTextures && scene->mNumTextures > 0) {
        const int index = scene->GetEmbeddedTextureAndIndex(p.c_str()).second;
        if (index >= 0) return "*" + std::to_string(index);
    }
    fs::path tp(p);
    if (tp.is_relative()) tp = dir / tp;
    return tp.lexically_normal().string();
}

bool finitePositive(float v) { return std::isfinite(v) && v >= 0.0f; }

ImportedMaterial convertMaterial(const aiMaterial* mat, const fs::path& dir, const aiScene* scene,
                                 bool* approximated, bool* otherTextures) {
    ImportedMaterial m;
    aiString name;
    if (mat->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) m.name = name.C_Str();

    aiColor4D c4;
    aiColor3D c3;
    if (mat->Get(AI_MATKEY_BASE_COLOR, c4) == AI_SUCCESS) {
        m.baseColor = {c4.r, c4.g, c4.b};
        m.opacity = c4.a;
    } else if (mat->Get(AI_MATKEY_COLOR_DIFFUSE, c3) == AI_SUCCESS) {
        m.baseColor = {c3.r, c3.g, c3.b};
    }
    float f = 0.0f;
    if (mat->Get(AI_MATKEY_OPACITY, f) == AI_SUCCESS) m.opacity = f;

    const bool hasMetallic = mat->Get(AI_MATKEY_METALLIC_FACTOR, f) == AI_SUCCESS;
    if (hasMetallic) m.metallic = f;
    if (mat->Get(AI_MATKEY_ROUGHNESS_FACTOR, f) == AI_SUCCESS) {
        m.roughness = f;
    } else if (mat->Get(AI_MATKEY_GLOSSINESS_FACTOR, f) == AI_SUCCESS) {
        m.roughness = 1.0f - f;  // specular-glossiness: glossiness is 1 - roughness
        *approximated = true;
    } else if (!hasMetallic && mat->Get(AI_MATKEY_SHININESS, f) == AI_SUCCESS && f > 0.0f) {
        // Phong exponent n to a microfacet roughness: alpha = sqrt(2 / (n + 2)) (Walter et al.
        // 2007, eq. 33 relates Phong and Beckmann), and roughness = sqrt(alpha).
        m.roughness = std::sqrt(std::sqrt(2.0f / (f + 2.0f)));
        *approximated = true;
    }
    // Formats without PBR data (OBJ/MTL, COLLADA, FBX's Phong): the specular colour Ks becomes the
    // dielectric specular layer's weight (its largest channel) and colour; none, or black, is none.
    if (!hasMetallic) {
        m.specular = 0.0f;
        if (mat->Get(AI_MATKEY_COLOR_SPECULAR, c3) == AI_SUCCESS) {
            const float w = std::max({c3.r, c3.g, c3.b});
            if (std::isfinite(w) && w > 0.0f) {
                m.specular = std::min(w, 1.0f);
                m.specularColor = glm::vec3(c3.r, c3.g, c3.b) / w;
            }
        }
    }
    if (mat->Get(AI_MATKEY_COLOR_EMISSIVE, c3) == AI_SUCCESS) m.emission = {c3.r, c3.g, c3.b};
    if (mat->Get(AI_MATKEY_EMISSIVE_INTENSITY, f) == AI_SUCCESS) m.emission *= f;
    if (mat->Get(AI_MATKEY_TRANSMISSION_FACTOR, f) == AI_SUCCESS) m.transmission = f;
    if (mat->Get(AI_MATKEY_REFRACTI, f) == AI_SUCCESS && f >= 1.0f) m.ior = f;
    int twoSided = 0;
    if (mat->Get(AI_MATKEY_TWOSIDED, twoSided) == AI_SUCCESS) m.doubleSided = twoSided != 0;

    m.baseColorTexture = texturePath(mat, aiTextureType_BASE_COLOR, dir, scene);
    if (m.baseColorTexture.empty()) m.baseColorTexture = texturePath(mat, aiTextureType_DIFFUSE, dir, scene);
    // glTF's packed metallic-roughness texture: Assimp 5.2 files it under UNKNOWN (the
    // AI_MATKEY_GLTF_PBRMETALLICROUGHNESS_METALLICROUGHNESS_TEXTURE key) and, for some files,
    // under METALNESS / DIFFUSE_ROUGHNESS.
    m.metallicRoughnessTexture = texturePath(mat, aiTextureType_UNKNOWN, dir, scene);
    if (m.metallicRoughnessTexture.empty())
        m.metallicRoughnessTexture = texturePath(mat, aiTextureType_METALNESS, dir, scene);
    if (m.metallicRoughnessTexture.empty())
        m.metallicRoughnessTexture = texturePath(mat, aiTextureType_DIFFUSE_ROUGHNESS, dir, scene);
    m.normalTexture = texturePath(mat, aiTextureType_NORMALS, dir, scene);
    if (m.normalTexture.empty()) {
        // OBJ files often put the normal map under "bump"; Assimp calls that HEIGHT.
        m.normalTexture = texturePath(mat, aiTextureType_HEIGHT, dir, scene);
    }
    if (mat->Get(AI_MATKEY_GLTF_TEXTURE_SCALE(aiTextureType_NORMALS, 0), f) == AI_SUCCESS) m.normalScale = f;
    m.emissionTexture = texturePath(mat, aiTextureType_EMISSIVE, dir, scene);
    if (!m.emissionTexture.empty() && m.emission == glm::vec3(0.0f)) m.emission = glm::vec3(1.0f);

    for (aiTextureType t : {aiTextureType_SPECULAR, aiTextureType_AMBIENT, aiTextureType_SHININESS,
                            aiTextureType_OPACITY, aiTextureType_DISPLACEMENT, aiTextureType_LIGHTMAP,
                            aiTextureType_REFLECTION, aiTextureType_AMBIENT_OCCLUSION,
                            aiTextureType_SHEEN, aiTextureType_CLEARCOAT, aiTextureType_TRANSMISSION})
        if (mat->GetTextureCount(t) > 0) *otherTextures = true;

    // Sanitise: factors from broken files must not put NaN into the renderer.
    for (int i = 0; i < 3; ++i) {
        if (!finitePositive(m.baseColor[i])) m.baseColor[i] = 0.8f;
        if (!finitePositive(m.emission[i])) m.emission[i] = 0.0f;
        if (!finitePositive(m.specularColor[i])) m.specularColor[i] = 1.0f;
    }
    m.baseColor = glm::min(m.baseColor, glm::vec3(1.0f));
    auto unit = [](float v, float fallback) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : fallback; };
    m.opacity = unit(m.opacity, 1.0f);
    m.roughness = unit(m.roughness, 1.0f);
    m.metallic = unit(m.metallic, 0.0f);
    m.transmission = unit(m.transmission, 0.0f);
    if (!std::isfinite(m.ior)) m.ior = 1.5f;
    if (!std::isfinite(m.normalScale)) m.normalScale = 1.0f;
    return m;
}

bool isGltfPath(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".gltf" || ext == ".glb";
}

// Assimp's file access, except that one file reads as the given bytes (prepareGltfForAssimp's
// replacement for a glTF file Assimp cannot read as it is); every other file (a .gltf's buffers
// and images) is read from disk.
class ReplacingIOSystem : public Assimp::DefaultIOSystem {
public:
    ReplacingIOSystem(std::string file, std::string bytes) : file_(std::move(file)), bytes_(std::move(bytes)) {}
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        if (file && isReplaced(file))
            return new Assimp::MemoryIOStream(reinterpret_cast<const std::uint8_t*>(bytes_.data()), bytes_.size());
        return Assimp::DefaultIOSystem::Open(file, mode);
    }

private:
    bool isReplaced(const char* file) const {
        if (file_ == file) return true;
        std::error_code ec;
        return fs::equivalent(fs::path(file_), fs::path(file), ec) && !ec;
    }
    std::string file_, bytes_;
};

// glTF files: what Assimp 5.2 does not pass on, from the file's JSON (mesh_import_gltf.h), laid
// over the materials Assimp made (the same order: Assimp's glTF importer makes material i from
// the file's material i and may append a default one). Reports, once per file, the material
// extensions and properties that are not mapped.
void applyGltfInfo(const std::string& path, const GltfInfo& info, MeshImportResult* r,
                   std::vector<GltfTextureRef>* uvTransforms) {
    std::vector<std::string> unsupported;
    for (const std::string& e : info.extensionsUsed)
        if (!isMappedGltfExtension(e)) unsupported.push_back(e);
    if (!unsupported.empty()) {
        std::string list;
        for (const std::string& e : unsupported) list += (list.empty() ? "" : ", ") + e;
        r->warnings.push_back(path + ": glTF extensions not supported (ignored): " + list);
    }
    const size_t n = std::min(info.materials.size(), r->materials.size());
    std::vector<std::string> ignored;
    bool mixedTransforms = false, otherUvSet = false, masked = false, blended = false;
    for (size_t i = 0; i < n; ++i) {
        const GltfMaterialInfo& g = info.materials[i];
        ImportedMaterial& m = r->materials[i];
        if (!g.name.empty() && !m.name.empty() && g.name != m.name) {
            r->warnings.push_back(path + ": material " + std::to_string(i) + " is '" + m.name + "' to Assimp and '" +
                                  g.name + "' in the file: its glTF extensions are not applied");
            continue;
        }
        m.alphaMode = g.alphaMode;
        m.alphaCutoff = g.alphaMode == 1 ? g.alphaCutoff : 0.5f;  // glTF: alphaCutoff is MASK's alone
        m.doubleSided = g.doubleSided;
        m.normalScale = g.normalScale;
        if (g.hasIor && g.ior >= 1.0f) m.ior = g.ior;
        m.specular = g.specular;
        m.specularColor = g.specularColor;
        m.clearcoat = g.clearcoat;
        m.clearcoatRoughness = g.clearcoatRoughness;
        m.sheenColor = g.sheenColor;
        m.sheenRoughness = g.sheenRoughness;
        m.transmission = std::max(m.transmission, g.transmission);
        m.attenuationColor = g.attenuationColor;
        m.attenuationDistance = g.attenuationDistance;
        m.volume = g.volume;
        m.diffuseTransmission = g.diffuseTransmission;
        m.diffuseTransmissionColor = g.diffuseTransmissionColor;
        m.emission = g.emissiveFactor * g.emissiveStrength;
        m.setTextureWrap(TextureSlot::BaseColor, g.baseColor.wrapS, g.baseColor.wrapT);
        m.setTextureWrap(TextureSlot::MetallicRoughness, g.metallicRoughness.wrapS, g.metallicRoughness.wrapT);
        m.setTextureWrap(TextureSlot::Normal, g.normal.wrapS, g.normal.wrapT);
        m.setTextureWrap(TextureSlot::Emission, g.emissive.wrapS, g.emissive.wrapT);
        const GltfTextureRef* first = nullptr;
        for (const GltfTextureRef* t : {&g.baseColor, &g.metallicRoughness, &g.normal, &g.emissive}) {
            if (!t->present) continue;
            if (t->texCoord != 0) otherUvSet = true;
            if (!first) first = t;
            else if (t->transformed != first->transformed || t->offset != first->offset || t->scale != first->scale ||
                     t->rotation != first->rotation)
                mixedTransforms = true;
        }
        if (first) (*uvTransforms)[i] = *first;
        masked |= g.alphaMode == 1;
        blended |= g.alphaMode == 2;
        for (const std::string& s : g.ignored)
            if (std::find(ignored.begin(), ignored.end(), s) == ignored.end()) ignored.push_back(s);
    }
    for (const std::string& s : ignored) r->warnings.push_back(path + ": not mapped (ignored): " + s);
    if (mixedTransforms)
        r->warnings.push_back(path + ": a material's textures have different KHR_texture_transforms: the base colour "
                                     "texture's is used for all of them");
    if (otherUvSet) r->warnings.push_back(path + ": textures on UV sets other than the first use the first");
    (void)masked;  // MASK is rendered as the file says (cut-outs: shaders/geometry/alpha_mask.glsl)
    if (blended)
        r->warnings.push_back(path + ": alphaMode BLEND is rendered as MASK (a point is cut out where its alpha is "
                                     "below 0.5; there is no partial transparency)");
}

struct Converter {
    const aiScene* scene = nullptr;
    std::string path;
    MeshImportResult* out = nullptr;
    std::size_t totalTriangles = 0;
    std::vector<bool> meshUsed;
    std::size_t pointLineMeshes = 0, pointLinePrims = 0;
    std::size_t emptyMeshes = 0;
    bool badTransform = false, tooDeep = false, tooBig = false, extraChannels = false, bones = false;

    void warn(const std::string& msg) { out->warnings.push_back(path + ": " + msg); }

    // Converts mesh mi under transform m; false when the total size limit is exceeded.
    bool addMesh(unsigned mi, const glm::mat4& m, const std::string& nodeName) {
        const aiMesh* am = scene->mMeshes[mi];
        if (!am) return true;
        if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || am->mNumFaces == 0 || am->mNumVertices == 0) {
            if (am->mPrimitiveTypes & (aiPrimitiveType_POINT | aiPrimitiveType_LINE)) {
                ++pointLineMeshes;
                pointLinePrims += am->mNumFaces;
            } else {
                ++emptyMeshes;
            }
            return true;
        }
        if (am->GetNumUVChannels() > 1 || am->GetNumColorChannels() > 0) extraChannels = true;
        if (am->HasBones()) bones = true;
        if (totalTriangles + am->mNumFaces > kMaxTotalTriangles) {
            tooBig = true;
            return false;
        }

        Mesh mesh;
        mesh.name = am->mName.length > 0 ? am->mName.C_Str() : nodeName;
        if (mesh.name.empty()) mesh.name = "mesh" + std::to_string(mi);
        mesh.material = am->mMaterialIndex < scene->mNumMaterials ? static_cast<int>(am->mMaterialIndex) : -1;

        const glm::mat3 linear(m);
        const glm::mat3 normalMatrix = glm::inverseTranspose(linear);
        const bool mirror = glm::determinant(linear) < 0.0f;

        const unsigned nv = am->mNumVertices;
        if (!am->mVertices) return true;
        mesh.positions.resize(nv);
        for (unsigned i = 0; i < nv; ++i) {
            const aiVector3D& p = am->mVertices[i];
            mesh.positions[i] = glm::vec3(m * glm::vec4(p.x, p.y, p.z, 1.0f));
        }
        if (am->mNormals) {
            mesh.normals.resize(nv);
            for (unsigned i = 0; i < nv; ++i) {
                const aiVector3D& n = am->mNormals[i];
                mesh.normals[i] = normalMatrix * glm::vec3(n.x, n.y, n.z);  // validate normalises
            }
        }
        if (am->HasTextureCoords(0)) {
            mesh.uvs.resize(nv);
            for (unsigned i = 0; i < nv; ++i) mesh.uvs[i] = {am->mTextureCoords[0][i].x, am->mTextureCoords[0][i].y};
        }
        if (am->mTangents && am->mBitangents && am->mNormals) {
            mesh.tangents.resize(nv);
            for (unsigned i = 0; i < nv; ++i) {
                const aiVector3D &t = am->mTangents[i], &b = am->mBitangents[i], &n = am->mNormals[i];
                // Handedness: whether (t, b, n) is right-handed in the file's object space.
                const float w = glm::dot(glm::cross(glm::vec3(n.x, n.y, n.z), glm::vec3(t.x, t.y, t.z)),
                                         glm::vec3(b.x, b.y, b.z)) < 0.0f ? -1.0f : 1.0f;
                glm::vec3 tw = linear * glm::vec3(t.x, t.y, t.z);
                const float len = glm::length(tw);
                tw = len > 0.0f ? tw / len : glm::vec3(std::nanf(""));  // validate drops NaN sets
                mesh.tangents[i] = glm::vec4(tw, mirror ? -w : w);
            }
        }
        mesh.triangles.reserve(am->mNumFaces);
        for (unsigned f = 0; f < am->mNumFaces; ++f) {
            const aiFace& face = am->mFaces[f];
            if (face.mNumIndices != 3 || !face.mIndices) continue;  // sorted by type: rare
            glm::uvec3 t{face.mIndices[0], face.mIndices[1], face.mIndices[2]};
            if (mirror) std::swap(t.y, t.z);
            mesh.triangles.push_back(t);
        }

        const MeshValidation v = validateMesh(mesh);
        if (!v.summary().empty()) warn("mesh '" + mesh.name + "': " + v.summary());
        if (mesh.triangles.empty()) {
            ++emptyMeshes;
            return true;
        }
        // Generated normals for meshes that lost theirs in validation (or never had any, which
        // Assimp's GenSmoothNormals should have prevented).
        if (mesh.normals.empty()) mesh.normals = computeVertexNormals(mesh.positions, mesh.triangles);
        totalTriangles += mesh.triangles.size();
        out->meshes.push_back(std::move(mesh));
        return true;
    }

    bool walk(const aiNode* node, const glm::mat4& parent, int depth) {
        if (!node) return true;
        if (depth > kMaxNodeDepth) {
            tooDeep = true;
            return true;
        }
        const glm::mat4 m = parent * toGlm(node->mTransformation);
        if (!finiteMat(m)) {
            badTransform = true;
            return true;
        }
        for (unsigned i = 0; i < node->mNumMeshes; ++i) {
            const unsigned mi = node->mMeshes[i];
            if (mi >= scene->mNumMeshes) continue;  // ValidateDataStructure rejects these
            meshUsed[mi] = true;
            if (!addMesh(mi, m, node->mName.C_Str())) return false;
        }
        for (unsigned i = 0; i < node->mNumChildren; ++i)
            if (!walk(node->mChildren[i], m, depth + 1)) return false;
        return true;
    }
};

std::string fsError(const std::error_code& ec) { return ec.message(); }

// Headers that declare element counts the file cannot possibly hold. Assimp allocates what the
// header declares before reading the data, so such a file (assimp-testmodels'
// invalid/OutOfMemory.off declares 3.5 billion vertices in 309 bytes) takes a minute of page
// faults or exhausts memory. Checked for the formats with a plain-text count header: OFF (every
// vertex takes at least 6 bytes, "0 0 0\n") and PLY (every element at least 1 byte). Returns an
// error message, or "" when the header is plausible or not recognised (Assimp decides then).
std::string implausibleHeader(const std::string& path, std::uintmax_t size) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext != ".off" && ext != ".ply") return {};
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return {};
    // PLY: up to 1 MiB, to find the end of the header (below); OFF: the counts come first.
    std::string head(ext == ".ply" ? std::size_t(1) << 20 : 4096, '\0');
    head.resize(std::fread(head.data(), 1, head.size(), f));
    std::fclose(f);
    if (ext == ".off") {
        // "[ST][C][N][4][n]OFF" then (after comments) "nv nf ne".
        std::size_t pos = head.find("OFF");
        if (pos == std::string::npos || pos > 8) return {};
        pos += 3;
        unsigned long long counts[2] = {0, 0};
        int got = 0;
        while (got < 2 && pos < head.size()) {
            const char c = head[pos];
            if (c == '#') {
                pos = head.find('\n', pos);
                if (pos == std::string::npos) return {};
            } else if (std::isdigit(static_cast<unsigned char>(c))) {
                counts[got++] = std::strtoull(head.c_str() + pos, nullptr, 10);
                while (pos < head.size() && std::isdigit(static_cast<unsigned char>(head[pos]))) ++pos;
                continue;
            } else if (!std::isspace(static_cast<unsigned char>(c))) {
                return {};
            }
            ++pos;
        }
        if (got == 2 && (counts[0] > size / 6 || counts[1] > size / 4))
            return path + ": the OFF header declares " + std::to_string(counts[0]) + " vertices and " +
                   std::to_string(counts[1]) + " faces, more than a file of " + std::to_string(size) +
                   " bytes can hold";
        return {};
    }
    // PLY: "element <name> <count>" lines up to "end_header". Without that line Assimp 5.2's PLY
    // reader never stops looking for it (a hang found by tests/fuzz: one corrupt byte in the
    // line), so a header that does not end within the first MiB (or the file) is refused.
    // The line must be exactly that (trailing blanks allowed): "end_header22e-16 ..." hangs too.
    std::size_t pos = 0;
    std::size_t endHeader = std::string::npos;
    for (std::size_t at = head.find("\nend_header"); at != std::string::npos; at = head.find("\nend_header", at + 1)) {
        std::size_t k = at + 11;
        while (k < head.size() && (head[k] == ' ' || head[k] == '\t' || head[k] == '\r')) ++k;
        if (k < head.size() && head[k] == '\n') {
            endHeader = at + 1;
            break;
        }
    }
    // Assimp takes the magic number in any case ("pLy" hung it: tests/fuzz, fuzz_mesh_common).
    const bool plyMagic = head.size() >= 3 && std::tolower(static_cast<unsigned char>(head[0])) == 'p' &&
                          std::tolower(static_cast<unsigned char>(head[1])) == 'l' &&
                          std::tolower(static_cast<unsigned char>(head[2])) == 'y';
    if (plyMagic && endHeader == std::string::npos)
        return path + ": the PLY header has no end_header line" +
               (size > head.size() ? " in its first " + std::to_string(head.size()) + " bytes" : std::string());
    while ((pos = head.find("element ", pos)) != std::string::npos && pos < endHeader) {
        pos += 8;
        const std::size_t sp = head.find(' ', pos);
        if (sp == std::string::npos) break;
        const unsigned long long count = std::strtoull(head.c_str() + sp + 1, nullptr, 10);
        if (count > size)
            return path + ": the PLY header declares " + std::to_string(count) + " '" +
                   head.substr(pos, sp - pos) + "' elements, more than a file of " +
                   std::to_string(size) + " bytes can hold";
    }
    return {};
}

MeshImportResult importImpl(const std::string& path) {
    MeshImportResult r;
    if (path.empty()) {
        r.error = "(empty path): no mesh file given";
        return r;
    }
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (ec || !fs::exists(st)) {
        r.error = path + ": cannot open: " + (ec ? fsError(ec) : std::string("no such file"));
        return r;
    }
    if (fs::is_directory(st)) {
        r.error = path + ": is a directory, not a mesh file";
        return r;
    }
    const auto size = fs::file_size(path, ec);
    if (ec) {
        r.error = path + ": cannot read: " + fsError(ec);
        return r;
    }
    if (size == 0) {
        r.error = path + ": the file is empty";
        return r;
    }
    if (!isMeshFileExtensionSupported(path)) {
        r.error = path + ": unsupported mesh file type '" + fs::path(path).extension().string() + "'";
        return r;
    }
    if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
        std::fclose(f);
    } else {
        r.error = path + ": cannot open: permission denied or unreadable";
        return r;
    }
    if (std::string why = implausibleHeader(path, size); !why.empty()) {
        r.error = why;
        return r;
    }

    Assimp::Importer importer;
    GltfForAssimp gltf;   // for glTF files: the file's JSON, read once, before and after Assimp
    if (isGltfPath(path)) {
        gltf = prepareGltfForAssimp(path);
        if (!gltf.error.empty()) {
            r.error = gltf.error;
            return r;
        }
        r.warnings.insert(r.warnings.end(), gltf.warnings.begin(), gltf.warnings.end());
        if (!gltf.replacement.empty())
            importer.SetIOHandler(new ReplacingIOSystem(path, std::move(gltf.replacement)));  // the importer owns it
    }
    // Points and lines are kept by SortByPType (so they can be counted and reported) and skipped
    // in the conversion.
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, 0);
    const unsigned flags = aiProcess_Triangulate | aiProcess_GenSmoothNormals |
                           aiProcess_CalcTangentSpace | aiProcess_JoinIdenticalVertices |
                           aiProcess_ValidateDataStructure | aiProcess_SortByPType |
                           aiProcess_FindInvalidData;
    const aiScene* scene = importer.ReadFile(path, flags);
    if (!scene) {
        std::string why = importer.GetErrorString();
        r.error = path + ": cannot import: " + (why.empty() ? std::string("unknown Assimp error") : why);
        return r;
    }
    if (scene->mNumMeshes == 0 || !scene->mMeshes) {
        r.error = path + ": the file has no meshes";
        return r;
    }

    const fs::path dir = fs::path(path).parent_path();
    bool approximated = false, otherTextures = false;
    for (unsigned i = 0; i < scene->mNumMaterials; ++i) {
        if (scene->mMaterials && scene->mMaterials[i])
            r.materials.push_back(convertMaterial(scene->mMaterials[i], dir, scene, &approximated, &otherTextures));
        else
            r.materials.push_back(ImportedMaterial{});
    }

    // The embedded images ("*N" paths): compressed files (PNG, JPEG) as their bytes, raw texels
    // (mHeight != 0: mWidth x mHeight aiTexels, b, g, r, a) as RGBA8 (mesh.h EmbeddedImage).
    for (unsigned i = 0; scene->mTextures && i < scene->mNumTextures; ++i) {
        EmbeddedImage e;
        const aiTexture* t = scene->mTextures[i];
        if (t && t->pcData) {
            e.name = t->mFilename.C_Str();
            if (t->mHeight == 0) {
                e.bytes.assign(reinterpret_cast<const char*>(t->pcData), t->mWidth);
            } else {
                e.width = int(std::min<unsigned>(t->mWidth, 1u << 30));
                e.height = int(std::min<unsigned>(t->mHeight, 1u << 30));
                // Sizes beyond the image limits are refused when the texture is used (textures.cpp).
                if (imageSizeProblem("", e.width, e.height, 4).empty()) {
                    const std::size_t n = std::size_t(e.width) * std::size_t(e.height);
                    e.bytes.resize(4 * n);
                    for (std::size_t k = 0; k < n; ++k) {
                        const aiTexel& x = t->pcData[k];
                        e.bytes[4 * k + 0] = char(x.r);
                        e.bytes[4 * k + 1] = char(x.g);
                        e.bytes[4 * k + 2] = char(x.b);
                        e.bytes[4 * k + 3] = char(x.a);
                    }
                }
            }
        }
        r.embedded.push_back(std::move(e));
    }
    std::vector<GltfTextureRef> uvTransforms(r.materials.size());
    if (isGltfPath(path)) applyGltfInfo(path, gltf.info, &r, &uvTransforms);

    Converter conv;
    conv.scene = scene;
    conv.path = path;
    conv.out = &r;
    conv.meshUsed.assign(scene->mNumMeshes, false);
    bool ok = conv.walk(scene->mRootNode, glm::mat4(1.0f), 0);
    // Meshes no node references (some importers leave them) are taken untransformed.
    for (unsigned i = 0; ok && i < scene->mNumMeshes; ++i)
        if (!conv.meshUsed[i]) ok = conv.addMesh(i, glm::mat4(1.0f), "");
    if (conv.tooBig) {
        r.meshes.clear();
        r.error = path + ": more than " + std::to_string(kMaxTotalTriangles) +
                  " triangles after flattening the node hierarchy";
        return r;
    }

    if (conv.pointLineMeshes)
        conv.warn(std::to_string(conv.pointLinePrims) + " point/line primitives in " +
                  std::to_string(conv.pointLineMeshes) + " meshes dropped (only triangles are rendered)");
    if (conv.emptyMeshes) conv.warn(std::to_string(conv.emptyMeshes) + " meshes without triangles dropped");
    if (conv.badTransform) conv.warn("nodes with non-finite transforms skipped (with their children)");
    if (conv.tooDeep) conv.warn("node hierarchy deeper than " + std::to_string(kMaxNodeDepth) + " cut");
    if (conv.extraChannels) conv.warn("extra UV channels and vertex colours ignored");
    if (conv.bones) conv.warn("skinning (bones) ignored: meshes imported in bind pose");
    if (scene->mNumAnimations) conv.warn(std::to_string(scene->mNumAnimations) + " animations ignored");
    if (scene->mNumCameras) conv.warn(std::to_string(scene->mNumCameras) + " cameras ignored");
    if (scene->mNumLights) conv.warn(std::to_string(scene->mNumLights) + " lights ignored");
    // KHR_texture_transform: one per material (its base colour texture's, else the first textured
    // slot's), applied to the UVs of its meshes in glTF's UV space (Assimp flips v: v_gltf = 1 - v).
    for (Mesh& mesh : r.meshes) {
        if (mesh.material < 0 || size_t(mesh.material) >= uvTransforms.size()) continue;
        const GltfTextureRef& t = uvTransforms[size_t(mesh.material)];
        if (!t.transformed) continue;
        for (glm::vec2& uv : mesh.uvs) {
            const glm::vec2 g = t.apply(glm::vec2(uv.x, 1.0f - uv.y));
            uv = glm::vec2(g.x, 1.0f - g.y);
        }
    }
    if (approximated) conv.warn("non-PBR materials (Phong shininess / specular-glossiness) mapped approximately to roughness");
    if (otherTextures) conv.warn("texture types other than base colour, metallic-roughness, normal and emission ignored");
    if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) conv.warn("Assimp marked the scene incomplete");

    if (r.meshes.empty()) r.error = path + ": no triangles to render (all meshes empty, degenerate or points/lines)";
    return r;
}

}  // namespace

bool isMeshFileExtensionSupported(const std::string& path) {
    try {
        std::string ext = fs::path(path).extension().string();
        if (ext.size() < 2) return false;
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        Assimp::Importer importer;
        return importer.IsExtensionSupported(ext.c_str());
    } catch (...) {
        return false;
    }
}

MeshImportResult importMeshFileInProcess(const std::string& path) {
    const auto t0 = std::chrono::steady_clock::now();
    MeshImportResult r;
    try {
        r = importImpl(path);
    } catch (const std::bad_alloc&) {
        r = MeshImportResult{};
        r.error = path + ": out of memory while importing";
    } catch (const std::exception& e) {
        r = MeshImportResult{};
        r.error = path + ": cannot import: " + e.what();
    } catch (...) {
        r = MeshImportResult{};
        r.error = path + ": cannot import: unknown error";
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (r.seconds > kSlowImportSeconds) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.1f", r.seconds);
        r.warnings.push_back(path + ": import took " + buf + " s");
    }
    return r;
}

}  // namespace caustic
