// compileScene's materials: the scene's and a model file's (mapped), and their textures.
#include "renderer/gpu_scene_builder.h"

namespace caustic::scene_compile {

bool Builder::addMaterial(const Material& m, const std::string& where, const std::string& baseDir, bool withTextures) {
    gpu::GpuMaterial g = convertMaterial(m);
    if (withTextures && !addTextures(m, where, baseDir, &g)) return false;
    out.materials.push_back(g);
    return true;
}

void Builder::addSurfaceParts(std::uint32_t index, const Material& m) {
    std::vector<gpu::GpuMaterial> parts = surfaceParts(m);
    if (parts.empty()) return;
    linkSurfaceParts(out.materials[index], m, static_cast<std::uint32_t>(out.materials.size()));
    out.materials.insert(out.materials.end(), parts.begin(), parts.end());
}

bool Builder::addTextures(const Material& m, const std::string& where, const std::string& baseDir, gpu::GpuMaterial* gm) {
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
        if (enc == TextureEncoding::LinearReflectance) {
            std::size_t above = 0;
            const int ch = std::min(image.channels, 3);
            for (std::size_t p = 0; p < image.pixels.size(); p += std::size_t(image.channels))
                for (int k = 0; k < ch; ++k) above += image.pixels[p + std::size_t(k)] > 1.0f;
            if (above > 0)
                out.warnings.push_back(context + file.string() + ": " + std::to_string(above) +
                                       " texel values above 1 clamped to 1 (an albedo reflects at most what it receives)");
        }
        *slot = static_cast<std::uint32_t>(out.textures.size());
        textureIndex.emplace(cacheKey, *slot - 1);
        return true;
    };
    const std::string ext = std::filesystem::path(m.albedoTexture).extension().string();
    const bool hdr = ext == ".hdr" || ext == ".exr" || ext == ".HDR" || ext == ".EXR" || ext == ".pfm";
    if (!texture(m.albedoTexture, "albedo_texture", hdr ? TextureEncoding::LinearReflectance : TextureEncoding::Srgb,
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

bool Builder::addFileMaterialTextures(std::uint32_t blas, size_t k, const std::string& file, const std::string& where) {
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

bool Builder::addFileMaterialTexturesWith(Material& m, gpu::GpuMaterial& g, const ImportedMaterial* im,
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
    const glm::uvec4 info = g.info;  // the link to the surface's parts (addSurfaceParts) stays
    g = convertMaterial(m);
    g.info.y |= info.y & (MAT_FLAG_TRANSMISSION_PART | MAT_FLAG_SUBSURFACE_PART);
    if (m.type == MaterialType::Surface) g.info.w = info.w;
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

}  // namespace caustic::scene_compile
