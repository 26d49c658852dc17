#include "renderer/renderer.h"

#include "renderer/bsdf_tables.h"

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

// A dispatch should take about this long: long enough to amortise its overhead, short enough that
// the driver never queues seconds of work (see docs/gpu-machine notes: a long queue is lost).
constexpr double kTargetDispatchSeconds = 0.05;
constexpr std::uint32_t kMaxSamplesPerDispatch = 64;
// With path regeneration (regeneratesPaths(): llvmpipe) a dispatch needs several samples per
// pixel for a lane whose path ended to have another one to start, and the more it holds the less
// its lanes idle at the end: batch dispatches there aim at this long instead (one sample of a
// large image may take longer; then it is one sample, as before). llvmpipe runs a dispatch on the
// CPU, with no watchdog; the regeneration is off on NVIDIA, whose driver drops long queues.
// The CAUSTIC_DISPATCH_SECONDS environment variable sets either target (for measuring).
constexpr double kRegeneratingDispatchSeconds = 1.0;

// The GL format of a scene texel view from its GLSL image format's name (TEXUNIT_*_FORMAT in
// shaders/shared/layout.h). Evaluated at compile time (TEXEL_VIEW in bindScene): a name it does
// not know stops the build.
consteval GLenum texelViewFormat(std::string_view glslFormat) {
    if (glslFormat == "rgba32ui") return GL_RGBA32UI;
    if (glslFormat == "r32ui") return GL_R32UI;
    throw "texelViewFormat: a TEXUNIT_*_FORMAT that is neither rgba32ui nor r32ui";
}

double targetDispatchSeconds() {
    if (const char* env = std::getenv("CAUSTIC_DISPATCH_SECONDS"); env && *env) {
        char* end = nullptr;
        const double v = std::strtod(env, &end);
        if (end != env && std::isfinite(v) && v > 0.0 && v <= 60.0) return v;
    }
    return regeneratesPaths() ? kRegeneratingDispatchSeconds : kTargetDispatchSeconds;
}

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

// The scene-specialised configuration of the integrator (shaders/scene/features.glsl) for the
// scene and settings of `frame`: the kinds of material, light, shape, environment, sampler and
// light selection present, the traversal the scene gets, whether it has one light only.
bool hasAlphaMask(const CompiledScene& c) {
    return std::any_of(c.instances.begin(), c.instances.end(),
                       [](const gpu::GpuInstance& i) { return (i.info2.w & PRIM_FLAG_ALPHA_MASK) != 0u; });
}

// The unspecialised program's one feature define: alpha masks are compiled in only for a scene
// that has one. Their test sits in traversal's innermost loop, where code size costs every ray on
// a GPU (docs/performance.md, "integrator profile"), so a scene without masks must not pay for it
// where specialisation is off either (NVIDIA, by default). With 0 the code is still compiled (a
// constant-false branch), so the general program still checks the whole source.
ShaderDefines generalDefines(bool alphaMask) { return {{"CAUSTIC_ALPHA_MASK", alphaMask ? "1u" : "0u"}}; }

std::vector<gpu::GpuPrimitive> primitiveHitRecords(const std::vector<gpu::GpuPrimitive>& primitives);

// Baked geometry (bake = true; geometry/bvh.glsl): records as constants of the program, each
// 32-bit word a literal (floats as uintBitsToFloat of their bits: no decimal round trip).
std::string glslWord(std::uint32_t u) {
    char b[16];
    std::snprintf(b, sizeof b, "0x%08xu", unsigned(u));
    return b;
}
std::string glslRow(const glm::uvec4& v) {
    return "uvec4(" + glslWord(v.x) + "," + glslWord(v.y) + "," + glslWord(v.z) + "," + glslWord(v.w) + ")";
}
std::string glslRow(const glm::vec4& v) {
    glm::uvec4 u;
    std::memcpy(&u, &v, sizeof u);
    return glslRow(u);
}

