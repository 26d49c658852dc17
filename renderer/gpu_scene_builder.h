// compileScene's builder (renderer/gpu_scene.h), shared by its source files: gpu_scene.cpp (the
// order of the work, analytic primitives), gpu_scene_geometry.cpp (meshes, instances, the BVHs'
// layout), gpu_scene_lights.cpp and gpu_scene_materials.cpp. Not for other code.
#pragma once

#include "renderer/gpu_scene.h"
#include "renderer/gpu_materials.h"
#include "renderer/mesh_import.h"
#include "renderer/scene_schema.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <limits>
#include <map>
#include <utility>

namespace caustic::scene_compile {

constexpr float kPi = std::numbers::pi_v<float>;

// Light areas and powers are computed in double and must fit the float the GPU uses (issue 12):
// an area below ~1e-38 underflows to 0 and one above 3.4e38 overflows, making the light's pdf
// (distance^2 / (cos * area)) infinite or zero. The lower bound 1e-30 leaves room for that
// division by a small area at any distance up to 1e4; the upper 1e30 for the power pi * A * L.
constexpr double kMinLightArea = 1e-30, kMaxLightArea = 1e30;

// A selection weight as a float: saturates at the largest float instead of overflowing to
// infinity (which would make every pmf inf / inf = NaN).
inline float saturatedPower(double power) {
    return static_cast<float>(std::min(power, double(std::numeric_limits<float>::max())));
}

inline std::string formatShort(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

struct Builder {
    Builder(const Scene& s, const ImageReader& reader, CompiledScene& o, std::string* e, MeshCache* cache,
            CompiledScene* previous)
        : scene(s), readImage(reader), out(o), error(e), meshCache(cache), reuse(previous) {}
    const Scene& scene;
    const ImageReader& readImage;
    CompiledScene& out;
    std::string* error;
    MeshCache* meshCache;                  // may be null
    std::vector<Aabb> primBounds;          // world bounds of each analytic primitive
    std::map<std::string, std::uint32_t> meshByFile;  // imported file -> BLAS index
    // Reuse of a previous compile's mesh data (compileScene's `reuse`): decided at the start,
    // when every mesh file is the same cache entry in the same order.
    CompiledScene* reuse;
    bool reusing = false;
    std::size_t reusedVertices = 0;   // the vertex count so far, while reusing (nothing is copied)
    bool reusedLayout = false;        // the previous bvhNodes/triangles/vertices were moved in
    std::vector<gpu::GpuBvhNode> previousTlas;   // the previous top level, to restore on failure

    // What a material's emission texture does to its light's power, for light selection only: the
    // texture's mean linear RGB at level 0 (1 without a texture), floored at 1e-3 so that a dark
    // texture leaves the light selectable. The texture's mean, not the surface's (a UV layout may
    // use part of it): an estimate, which costs noise where it is off, never bias (the sampled
    // radiance is the texture's: lights/lights.glsl). Cached per material.
    std::map<std::uint32_t, glm::vec3> emissionMeans;

    // The textures loaded so far, by file (or a model file's key) and encoding: each is read once.
    std::map<std::pair<std::string, TextureEncoding>, std::uint32_t> textureIndex;

    std::vector<std::uint32_t> meshVertexBase;
    static constexpr std::uint32_t kFileMaterials = 0xffffffffu;  // addMeshInstance: use the file's
    std::vector<std::uint32_t> meshMaterialBase;          // per BLAS: its first file material
    std::vector<std::vector<std::uint32_t>> meshSlots;    // per BLAS: each triangle's file material
    // While a model file's material is loaded: its embedded images and wrap modes (textures.cpp).
    const FileTextures* fileTextures = nullptr;
    std::vector<std::vector<Material>> meshMaterials;     // per BLAS: the file's materials, mapped
    std::vector<std::vector<std::string>> meshMappingWarnings;  // reported once an object uses them
    std::vector<bool> meshTexturesLoaded;                 // per BLAS: its file materials' textures

    // The cache entry compileScene would use for a file: the cached one while the file's time
    // still matches, else null.
    std::shared_ptr<const MeshCacheEntry> cachedEntry(const std::string& file) const;

    bool canReuse() const;

    // Replaces the first `oldTop` nodes of `nodes` (a top level's reserved nodes followed by the
    // meshes' BVHs) with `top` (the new reserved nodes), moving the meshes' nodes by the
    // difference and their interior nodes' child links with them (only when the top level
    // outgrew its reserve).
    static void shiftMeshNodes(std::vector<gpu::GpuBvhNode>& nodes, std::uint32_t oldTop,
                               const std::vector<gpu::GpuBvhNode>& top);

    // After a failed compile: gives back what was moved out of *reuse.
    void restoreReuse();

    void growBounds(glm::vec3 p);

    std::uint32_t addQuad(const glm::mat4& m, std::uint32_t material, std::uint32_t flags = 0);

    std::uint32_t addSphere(const glm::mat4& m, std::uint32_t material, std::uint32_t flags = 0);

    void addLight(gpu::GpuLight l, float power, int primitive, const LightBounds& bounds);

    bool lightAreaFits(double area, const std::string& where);

    glm::vec3 emissionTextureMean(std::uint32_t material);

    bool addRectLight(std::uint32_t prim, glm::vec3 radiance, bool twoSided, const std::string& where);

    // A sphere light needs a similarity transform (sampled by the cone it subtends). One-sided: it
    // emits outwards only (nothing reaches a point inside it).
    bool addSphereLight(std::uint32_t prim, const glm::mat4& m, glm::vec3 radiance, const std::string& where,
                        bool twoSided = true);

    // Appends a material (and loads its textures unless withTextures is false) to the material table.
    bool addMaterial(const Material& m, const std::string& where, const std::string& baseDir, bool withTextures = true);
    // A surface's transmission and subsurface parts (integrator/surface_parts.glsl), appended to the
    // materials and linked from material `index` (m's); nothing for other materials.
    void addSurfaceParts(std::uint32_t index, const Material& m);

    // Loads m's textures into g's slots, each file once per encoding, relative paths against baseDir.
    bool addTextures(const Material& m, const std::string& where, const std::string& baseDir, gpu::GpuMaterial* gm);

    // Imports a file, merges its meshes and builds their BVH (prepareMesh).
    bool loadMesh(const std::string& file, const std::string& where, MeshCacheEntry* entry);

    bool importMesh(const std::string& file, const std::string& where, std::uint32_t* blasIndex);

    // The textures of a file's material k; one with a glTF metallic-roughness texture is first
    // mapped again with the texture read (mapImportedMaterial, bakeMetallicRoughness), and its
    // roughness, as GGX alpha, goes into the roughness slot.
    bool addFileMaterialTextures(std::uint32_t blas, size_t k, const std::string& file, const std::string& where);

    bool addFileMaterialTexturesWith(Material& m, gpu::GpuMaterial& g, const ImportedMaterial* im,
                                     const std::string& where);

    bool addMeshInstance(const Object& o, std::uint32_t objectIndex, const glm::mat4& m, std::uint32_t material,
                         const glm::vec3* emission, bool twoSided, const std::string& where);

    // Lays the meshes' BVHs and triangles out for the GPU and builds the top level over every
    // analytic primitive and mesh instance.
    bool finishGeometry();

    void layOutMeshes(std::vector<std::uint32_t>& rootOf, std::vector<std::uint32_t>& firstTriangleOf);

    std::uint32_t internalMaterial(glm::vec3 emission);

    bool run();
};

}  // namespace caustic::scene_compile
