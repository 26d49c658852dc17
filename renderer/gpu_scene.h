// Scene -> the flat arrays the GPU reads (shaders/shared/layout.h). Pure CPU code: no GL, so it
// is unit-tested directly, and the Renderer only uploads what this produces.
#pragma once

#include "renderer/bvh.h"
#include "renderer/image.h"
#include "renderer/light_tree.h"
#include "renderer/mesh.h"
#include "renderer/mesh_cache.h"
#include "renderer/scene.h"
#include "shaders/shared/layout.h"

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace caustic {

// Luminance of a linear Rec. 709 / sRGB colour (ITU-R BT.709 weights): light powers, selection
// weights and the environment's sampling tables.
inline float luminance(glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

// An equirectangular environment map and the tables that importance-sample it: texel (i, j) is
// chosen with probability proportional to w_ij = luminance * sin(theta_j) (luminance taken as the
// integral of the bilinearly filtered map over the cell, so that every direction the bilinear
// lookup can light up has a non-zero pdf), over cells of 1/s texel per axis, s = 4, 2 or 1
// (buildEnvironmentMap says which and why). PBRT 4th ed. sec. 12.5.2 describes the two-level CDF.
struct EnvironmentMap {
    int width = 0, height = 0;
    int tableScale = 1;                  // the sampling table has (s width) x (s height) cells
    std::vector<glm::vec4> texels;       // RGB radiance (alpha unused), row 0 = the zenith
    std::vector<float> marginalCdf;      // s height + 1 entries, 0 ... 1
    std::vector<float> conditionalCdf;   // s height rows of s width + 1 entries, 0 ... 1
    // Guide tables (Chen and Asau 1974, "On generating random variates from an empirical
    // distribution"): for a CDF of n intervals and G = 2^log2 buckets, guide[k] (k = 0 ... G) is
    // the largest i < n with cdf[i] <= k / G, so the interval of any u in [k / G, (k + 1) / G)
    // lies in [guide[k], guide[k + 1]] and the sampler searches only there (u G is exact in
    // float for a power of two G; the interval found is the full binary search's, bit for bit).
    // Indices stored as floats (exact below 2^24).
    std::vector<float> marginalGuide;    // 2^marginalGuideLog2 + 1 entries
    std::vector<float> conditionalGuide; // s height rows of 2^conditionalGuideLog2 + 1 entries
    int marginalGuideLog2 = 0, conditionalGuideLog2 = 0;
    glm::vec3 average{0.0f};             // mean radiance over the sphere (before intensity)
};

// Builds the tables from RGB(A) pixels; fails for an empty, non-finite or negative image.
bool buildEnvironmentMap(const ImageData& image, EnvironmentMap* out, std::string* error);

// A camera's aperture image (Camera::apertureImage) as the camera reads it: its transmission per
// texel (the mean of the image's colour channels as stored, clamped to [0, 1]; an image larger
// than kMaxApertureSide a side is box-averaged down to fit), the CDF over its rows (height + 1
// entries from 0 to 1) and each row's CDF over its texels (width + 1 each).
inline constexpr int kMaxApertureSide = 256;
struct ApertureImage {
    int width = 0, height = 0;
    std::vector<float> mask, marginalCdf, conditionalCdf;
};
// False (with the reason) for an image with no texel above 0.
bool buildApertureImage(const ImageData& image, ApertureImage* out, std::string* error);
// The scene camera's aperture image read (through `readImage`) and built; errors name
// camera.aperture_image and the file.
bool readApertureImage(const Scene& scene, const ImageReader& readImage, ApertureImage* out, std::string* error);

struct CompiledScene {
    std::vector<gpu::GpuPrimitive> primitives;
    std::vector<gpu::GpuMaterial> materials;
    std::vector<gpu::GpuLight> lights;
    std::vector<float> lightCdf;        // lightCdf[i] = P(index <= i)
    std::vector<float> lightPower;      // the power each light was weighed by (W; see docs)
    int envLightIndex = -1;             // index into lights, -1 when there is no environment
    std::vector<LightBounds> lightBounds;  // per light (the environment's is empty), for the tree
    LightTree lightTree;                // over every light but the environment (renderer/light_tree.h)
    float envImportance = 0.0f;         // the environment's irradiance estimate, pi * mean luminance
    EnvironmentMap envMap;              // when the environment is a map
    std::vector<glm::uvec2> texels;     // material textures' mip chains (RGBA halves), see GpuTexture
    std::vector<gpu::GpuTexture> textures;
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};  // of all finite geometry
    ApertureImage aperture;             // the camera's aperture image (width 0: none)

    // Geometry acceleration (docs/design.md, "Geometry"): one top-level BVH over every analytic
    // primitive and every mesh instance, then one BVH per distinct mesh file.
    std::vector<gpu::GpuBvhNode> bvhNodes;        // top level at 0 (empty: nothing to hit)
    std::uint32_t tlasNodeCount = 0;
    // Nodes reserved for the top level (a power of two >= tlasNodeCount, at least 64; the rest are
    // empty): the meshes' BVHs follow, so they stay where they are, and stay uploaded, when an
    // object is added or removed beside them.
    std::uint32_t tlasNodeCapacity = 0;
    std::vector<std::uint32_t> tlasRefs;          // primitive index or TLAS_REF_INSTANCE | instance
    std::vector<gpu::GpuInstance> instances;
    // Every mesh's BVH again, 4-wide (renderer/bvh.h, collapseBvh4), for the 4-wide walk
    // (geometry/walk_wide4.glsl); an instance's root is its wideRoot.
    std::vector<gpu::GpuWideBvhNode> wideNodes;
    std::vector<gpu::GpuTriangle> triangles;
    std::vector<gpu::GpuVertex> vertices;
    std::vector<float> meshLightCdf;
    // The same meshes on the CPU (BVHs, instances, positions), for CPU queries and tests.
    SceneBvh meshBvh;
    std::vector<std::vector<glm::vec3>> meshPositions;
    std::vector<std::uint32_t> instanceObject;    // the scene object each instance came from
    std::vector<std::string> warnings;            // what mesh import reported (file: message)
    // The cache entries of the meshes, in BLAS order: what a later compile may reuse from this
    // one (compileScene's `reuse`).
    std::vector<std::shared_ptr<const struct MeshCacheEntry>> meshEntries;
};

// The mesh cache (MeshCacheEntry, MeshCache, meshCacheKey, prepareMesh): renderer/mesh_cache.h.

// Level 0 of material texture `index` (0-based), bilinear with its wrap modes: the CPU twin of
// bsdf/texture.glsl textureBilinear (renderer/textures.cpp). White for a bad index.
glm::vec4 sampleTextureLevel0(const CompiledScene& c, std::uint32_t index, glm::vec2 uv);
// The CPU twin of geometry/alpha_mask.glsl alphaMaskKeeps, for a hit of the CPU traversal (the
// triangle's slot in its BLAS, which is its place after the instance's first GPU triangle): false
// where the triangle's material cuts the point out. The editor's picking filters with it
// (intersectScene's HitFilter), so a click passes through the holes the renderer shows.
bool alphaMaskKeeps(const CompiledScene& c, std::uint32_t instance, std::uint32_t slot, float u, float v);
// The closest mesh surface the renderer shows along the ray (CPU traversal of c.meshBvh, through
// alpha cut-outs): what the editor's picking and focus overlay ask.
RayHit intersectVisibleMeshes(const CompiledScene& c, const Ray& ray);

// How a file's values become texels: sRGB-decoded, linear as they are, or linear with RGB clamped
// to [0, 1] (an HDR albedo: a surface reflects at most what it receives).
enum class TextureEncoding { Srgb, Linear, LinearReflectance };

// Appends the image and its mip chain (linear RGBA, 2x2 box filtered) to out->texels and its
// descriptor to out->textures; fails for an empty, truncated or non-finite image, or one with a
// value beyond the half-float range the GPU stores (65,504).
// wrap: GpuTexture's TEXTURE_WRAP_* bits (repeat by default).
bool addTexture(const ImageData& image, TextureEncoding encoding, CompiledScene* out, std::string* error,
                std::uint32_t wrap = 0);

// Where a model file's material textures come from: the file's embedded images ("*N" paths) and
// its samplers' wrap modes (ImportedMaterial::wrap), for readTextureImage and addTexture.
struct FileTextures {
    std::string file;                                   // the model file
    const std::vector<EmbeddedImage>* embedded = nullptr;
    std::uint32_t wraps = 0;                            // ImportedMaterial::wrap
    // The texture cache key of a path ("*N" is the file's own).
    std::string key(const std::string& path) const { return !path.empty() && path[0] == '*' ? file + path : path; }
    // The GpuTexture wrap bits of the slot named by the scene key ("albedo_texture", ...).
    std::uint32_t wrap(const std::string& slotKey) const;
};
// An image a texture slot names: a file through the reader, or (files non-null, path "*N") the
// model file's embedded image N decoded from memory. Errors name the file (and the image).
bool readTextureImage(const ImageReader& reader, const FileTextures* files, const std::string& path, ImageData* out,
                      std::string* error);
// Decodes an image file held in memory (a texture embedded in a model file: glTF's PNG or JPEG,
// told apart by their signatures) into 8-bit values as floats in [0, 1] (16-bit PNGs in 16 bits),
// without colour conversion. Errors start with `what` (the file and the texture).
bool decodeImageBytes(const std::string& bytes, const std::string& what, ImageData* out, std::string* error);
// An embedded image of raw texels (EmbeddedImage::raw()) as 8-bit RGBA values as floats in [0, 1];
// refused (the message starting with `what`) beyond the image limits or when its bytes do not
// match its size.
bool rawTexelImage(const EmbeddedImage& e, const std::string& what, ImageData* out, std::string* error);
// An image file read without OpenImageIO (the lean binaries: caustic-bench, the GPU machine's
// build): PNG and JPEG told by their signatures, decoded as decodeImageBytes does; anything else
// read as a Radiance HDR file (renderer/hdr_file.h). Errors name the file.
bool readImageWithoutOpenImageIo(const std::string& path, ImageData* out, std::string* error);

// Fails (with a message naming the scene entry, e.g. "objects[2]: ...") only for scenes that
// pass validation but cannot be rendered as given. readImage loads the files the scene names
// (environment maps; later textures), relative paths resolved against scene.sourcePath.
//
// reuse: a previous compile whose mesh data (vertices, triangles, the meshes' BVH nodes, the CPU
// BLASes) may be moved into *out instead of being laid out again, when the new scene uses the same
// mesh files, in the same order, from the same cache entries (a transform or material edit): a
// million-triangle mesh made every gizmo step cost 0.38 s of copying otherwise. What is moved is
// moved back if the compile fails, so *reuse stays valid for its owner.
bool compileScene(const Scene& scene, const ImageReader& readImage, CompiledScene* out, std::string* error,
                  MeshCache* meshCache = nullptr, CompiledScene* reuse = nullptr);
// A model file's material (glTF metallic-roughness terms and the material extensions the importer
// read) as a caustic material: KHR_materials_transmission above 0.5 -> dielectric (ior, alpha =
// roughness^2, KHR_materials_volume's attenuation colour and distance as transmission_color and
// transmission_depth), everything else the layered surface (base colour, metallic, perceptual roughness,
// ior, specular, clearcoat, sheen, emission; docs/scene-format.md lists the mapping); base colour,
// normal (with its scale), emission and metallic-roughness textures carry over, the last in the
// roughness slot (baked by bakeMetallicRoughness and wired by compileScene); alphaMode MASK and
// BLEND become AlphaMode::Mask with the factor's alpha folded into the cutoff. What does not map is appended
// to *unmapped. mr (the baked texture) is accepted for the compile's second pass and changes
// nothing in the mapping: the surface material reads metalness per texel.
Material mapImportedMaterial(const struct ImportedMaterial& in, std::vector<std::string>* unmapped,
                             const struct MetallicRoughnessMap* mr = nullptr);

// A glTF metallic-roughness texture, read: roughness and metalness per texel, each times its
// factor, for the surface material's roughness slot (shaders/bsdf/material.glsl squares the
// roughness and, with MAT_FLAG_METAL_TEXTURE, reads the metalness from G), and what its metalness
// does over the texels. Fails for an empty image or non-finite texels.
struct MetallicRoughnessMap {
    ImageData texture;            // RGB, the texture's size: R the perceptual roughness
                                  // (roughnessFactor * G), G the metalness (metallicFactor * B)
    float metalMin = 0.0f, metalMax = 0.0f, metalMean = 0.0f;
    float metalFraction = 0.0f;   // the fraction of texels whose metalness is above 0.5
};
bool bakeMetallicRoughness(const ImageData& image, float roughnessFactor, float metallicFactor,
                           MetallicRoughnessMap* out, std::string* error);

// The CDF tables as the GPU reads them: one array, in the order of GpuFrame::tables (light
// selection, environment rows, environment columns, mesh lights), then the environment's guide
// tables (GpuFrame::envGuide).
std::vector<float> packTables(const CompiledScene& compiled);
// Where packTables puts each table, without packing them (makeFrame, every dispatch):
// `tables` is frame.tables, `guides` frame.envGuide's x and y.
struct TableOffsets {
    glm::uvec4 tables{0u};
    glm::uvec2 guides{0u};
    std::uint32_t aperture = 0;   // the aperture image's row CDF, its rows' CDFs, its texels
    std::size_t total = 0;
};
TableOffsets tableOffsets(const CompiledScene& compiled);

// For scenes that name no files.
inline bool compileScene(const Scene& scene, CompiledScene* out, std::string* error) {
    return compileScene(scene, ImageReader{}, out, error);
}

// The per-dispatch constants for an image of the scene's render.width x render.height.
gpu::GpuFrame makeFrame(const Scene& scene, const CompiledScene& compiled, std::uint32_t strategy);

}  // namespace caustic
