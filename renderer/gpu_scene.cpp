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

namespace caustic {
namespace gpu {
static_assert(sizeof(GpuPrimitive) == 64);
static_assert(sizeof(GpuMaterial) == 128);
static_assert(offsetof(GpuMaterial, textures) == 96);
static_assert(sizeof(GpuTexture) == 16);
static_assert(sizeof(GpuLight) == 96);
static_assert(sizeof(GpuFrame) == 336);
static_assert(sizeof(GpuLightNode) == 64);
static_assert(offsetof(GpuLight, info) == 64);
static_assert(sizeof(GpuBvhNode) == 32 && sizeof(GpuBvhNode) == sizeof(caustic::BvhNode));
static_assert(sizeof(GpuInstance) == 144);
static_assert(sizeof(GpuWideBvhNode) == 64);
static_assert(sizeof(GpuTriangle) == 64);
static_assert(sizeof(GpuVertex) == 32);
static_assert(offsetof(GpuFrame, envZenith) == 160);
}  // namespace gpu

namespace {
constexpr float kPi = std::numbers::pi_v<float>;

// Light areas and powers are computed in double and must fit the float the GPU uses (issue 12):
// an area below ~1e-38 underflows to 0 and one above 3.4e38 overflows, making the light's pdf
// (distance^2 / (cos * area)) infinite or zero. The lower bound 1e-30 leaves room for that
// division by a small area at any distance up to 1e4; the upper 1e30 for the power pi * A * L.
constexpr double kMinLightArea = 1e-30, kMaxLightArea = 1e30;

// A selection weight as a float: saturates at the largest float instead of overflowing to
// infinity (which would make every pmf inf / inf = NaN).
float saturatedPower(double power) {
    return static_cast<float>(std::min(power, double(std::numeric_limits<float>::max())));
}

std::string formatShort(double x) {
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

    // The cache entry compileScene would use for a file: the cached one while the file's time
    // still matches, else null.
    std::shared_ptr<const MeshCacheEntry> cachedEntry(const std::string& file) const {
        if (!meshCache) return nullptr;
        std::error_code ec;
        const auto stamp = std::filesystem::last_write_time(file, ec);
        std::shared_ptr<const MeshCacheEntry> entry = meshCache->find(file);
        return entry && !ec && entry->stamp == stamp ? entry : nullptr;
    }

    bool canReuse() const {
        if (!reuse || !meshCache) return false;
        std::vector<std::string> files;
        for (const Object& o : scene.objects) {
            if (o.shape != Shape::Mesh) continue;
            const std::string key = meshCacheKey(scene, o.file);
            if (std::find(files.begin(), files.end(), key) == files.end()) files.push_back(key);
        }
        if (files.empty() || files.size() != reuse->meshEntries.size() || files.size() != reuse->meshBvh.blases.size() ||
            files.size() != reuse->meshPositions.size())
            return false;
        for (std::size_t i = 0; i < files.size(); ++i)
            if (!reuse->meshEntries[i] || cachedEntry(files[i]) != reuse->meshEntries[i]) return false;
        return true;
    }

    // Replaces the first `oldTop` nodes of `nodes` (a top level's reserved nodes followed by the
    // meshes' BVHs) with `top` (the new reserved nodes), moving the meshes' nodes by the
    // difference and their interior nodes' child links with them (only when the top level
    // outgrew its reserve).
    static void shiftMeshNodes(std::vector<gpu::GpuBvhNode>& nodes, std::uint32_t oldTop,
                               const std::vector<gpu::GpuBvhNode>& top) {
        const auto newTop = static_cast<std::uint32_t>(top.size());
        if (newTop != oldTop) {
            nodes.erase(nodes.begin(), nodes.begin() + oldTop);
            nodes.insert(nodes.begin(), top.begin(), top.end());
            for (std::size_t i = newTop; i < nodes.size(); ++i)
                if ((nodes[i].countAndAxis >> 2) == 0) nodes[i].rightOrFirst = nodes[i].rightOrFirst - oldTop + newTop;
        } else {
            std::copy(top.begin(), top.end(), nodes.begin());
        }
    }

    // After a failed compile: gives back what was moved out of *reuse.
    void restoreReuse() {
        if (!reusing) return;
        for (std::size_t i = 0; i < out.meshBvh.blases.size(); ++i) {
            reuse->meshBvh.blases[i] = std::move(out.meshBvh.blases[i]);
            reuse->meshPositions[i] = std::move(out.meshPositions[i]);
        }
        if (reusedLayout) {
            reuse->bvhNodes = std::move(out.bvhNodes);
            shiftMeshNodes(reuse->bvhNodes, out.tlasNodeCapacity, previousTlas);
            reuse->triangles = std::move(out.triangles);
            reuse->vertices = std::move(out.vertices);
        }
    }

    void growBounds(glm::vec3 p) {
        out.boundsMin = glm::min(out.boundsMin, p);
        out.boundsMax = glm::max(out.boundsMax, p);
    }

    std::uint32_t addQuad(const glm::mat4& m, std::uint32_t material, std::uint32_t flags = 0) {
        gpu::GpuPrimitive p{};
        glm::vec3 corner = glm::vec3(m * glm::vec4(-1, -1, 0, 1));
        glm::vec3 eu = glm::vec3(m * glm::vec4(2, 0, 0, 0));
        glm::vec3 ev = glm::vec3(m * glm::vec4(0, 2, 0, 0));
        p.a = glm::vec4(corner, 0);
        p.b = glm::vec4(eu, 0);
        p.c = glm::vec4(ev, 0);
        p.info = glm::uvec4(PRIM_QUAD, material, 0, flags);
        Aabb box;
        for (glm::vec3 q : {corner, corner + eu, corner + ev, corner + eu + ev}) {
            growBounds(q);
            box.grow(q);
        }
        // A flat box is fine for the slab test, but give it a sliver of thickness so that
        // rounding cannot make it empty.
        const glm::vec3 pad = 1e-6f * (glm::abs(box.min) + glm::abs(box.max)) + 1e-20f;
        primBounds.push_back({box.min - pad, box.max + pad});
        out.primitives.push_back(p);
        return static_cast<std::uint32_t>(out.primitives.size() - 1);
    }

    std::uint32_t addSphere(const glm::mat4& m, std::uint32_t material, std::uint32_t flags = 0) {
        glm::mat4 w2o = glm::inverse(m);
        glm::mat4 rows = glm::transpose(w2o);  // rows of w2o as columns
        gpu::GpuPrimitive p{};
        p.a = rows[0];
        p.b = rows[1];
        p.c = rows[2];
        p.info = glm::uvec4(PRIM_SPHERE, material, 0, flags);
        // Bounds of the transformed unit sphere: |row_i of the linear part| around the centre.
        glm::vec3 c = glm::vec3(m[3]);
        glm::mat3 lin(m);
        glm::vec3 ext(glm::length(glm::vec3(lin[0].x, lin[1].x, lin[2].x)),
                      glm::length(glm::vec3(lin[0].y, lin[1].y, lin[2].y)),
                      glm::length(glm::vec3(lin[0].z, lin[1].z, lin[2].z)));
        growBounds(c - ext);
        growBounds(c + ext);
        primBounds.push_back({c - ext, c + ext});
        out.primitives.push_back(p);
        return static_cast<std::uint32_t>(out.primitives.size() - 1);
    }

    void addLight(gpu::GpuLight l, float power, int primitive, const LightBounds& bounds) {
        if (primitive >= 0) {
            out.primitives[primitive].info.z = static_cast<std::uint32_t>(out.lights.size() + 1);
            l.info.z = static_cast<std::uint32_t>(primitive);
            if (out.materials[out.primitives[primitive].info.y].textures.w != 0u) l.info.y |= LIGHT_FLAG_EMISSION_TEXTURE;
        }
        out.lights.push_back(l);
        out.lightPower.push_back(power);
        out.lightBounds.push_back(bounds);
    }

    bool lightAreaFits(double area, const std::string& where) {
        if (area >= kMinLightArea && area <= kMaxLightArea) return true;
        *error = where + ": the emitter's area (" + formatShort(area) +
                 ") is outside what the renderer's 32-bit floats handle (1e-30 to 1e30 square units); scale it";
        return false;
    }

    // What a material's emission texture does to its light's power, for light selection only: the
    // texture's mean linear RGB at level 0 (1 without a texture), floored at 1e-3 so that a dark
    // texture leaves the light selectable. The texture's mean, not the surface's (a UV layout may
    // use part of it): an estimate, which costs noise where it is off, never bias (the sampled
    // radiance is the texture's: lights/lights.glsl). Cached per material.
    std::map<std::uint32_t, glm::vec3> emissionMeans;
    glm::vec3 emissionTextureMean(std::uint32_t material) {
        const std::uint32_t slot = out.materials[material].textures.w;
        if (slot == 0) return glm::vec3(1.0f);
        if (auto found = emissionMeans.find(material); found != emissionMeans.end()) return found->second;
        const gpu::GpuTexture& t = out.textures[slot - 1];
        const size_t n = size_t(t.info.y) * size_t(t.info.z);
        glm::dvec3 sum(0.0);
        for (size_t i = 0; i < n && t.info.x + i < out.texels.size(); ++i) {
            const glm::uvec2 h = out.texels[t.info.x + i];
            sum += glm::dvec3(glm::unpackHalf2x16(h.x).x, glm::unpackHalf2x16(h.x).y, glm::unpackHalf2x16(h.y).x);
        }
        const glm::vec3 mean = glm::max(glm::vec3(sum / double(std::max<size_t>(n, 1))), glm::vec3(1e-3f));
        emissionMeans.emplace(material, mean);
        return mean;
    }

    bool addRectLight(std::uint32_t prim, glm::vec3 radiance, bool twoSided, const std::string& where) {
        const auto& p = out.primitives[prim];
        gpu::GpuLight l{};
        const double areaD = glm::length(glm::cross(glm::dvec3(glm::vec3(p.b)), glm::dvec3(glm::vec3(p.c))));
        if (!lightAreaFits(areaD, where)) return false;
        const float area = static_cast<float>(areaD);
        l.p0 = p.a;
        l.p1 = glm::vec4(glm::vec3(p.b), area);
        l.p2 = p.c;
        l.color = glm::vec4(radiance, 0);
        l.info = glm::uvec4(LIGHT_RECT, twoSided ? LIGHT_FLAG_TWO_SIDED : 0u, 0, 0);
        LightBounds bounds;
        const glm::vec3 o(p.a), u(p.b), v(p.c);
        bounds.boundsMin = glm::min(glm::min(o, o + u), glm::min(o + v, o + u + v));
        bounds.boundsMax = glm::max(glm::max(o, o + u), glm::max(o + v, o + u + v));
        const glm::vec3 n = glm::cross(u, v);
        bounds.axis = glm::length(n) > 0.0f ? n / glm::length(n) : glm::vec3(0, 0, 1);
        bounds.cosThetaO = twoSided ? -1.0f : 1.0f;
        const float y = luminance(radiance * emissionTextureMean(p.info.y));
        bounds.intensity = saturatedPower(areaD * y);
        addLight(l, saturatedPower(kPi * areaD * y * (twoSided ? 2.0 : 1.0)), static_cast<int>(prim), bounds);
        return true;
    }

    // A sphere light needs a similarity transform (sampled by the cone it subtends). One-sided: it
    // emits outwards only (nothing reaches a point inside it).
    bool addSphereLight(std::uint32_t prim, const glm::mat4& m, glm::vec3 radiance, const std::string& where,
                        bool twoSided = true) {
        glm::mat3 lin(m);
        float sx = glm::length(lin[0]), sy = glm::length(lin[1]), sz = glm::length(lin[2]);
        float tol = 1e-4f * std::max({sx, sy, sz});
        if (std::abs(sx - sy) > tol || std::abs(sx - sz) > tol || std::abs(glm::dot(lin[0], lin[1])) > tol * sx ||
            std::abs(glm::dot(lin[0], lin[2])) > tol * sx || std::abs(glm::dot(lin[1], lin[2])) > tol * sx) {
            *error = where + ": an emissive sphere must be uniformly scaled (it is sampled as a sphere light)";
            return false;
        }
        if (!lightAreaFits(4.0 * kPi * double(sx) * sx, where)) return false;
        gpu::GpuLight l{};
        l.p0 = glm::vec4(glm::vec3(m[3]), sx);
        l.color = glm::vec4(radiance, 0);
        l.info = glm::uvec4(LIGHT_SPHERE, twoSided ? LIGHT_FLAG_TWO_SIDED : 0u, 0, 0);
        LightBounds bounds;
        bounds.boundsMin = glm::vec3(m[3]) - sx;
        bounds.boundsMax = glm::vec3(m[3]) + sx;
        const float y = luminance(radiance * emissionTextureMean(out.primitives[prim].info.y));
        bounds.intensity = saturatedPower(kPi * double(sx) * sx * y);
        addLight(l, saturatedPower(kPi * 4.0 * kPi * double(sx) * sx * y), static_cast<int>(prim), bounds);
        return true;
    }

    // Imports a model file once (every object using it shares its BVH), merging its meshes.
    std::map<std::pair<std::string, TextureEncoding>, std::uint32_t> textureIndex;

    // Appends a material (and loads its textures unless withTextures is false) to the material table.
    bool addMaterial(const Material& m, const std::string& where, const std::string& baseDir, bool withTextures = true) {
        gpu::GpuMaterial g = convertMaterial(m);
        if (withTextures && !addTextures(m, where, baseDir, &g)) return false;
        out.materials.push_back(g);
        return true;
    }

    // Loads m's textures into g's slots, each file once per encoding, relative paths against baseDir.
    bool addTextures(const Material& m, const std::string& where, const std::string& baseDir, gpu::GpuMaterial* gm) {
        gpu::GpuMaterial& g = *gm;
        auto texture = [&](const std::string& name, const char* key, TextureEncoding enc, std::uint32_t* slot) {
            if (name.empty()) return true;
            const std::filesystem::path file(resolvePathIn(baseDir, name));
            // A model file's embedded image ("*N") is its file's: the key names both.
            const auto cacheKey = std::make_pair(fileTextures ? fileTextures->key(name) : file.string(), enc);
            if (auto found = textureIndex.find(cacheKey); found != textureIndex.end()) {
                *slot = found->second + 1;
                return true;
            }
            const std::string context = where + "." + key + " (material '" + m.name + "'): ";
            ImageData image;
            std::string why;
            if (!readTextureImage(readImage, fileTextures, file.string(), &image, &why)) {
                *error = context + why;
                return false;
            }
            const std::uint32_t wrap = fileTextures ? fileTextures->wrap(key) : 0u;
            if (!addTexture(image, enc, &out, &why, wrap)) {
                *error = context + file.string() + ": " + why;
                return false;
            }
            *slot = static_cast<std::uint32_t>(out.textures.size());
            textureIndex.emplace(cacheKey, *slot - 1);
            return true;
        };
        const std::string ext = std::filesystem::path(m.albedoTexture).extension().string();
        const bool hdr = ext == ".hdr" || ext == ".exr" || ext == ".HDR" || ext == ".EXR" || ext == ".pfm";
        if (!texture(m.albedoTexture, "albedo_texture", hdr ? TextureEncoding::Linear : TextureEncoding::Srgb,
                     &g.textures.x) ||
            !texture(m.normalTexture, "normal_texture", TextureEncoding::Linear, &g.textures.y) ||
            !texture(m.roughnessTexture, "roughness_texture", TextureEncoding::Linear, &g.textures.z))
            return false;
        const std::string emissionExt = std::filesystem::path(m.emissionTexture).extension().string();
        const bool emissionHdr = emissionExt == ".hdr" || emissionExt == ".exr" || emissionExt == ".HDR" ||
                                 emissionExt == ".EXR" || emissionExt == ".pfm";
        if (!texture(m.emissionTexture, "emission_texture", emissionHdr ? TextureEncoding::Linear : TextureEncoding::Srgb,
                     &g.textures.w))
            return false;
        return true;
    }

    // Imports a file, merges its meshes and builds their BVH (prepareMesh).
    bool loadMesh(const std::string& file, const std::string& where, MeshCacheEntry* entry) {
        std::string why;
        if (prepareMesh(file, entry, &why)) return true;
        *error = where + ".file: " + why;
        return false;
    }

    bool importMesh(const std::string& file, const std::string& where, std::uint32_t* blasIndex) {
        if (auto it = meshByFile.find(file); it != meshByFile.end()) {
            *blasIndex = it->second;
            return true;
        }
        std::shared_ptr<const MeshCacheEntry> entry = cachedEntry(file);
        if (!entry) {
            auto made = std::make_shared<MeshCacheEntry>();
            if (!loadMesh(file, where, made.get())) return false;
            entry = made;
            if (meshCache) meshCache->insert(file, entry);
        }
        for (const std::string& w : entry->warnings) out.warnings.push_back(w);
        meshMaterialBase.push_back(static_cast<std::uint32_t>(out.materials.size()));
        // The file's textures wait until an object uses the file's own materials (addMeshInstance):
        // a model whose objects all have scene materials imports even if its textures are missing.
        for (size_t k = 0; k < entry->materials.size(); ++k)
            addMaterial(entry->materials[k], where, "", false);
        meshTexturesLoaded.push_back(false);
        meshSlots.push_back(entry->triangleSlot);
        meshMaterials.push_back(entry->materials);
        meshMappingWarnings.push_back(entry->mappingWarnings);
        out.meshEntries.push_back(entry);
        std::uint32_t vertexBase;
        if (reusing) {  // the same entry as the previous compile's BLAS of this index: move it
            const std::size_t index = out.meshBvh.blases.size();
            out.meshBvh.blases.push_back(std::move(reuse->meshBvh.blases[index]));
            out.meshPositions.push_back(std::move(reuse->meshPositions[index]));
            vertexBase = static_cast<std::uint32_t>(reusedVertices);
            reusedVertices += entry->vertices.size();
        } else {
            vertexBase = static_cast<std::uint32_t>(out.vertices.size());
            out.vertices.insert(out.vertices.end(), entry->vertices.begin(), entry->vertices.end());
            out.meshBvh.blases.push_back(entry->blas);
            out.meshPositions.push_back(entry->positions);
        }
        meshVertexBase.push_back(vertexBase);
        *blasIndex = static_cast<std::uint32_t>(out.meshBvh.blases.size() - 1);
        meshByFile.emplace(file, *blasIndex);
        return true;
    }
    std::vector<std::uint32_t> meshVertexBase;
    static constexpr std::uint32_t kFileMaterials = 0xffffffffu;  // addMeshInstance: use the file's
    std::vector<std::uint32_t> meshMaterialBase;          // per BLAS: its first file material
    std::vector<std::vector<std::uint32_t>> meshSlots;    // per BLAS: each triangle's file material
    // While a model file's material is loaded: its embedded images and wrap modes (textures.cpp).
    const FileTextures* fileTextures = nullptr;
    std::vector<std::vector<Material>> meshMaterials;     // per BLAS: the file's materials, mapped
    std::vector<std::vector<std::string>> meshMappingWarnings;  // reported once an object uses them
    std::vector<bool> meshTexturesLoaded;                 // per BLAS: its file materials' textures

    // The textures of a file's material k; one with a glTF metallic-roughness texture is first
    // mapped again with the texture read (mapImportedMaterial, bakeMetallicRoughness), and its
    // roughness, as GGX alpha, goes into the roughness slot.
    bool addFileMaterialTextures(std::uint32_t blas, size_t k, const std::string& file, const std::string& where) {
        Material& m = meshMaterials[blas][k];
        gpu::GpuMaterial& g = out.materials[meshMaterialBase[blas] + k];
        const std::vector<ImportedMaterial>& imported = out.meshEntries[blas]->imported;
        const ImportedMaterial* im = k < imported.size() ? &imported[k] : nullptr;
        const FileTextures files{file, &out.meshEntries[blas]->embedded, im ? im->wrap : 0u};
        fileTextures = &files;
        const bool ok = addFileMaterialTexturesWith(m, g, im, where);
        fileTextures = nullptr;
        return ok;
    }

    bool addFileMaterialTexturesWith(Material& m, gpu::GpuMaterial& g, const ImportedMaterial* im,
                                     const std::string& where) {
        if (!im || im->metallicRoughnessTexture.empty()) return addTextures(m, where, "", &g);
        const std::string& texture = im->metallicRoughnessTexture;
        const std::string context = where + ".metallic_roughness_texture (material '" + m.name + "'): ";
        ImageData image;
        MetallicRoughnessMap mr;
        std::string why;
        if (!readTextureImage(readImage, fileTextures, texture, &image, &why)) {
            *error = context + why;
            return false;
        }
        if (!bakeMetallicRoughness(image, im->roughness, im->metallic, &mr, &why)) {
            *error = context + texture + ": " + why;
            return false;
        }
        std::vector<std::string> unmapped;  // the same as the import's mapping reported (mappingWarnings)
        m = mapImportedMaterial(*im, &unmapped, &mr);
        Material others = m;   // albedo and normal maps as usual; the roughness slot is filled here
        others.roughnessTexture.clear();
        g = convertMaterial(m);
        if (!addTextures(others, where, "", &g)) return false;
        if (m.roughnessTexture.empty()) return true;  // diffuse: no roughness to map
        // One baked texture per (file, roughness factor): the factor is part of every texel.
        char factor[32];
        std::snprintf(factor, sizeof factor, "%.9g", double(im->roughness));
        const auto cacheKey = std::make_pair("glTF metallic-roughness x" + std::string(factor) + " " + fileTextures->key(texture),
                                             TextureEncoding::Linear);
        if (m.type == MaterialType::Surface) g.info.y |= MAT_FLAG_METAL_TEXTURE;
        if (auto found = textureIndex.find(cacheKey); found != textureIndex.end()) {
            g.textures.z = found->second + 1;
            return true;
        }
        if (!addTexture(mr.texture, TextureEncoding::Linear, &out, &why, fileTextures->wrap("roughness_texture"))) {
            *error = context + texture + ": " + why;
            return false;
        }
        g.textures.z = static_cast<std::uint32_t>(out.textures.size());
        textureIndex.emplace(cacheKey, g.textures.z - 1);
        return true;
    }

    bool addMeshInstance(const Object& o, std::uint32_t objectIndex, const glm::mat4& m, std::uint32_t material,
                         const glm::vec3* emission, bool twoSided, const std::string& where) {
        std::uint32_t blas = 0;
        if (!importMesh(meshCacheKey(scene, o.file), where, &blas)) return false;
        const glm::mat4 w2o = glm::inverse(m);
        if (!std::isfinite(glm::determinant(m)) || std::abs(glm::determinant(glm::mat3(m))) < 1e-30f) {
            *error = where + ".transform: not invertible";
            return false;
        }
        out.meshBvh.instances.push_back({blas, m});
        out.meshBvh.worldToObject.push_back(w2o);
        out.instanceObject.push_back(objectIndex);
        const glm::mat4 w2oRows = glm::transpose(w2o), o2wRows = glm::transpose(m);
        gpu::GpuInstance gi{};
        gi.worldToObject0 = w2oRows[0];
        gi.worldToObject1 = w2oRows[1];
        gi.worldToObject2 = w2oRows[2];
        gi.objectToWorld0 = o2wRows[0];
        gi.objectToWorld1 = o2wRows[1];
        gi.objectToWorld2 = o2wRows[2];
        const bool fromFile = material == kFileMaterials;
        if (fromFile && !meshTexturesLoaded[blas]) {
            const std::string file = meshCacheKey(scene, o.file);
            for (size_t k = 0; k < meshMaterials[blas].size(); ++k)
                if (!addFileMaterialTextures(blas, k, file, where + ".file (" + file + ") material " + std::to_string(k)))
                    return false;
            meshTexturesLoaded[blas] = true;
        }
        if (fromFile) {
            for (const std::string& w : meshMappingWarnings[blas]) out.warnings.push_back(w);
            meshMappingWarnings[blas].clear();  // once per file
        }
        gi.info = glm::uvec4(0, 0, fromFile ? meshMaterialBase[blas] : material, 0);  // offsets: finishGeometry
        // Whether traversal must test the mesh's hits against an alpha mask (geometry/alpha_mask.glsl).
        bool masked = false;
        if (fromFile) {
            for (size_t k = 0; k < meshMaterials[blas].size(); ++k)
                masked = masked || (out.materials[meshMaterialBase[blas] + k].info.y & MAT_FLAG_ALPHA_MASK) != 0u;
        } else {
            masked = (out.materials[material].info.y & MAT_FLAG_ALPHA_MASK) != 0u;
        }
        gi.info2 = glm::uvec4(meshVertexBase[blas], out.meshBvh.blases[blas].triangles.size(), fromFile ? 1u : 0u,
                              (twoSided ? 0u : PRIM_FLAG_ONE_SIDED_EMITTER) | (masked ? PRIM_FLAG_ALPHA_MASK : 0u));
        out.instances.push_back(gi);
        const Aabb local = out.meshBvh.blases[blas].bvh.nodes.front().bounds();
        for (int c = 0; c < 8; ++c) {
            const glm::vec3 corner((c & 1) ? local.max.x : local.min.x, (c & 2) ? local.max.y : local.min.y,
                                   (c & 4) ? local.max.z : local.min.z);
            growBounds(glm::vec3(m * glm::vec4(corner, 1.0f)));
        }
        // An emissive mesh is a light: triangles chosen by world area times emitted luminance
        // (only emitting triangles), then a uniform point; each triangle's radiance comes from
        // its material in the shader.
        const MeshBlas& meshBlas = out.meshBvh.blases[blas];
        auto triangleEmission = [&](std::uint32_t k) -> glm::vec3 {
            if (!fromFile) return emission ? *emission : glm::vec3(0.0f);
            return meshMaterials[blas][meshSlots[blas][meshBlas.triangleIds[k]]].emission;
        };
        bool anyEmission = false;
        for (std::uint32_t k = 0; k < meshBlas.triangles.size() && !anyEmission; ++k)
            anyEmission = luminance(triangleEmission(k)) > 0.0f;
        if (anyEmission) {
            const MeshBlas& b = meshBlas;
            const std::vector<glm::vec3>& pos = out.meshPositions[blas];
            gpu::GpuLight l{};
            const auto cdfOffset = static_cast<std::uint32_t>(out.meshLightCdf.size());
            double total = 0.0, power = 0.0;
            std::vector<double> areas;
            std::vector<glm::dvec3> normals;  // unit front normals of the emitting triangles (world)
            // Of the emitting triangles; a two-sided mesh's normals point every way.
            LightBounds bounds;
            bounds.boundsMin = glm::vec3(std::numeric_limits<float>::max());
            bounds.boundsMax = glm::vec3(-std::numeric_limits<float>::max());
            // Front normals as the shader computes them: the object-space cross product under the
            // inverse transpose (lights/lights.glsl, geometry/intersect.glsl).
            const glm::dmat3 normalMatrix = glm::transpose(glm::dmat3(glm::mat3(w2o)));
            for (std::uint32_t k = 0; k < b.triangles.size(); ++k) {
                const glm::uvec3 t = b.triangles[k];
                const glm::vec3 p0 = glm::vec3(m * glm::vec4(pos[t.x], 1)), p1 = glm::vec3(m * glm::vec4(pos[t.y], 1)),
                                p2 = glm::vec3(m * glm::vec4(pos[t.z], 1));
                const double a = 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
                const double y = luminance(triangleEmission(k));
                areas.push_back(std::isfinite(a) && y > 0.0 ? a : 0.0);
                if (areas.back() > 0.0) {
                    bounds.boundsMin = glm::min(bounds.boundsMin, glm::min(p0, glm::min(p1, p2)));
                    bounds.boundsMax = glm::max(bounds.boundsMax, glm::max(p0, glm::max(p1, p2)));
                    const glm::dvec3 q0(pos[t.x]), q1(pos[t.y]), q2(pos[t.z]);
                    const glm::dvec3 n = normalMatrix * glm::cross(q1 - q0, q2 - q0);
                    if (glm::length(n) > 0.0) normals.push_back(glm::normalize(n));
                }
                total += areas.back();
                if (areas.back() > 0.0) {
                    const std::uint32_t mat =
                        fromFile ? meshMaterialBase[blas] + meshSlots[blas][meshBlas.triangleIds[k]] : material;
                    power += areas.back() * luminance(triangleEmission(k) * emissionTextureMean(mat));
                }
            }
            if (!(total > 0.0)) {
                *error = where + ": an emissive mesh needs a non-zero area";
                return false;
            }
            double run = 0.0;
            for (double a : areas) {
                run += a / total;
                out.meshLightCdf.push_back(static_cast<float>(run));
            }
            out.meshLightCdf.back() = 1.0f;
            const auto instance = static_cast<std::uint32_t>(out.instances.size() - 1);
            l.p0 = glm::vec4(static_cast<float>(total), 0, 0, 0);
            l.color = glm::vec4(static_cast<float>(power / total));  // mean luminance (informative)
            bool textured = false;  // some emitting triangle's material has an emission texture
            for (std::uint32_t k = 0; k < b.triangles.size() && !textured; ++k) {
                if (!(areas[k] > 0.0)) continue;
                const std::uint32_t mat = fromFile ? meshMaterialBase[blas] + meshSlots[blas][meshBlas.triangleIds[k]] : material;
                textured = out.materials[mat].textures.w != 0u;
            }
            l.info = glm::uvec4(LIGHT_MESH, (twoSided ? LIGHT_FLAG_TWO_SIDED : 0u) | (textured ? LIGHT_FLAG_EMISSION_TEXTURE : 0u),
                                instance, cdfOffset);
            out.instances.back().info.w = static_cast<std::uint32_t>(out.lights.size() + 1);
            out.lights.push_back(l);
            out.lightPower.push_back(static_cast<float>((twoSided ? 2.0 : 1.0) * std::numbers::pi * power));
            bounds.intensity = static_cast<float>(power);  // sum of L A: each face of a flat mesh
            if (!twoSided) {
                // One-sided: a cone around the mean front normal holding every triangle's normal
                // (all directions when they cancel out: a closed mesh), emitting up to 90 degrees
                // beyond it.
                glm::dvec3 sum(0.0);
                for (const glm::dvec3& n : normals) sum += n;
                if (glm::length(sum) > 1e-6 * double(normals.size())) {
                    const glm::dvec3 axis = glm::normalize(sum);
                    double cosO = 1.0;
                    for (const glm::dvec3& n : normals) cosO = std::min(cosO, glm::dot(n, axis));
                    bounds.axis = glm::vec3(axis);
                    // Rounding must not leave a normal outside the cone.
                    bounds.cosThetaO = static_cast<float>(std::max(-1.0, cosO - 1e-6));
                }
            }
            out.lightBounds.push_back(bounds);
        }
        return true;
    }

    // Lays the meshes' BVHs and triangles out for the GPU and builds the top level over every
    // analytic primitive and mesh instance.
    bool finishGeometry() {
        std::vector<Aabb> bounds = primBounds;
        std::vector<std::uint32_t> refs;
        for (std::uint32_t i = 0; i < primBounds.size(); ++i) refs.push_back(i);
        const std::vector<Aabb> instBounds = instanceWorldBounds(out.meshBvh.blases, out.meshBvh.instances);
        for (std::uint32_t i = 0; i < instBounds.size(); ++i) {
            bounds.push_back(instBounds[i]);
            refs.push_back(TLAS_REF_INSTANCE | i);
        }
        BvhBuildOptions tlasOptions;
        tlasOptions.maxLeafSize = 1;  // a leaf is one primitive or one instance
        Bvh tlas = buildBvh(bounds, tlasOptions);
        out.bvhNodes.clear();
        for (const BvhNode& n : tlas.nodes) out.bvhNodes.push_back(std::bit_cast<gpu::GpuBvhNode>(n));
        out.tlasNodeCount = static_cast<std::uint32_t>(tlas.nodes.size());
        out.tlasNodeCapacity = out.tlasNodeCount == 0 ? 0u : std::max(64u, std::bit_ceil(out.tlasNodeCount));
        out.bvhNodes.resize(out.tlasNodeCapacity, gpu::GpuBvhNode{});
        out.tlasRefs.clear();
        for (std::uint32_t id : tlas.primIndices) out.tlasRefs.push_back(refs[id]);
        // Each mesh's BVH after the top level, its triangles in leaf order.
        std::vector<std::uint32_t> rootOf, firstTriangleOf;
        if (reusing) {
            // The previous compile laid out the same meshes after its top level: take its arrays
            // and put the new top level in place of the old one (the same size after a transform
            // edit; after adding or removing a primitive the meshes' nodes shift, and their
            // child links with them).
            std::uint32_t root = out.tlasNodeCapacity, first = 0;
            for (const MeshBlas& blas : out.meshBvh.blases) {
                rootOf.push_back(root);
                firstTriangleOf.push_back(first);
                root += static_cast<std::uint32_t>(blas.bvh.nodes.size());
                first += static_cast<std::uint32_t>(blas.triangles.size());
            }
            std::vector<gpu::GpuBvhNode> tlasNodes = std::move(out.bvhNodes);
            previousTlas.assign(reuse->bvhNodes.begin(), reuse->bvhNodes.begin() + reuse->tlasNodeCapacity);
            out.bvhNodes = std::move(reuse->bvhNodes);
            shiftMeshNodes(out.bvhNodes, reuse->tlasNodeCapacity, tlasNodes);
            out.triangles = std::move(reuse->triangles);
            out.vertices = std::move(reuse->vertices);
            reusedLayout = true;
        } else {
            layOutMeshes(rootOf, firstTriangleOf);
        }
        for (size_t i = 0; i < out.instances.size(); ++i) {
            const std::uint32_t b = out.meshBvh.instances[i].mesh;
            out.instances[i].info.x = rootOf[b];
            out.instances[i].info.y = firstTriangleOf[b];
        }
        out.meshBvh.tlas = Bvh{};  // the CPU mirror of the mesh-only top level, for CPU queries
        buildTlas(out.meshBvh);
        // Each mesh's BVH in its 4-wide form (CAUSTIC_WIDE_BVH), and where asked for as pair
        // records (CAUSTIC_PAIR_BVH) and 8-wide nodes (CAUSTIC_WIDE_BVH=8), made with its cache
        // entry and placed here (a copy and an add; an entry without one appends nothing).
        out.wideNodes.clear();
        out.pairNodes.clear();
        out.wide8Nodes.clear();
        std::vector<std::uint32_t> wideRootOf, pairRootOf, wide8RootOf;
        for (const auto& entry : out.meshEntries) {
            wideRootOf.push_back(static_cast<std::uint32_t>(out.wideNodes.size()));
            appendWideBvh(entry->wideNodes, wideRootOf.back(), out.wideNodes);
            pairRootOf.push_back(static_cast<std::uint32_t>(out.pairNodes.size()));
            appendPairBvh(entry->pairNodes, pairRootOf.back(), out.pairNodes);
            wide8RootOf.push_back(static_cast<std::uint32_t>(out.wide8Nodes.size()));
            if (!appendWide8Bvh(entry->wide8Nodes, wide8RootOf.back(), out.wide8Nodes)) {
                *error = "the scene's meshes need more than 2^24 / 6 8-wide BVH nodes (CAUSTIC_WIDE_BVH=8)";
                return false;
            }
        }
        for (size_t i = 0; i < out.instances.size(); ++i) {
            const std::uint32_t mesh = out.meshBvh.instances[i].mesh;
            out.instances[i].info3 = glm::uvec4(wideRootOf[mesh], pairRootOf[mesh], wide8RootOf[mesh], 0);
        }
        return true;
    }

    void layOutMeshes(std::vector<std::uint32_t>& rootOf, std::vector<std::uint32_t>& firstTriangleOf) {
        for (size_t b = 0; b < out.meshBvh.blases.size(); ++b) {
            const MeshBlas& blas = out.meshBvh.blases[b];
            rootOf.push_back(static_cast<std::uint32_t>(out.bvhNodes.size()));
            firstTriangleOf.push_back(static_cast<std::uint32_t>(out.triangles.size()));
            for (BvhNode n : blas.bvh.nodes) {
                if (n.isLeaf()) {
                    // Leaf ranges index the mesh's reordered triangles: keep them relative.
                } else {
                    n.rightOrFirst += rootOf.back();
                }
                out.bvhNodes.push_back(std::bit_cast<gpu::GpuBvhNode>(n));
            }
            const std::vector<glm::vec3>& pos = out.meshPositions[b];
            for (size_t k = 0; k < blas.triangles.size(); ++k) {
                const glm::uvec3 t = blas.triangles[k];
                gpu::GpuTriangle gt{};
                gt.p0 = glm::vec4(pos[t.x], std::bit_cast<float>(meshSlots[b][blas.triangleIds[k]]));
                gt.p1 = glm::vec4(pos[t.y], 0);
                gt.p2 = glm::vec4(pos[t.z], 0);
                gt.v = glm::uvec4(t + glm::uvec3(meshVertexBase[b]), blas.triangleIds[k]);
                out.triangles.push_back(gt);
            }
        }
    }

    std::uint32_t internalMaterial(glm::vec3 emission) {
        gpu::GpuMaterial m{};
        m.albedo = glm::vec4(0, 0, 0, 0);
        m.emission = glm::vec4(emission, 0);
        m.info = glm::uvec4(MAT_DIFFUSE, 0, 0, 0);
        out.materials.push_back(m);
        return static_cast<std::uint32_t>(out.materials.size() - 1);
    }

    bool run() {
        out = CompiledScene{};
        reusing = canReuse();
        out.boundsMin = glm::vec3(std::numeric_limits<float>::max());
        out.boundsMax = glm::vec3(-std::numeric_limits<float>::max());
        const std::string sceneDir = sceneFolder(scene);
        for (size_t i = 0; i < scene.materials.size(); ++i)
            if (!addMaterial(scene.materials[i], "materials[" + std::to_string(i) + "]", sceneDir)) return false;
        for (size_t i = 0; i < scene.objects.size(); ++i) {
            const Object& o = scene.objects[i];
            const std::string where = "objects[" + std::to_string(i) + "]";
            if (o.shape == Shape::Mesh && o.material.empty()) {  // the file's own materials
                if (!addMeshInstance(o, static_cast<std::uint32_t>(i), o.transform.toMatrix(), kFileMaterials, nullptr, true,
                                     where))
                    return false;
                continue;
            }
            auto it = std::find_if(scene.materials.begin(), scene.materials.end(),
                                   [&](const Material& m) { return m.name == o.material; });
            if (it == scene.materials.end()) {
                *error = where + ".material: unknown material '" + o.material + "'";
                return false;
            }
            auto mat = static_cast<std::uint32_t>(it - scene.materials.begin());
            // The object's own emission (one-sided unless two_sided) replaces its material's
            // (two-sided) in a copy of the material that only this object uses.
            glm::vec3 emission = it->emission;
            bool twoSided = true;
            if (o.emits()) {
                emission = o.emission;
                twoSided = o.twoSided;
                gpu::GpuMaterial copy = out.materials[mat];
                copy.emission = glm::vec4(emission, copy.emission.w);  // w: the normal scale
                out.materials.push_back(copy);
                mat = static_cast<std::uint32_t>(out.materials.size() - 1);
            }
            if (o.shape != Shape::Mesh && it->alphaMode == AlphaMode::Mask)
                out.warnings.push_back(where + ": material '" + it->name + "' has alpha_mode 'mask', which only "
                                       "meshes honour: this " + std::string(enumName(o.shape)) + " is opaque");
            const bool emissive = glm::any(glm::greaterThan(emission, glm::vec3(0.0f)));
            const std::uint32_t primFlags = emissive && !twoSided ? PRIM_FLAG_ONE_SIDED_EMITTER : 0u;
            glm::mat4 m = o.transform.toMatrix();
            switch (o.shape) {
                case Shape::Mesh: {
                    if (!addMeshInstance(o, static_cast<std::uint32_t>(i), m, mat, emissive ? &emission : nullptr,
                                         twoSided, where))
                        return false;
                    break;
                }
                case Shape::Sphere: {
                    std::uint32_t p = addSphere(m, mat, primFlags);
                    if (emissive && !addSphereLight(p, m, emission, where, twoSided)) return false;
                    break;
                }
                case Shape::Quad: {
                    std::uint32_t p = addQuad(m, mat, primFlags);
                    if (emissive && !addRectLight(p, emission, twoSided, where)) return false;
                    break;
                }
                case Shape::Box: {
                    // Six faces of [-1,1]^3, each the canonical quad turned to face outward.
                    const glm::mat4 I(1.0f);
                    const glm::vec3 X(1, 0, 0), Y(0, 1, 0);
                    const glm::mat4 faces[6] = {
                        glm::translate(I, {0, 0, 1}),
                        glm::rotate(glm::translate(I, {0, 0, -1}), kPi, Y),
                        glm::rotate(glm::translate(I, {1, 0, 0}), kPi / 2, Y),
                        glm::rotate(glm::translate(I, {-1, 0, 0}), -kPi / 2, Y),
                        glm::rotate(glm::translate(I, {0, 1, 0}), -kPi / 2, X),
                        glm::rotate(glm::translate(I, {0, -1, 0}), kPi / 2, X),
                    };
                    for (const glm::mat4& f : faces) {
                        std::uint32_t p = addQuad(m * f, mat, primFlags);
                        if (emissive && !addRectLight(p, emission, twoSided, where)) return false;
                    }
                    break;
                }
            }
        }
        for (size_t i = 0; i < scene.lights.size(); ++i) {
            const Light& L = scene.lights[i];
            const std::string where = "lights[" + std::to_string(i) + "]";
            switch (L.type) {
                case LightType::Rect: {
                    std::uint32_t p = addQuad(L.transform.toMatrix(), internalMaterial(L.color),
                                              L.twoSided ? 0u : PRIM_FLAG_ONE_SIDED_EMITTER);
                    if (!addRectLight(p, L.color, L.twoSided, where + ".transform")) return false;
                    break;
                }
                case LightType::Sphere: {
                    glm::mat4 m = glm::scale(glm::translate(glm::mat4(1.0f), L.position), glm::vec3(L.radius));
                    std::uint32_t p = addSphere(m, internalMaterial(L.color));
                    if (!addSphereLight(p, m, L.color, where + ".radius")) return false;
                    break;
                }
                case LightType::Point:
                case LightType::Spot: {
                    gpu::GpuLight l{};
                    l.p0 = glm::vec4(L.position, 0);
                    l.color = glm::vec4(L.color, 0);
                    float power = 4.0f * kPi * luminance(L.color);
                    if (L.type == LightType::Spot) {
                        float cosOuter = std::cos(glm::radians(L.outerAngle));
                        float cosInner = std::cos(glm::radians(L.innerAngle));
                        // smoothstep needs edge0 < edge1.
                        if (cosInner <= cosOuter) cosInner = cosOuter + 1e-6f;
                        const float outer = glm::radians(L.outerAngle), inner = glm::radians(L.innerAngle);
                        // Normalised in double: a direction as short as 1e-44 (a float denormal)
                        // has a length whose square underflows in float.
                        l.p1 = glm::vec4(glm::vec3(glm::normalize(glm::dvec3(L.direction))), cosOuter);
                        l.p2 = glm::vec4(outer, inner, 0, cosInner);
                        if (L.falloff == SpotFalloff::Smoothstep) {
                            // PBRT 4th ed. eq. 12.3 (the smoothstep falloff's approximate power).
                            power = 2.0f * kPi * luminance(L.color) * (1.0f - 0.5f * (cosInner + cosOuter));
                        } else {
                            // Linear in the angle: 2 pi I (integral of the falloff times sin theta),
                            // the ring by the midpoint rule.
                            double ring = 0.0;
                            constexpr int kSteps = 256;
                            for (int k = 0; k < kSteps; ++k) {
                                const double th = inner + (outer - inner) * (k + 0.5) / kSteps;
                                ring += (outer - th) / std::max(double(outer - inner), 1e-12) * std::sin(th) *
                                        (outer - inner) / kSteps;
                            }
                            power = static_cast<float>(2.0 * kPi * luminance(L.color) * (1.0 - std::cos(inner) + ring));
                        }
                    }
                    std::uint32_t flags = 0;
                    if (L.type == LightType::Spot && L.falloff == SpotFalloff::LinearAngle) flags |= LIGHT_FLAG_LINEAR_ANGLE;
                    l.info = glm::uvec4(L.type == LightType::Spot ? LIGHT_SPOT : LIGHT_POINT, flags, 0, 0);
                    LightBounds bounds;
                    bounds.boundsMin = bounds.boundsMax = L.position;
                    bounds.intensity = luminance(L.color);
                    if (L.type == LightType::Spot) {  // full intensity inside the inner cone, none beyond the outer
                        bounds.axis = glm::vec3(l.p1);
                        bounds.cosThetaO = l.p2.w;
                        bounds.cosThetaE = std::cos(std::max(std::acos(std::clamp(l.p1.w, -1.0f, 1.0f)) -
                                                                 std::acos(std::clamp(l.p2.w, -1.0f, 1.0f)), 0.0f));
                    }
                    addLight(l, power, -1, bounds);
                    growBounds(L.position);
                    break;
                }
            }
        }
        if (!finishGeometry()) return false;
        if (out.primitives.empty() && out.lights.empty() && out.instances.empty())
            out.boundsMin = out.boundsMax = glm::vec3(0.0f);
        const Environment& env = scene.environment;
        if (env.type == EnvironmentType::Map) {
            if (env.file.empty()) {
                *error = "environment.file: a map environment needs a file";
                return false;
            }
            const std::filesystem::path file(resolveScenePath(scene, env.file));
            ImageData image;
            std::string why;
            if (!readImage) {
                *error = "environment.file: " + file.string() + ": this build cannot read images";
                return false;
            }
            if (!readImage(file.string(), &image, &why) || !buildEnvironmentMap(image, &out.envMap, &why)) {
                *error = "environment.file: " + why;
                return false;
            }
            // The same bound as the scene reader's on emitted radiance (renderer/scene_io.cpp,
            // kMaxRadiance: the film's float sums of squares stay finite).
            float brightest = 0.0f;
            for (size_t k = 0; k < image.pixels.size(); ++k)
                if (image.channels < 4 || k % 4 != 3) brightest = std::max(brightest, image.pixels[k]);
            if (double(brightest) * env.intensity > 1e12) {
                *error = "environment.file: " + file.string() + ": the brightest texel (" + formatShort(brightest) +
                         ") times the intensity exceeds 1e12, the most a channel may emit";
                return false;
            }
        }
        if (env.type != EnvironmentType::None) {
            glm::vec3 average = env.type == EnvironmentType::Constant ? env.radiance
                                : env.type == EnvironmentType::Map   ? out.envMap.average
                                    // mean of the sky over the sphere: horizon below, and the
                                    // mean of sqrt(y) over the upper half (y uniform) is 2/3.
                                    : env.horizon + (env.zenith - env.horizon) / 3.0f;
            average *= env.intensity;
            // In double: the bounds of an object at 1e19 give a radius whose square, times pi^2,
            // overflows a float (the pmfs became inf / inf = NaN).
            double radius = 0.5 * glm::length(glm::dvec3(out.boundsMax) - glm::dvec3(out.boundsMin));
            radius = std::max(radius, 1e-3);
            gpu::GpuLight l{};
            l.info = glm::uvec4(LIGHT_ENV, 0, 0, 0);
            out.envLightIndex = static_cast<int>(out.lights.size());
            // Power an infinite light delivers into the scene's bounding sphere: pi * pi r^2 * L
            // (power selection). The light tree weighs it by the irradiance it gives a surface,
            // pi * L, in the same unit as a tree node's importance (lights/light_select.glsl).
            addLight(l, saturatedPower(kPi * kPi * radius * radius * luminance(average)), -1, LightBounds{});
            out.envImportance = kPi * luminance(average);
        }
        // The light tree over every other light.
        std::vector<std::uint32_t> members;
        for (size_t i = 0; i < out.lights.size(); ++i)
            if (static_cast<int>(i) != out.envLightIndex) members.push_back(static_cast<std::uint32_t>(i));
        out.lightTree = buildLightTree(out.lightBounds, members);
        for (size_t i = 0; i < out.lights.size(); ++i) out.lights[i].tree.x = out.lightTree.trails[i];
        // Selection probabilities: by power (default) or uniform; uniform when nothing emits.
        double total = 0.0;
        for (float p : out.lightPower) total += p;
        bool uniform = scene.render.lightSelection == LightSelection::Uniform || !(total > 0.0);
        double acc = 0.0;
        const size_t n = out.lights.size();
        for (size_t i = 0; i < n; ++i) {
            double pmf = uniform ? 1.0 / double(n) : out.lightPower[i] / total;
            out.lights[i].color.w = static_cast<float>(pmf);
            acc += pmf;
            out.lightCdf.push_back(static_cast<float>(acc));
        }
        if (!out.lightCdf.empty()) out.lightCdf.back() = 1.0f;
        return true;
    }
};

}  // namespace

bool compileScene(const Scene& scene, const ImageReader& readImage, CompiledScene* out, std::string* error,
                  MeshCache* meshCache, CompiledScene* reuse) {
    Builder b(scene, readImage, *out, error, meshCache, reuse == out ? nullptr : reuse);
    if (b.run()) return true;
    b.restoreReuse();
    return false;
}

}  // namespace caustic
