// The integrator's programs: the scene-specialised configuration (featureDefines), baked
// geometry, and building, caching and choosing the program a dispatch uses.
#include "renderer/renderer.h"
#include "renderer/renderer_internal.h"

#include "renderer/bsdf_tables.h"
#include "renderer/program_builder.h"

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

// The scene-specialised configuration of the integrator (shaders/scene/features.glsl) for the
// scene and settings of `frame`: the kinds of material, light, shape, environment, sampler and
// light selection present, the traversal the scene gets, whether it has one light only.
bool hasAlphaMask(const CompiledScene& c) {
    return std::any_of(c.instances.begin(), c.instances.end(),
                       [](const gpu::GpuInstance& i) { return (i.flags & PRIM_FLAG_ALPHA_MASK) != 0u; });
}

// What the scene's media need of the integrator (CAUSTIC_MEDIA, MEDIA_* bits;
// integrator/medium.glsl): 0 without any, so that a scene without media runs the code it ran
// before they existed, specialised or not.
std::uint32_t mediaBits(const gpu::GpuFrame& frame, const CompiledScene& c) {
    std::uint32_t bits = 0;
    auto add = [&](glm::vec3 sigmaA, glm::vec3 sigmaS) {
        if (sigmaA != glm::vec3(0.0f) || sigmaS != glm::vec3(0.0f)) bits |= MEDIA_ABSORBING;
        if (sigmaS != glm::vec3(0.0f)) bits |= MEDIA_SCATTERING;
    };
    add(glm::vec3(frame.mediumA), glm::vec3(frame.mediumS));
    for (const gpu::GpuMaterial& m : c.materials) {
        if ((m.info.y & MAT_FLAG_MEDIUM) != 0u) add(glm::vec3(m.k), glm::vec3(m.eta));
        if (m.info.x == MAT_VOLUME) bits |= MEDIA_BOUNDARIES | MEDIA_ABSORBING;
        if ((m.info.y & (MAT_FLAG_TRANSMISSION_PART | MAT_FLAG_SUBSURFACE_PART)) != 0u)
            bits |= MEDIA_SURFACE_PARTS;  // info.w: the parts' index, not a priority
        else if (m.info.w != 0u)
            bits |= MEDIA_NESTED;
        if ((m.info.y & MAT_FLAG_RANDOM_WALK) != 0u) bits |= MEDIA_RANDOM_WALK;
    }
    return bits;
}

// The unspecialised program's feature defines: alpha masks and media are compiled in only for a
// scene that has them. Their test sits in traversal's innermost loop, where code size costs every ray on
// a GPU (docs/performance.md, "The integrator profile (H100)"), so a scene without masks must not
// pay for it where specialisation is off either (NVIDIA, by default). With 0 the code is still
// compiled (a constant-false branch), so the general program still checks the whole source.
ShaderDefines generalDefines(bool alphaMask, std::uint32_t media) {
    return {{"CAUSTIC_ALPHA_MASK", alphaMask ? "1u" : "0u"}, {"CAUSTIC_MEDIA", std::to_string(media) + "u"}};
}

// The media the general program (Renderer::generalProgram) is built for.
constexpr std::uint32_t kGeneralMedia = MEDIA_ABSORBING | MEDIA_SCATTERING | MEDIA_BOUNDARIES | MEDIA_NESTED;


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
        out += glslRow(glm::uvec4(in.rootNode, in.firstTriangle, in.material, in.light)) + "," +
               glslRow(glm::uvec4(in.firstVertex, in.triangleCount, in.fileMaterials, in.flags)) + "," +
               glslRow(glm::uvec4(in.wideRoot, in.unused0, in.unused1, in.unused2)) + ",";
        const gpu::GpuBvhNode& root = c.bvhNodes[in.rootNode];
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
    // run under a lane mask at every vertex (docs/performance.md).
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
            {"CAUSTIC_MEDIA", std::to_string(mediaBits(frame, c)) + "u"},
            {"CAUSTIC_SINGLE_LIGHT", singleLight ? "1u" : "0u"},
            {"CAUSTIC_CAMERA", std::to_string((frame.camInfo.z != 0u ? CAMERA_LENS_SYSTEM : 0u) |
                                              (frame.aperture.w != 0u ? CAMERA_APERTURE_IMAGE : 0u)) + "u"},
            {"CAUSTIC_TRAVERSAL", bruteForce ? "1u" : "2u"}};
    if (bake && bruteForce) defines.push_back({"CAUSTIC_BAKED_PRIMITIVES", bakedPrimitiveTests(c)});
    // A baked top level: at most 32 entries, of them at most 16 instances (traceScenePair keeps
    // both of a step's rays' instance candidates in one 32-bit mask), and a path step's
    // continuation and shadow rays walked together (integrator/path.glsl, CAUSTIC_PAIRED_TRACE).
    // (Not with media: a medium's shadow rays cross boundaries and carry a transmittance.)
    if (bake && !bruteForce && !c.instances.empty() && c.instances.size() <= 16 && mediaBits(frame, c) == 0u &&
        c.primitives.size() + c.instances.size() <= BVH_BRUTE_FORCE_MAX) {
        defines.push_back({"CAUSTIC_BAKED_TOP_LEVEL", bakedPrimitiveTests(c) + bakedInstanceTests(c)});
        defines.push_back({"CAUSTIC_PAIRED_TRACE", "1"});
    }
    return defines;
}

}  // namespace