// A brute-force program's primitives: one BAKED_PRIMITIVE(kind, a, b, c, index) each. On
// llvmpipe the loop over primitives then unrolls into tests on immediates: the Cornell box's 18
// quad tests per ray read three texel fetches each otherwise (each a gather of 8 lanes), and with
// them baked the box renders 1.6-2.2x faster, the same image bit for bit (docs/performance.md).
// Neither a uniform block nor a constant array indexed in the loop did this (both slower than the
// fetches).
std::string bakedPrimitiveTests(const CompiledScene& c) {
    std::string out;
    const std::vector<gpu::GpuPrimitive> hits = primitiveHitRecords(c.primitives);
    for (std::size_t i = 0; i < hits.size(); ++i)
        out += "BAKED_PRIMITIVE(" + std::to_string(hits[i].info.x) + "u," + glslRow(hits[i].a) + "," + glslRow(hits[i].b) +
               "," + glslRow(hits[i].c) + "," + std::to_string(i) + "u) ";
    return out;
}

// The same for mesh instances (a few meshes and primitives: CAUSTIC_BAKED_TOP_LEVEL), one
// BAKED_INSTANCE(index, the record's nine rows, its tree's root box min and max) each.
std::string bakedInstanceTests(const CompiledScene& c) {
    std::string out;
    for (std::size_t i = 0; i < c.instances.size(); ++i) {
        const gpu::GpuInstance& in = c.instances[i];
        out += "BAKED_INSTANCE(" + std::to_string(i) + "u,";
        for (const glm::vec4& r : {in.worldToObject0, in.worldToObject1, in.worldToObject2, in.objectToWorld0,
                                   in.objectToWorld1, in.objectToWorld2})
            out += glslRow(r) + ",";
        out += glslRow(in.info) + "," + glslRow(in.info2) + "," + glslRow(in.info3) + ",";
        const gpu::GpuBvhNode& root = c.bvhNodes[in.info.x];
        out += glslRow(glm::vec4(root.boundsMin, 0.0f)) + "," + glslRow(glm::vec4(root.boundsMax, 0.0f)) + ") ";
    }
    return out;
}

ShaderDefines featureDefines(const gpu::GpuFrame& frame, const CompiledScene& c, bool bake) {
    std::uint32_t materials = 0, lights = 0, shapes = 0;
    bool textures = false, emissionTextures = false;
    for (const gpu::GpuMaterial& m : c.materials) {
        materials |= 1u << (m.info.x & 31u);
        textures = textures || m.textures != glm::uvec4(0u);
        emissionTextures = emissionTextures || m.textures.w != 0u;
    }
    const bool alphaMask = hasAlphaMask(c);
    for (const gpu::GpuLight& l : c.lights) lights |= 1u << (l.info.x & 31u);
    for (const gpu::GpuPrimitive& p : c.primitives) shapes |= 1u << (p.info.x & 31u);
    if (!c.instances.empty()) shapes |= 1u << 16;  // SHAPE_BIT_MESH
    const bool bruteForce = frame.geometry.y == 0 && frame.counts.x <= BVH_BRUTE_FORCE_MAX;
    // One light, the environment included: every selection rule picks it with probability 1
    // (power and uniform selection give 1 exactly; the tree gives the environment 1 when it holds
    // no other light), and the program need not carry the selection code, which llvmpipe would
    // run under a lane mask at every vertex (docs/performance.md, session 10).
    const bool singleLight = c.lights.size() == 1;
    auto hex = [](std::uint32_t v) {
        char b[16];
        std::snprintf(b, sizeof b, "0x%xu", unsigned(v));
        return std::string(b);
    };
    ShaderDefines defines = {{"CAUSTIC_MATERIALS", hex(materials)},
            {"CAUSTIC_LIGHTS", hex(lights)},
            {"CAUSTIC_SHAPES", hex(shapes)},
            {"CAUSTIC_ENVIRONMENTS", hex(1u << (frame.envInfo.x & 31u))},
            {"CAUSTIC_SAMPLERS", hex(1u << (frame.sampling.x & 31u))},
            {"CAUSTIC_LIGHT_SELECTIONS", hex(1u << (frame.sampling.y & 31u))},
            {"CAUSTIC_TEXTURES", textures ? "1u" : "0u"},
            {"CAUSTIC_ALPHA_MASK", alphaMask ? "1u" : "0u"},
            {"CAUSTIC_EMISSION_TEXTURES", emissionTextures ? "1u" : "0u"},
            {"CAUSTIC_SINGLE_LIGHT", singleLight ? "1u" : "0u"},
            {"CAUSTIC_TRAVERSAL", bruteForce ? "1u" : "2u"}};
    if (bake && bruteForce) defines.push_back({"CAUSTIC_BAKED_PRIMITIVES", bakedPrimitiveTests(c)});
    // A baked top level: at most 32 entries, of them at most 16 instances (traceScenePair keeps
    // both of a step's rays' instance candidates in one 32-bit mask), and a path step's
    // continuation and shadow rays walked together (integrator/path.glsl, CAUSTIC_PAIRED_TRACE).
    if (bake && !bruteForce && !c.instances.empty() && c.instances.size() <= 16 &&
        c.primitives.size() + c.instances.size() <= BVH_BRUTE_FORCE_MAX) {
        defines.push_back({"CAUSTIC_BAKED_TOP_LEVEL", bakedPrimitiveTests(c) + bakedInstanceTests(c)});
        defines.push_back({"CAUSTIC_PAIRED_TRACE", "1"});
    }
    return defines;
}

