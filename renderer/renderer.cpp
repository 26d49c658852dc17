// The renderer's life and its scene on the GPU: creation, compiling and uploading a scene,
// applying edits (only what they change), and the image reader.
#include "renderer/renderer.h"
#include "renderer/renderer_internal.h"

#include "renderer/bsdf_tables.h"
#include "renderer/camera.h"

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <string_view>

namespace caustic {
namespace {

template <class T>
void uploadBuffer(unsigned buffer, const std::vector<T>& data) {
    // An empty SSBO cannot be bound with a size of zero; keep one zeroed element.
    std::vector<T> padded = data.empty() ? std::vector<T>(1) : data;
    glNamedBufferData(buffer, static_cast<GLsizeiptr>(padded.size() * sizeof(T)), padded.data(), GL_STATIC_DRAW);
}

// Drains the GL error queue: the names of the errors raised since the last call ("" if none).
std::string glErrorsSince() {
    std::string out;
    for (int i = 0; i < 16; ++i) {   // the queue holds one flag per kind; a lost context repeats
        const GLenum e = glGetError();
        if (e == GL_NO_ERROR) break;
        const char* name = e == GL_OUT_OF_MEMORY       ? "GL_OUT_OF_MEMORY"
                           : e == GL_INVALID_VALUE     ? "GL_INVALID_VALUE"
                           : e == GL_INVALID_OPERATION ? "GL_INVALID_OPERATION"
                           : e == GL_INVALID_ENUM      ? "GL_INVALID_ENUM"
                                                       : nullptr;
        char buf[32];
        if (!name) std::snprintf(buf, sizeof buf, "GL error 0x%04x", unsigned(e));
        out += (out.empty() ? "" : ", ") + std::string(name ? name : buf);
    }
    return out;
}

}  // namespace

// The primitives as the ray tests read them (shaders/scene/buffers.glsl, primitiveHits): spheres
// unchanged, quads (corner a, edges b and c) in plane form, so that a ray's test makes one
// division and no cross products (on llvmpipe the Cornell box's 18 quad tests per ray were most
// of its time: docs/performance.md).
std::vector<gpu::GpuPrimitive> primitiveHitRecords(const std::vector<gpu::GpuPrimitive>& primitives) {
    std::vector<gpu::GpuPrimitive> out = primitives;
    for (gpu::GpuPrimitive& p : out) {
        if (p.info.x != PRIM_QUAD) continue;
        // In double, with the normal normalised: N = e1 x e2 scales with the square of the quad's
        // size and N.N with its fourth power, which in float flushed to zero below a scale of
        // ~1e-9 (the quad then missed every ray; docs/reliability.md, scale invariance).
        const glm::dvec3 corner(glm::vec3(p.a)), e1(glm::vec3(p.b)), e2(glm::vec3(p.c));
        const glm::dvec3 n0 = glm::cross(e1, e2);
        const double len = glm::length(n0);
        // A degenerate quad (zero area) gets N = 0: the test's |N.d| < 1e-20 rejects every ray.
        const glm::dvec3 n = len > 0.0 ? n0 / len : glm::dvec3(0.0);
        // U.p - U.corner and V.p - V.corner are the hit's coordinates along e1 and e2 (0..1).
        const glm::dvec3 u = len > 0.0 ? glm::cross(e2, n) / len : glm::dvec3(0.0);
        const glm::dvec3 v = len > 0.0 ? glm::cross(n, e1) / len : glm::dvec3(0.0);
        p.a = glm::vec4(glm::vec3(n), float(glm::dot(n, corner)));
        p.b = glm::vec4(glm::vec3(u), float(glm::dot(u, corner)));
        p.c = glm::vec4(glm::vec3(v), float(glm::dot(v, corner)));
    }
    return out;
}

std::unique_ptr<Renderer> Renderer::create(const std::string& shaderDir, const IntegratorConfig& config,
                                           std::string* error) {
    std::unique_ptr<Renderer> r(new Renderer());
    r->m_shaderDir = shaderDir;
    r->m_config = resolveIntegratorConfig(config);
    r->m_specialize = r->m_config.specialize;
    // The general program now only where it is the one that renders (specialisation off: NVIDIA
    // by default); with specialisation on (llvmpipe) it is built only if a scene's own program
    // fails (selectProgram) or program() is asked for before any scene: its GLSL and NIR passes
    // took 4.8 s of a 16 x 16 Cornell box's 11.7 s on llvmpipe, for a program never used. A source
    // that does not compile then fails setScene, with the same message.
    if (!r->m_specialize) {
        r->m_general = r->generalProgram(error);
        if (!r->m_general) return nullptr;
        r->m_program = r->m_general;
    }
    r->m_limits = queryGpuLimits(r->m_config.fetchTexels);
    unsigned buffers[6];
    glCreateBuffers(6, buffers);
    r->m_frameUbo = buffers[0];
    r->m_primitives = buffers[1];
    r->m_materials = buffers[2];
    r->m_lights = buffers[3];
    r->m_tables = buffers[4];
    r->m_counters = buffers[5];
    const std::uint32_t zero[COUNTER_WORDS] = {};
    glNamedBufferData(r->m_counters, sizeof zero, zero, GL_DYNAMIC_COPY);
    glCreateBuffers(kGeometryBuffers, r->m_geometry);
    // Material textures and the BSDF tables (the GGX albedo table is the same for every scene).
    unsigned materialBuffers[3];
    glCreateBuffers(3, materialBuffers);
    r->m_texels = materialBuffers[0];
    r->m_textures = materialBuffers[1];
    r->m_bsdfTables = materialBuffers[2];
    glCreateBuffers(1, &r->m_lightTree);
    glCreateBuffers(1, &r->m_lensUbo);
    {
        const std::vector<glm::vec4> zeros(kLensBlockRows, glm::vec4(0.0f));
        glNamedBufferData(r->m_lensUbo, GLsizeiptr(zeros.size() * sizeof(glm::vec4)), zeros.data(), GL_STATIC_DRAW);
    }
    glCreateBuffers(1, &r->m_primitiveHits);
    glCreateBuffers(1, &r->m_wideNodes);
    glCreateTextures(GL_TEXTURE_BUFFER, kTexelViews, r->m_texelViews);
    r->m_imageLoads = imageUnitsForTexelViews();
    if (!computeBsdfTables(shaderDir, r->m_bsdfTables, error)) return nullptr;
    return r;
}

Renderer::~Renderer() {
    unsigned buffers[6] = {m_frameUbo, m_primitives, m_materials, m_lights, m_tables, m_counters};
    glDeleteBuffers(6, buffers);
    glDeleteBuffers(kGeometryBuffers, m_geometry);
    unsigned materialBuffers[3] = {m_texels, m_textures, m_bsdfTables};
    glDeleteBuffers(3, materialBuffers);
    glDeleteBuffers(1, &m_lightTree);
    glDeleteBuffers(1, &m_lensUbo);
    glDeleteBuffers(1, &m_primitiveHits);
    glDeleteBuffers(1, &m_wideNodes);
    glDeleteTextures(kTexelViews, m_texelViews);
    unsigned textures[5] = {m_accum, m_accumSq, m_albedo, m_normal, m_envTexture};
    glDeleteTextures(5, textures);
    for (const auto& [key, program] : m_programs) glDeleteProgram(program);
    // Builds still asked for: the builder deletes what it finishes after this; done ones are ours.
    for (const auto& [key, build] : m_building)
        if (const unsigned program = build->abandon()) glDeleteProgram(program);
}

bool Renderer::setScene(const Scene& scene, std::string* error) {
    // The meshes' laid-out data moves over from the last compile when the files are the same (an
    // object added or removed beside a big mesh). When it stayed in place (the top level within its
    // reserve of nodes), the meshes' triangles, vertices and nodes on the GPU are still right and
    // only the rest is uploaded; otherwise everything is.
    const auto previousMeshes = m_compiled.meshEntries;
    const std::size_t previousNodes = m_compiled.bvhNodes.size();
    const std::uint32_t previousReserve = m_compiled.tlasNodeCapacity;
    if (!prepareLens(scene, error)) return false;
    CompiledScene compiled;
    if (!compileChecked(scene, &compiled, error)) return false;
    const bool meshesInPlace = m_uploaded && !compiled.meshEntries.empty() && compiled.meshEntries == previousMeshes &&
                               compiled.bvhNodes.size() == previousNodes && compiled.tlasNodeCapacity == previousReserve;
    glErrorsSince();   // errors of earlier work are not this upload's
    m_scene = scene;
    m_compiled = std::move(compiled);
    std::string glErrors = upload(!meshesInPlace);
    m_uploaded = glErrors.empty();
    const PixelRect region = cropOf(scene);
    m_region = region;
    if (m_width != region.x1 - region.x0 || m_height != region.y1 - region.y0) {
        unsigned textures[4] = {m_accum, m_accumSq, m_albedo, m_normal};
        if (m_accum) glDeleteTextures(4, textures);
        glCreateTextures(GL_TEXTURE_2D, 4, textures);
        m_accum = textures[0];
        m_accumSq = textures[1];
        m_albedo = textures[2];
        m_normal = textures[3];
        m_width = region.x1 - region.x0;
        m_height = region.y1 - region.y0;
        for (unsigned t : textures) glTextureStorage2D(t, 1, GL_RGBA32F, m_width, m_height);
        if (glErrors.empty()) glErrors = glErrorsSince();
    }
    if (!glErrors.empty()) {
        // What the driver refused despite the limit checks (out of GPU memory, most likely): the
        // buffers are incomplete, so the next scene uploads everything.
        m_uploaded = false;
        *error = "uploading the scene to the GPU failed: " + glErrors;
        return false;
    }
    if (!m_deferBuilds && !m_builder && !selectProgram(error)) return false;  // compiled now, not inside the first render
    resetAccumulation();
    return true;
}

bool Renderer::prepareLens(const Scene& scene, std::string* error) {
    static_assert(kLensMaxSurfaces == LENS_MAX_SURFACES && kLensPupilBins == LENS_PUPIL_BINS);
    const Camera& c = scene.camera;
    if (c.lens.empty()) {
        if (!m_lensKey.empty()) {
            const std::vector<glm::vec4> zeros(kLensBlockRows, glm::vec4(0.0f));
            glNamedBufferData(m_lensUbo, GLsizeiptr(zeros.size() * sizeof(glm::vec4)), zeros.data(), GL_STATIC_DRAW);
        }
        m_lensKey.clear();
        m_lensCamera.reset();
        return true;
    }
    const std::string path = resolveScenePath(scene, c.lens);
    LensCameraSettings settings = lensCameraSettings(c, scene.render.width, scene.render.height);
    std::error_code ec;
    const auto stamp = std::filesystem::last_write_time(path, ec);
    std::string apertureKey;
    if (!c.apertureImage.empty()) {
        const std::string file = resolveScenePath(scene, c.apertureImage);
        std::error_code ignored;
        const auto apertureStamp = std::filesystem::last_write_time(file, ignored);
        apertureKey = file + " " + std::to_string(ignored ? -1LL : static_cast<long long>(apertureStamp.time_since_epoch().count()));
    }
    char key[512];
    std::snprintf(key, sizeof key, "%lld %.17g %.17g %.17g %.17g %d %.17g %d",
                  ec ? -1LL : static_cast<long long>(stamp.time_since_epoch().count()), settings.focusDistanceMm,
                  settings.fNumber, settings.filmWidthMm, settings.filmHeightMm, settings.blades,
                  settings.bladeRotation, settings.dispersion ? 1 : 0);
    const std::string fullKey = path + "\n" + key + "\n" + apertureKey;
    if (fullKey == m_lensKey) return true;
    if (!c.apertureImage.empty()) {
        ApertureImage aperture;
        if (!readApertureImage(scene, m_readImage, &aperture, error)) return false;
        settings.aperture = {aperture.width, aperture.height, std::move(aperture.mask)};
    }
    LensSystem lens;
    std::string why;
    if (!readLensFile(path, &lens, &why)) {
        *error = "camera.lens: " + why;
        return false;
    }
    auto camera = std::make_shared<LensCamera>();
    if (!prepareLensCamera(lens, settings, camera.get(), &why)) {
        *error = "camera.lens: " + path + ": " + why;
        return false;
    }
    for (const std::string& note : camera->notes) std::fprintf(stderr, "caustic: camera.lens: %s: %s\n", path.c_str(), note.c_str());
    std::vector<glm::vec4> block = lensUniformBlock(*camera);
    block[2].w = static_cast<float>(1.0 / kMillimetresPerSceneUnit);
    glNamedBufferData(m_lensUbo, GLsizeiptr(block.size() * sizeof(glm::vec4)), block.data(), GL_STATIC_DRAW);
    m_lensCamera = std::move(camera);
    m_lensKey = fullKey;
    return true;
}

PixelRect Renderer::cropOf(const Scene& scene) const {
    const PixelRect whole{0, 0, scene.render.width, scene.render.height};
    if (m_crop.x1 <= m_crop.x0 || m_crop.y1 <= m_crop.y0) return whole;
    return {std::clamp(m_crop.x0, 0, whole.x1), std::clamp(m_crop.y0, 0, whole.y1),
            std::clamp(m_crop.x1, 0, whole.x1), std::clamp(m_crop.y1, 0, whole.y1)};
}

bool Renderer::compileChecked(const Scene& scene, CompiledScene* out, std::string* error) {
    if (!compileScene(scene, m_readImage, out, error, &m_meshCache, &m_compiled)) return false;
    const std::string problem = gpuLimitProblem(scene, *out, m_limits);
    if (problem.empty()) return true;
    *error = problem;
    // The compile moved the last scene's mesh data into *out; compiling that scene again (its
    // meshes and images come from the caches) puts m_compiled back as the GPU holds it.
    CompiledScene previous;
    std::string ignored;
    if (m_uploaded && compileScene(m_scene, m_readImage, &previous, &ignored, &m_meshCache, out))
        m_compiled = std::move(previous);
    return false;
}

void Renderer::setImageReader(ImageReader reader) {
    struct Cached {
        std::filesystem::file_time_type stamp;
        std::shared_ptr<const ImageData> image;
    };
    auto cache = std::make_shared<std::map<std::string, Cached>>();
    m_readImage = [reader = std::move(reader), cache](const std::string& path, ImageData* out, std::string* error) {
        std::error_code ec;
        const auto stamp = std::filesystem::last_write_time(path, ec);
        if (!ec) {
            if (auto it = cache->find(path); it != cache->end() && it->second.stamp == stamp) {
                *out = *it->second.image;
                return true;
            }
        }
        if (!reader) {
            *error = path + ": this build cannot read images";
            return false;
        }
        if (!reader(path, out, error)) return false;
        if (!ec) (*cache)[path] = {stamp, std::make_shared<const ImageData>(*out)};
        return true;
    };
}

bool Renderer::update(const Scene& scene, std::uint32_t dirty, std::string* error) {
    const bool sameSize = scene.render.width == m_width && scene.render.height == m_height;
    if ((dirty & ~std::uint32_t(kDirtyCamera | kDirtySettings | kDirtyMaterials | kDirtyTransforms)) != 0 ||
        !sameSize || scene.materials.size() != m_scene.materials.size() ||
        scene.camera.apertureImage != m_scene.camera.apertureImage ||
        scene.render.lightSelection != m_scene.render.lightSelection)
        return setScene(scene, error);
    if (!prepareLens(scene, error)) return false;
    if (dirty & (kDirtyMaterials | kDirtyTransforms)) {
        // Recompiling on the CPU is cheap (meshes come from the cache, their BVHs untouched); what
        // is uploaded is only what changed. Transforms: primitives, instances, lights and the top
        // level of the BVH (whose node count stays 2n - 1 for n entries, so it is rewritten in
        // place); materials: the material table and textures. Anything that changes the sizes of
        // the mesh data (an emission change alters the light list, for one) uploads everything.
        // The mesh data moves from m_compiled into the new compile (nothing is copied; on failure
        // it is moved back), so the sizes to compare are taken first.
        const std::size_t nodes = m_compiled.bvhNodes.size(), triangles = m_compiled.triangles.size(),
                          lights = m_compiled.lights.size();
        const std::uint32_t tlasNodes = m_compiled.tlasNodeCount;
        CompiledScene compiled;
        if (!compileChecked(scene, &compiled, error)) return false;
        const bool sameLayout = compiled.bvhNodes.size() == nodes && compiled.tlasNodeCount == tlasNodes &&
                                compiled.triangles.size() == triangles && compiled.lights.size() == lights;
        glErrorsSince();
        m_scene = scene;
        if (!sameLayout) {
            m_compiled = std::move(compiled);
            if (const std::string glErrors = upload(); !glErrors.empty()) {
                m_uploaded = false;
                *error = "uploading the scene to the GPU failed: " + glErrors;
                return false;
            }
        } else {
            if (dirty & kDirtyTransforms) {
                uploadBuffer(m_primitives, compiled.primitives);
                uploadBuffer(m_primitiveHits, primitiveHitRecords(compiled.primitives));
                uploadBuffer(m_lights, compiled.lights);
                uploadBuffer(m_lightTree, compiled.lightTree.nodes);
                uploadBuffer(m_tables, packTables(compiled));
                uploadBuffer(m_geometry[1], compiled.tlasRefs);
                uploadBuffer(m_geometry[2], compiled.instances);
                if (compiled.tlasNodeCount > 0)
                    glNamedBufferSubData(m_geometry[0], 0, GLsizeiptr(compiled.tlasNodeCount * sizeof(gpu::GpuBvhNode)),
                                         compiled.bvhNodes.data());
            }
            if (dirty & kDirtyMaterials) {
                // Emission lives in the lights too (radiance, selection probabilities), and an
                // alpha mask in the instances' flags (PRIM_FLAG_ALPHA_MASK).
                uploadBuffer(m_geometry[2], compiled.instances);
                uploadBuffer(m_lights, compiled.lights);
                uploadBuffer(m_lightTree, compiled.lightTree.nodes);
                uploadBuffer(m_tables, packTables(compiled));
                uploadBuffer(m_materials, compiled.materials);
                uploadBuffer(m_texels, compiled.texels);
                uploadBuffer(m_textures, compiled.textures);
            }
            m_compiled = std::move(compiled);
            if (const std::string glErrors = glErrorsSince(); !glErrors.empty()) {
                m_uploaded = false;
                *error = "uploading the scene to the GPU failed: " + glErrors;
                return false;
            }
        }
    }
    m_scene = scene;  // camera and settings live in the frame constants, made per dispatch
    if (!m_deferBuilds && !m_builder && !selectProgram(error)) return false;  // compiled now, not inside the first render
    resetAccumulation();
    return true;
}

std::string Renderer::upload(bool meshes) {
    uploadBuffer(m_primitives, m_compiled.primitives);
    uploadBuffer(m_primitiveHits, primitiveHitRecords(m_compiled.primitives));
    uploadBuffer(m_materials, m_compiled.materials);
    uploadBuffer(m_lights, m_compiled.lights);
    uploadBuffer(m_lightTree, m_compiled.lightTree.nodes);
    uploadBuffer(m_tables, packTables(m_compiled));
    // The environment map (a 1x1 black texture when there is none, so the sampler is always
    // complete). Mipmaps are not needed: the map is looked up at level 0 only.
    const EnvironmentMap& env = m_compiled.envMap;
    const int w = std::max(env.width, 1), h = std::max(env.height, 1);
    if (m_envTexture) glDeleteTextures(1, &m_envTexture);
    glCreateTextures(GL_TEXTURE_2D, 1, &m_envTexture);
    glTextureStorage2D(m_envTexture, 1, GL_RGBA32F, w, h);
    const glm::vec4 black(0.0f);
    glTextureSubImage2D(m_envTexture, 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, env.texels.empty() ? &black : env.texels.data());
    glTextureParameteri(m_envTexture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(m_envTexture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(m_envTexture, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(m_envTexture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    if (meshes) {
        uploadBuffer(m_geometry[0], m_compiled.bvhNodes);
        uploadBuffer(m_geometry[3], m_compiled.triangles);
        uploadBuffer(m_wideNodes, m_compiled.wideNodes);
        uploadBuffer(m_geometry[4], m_compiled.vertices);
    } else {  // the top level's reserve only
        glNamedBufferSubData(m_geometry[0], 0, GLsizeiptr(m_compiled.tlasNodeCapacity * sizeof(gpu::GpuBvhNode)),
                             m_compiled.bvhNodes.data());
    }
    uploadBuffer(m_geometry[1], m_compiled.tlasRefs);
    uploadBuffer(m_geometry[2], m_compiled.instances);
    uploadBuffer(m_texels, m_compiled.texels);
    uploadBuffer(m_textures, m_compiled.textures);
    return glErrorsSince();
}

}  // namespace caustic
