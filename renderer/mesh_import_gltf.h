// What a glTF 2.0 file (.gltf or .glb) says about its materials beyond what Assimp 5.2 passes on:
// read from the file's own JSON (for a .glb its JSON chunk), so that the material extensions,
// KHR_texture_transform, the samplers' wrap modes, the alpha mode and the list of extensions the
// file uses are taken as the glTF 2.0 specification and the Khronos extension documents define
// them. Geometry, UVs and embedded images still come from Assimp (renderer/mesh_import.cpp).
// Hostile input: every value is type-checked; what is missing or malformed keeps its glTF default.
#pragma once

#include "renderer/mesh.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace caustic {

// A textureInfo: present, its UV set, its KHR_texture_transform and its sampler's wrap modes.
struct GltfTextureRef {
    bool present = false;
    int texCoord = 0;
    bool transformed = false;          // has KHR_texture_transform
    glm::vec2 offset{0.0f}, scale{1.0f};
    float rotation = 0.0f;             // radians
    std::uint32_t wrapS = kWrapRepeat, wrapT = kWrapRepeat;
    bool operator==(const GltfTextureRef&) const = default;
    // The transform in glTF's UV space (v down from the top): scale, then rotation, then offset.
    glm::vec2 apply(glm::vec2 uv) const;
};

struct GltfMaterialInfo {
    std::string name;
    GltfTextureRef baseColor, metallicRoughness, normal, emissive;
    int alphaMode = 0;                 // 0 OPAQUE, 1 MASK, 2 BLEND
    float alphaCutoff = 0.5f;
    bool doubleSided = false;
    float normalScale = 1.0f;
    bool hasIor = false;
    float ior = 1.5f;
    bool hasSpecular = false;
    float specular = 1.0f;
    glm::vec3 specularColor{1.0f};
    float clearcoat = 0.0f, clearcoatRoughness = 0.0f;
    glm::vec3 sheenColor{0.0f};
    float sheenRoughness = 0.0f;
    float transmission = 0.0f;
    glm::vec3 attenuationColor{1.0f};  // KHR_materials_volume
    float attenuationDistance = 0.0f;  // 0: absent or infinite (the extension's default)
    bool volume = false;               // KHR_materials_volume with thicknessFactor > 0 (0: thin-walled)
    float diffuseTransmission = 0.0f;  // KHR_materials_diffuse_transmission
    glm::vec3 diffuseTransmissionColor{1.0f};
    glm::vec3 emissiveFactor{0.0f};
    float emissiveStrength = 1.0f;
    std::vector<std::string> ignored;  // what the material has that is not mapped ("clearcoatTexture", ...)
};

struct GltfInfo {
    std::vector<GltfMaterialInfo> materials;
    std::vector<std::string> extensionsUsed;
};

// What Assimp 5.2.5 is to read of a glTF file (mesh_import.cpp hands it `replacement` instead of
// the file's bytes when that is not empty): valid glTF 2.0 that it cannot read safely, made
// readable where caustic loses nothing by it (a skin without inverseBindMatrices: the nodes'
// references to it dropped), with a warning each. `error` ("<path>: ...") refuses the file: its
// JSON does not parse (Assimp's reader crashes on some such files; glTF is UTF-8 JSON).
// `info`: what the file says of its materials beyond what Assimp passes on, from the same parse
// (mesh_import.cpp lays it over Assimp's materials after the import).
struct GltfForAssimp {
    std::string error;
    std::string replacement;
    std::vector<std::string> warnings;
    GltfInfo info;
};
GltfForAssimp prepareGltfForAssimp(const std::string& path);

// The material extensions this importer maps (the others in extensionsUsed are reported).
bool isMappedGltfExtension(const std::string& name);

}  // namespace caustic