// Whether the integrator is built per scene (featureDefines): by default on llvmpipe, where code
// a scene does not use still costs its full time (shaders/scene/features.glsl);
// $CAUSTIC_SPECIALIZE = 1 or 0 forces it on or off.
bool specializeByDefault() {
    if (const char* env = std::getenv("CAUSTIC_SPECIALIZE"); env && *env) return std::strcmp(env, "0") != 0;
    return onLlvmpipe();
}

// setBakeGeometry's choice, unless $CAUSTIC_BAKE_GEOMETRY = 1 or 0 forces it on or off.
bool bakeGeometry(bool requested) {
    if (const char* env = std::getenv("CAUSTIC_BAKE_GEOMETRY"); env && *env) return std::strcmp(env, "0") != 0;
    return requested;
}

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

void waitFence(GLsync fence) {
    while (glClientWaitSync(fence, GL_SYNC_FLUSH_COMMANDS_BIT, 100'000'000) == GL_TIMEOUT_EXPIRED) {}
    glDeleteSync(fence);
}

}  // namespace

std::unique_ptr<Renderer> Renderer::create(const std::string& shaderDir, std::string* error) {
    std::unique_ptr<Renderer> r(new Renderer());
    r->m_shaderDir = shaderDir;
    r->m_specialize = specializeByDefault();
    // The general program now only where it is the one that renders (specialisation off: NVIDIA
    // by default); with specialisation on (llvmpipe) it is built only if a scene's own program
    // fails (selectProgram) or program() is asked for before any scene: its GLSL and NIR passes
    // took 4.8 s of a 16 x 16 Cornell box's 11.7 s on llvmpipe, for a program never used
    // (session 15). A source that does not compile then fails setScene, with the same message.
    if (!r->m_specialize) {
        r->m_general = r->generalProgram(error);
        if (!r->m_general) return nullptr;
        r->m_program = r->m_general;
    }
    {
        const ShaderDefines defines = integratorDefines();
        const bool texelFetching = std::any_of(defines.begin(), defines.end(),
                                               [](const auto& d) { return d.first == "CAUSTIC_FETCH_TEXELS"; });
        r->m_limits = queryGpuLimits(texelFetching);
    }
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
    glCreateBuffers(1, &r->m_primitiveHits);
    glCreateBuffers(1, &r->m_wideNodes);
    glCreateBuffers(1, &r->m_pairNodes);
    glCreateBuffers(1, &r->m_wide8Nodes);
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
    glDeleteBuffers(1, &m_primitiveHits);
    glDeleteBuffers(1, &m_wideNodes);
    glDeleteBuffers(1, &m_pairNodes);
    glDeleteBuffers(1, &m_wide8Nodes);
    glDeleteTextures(kTexelViews, m_texelViews);
    unsigned textures[5] = {m_accum, m_accumSq, m_albedo, m_normal, m_envTexture};
    glDeleteTextures(5, textures);
    for (const auto& [key, program] : m_programs) glDeleteProgram(program);
}