ShaderDefines Renderer::featureDefines() const {
    return caustic::featureDefines(makeFrame(m_scene, m_compiled, m_strategy), m_compiled, m_config.bakeGeometry.value_or(m_bakeGeometry));
}

unsigned Renderer::generalProgram(std::string* error, bool* pending) {
    if (!m_general) {
        ShaderDefines defines = m_config.defines();
        for (const auto& d : generalDefines(false, kGeneralMedia)) defines.push_back(d);
        m_general = buildProgram("integrator/path.comp", defines, error, pending);
    }
    return m_general;
}

namespace {

std::string programKey(const std::string& file, const ShaderDefines& defines) {
    std::string key = file + ":";
    for (const auto& [name, value] : defines) key += name + "=" + value + ";";
    return key;
}

}  // namespace

unsigned Renderer::standInProgram() const { return m_general != 0 && generalRendersScene() ? m_general : 0u; }

bool Renderer::generalRendersScene() const {
    return !hasAlphaMask(m_compiled) && (mediaBits(makeFrame(m_scene, m_compiled, m_strategy), m_compiled) & ~kGeneralMedia) == 0u;
}

void Renderer::setProgramBuilder(std::shared_ptr<ProgramBuilder> builder) { m_builder = std::move(builder); }

unsigned Renderer::program() {
    if (m_program) return m_program;
    std::string error;
    return generalProgram(&error);
}

ShaderDefines Renderer::selectedDefines() const {
    ShaderDefines defines = m_config.defines();
    const ShaderDefines features =
        m_specialize ? featureDefines()
                     : generalDefines(hasAlphaMask(m_compiled), mediaBits(makeFrame(m_scene, m_compiled, m_strategy), m_compiled));
    defines.insert(defines.end(), features.begin(), features.end());
    return defines;
}

bool Renderer::programPending() const {
    const std::string key = programKey("integrator/path.comp", selectedDefines());
    if (m_programs.contains(key) || m_programFailures.contains(key)) return false;
    // Built in the background and done: taken at the next dispatch, which then renders with it.
    const auto it = m_building.find(key);
    return it == m_building.end() || !it->second->done();
}

bool Renderer::selectProgram(std::string* error) {
    // Keyed by the defines: the same kinds of content reuse the program built for them. A failure
    // falls back to the general program; when that fails too (the source does not compile), there
    // is no program (m_program 0) and dispatches render nothing until one builds.
    // With a builder (setProgramBuilder) a program not built yet is asked for and this returns at
    // once: meanwhile a stand-in renders where one is built and renders the scene right
    // (standInProgram: the same image, it differs only in code the scene does not reach), else
    // nothing renders (false with no error, m_waitingForBuild) and the accumulated image stays as
    // it is.
    std::string why;
    bool pending = false;
    bool* async = m_builder ? &pending : nullptr;
    const ShaderDefines wanted = selectedDefines();
    if (m_builder) settleBuilds(programKey("integrator/path.comp", wanted));
    const unsigned selected = buildProgram("integrator/path.comp", wanted, &why, async);
    if (selected) m_program = selected;
    m_waitingForBuild = pending;
    const bool built = selected != 0;
    if (built) {
        m_programFellBack = false;
        return true;
    }
    if (pending) {
        m_programFellBack = false;
        m_program = standInProgram();
        error->clear();
        return m_program != 0;
    }
    std::string generalWhy;
    const unsigned general = generalProgram(&generalWhy, async);
    if (pending) {
        m_waitingForBuild = true;
        m_programFellBack = false;
        m_program = 0;
        error->clear();
        return false;
    }
    if (general) {
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

unsigned Renderer::buildProgram(const std::string& file, const ShaderDefines& defines, std::string* error, bool* pending) {
    const std::string key = programKey(file, defines);
    if (auto it = m_programs.find(key); it != m_programs.end()) return it->second;
    // A failure is kept too: every dispatch selects its program, and retrying a source that does
    // not compile cost seconds each time on llvmpipe.
    if (auto it = m_programFailures.find(key); it != m_programFailures.end()) {
        *error = it->second;
        return 0;
    }
    if (pending) {   // built on the builder's thread: asked for once, taken when done
        if (auto it = m_building.find(key); it != m_building.end()) {
            if (!it->second->done()) {
                *pending = true;
                return 0;
            }
            const unsigned program = it->second->program();
            if (program) m_programs.emplace(key, program);
            else m_programFailures.emplace(key, *error = it->second->error());
            m_building.erase(it);
            return program;
        }
    }
    ShaderLoader loader(m_shaderDir);
    ShaderSource source;
    if (!loader.load(file, defines, &source, error)) return 0;
    if (pending) {
        m_building.emplace(key, m_builder->request(std::move(source), file, m_config.compileTimes));
        *pending = true;
        return 0;
    }
    const unsigned program = compileComputeProgram(source, file, error, m_config.compileTimes);
    if (program) m_programs.emplace(key, program);
    else m_programFailures.emplace(key, *error);
    return program;
}

void Renderer::settleBuilds(const std::string& wantedKey) {
    // Finished for a scene no longer shown (an edit came first): kept like any other, so that what
    // the builder made never piles up here.
    for (auto it = m_building.begin(); it != m_building.end();) {
        if (it->first == wantedKey || !it->second->done()) {
            ++it;
            continue;
        }
        if (const unsigned program = it->second->program()) m_programs.emplace(it->first, program);
        else m_programFailures.emplace(it->first, it->second->error());
        it = m_building.erase(it);
    }
}

}  // namespace caustic
