// Triangle meshes as the renderer keeps them (indexed, one material each) and the materials an
// imported file describes, plus the validation every mesh goes through before a BVH is built
// over it. No GL, no Assimp: renderer/mesh_import.h fills these from files.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace caustic {

// What a file says about a material, in glTF 2.0 metallic-roughness terms (other formats are
// mapped onto it by Assimp; what cannot be mapped is reported as an import warning). Texture
// paths are as the file gives them, resolved against the model file's folder when relative;
// empty when absent. A path "*N" names the file's embedded image N (a .glb buffer view or a
// data URI), whose bytes are MeshImportResult::embedded[N].
// Texture wrap modes (glTF samplers) per slot, 2 bits per axis: see textureWrap().
inline constexpr std::uint32_t kWrapRepeat = 0, kWrapClamp = 1, kWrapMirror = 2;
enum class TextureSlot { BaseColor = 0, MetallicRoughness = 1, Normal = 2, Emission = 3 };
struct ImportedMaterial {
    std::string name;
    glm::vec3 baseColor{0.8f};            // linear RGB factor
    float opacity = 1.0f;                 // base colour alpha factor
    std::string baseColorTexture;
    float roughness = 1.0f;               // glTF defaults: roughness 1, metallic 1 when the file
    float metallic = 0.0f;                // has PBR data; 0 metallic when it has none
    std::string metallicRoughnessTexture; // glTF: G = roughness, B = metallic
    std::string normalTexture;
    float normalScale = 1.0f;
    glm::vec3 emission{0.0f};             // emissive factor x KHR_materials_emissive_strength
    std::string emissionTexture;
    float transmission = 0.0f;            // KHR_materials_transmission factor
    float ior = 1.5f;                     // KHR_materials_ior
    glm::vec3 attenuationColor{1.0f};     // KHR_materials_volume: attenuationColor
    float attenuationDistance = 0.0f;     //   attenuationDistance (world units); 0: infinite, no absorption
    bool volume = false;                  //   present with thicknessFactor > 0 (else thin-walled)
    float diffuseTransmission = 0.0f;     // KHR_materials_diffuse_transmission: diffuseTransmissionFactor
    glm::vec3 diffuseTransmissionColor{1.0f};  //   diffuseTransmissionColorFactor
    bool doubleSided = false;
    float specular = 1.0f;                // KHR_materials_specular: specularFactor
    glm::vec3 specularColor{1.0f};        //   specularColorFactor
    float clearcoat = 0.0f;               // KHR_materials_clearcoat: clearcoatFactor
    float clearcoatRoughness = 0.0f;      //   clearcoatRoughnessFactor (perceptual)
    glm::vec3 sheenColor{0.0f};           // KHR_materials_sheen: sheenColorFactor
    float sheenRoughness = 0.0f;          //   sheenRoughnessFactor
    int alphaMode = 0;                    // glTF alphaMode: 0 OPAQUE, 1 MASK, 2 BLEND
    float alphaCutoff = 0.5f;
    std::uint32_t wrap = 0;               // wrap modes per TextureSlot: bits 4 slot + 2 axis (u, v)

    std::uint32_t textureWrap(TextureSlot slot, int axis) const {
        return (wrap >> (4 * static_cast<int>(slot) + 2 * axis)) & 3u;
    }
    void setTextureWrap(TextureSlot slot, std::uint32_t u, std::uint32_t v) {
        const int shift = 4 * static_cast<int>(slot);
        wrap = (wrap & ~(15u << shift)) | ((u & 3u) << shift) | ((v & 3u) << (shift + 2));
    }
};

// An image embedded in a model file. Either a compressed image file as its bytes (PNG or JPEG;
// renderer/textures.cpp decodeImageBytes decodes it; width and height 0), or raw texels (Assimp's
// aiTexture with mHeight != 0, as MDL files store their skins): width x height texels of 8-bit
// R, G, B, A (reordered from Assimp's b, g, r, a), row 0 first. Raw texels beyond the image limits
// (renderer/image.h) keep their declared size and no bytes; the texture reader refuses them.
struct EmbeddedImage {
    std::string name;                     // what the file calls it ("" when it has no name)
    std::string bytes;
    int width = 0, height = 0;            // > 0: raw RGBA8 texels
    bool raw() const { return width > 0 && height > 0; }
};

struct Mesh {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;       // per vertex, unit length; empty or positions.size()
    std::vector<glm::vec2> uvs;           // first UV channel; empty or positions.size()
    std::vector<glm::vec4> tangents;      // xyz unit tangent, w = +-1 handedness (bitangent =
                                          // w * cross(normal, tangent)); empty or positions.size()
    std::vector<glm::uvec3> triangles;    // counter-clockwise = front
    int material = -1;                    // index into the importer's materials, -1: none
};

struct MeshValidation {
    std::size_t droppedOutOfRange = 0;    // triangles with an index >= positions.size()
    std::size_t droppedNonFinite = 0;     // triangles with a NaN / infinite vertex position
    std::size_t droppedDegenerate = 0;    // repeated index or exactly zero area
    std::size_t fixedNormals = 0;         // non-finite or zero normals replaced
    std::size_t fixedUvs = 0;             // non-finite UVs set to 0
    bool droppedTangents = false;         // tangents cleared (wrong count or non-finite)
    bool droppedNormals = false;          // normals cleared (wrong count)
    bool droppedUvs = false;              // UVs cleared (wrong count)

    std::size_t droppedTriangles() const { return droppedOutOfRange + droppedNonFinite + droppedDegenerate; }
    // One line describing what was changed ("" when nothing): for import warnings.
    std::string summary() const;
};

// Makes a mesh safe to build a BVH over and to shade: drops triangles with out-of-range indices,
// non-finite vertices or no area (a degenerate triangle can never be hit, and its normal is
// undefined); clears attribute arrays whose size does not match the positions; replaces
// non-finite or zero normals by the area-weighted normal of the triangles around the vertex (or
// +z when none); sets non-finite UVs to 0; clears tangents when any is non-finite. Vertices are
// kept (indices stay valid). Returns what it did.
MeshValidation validateMesh(Mesh& mesh);

// Area-weighted smooth vertex normals from the triangles (+z for vertices no triangle uses).
std::vector<glm::vec3> computeVertexNormals(const std::vector<glm::vec3>& positions,
                                            const std::vector<glm::uvec3>& triangles);

// A closed UV sphere (for tests and benchmarks): single-vertex poles on +-y, `rings` bands of
// `segments` vertices between them (rings >= 2, segments >= 3), shared vertices, triangles
// counter-clockwise seen from outside. The radius towards polar angle theta (from +y) and azimuth
// phi (from +x towards +z) is radius(theta, phi); without one, 1.
Mesh makeUvSphere(std::uint32_t rings, std::uint32_t segments,
                  const std::function<float(float theta, float phi)>& radius = {});

}  // namespace caustic