ShaderDefines Renderer::featureDefines() const {
    return caustic::featureDefines(makeFrame(m_scene, m_compiled, m_strategy), m_compiled, bakeGeometry(m_bakeGeometry));
}

unsigned Renderer::generalProgram(std::string* error) {
    if (!m_general) {
        ShaderDefines defines = integratorDefines();
        for (const auto& d : generalDefines(false)) defines.push_back(d);
        m_general = buildProgram("integrator/path.comp", defines, error);
    }
    return m_general;
}

unsigned Renderer::program() {
    if (m_program) return m_program;
    std::string error;
    return generalProgram(&error);
}

bool Renderer::selectProgram(std::string* error) {
    // Keyed by the defines: the same kinds of content reuse the program built for them. A failure
    // falls back to the general program; when that fails too (the source does not compile), there
    // is no program (m_program 0) and dispatches render nothing until one builds.
    std::string why;
    const bool built = m_specialize ? useProgram(featureDefines(), &why)
                                    : useProgram(generalDefines(hasAlphaMask(m_compiled)), &why);
    if (built) {
        m_programFellBack = false;
        return true;
    }
    std::string generalWhy;
    if (const unsigned general = generalProgram(&generalWhy)) {
        // Said once per failure, not before every dispatch (each selects its program).
        if (!m_programFellBack || why != m_fallbackReason)
            std::fprintf(stderr, "caustic: the %s integrator failed to build, using the general one: %s\n",
                         m_specialize ? "specialised" : "alpha-masked", why.c_str());
        m_fallbackReason = why;
        m_program = general;
        m_programFellBack = true;
        return true;
    }
    m_programFellBack = false;
    m_program = 0;
    *error = why;
    return false;
}

unsigned Renderer::buildProgram(const std::string& file, const ShaderDefines& defines, std::string* error) {
    std::string key = file + ":";
    for (const auto& [name, value] : defines) key += name + "=" + value + ";";
    if (auto it = m_programs.find(key); it != m_programs.end()) return it->second;
    // A failure is kept too: every dispatch selects its program, and retrying a source that does
    // not compile cost seconds each time on llvmpipe.
    if (auto it = m_programFailures.find(key); it != m_programFailures.end()) {
        *error = it->second;
        return 0;
    }
    ShaderLoader loader(m_shaderDir);
    ShaderSource source;
    if (!loader.load(file, defines, &source, error)) return 0;
    const unsigned program = compileComputeProgram(source, file, error);
    if (program) m_programs.emplace(key, program);
    else m_programFailures.emplace(key, *error);
    return program;
}

bool Renderer::useProgram(const ShaderDefines& features, std::string* error) {
    ShaderDefines defines = integratorDefines();
    defines.insert(defines.end(), features.begin(), features.end());
    const unsigned program = buildProgram("integrator/path.comp", defines, error);
    if (!program) return false;
    m_program = program;
    return true;
}

bool Renderer::setScene(const Scene& scene, std::string* error) {
    // The meshes' laid-out data moves over from the last compile when the files are the same (an
    // object added or removed beside a big mesh). When it stayed in place (the top level within its
    // reserve of nodes), the meshes' triangles, vertices and nodes on the GPU are still right and
    // only the rest is uploaded; otherwise everything is.
    const auto previousMeshes = m_compiled.meshEntries;
    const std::size_t previousNodes = m_compiled.bvhNodes.size();
    const std::uint32_t previousReserve = m_compiled.tlasNodeCapacity;
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
    if (!selectProgram(error)) return false;  // compiled now, not inside the first render
    resetAccumulation();
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
        scene.render.lightSelection != m_scene.render.lightSelection)
        return setScene(scene, error);
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
    if (!selectProgram(error)) return false;  // compiled now, not inside the first render
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
        uploadBuffer(m_pairNodes, m_compiled.pairNodes);
        uploadBuffer(m_wide8Nodes, m_compiled.wide8Nodes);
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

