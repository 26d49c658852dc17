// compileScene's meshes: importing (through the mesh cache), instances, emissive meshes, and
// the layout of every BVH in the GPU's buffers, reusing a previous compile's where it can.
#include "renderer/gpu_scene_builder.h"

namespace caustic::scene_compile {

std::shared_ptr<const MeshCacheEntry> Builder::cachedEntry(const std::string& file) const {
    if (!meshCache) return nullptr;
    std::error_code ec;
    const auto stamp = std::filesystem::last_write_time(file, ec);
    std::shared_ptr<const MeshCacheEntry> entry = meshCache->find(file);
    return entry && !ec && entry->stamp == stamp ? entry : nullptr;
}

bool Builder::canReuse() const {
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

void Builder::shiftMeshNodes(std::vector<gpu::GpuBvhNode>& nodes, std::uint32_t oldTop,
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

void Builder::restoreReuse() {
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

bool Builder::loadMesh(const std::string& file, const std::string& where, MeshCacheEntry* entry) {
    std::string why;
    if (prepareMesh(file, entry, &why)) return true;
    *error = where + ".file: " + why;
    return false;
}

bool Builder::importMesh(const std::string& file, const std::string& where, std::uint32_t* blasIndex) {
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
    for (size_t k = 0; k < entry->materials.size(); ++k)
        addSurfaceParts(meshMaterialBase.back() + static_cast<std::uint32_t>(k), entry->materials[k]);
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

bool Builder::addMeshInstance(const Object& o, std::uint32_t objectIndex, const glm::mat4& m, std::uint32_t material,
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
    gi.material = fromFile ? meshMaterialBase[blas] : material;  // rootNode, firstTriangle: finishGeometry
    // Whether traversal must test the mesh's hits against an alpha mask (geometry/alpha_mask.glsl).
    bool masked = false;
    if (fromFile) {
        for (size_t k = 0; k < meshMaterials[blas].size(); ++k)
            masked = masked || (out.materials[meshMaterialBase[blas] + k].info.y & MAT_FLAG_ALPHA_MASK) != 0u;
    } else {
        masked = (out.materials[material].info.y & MAT_FLAG_ALPHA_MASK) != 0u;
    }
    gi.firstVertex = meshVertexBase[blas];
    gi.triangleCount = static_cast<std::uint32_t>(out.meshBvh.blases[blas].triangles.size());
    gi.fileMaterials = fromFile ? 1u : 0u;
    gi.flags = (twoSided ? 0u : PRIM_FLAG_ONE_SIDED_EMITTER) | (masked ? PRIM_FLAG_ALPHA_MASK : 0u);
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
        out.instances.back().light = static_cast<std::uint32_t>(out.lights.size() + 1);
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

bool Builder::finishGeometry() {
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
        out.instances[i].rootNode = rootOf[b];
        out.instances[i].firstTriangle = firstTriangleOf[b];
    }
    out.meshBvh.tlas = Bvh{};  // the CPU mirror of the mesh-only top level, for CPU queries
    buildTlas(out.meshBvh);
    // Each mesh's BVH in its 4-wide form, made with its cache entry and placed here (a copy
    // and an add).
    out.wideNodes.clear();
    std::vector<std::uint32_t> wideRootOf;
    for (const auto& entry : out.meshEntries) {
        wideRootOf.push_back(static_cast<std::uint32_t>(out.wideNodes.size()));
        appendWideBvh(entry->wideNodes, wideRootOf.back(), out.wideNodes);
    }
    for (size_t i = 0; i < out.instances.size(); ++i)
        out.instances[i].wideRoot = wideRootOf[out.meshBvh.instances[i].mesh];
    return true;
}

void Builder::layOutMeshes(std::vector<std::uint32_t>& rootOf, std::vector<std::uint32_t>& firstTriangleOf) {
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

}  // namespace caustic::scene_compile