void Renderer::setStrategy(std::uint32_t strategy) {
    m_strategy = strategy;
    // The program is built by the next setScene or dispatch: caustic sets the strategy before the
    // scene, and building it here made a program for the empty scene (2 s on llvmpipe) never used.
    resetAccumulation();
}

void Renderer::resetAccumulation() {
    const float zero[4] = {0, 0, 0, 0};
    if (m_accum) {
        glClearTexImage(m_accum, 0, GL_RGBA, GL_FLOAT, zero);
        glClearTexImage(m_accumSq, 0, GL_RGBA, GL_FLOAT, zero);
        glClearTexImage(m_albedo, 0, GL_RGBA, GL_FLOAT, zero);
        glClearTexImage(m_normal, 0, GL_RGBA, GL_FLOAT, zero);
    }
    const std::uint32_t counters[COUNTER_WORDS] = {};
    glNamedBufferSubData(m_counters, 0, sizeof counters, counters);
    m_samplesDone = 0;
    m_bandTile = 0;
}

void Renderer::bindScene(std::uint32_t firstSample, std::uint32_t samples) { bindScene(firstSample, samples, 0, ~0u); }

std::uint32_t Renderer::tileCount() const {
    return ((static_cast<std::uint32_t>(m_width) + 7) / 8) * ((static_cast<std::uint32_t>(m_height) + 7) / 8);
}

void Renderer::bindScene(std::uint32_t firstSample, std::uint32_t samples, std::uint32_t tile0, std::uint32_t tile1) {
    gpu::GpuFrame frame = makeFrame(m_scene, m_compiled, m_strategy);
    frame.image.z = m_sampleBase + firstSample;
    frame.dispatch.x = samples;
    frame.options.y = static_cast<std::uint32_t>(m_region.x0);   // the crop's origin (path.comp)
    frame.options.z = static_cast<std::uint32_t>(m_region.y0);
    frame.dispatch.z = tile0;
    frame.dispatch.w = std::min(tile1, tileCount());
    // A fresh buffer store per dispatch (orphaning) so an in-flight dispatch keeps its constants.
    glNamedBufferData(m_frameUbo, sizeof frame, &frame, GL_STREAM_DRAW);
    glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_FRAME_UBO, m_frameUbo);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_PRIMITIVES, m_primitives);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_PRIMITIVE_HITS, m_primitiveHits);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_MATERIALS, m_materials);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_LIGHTS, m_lights);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_LIGHT_TREE, m_lightTree);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TABLES, m_tables);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_COUNTERS, m_counters);
    const unsigned geometryBindings[kGeometryBuffers] = {BINDING_BVH_NODES, BINDING_TLAS_REFS, BINDING_INSTANCES,
                                                         BINDING_TRIANGLES, BINDING_VERTICES};
    for (int i = 0; i < kGeometryBuffers; ++i)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, geometryBindings[i], m_geometry[i]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEXELS, m_texels);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TEXTURES, m_textures);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_BSDF_TABLES, m_bsdfTables);
    glBindTextureUnit(TEXUNIT_ENV_MAP, m_envTexture);
    // The buffer textures over the same buffers (read instead of them with CAUSTIC_FETCH_TEXELS,
    // shaders/scene/buffers.glsl), attached again each time: an upload may have replaced a
    // buffer's data store, and with it its size.
    // Each view's format is its unit's TEXUNIT_*_FORMAT (shaders/shared/layout.h), the GLSL image
    // format's name that the shaders' declarations use too, spelled here as the GL enum.
#define TEXEL_VIEW(unit, buffer) {unit, buffer, texelViewFormat(TEXEL_VIEW_FORMAT_NAME(unit##_FORMAT))}
#define TEXEL_VIEW_FORMAT_NAME(format) TEXEL_VIEW_STRING(format)
#define TEXEL_VIEW_STRING(format) #format
    const struct { unsigned unit, buffer; GLenum format; } views[kTexelViews] = {
        TEXEL_VIEW(TEXUNIT_PRIMITIVES, m_primitives),        TEXEL_VIEW(TEXUNIT_BVH_NODES, m_geometry[0]),
        TEXEL_VIEW(TEXUNIT_TRIANGLES, m_geometry[3]),        TEXEL_VIEW(TEXUNIT_TLAS_REFS, m_geometry[1]),
        TEXEL_VIEW(TEXUNIT_INSTANCES, m_geometry[2]),        TEXEL_VIEW(TEXUNIT_MATERIALS, m_materials),
        TEXEL_VIEW(TEXUNIT_PRIMITIVE_HITS, m_primitiveHits), TEXEL_VIEW(TEXUNIT_WIDE_NODES, m_wideNodes),
        TEXEL_VIEW(TEXUNIT_VERTICES, m_geometry[4]),         TEXEL_VIEW(TEXUNIT_TABLES, m_tables),
        TEXEL_VIEW(TEXUNIT_LIGHTS, m_lights),                TEXEL_VIEW(TEXUNIT_LIGHT_TREE, m_lightTree),
        TEXEL_VIEW(TEXUNIT_BSDF_TABLES, m_bsdfTables),       TEXEL_VIEW(TEXUNIT_PAIR_NODES, m_pairNodes),
        TEXEL_VIEW(TEXUNIT_WIDE8_NODES, m_wide8Nodes)};
#undef TEXEL_VIEW_STRING
#undef TEXEL_VIEW_FORMAT_NAME
#undef TEXEL_VIEW
    for (int i = 0; i < kTexelViews; ++i) {
        glTextureBuffer(m_texelViews[i], views[i].format, views[i].buffer);
        glBindTextureUnit(views[i].unit, m_texelViews[i]);
        // The same views as images, for a program that reads them so (CAUSTIC_IMAGE_LOADS), where
        // the context has the image units (GL guarantees 8).
        if (m_imageLoads)
            glBindImageTexture(IMAGE_UNIT_TEXELS + views[i].unit, m_texelViews[i], 0, GL_FALSE, 0, GL_READ_ONLY,
                               views[i].format);
    }
}

void Renderer::dispatch(std::uint32_t firstSample, std::uint32_t samples, std::uint32_t tile0, std::uint32_t tile1) {
    tile1 = std::min(tile1, tileCount());
    if (tile0 >= tile1) return;
    std::string error;
    if (!selectProgram(&error)) {
        // setScene and update report this; a dispatch without a program renders nothing.
        if (error != m_programError) std::fprintf(stderr, "caustic: no integrator to render with: %s\n", error.c_str());
        m_programError = error;
        return;
    }
    m_programError.clear();
    bindScene(firstSample, samples, tile0, tile1);
    glUseProgram(m_program);
    glBindImageTexture(BINDING_ACCUM_IMAGE, m_accum, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(BINDING_ACCUM_SQ_IMAGE, m_accumSq, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(BINDING_ALBEDO_IMAGE, m_albedo, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(BINDING_NORMAL_IMAGE, m_normal, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    // One work group per 8x8 tile, DISPATCH_STRIDES bands of them interleaved (integrator/path.comp);
    // a grid of at most 65535 groups a side (the least GL guarantees), the kernel skipping the
    // groups beyond the tiles.
    const std::uint32_t tiles = tile1 - tile0;
    const std::uint32_t groups = DISPATCH_STRIDES * ((tiles + DISPATCH_STRIDES - 1) / DISPATCH_STRIDES);
    const std::uint32_t gx = std::min<std::uint32_t>(groups, 65535u);
    glDispatchCompute(gx, (groups + gx - 1) / gx, 1);
    // The next dispatch reads what this one wrote.
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                    GL_TEXTURE_UPDATE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

void Renderer::render(int count, const std::function<void(int)>& progress) {
    using Clock = std::chrono::steady_clock;
    struct InFlight { GLsync fence; std::uint32_t samples; Clock::time_point issued; };
    std::deque<InFlight> inFlight;
    if (count > 0 && m_bandTile > 0) {  // first the rest of a sample that renderFor started
        finishBand();
        --count;
    }
    int issued = 0;
    const int firstSample = m_samplesDone;  // m_samplesDone counts retired samples only
    auto retireOldest = [&] {
        InFlight f = inFlight.front();
        inFlight.pop_front();
        waitFence(f.fence);
        // With two in flight the wait measures roughly one dispatch; smooth the estimate.
        double seconds = std::chrono::duration<double>(Clock::now() - f.issued).count() / double(f.samples);
        if (!inFlight.empty()) seconds *= 0.5;
        m_secondsPerSample = m_secondsPerSample == 0.0 ? seconds : 0.7 * m_secondsPerSample + 0.3 * seconds;
        m_samplesDone += static_cast<int>(f.samples);
        if (progress) progress(m_samplesDone);
    };
    const double target = targetDispatchSeconds();
    while (issued < count) {
        std::uint32_t n = 1;
        if (m_secondsPerSample > 0.0)
            n = static_cast<std::uint32_t>(std::clamp(target / m_secondsPerSample, 1.0, double(kMaxSamplesPerDispatch)));
        n = std::min<std::uint32_t>(n, static_cast<std::uint32_t>(count - issued));
        dispatch(static_cast<std::uint32_t>(firstSample + issued), n);
        inFlight.push_back({glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0), n, Clock::now()});
        issued += static_cast<int>(n);
        if (inFlight.size() >= 2) retireOldest();
    }
    while (!inFlight.empty()) retireOldest();
}

long long Renderer::tilePixels(std::uint32_t tile0, std::uint32_t tile1) const {
    // Tiles on the right and bottom edges may be partly outside the image.
    const std::uint32_t tilesX = (static_cast<std::uint32_t>(m_width) + 7) / 8;
    long long pixels = 0;
    for (std::uint32_t t = tile0; t < tile1; ++t) {
        const int x = static_cast<int>(t % tilesX) * 8, y = static_cast<int>(t / tilesX) * 8;
        pixels += static_cast<long long>(std::min(8, m_width - x)) * std::min(8, m_height - y);
    }
    return pixels;
}

double Renderer::finishBand() {
    const auto t0 = std::chrono::steady_clock::now();
    dispatch(static_cast<std::uint32_t>(m_samplesDone), 1, m_bandTile, ~0u);
    waitFence(glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0));
    ++m_samplesDone;
    m_bandTile = 0;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Renderer::Progress Renderer::renderFor(double budgetSeconds, int maxSamples) {
    using Clock = std::chrono::steady_clock;
    Progress p;
    if (maxSamples <= 0 || m_width <= 0 || m_height <= 0) return p;
    const auto start = Clock::now();
    const long long pixels = static_cast<long long>(m_width) * m_height;
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    auto learn = [&](long long pixelSamples, double seconds) {
        if (pixelSamples <= 0 || !(seconds > 0.0)) return;
        const double v = seconds / double(pixelSamples);
        // Quick to follow a heavier scene (an edit), smooth otherwise.
        const double a = v > m_secondsPerPixelSample ? 0.6 : 0.3;
        m_secondsPerPixelSample = m_secondsPerPixelSample == 0.0 ? v : (1.0 - a) * m_secondsPerPixelSample + a * v;
    };
    // Whole samples while one of the whole image fits what is left of the budget. Unmeasured (a
    // new scene, a first call), the first band measures.
    while (m_bandTile == 0 && m_secondsPerPixelSample > 0.0 && p.samplesCompleted < maxSamples) {
        const double left = budgetSeconds - elapsed();
        const double perSample = m_secondsPerPixelSample * double(pixels);
        if (perSample > left) break;
        const int n = std::clamp(static_cast<int>(left / perSample), 1, maxSamples - p.samplesCompleted);
        const auto t0 = Clock::now();
        render(n);
        learn(pixels * n, std::chrono::duration<double>(Clock::now() - t0).count());
        p.samplesCompleted += n;
        p.pixelSamples += pixels * n;
    }
    // Then runs of 8x8 tiles (in rows of tiles) of the next sample; at least one tile per call,
    // so progress never stops (a tile of 64 pixels is the smallest unit of work: on llvmpipe a
    // row of tiles across a 512-pixel image took 20 ms, more than a frame's budget).
    const std::uint32_t tiles = tileCount();
    while (p.samplesCompleted < maxSamples) {
        const double left = budgetSeconds - elapsed();
        if (left <= 0.0 && p.pixelSamples > 0) break;
        // Tiles differ in cost (a wall, the sky) and the estimate lags: aim a little short.
        std::uint32_t n = 1;
        if (m_secondsPerPixelSample > 0.0)
            n = static_cast<std::uint32_t>(std::clamp(0.8 * left / (m_secondsPerPixelSample * 64.0), 1.0, double(tiles)));
        const std::uint32_t tile1 = std::min(tiles, m_bandTile + n);
        const auto t0 = Clock::now();
        dispatch(static_cast<std::uint32_t>(m_samplesDone), 1, m_bandTile, tile1);
        waitFence(glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0));
        learn(64LL * (tile1 - m_bandTile), std::chrono::duration<double>(Clock::now() - t0).count());
        p.pixelSamples += tilePixels(m_bandTile, tile1);
        if (tile1 >= tiles) {
            m_bandTile = 0;
            ++m_samplesDone;
            ++p.samplesCompleted;
        } else {
            m_bandTile = tile1;
        }
    }
    p.seconds = elapsed();
    return p;
}

std::array<std::uint32_t, COUNTER_WORDS> Renderer::readCounters() const {
    std::array<std::uint32_t, COUNTER_WORDS> counters{};
    glGetNamedBufferSubData(m_counters, 0, sizeof counters, counters.data());
    return counters;
}

namespace {
// The 64-bit count in counter words (lo, lo + 1) (integrator/film.glsl, addCount64).
std::uint64_t count64(const std::array<std::uint32_t, COUNTER_WORDS>& counters, int lo) {
    return (std::uint64_t(counters[lo + 1]) << 32) | counters[lo];
}
}  // namespace

std::uint64_t Renderer::droppedSamples() const { return readCounters()[COUNTER_DROPPED]; }

std::uint64_t Renderer::raysTraced() const { return count64(readCounters(), COUNTER_RAYS_LO); }

WalkStats Renderer::walkStats() const {
    const auto counters = readCounters();
    return {count64(counters, COUNTER_WALK_GROUP_STEPS), count64(counters, COUNTER_WALK_LANE_STEPS),
            count64(counters, COUNTER_WALK_TREES), counters[COUNTER_SUBGROUP_SIZE]};
}

std::vector<RowBand> readBackBands(int width, int height, std::size_t bytesPerPixel, std::size_t maxBytes) {
    std::vector<RowBand> bands;
    if (width <= 0 || height <= 0) return bands;
    const std::size_t rowBytes = std::size_t(width) * bytesPerPixel;
    const int perBand = static_cast<int>(std::clamp<std::size_t>(maxBytes / std::max<std::size_t>(rowBytes, 1), 1,
                                                                 std::size_t(height)));
    for (int y = 0; y < height; y += perBand) bands.push_back({y, std::min(perBand, height - y)});
    return bands;
}

Accumulators Renderer::readAccumulators() const {
    Accumulators a;
    a.width = m_width;
    a.height = m_height;
    const size_t n = static_cast<size_t>(m_width) * m_height;
    a.sum.resize(n);
    a.sumSq.resize(n);
    a.albedo.resize(n);
    a.normal.resize(n);
    // In bands of rows: one call's byte count is a GLsizei (readBackBands).
    for (const RowBand& band : readBackBands(m_width, m_height, sizeof(glm::vec4))) {
        const size_t offset = size_t(band.y0) * size_t(m_width);
        const auto bytes = static_cast<GLsizei>(size_t(band.rows) * size_t(m_width) * sizeof(glm::vec4));
        for (const auto& [texture, out] : {std::pair{m_accum, &a.sum}, std::pair{m_accumSq, &a.sumSq},
                                           std::pair{m_albedo, &a.albedo}, std::pair{m_normal, &a.normal}})
            glGetTextureSubImage(texture, 0, 0, band.y0, 0, m_width, band.rows, 1, GL_RGBA, GL_FLOAT, bytes,
                                 out->data() + offset);
    }
    return a;
}

Film Renderer::readFilm() const { return resolveFilm(readAccumulators()); }

}  // namespace caustic
