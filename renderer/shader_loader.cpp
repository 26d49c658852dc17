#include "renderer/shader_loader.h"

#include "renderer/bvh.h"
#include "renderer/file_util.h"
#include "shaders/shared/layout.h"

#include <glad/gl.h>

#include <algorithm>
#include <cstdlib>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <regex>
#include <sstream>

namespace caustic {
namespace fs = std::filesystem;

namespace {

std::string trimLeft(const std::string& s) {
    size_t i = s.find_first_not_of(" \t");
    return i == std::string::npos ? std::string() : s.substr(i);
}

// Parses `#include "name"`; returns false if the line is not an include directive.
bool parseInclude(const std::string& line, std::string* name, bool* malformed) {
    std::string t = trimLeft(line);
    if (t.rfind("#", 0) != 0) return false;
    t = trimLeft(t.substr(1));
    if (t.rfind("include", 0) != 0) return false;
    t = trimLeft(t.substr(7));
    if (t.rfind("<", 0) == 0) {  // a system header: C++-only code in a shared header
        name->clear();
        *malformed = false;
        return true;
    }
    size_t a = t.find('"');
    size_t b = a == std::string::npos ? a : t.find('"', a + 1);
    *malformed = (a != 0 || b == std::string::npos);
    if (!*malformed) *name = t.substr(a + 1, b - a - 1);
    return true;
}

}  // namespace

bool ShaderLoader::load(const std::string& entry, const ShaderDefines& defines, ShaderSource* out,
                        std::string* error) const {
    out->text.clear();
    out->files.clear();
    std::vector<std::string> seen;
    if (!appendFile(entry, "", 0, out, &seen, error)) return false;
    // #version must be the first statement: hoist it and put the defines right after it.
    const std::string& text = out->text;
    size_t v = text.find("#version");
    if (v == std::string::npos) {
        *error = entry + ": no #version directive";
        return false;
    }
    size_t eol = text.find('\n', v);
    std::string versionLine = text.substr(v, eol - v);
    std::string rest = text.substr(0, v) + "\n" + text.substr(eol + 1);
    std::string head = versionLine + "\n";
    for (const auto& [name, value] : defines) head += "#define " + name + " " + value + "\n";
    out->text = head + rest;
    return true;
}

bool ShaderLoader::appendFile(const std::string& rel, const std::string& includedFrom, int includedAtLine,
                              ShaderSource* out, std::vector<std::string>* seen, std::string* error) const {
    fs::path full = fs::path(m_root) / rel;
    std::string key = fs::weakly_canonical(full).string();
    if (std::find(seen->begin(), seen->end(), key) != seen->end()) return true;  // once only
    seen->push_back(key);
    std::string readError;
    auto text = readTextFile(full.string(), &readError);
    if (!text) {
        *error = includedFrom.empty() ? readError
                                      : includedFrom + ":" + std::to_string(includedAtLine) +
                                            ": cannot include \"" + rel + "\": " + readError;
        return false;
    }
    const int index = static_cast<int>(out->files.size());
    out->files.push_back(rel);
    out->text += "#line 1 " + std::to_string(index) + "\n";
    std::istringstream in(*text);
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        std::string name;
        bool malformed = false;
        if (!parseInclude(line, &name, &malformed)) {
            // #version is hoisted by load(); keep the line count by leaving an empty line.
            out->text += line;
            out->text += '\n';
            continue;
        }
        if (!malformed && name.empty()) {
            // `#include <...>` belongs to the C++ side of a shared header (inside #ifdef
            // __cplusplus); GLSL has no system headers, so it becomes a comment.
            out->text += "// " + line + "\n";
            continue;
        }
        if (malformed) {
            *error = rel + ":" + std::to_string(lineNo) + ": malformed #include (expected #include \"file\")";
            return false;
        }
        // Relative to the including file first, then to the root.
        fs::path dir = fs::path(rel).parent_path();
        std::string target = (dir / name).lexically_normal().string();
        if (!fs::exists(fs::path(m_root) / target)) target = fs::path(name).lexically_normal().string();
        if (!appendFile(target, rel, lineNo, out, seen, error)) return false;
        out->text += "#line " + std::to_string(lineNo + 1) + " " + std::to_string(index) + "\n";
    }
    return true;
}

std::string mapShaderLog(const std::string& log, const ShaderSource& source) {
    static const std::regex mesa(R"(^(\d+):(\d+)\((\d+)\))");
    static const std::regex nvidia(R"(^(\d+)\((\d+)\))");
    std::istringstream in(log);
    std::string line, out;
    auto fileName = [&](const std::string& idx) {
        size_t i = std::stoul(idx);
        return i < source.files.size() ? source.files[i] : "<source " + idx + ">";
    };
    while (std::getline(in, line)) {
        std::smatch m;
        if (std::regex_search(line, m, mesa))
            line = fileName(m[1]) + ":" + m[2].str() + "(" + m[3].str() + ")" + m.suffix().str();
        else if (std::regex_search(line, m, nvidia))
            line = fileName(m[1]) + ":" + m[2].str() + m.suffix().str();
        out += line + "\n";
    }
    return out;
}

unsigned compileComputeProgram(const ShaderSource& source, const std::string& entryName, std::string* error) {
    // $CAUSTIC_COMPILE_TIMES = 1 prints each program's compile and link times to stderr (a
    // profiling aid: on llvmpipe the link runs the GLSL and NIR passes; LLVM compiles the program
    // at its first dispatch).
    const char* timesEnv = std::getenv("CAUSTIC_COMPILE_TIMES");
    const bool printTimes = timesEnv && std::strcmp(timesEnv, "1") == 0;
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
    const char* text = source.text.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    const auto t1 = Clock::now();
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    auto infoLog = [](GLuint obj, bool isProgram) {
        GLint len = 0;
        isProgram ? glGetProgramiv(obj, GL_INFO_LOG_LENGTH, &len) : glGetShaderiv(obj, GL_INFO_LOG_LENGTH, &len);
        std::string log(static_cast<size_t>(std::max(len, 1)), '\0');
        isProgram ? glGetProgramInfoLog(obj, len, nullptr, log.data()) : glGetShaderInfoLog(obj, len, nullptr, log.data());
        log.resize(std::strlen(log.c_str()));
        return log;
    };
    if (!ok) {
        *error = "shader " + entryName + " failed to compile:\n" + mapShaderLog(infoLog(shader, false), source);
        glDeleteShader(shader);
        return 0;
    }
    GLuint program = glCreateProgram();
    glAttachShader(program, shader);
    glLinkProgram(program);
    glDeleteShader(shader);
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (printTimes) {
        const auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
        std::fprintf(stderr, "caustic: %s: %zu bytes of source, compiled in %.0f ms, linked in %.0f ms\n",
                     entryName.c_str(), source.text.size(), ms(t1 - t0), ms(Clock::now() - t1));
    }
    if (!ok) {
        *error = "shader " + entryName + " failed to link:\n" + mapShaderLog(infoLog(program, true), source);
        glDeleteProgram(program);
        return 0;
    }
    return program;
}

bool onLlvmpipe() {
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return renderer && std::strstr(renderer, "llvmpipe") != nullptr;
}

ShaderDefines integratorDefines() {
    bool fetchTexels = false;
    if (const char* env = std::getenv("CAUSTIC_FETCH_TEXELS"); env && *env) {
        fetchTexels = std::strcmp(env, "0") != 0;
    } else {
        fetchTexels = onLlvmpipe();
    }
    ShaderDefines defines;
    if (fetchTexels) defines.emplace_back("CAUSTIC_FETCH_TEXELS", "1");
    // Which form of the meshes' trees the walk reads (geometry/bvh.glsl; both extra forms only
    // through buffer textures). On llvmpipe the 4-wide nodes with the register stack (below):
    // against the pair records (renderer/bvh.h, buildPairBvh) mesh-knot 1.13x, textured-gltf
    // 1.09x, textured-mesh 1.11x, gltf-cutouts 1.04x; against the binary nodes about 1.3x on the
    // knot (docs/performance.md, session 13). $CAUSTIC_WIDE_BVH = 0 or 1 and $CAUSTIC_PAIR_BVH
    // = 1 choose (the pair records when the 4-wide nodes are off); neither forces the binary
    // nodes, NVIDIA's (the others are unmeasured there). $CAUSTIC_WIDE_BVH = 8 takes the 8-wide
    // nodes (renderer/bvh.h, buildWide8Bvh): 0.88-0.97x on llvmpipe (session 21), kept to be
    // measured on NVIDIA.
    const int wideAsked = wideBvhRequest();
    const bool pairAsked = pairBvhRequested();
    bool wide = onLlvmpipe() && !pairAsked;
    if (wideAsked >= 0) wide = wideAsked != 0;
    wide = wide && fetchTexels;
    if (wide) defines.emplace_back("CAUSTIC_WIDE_BVH", wideAsked == 8 ? "8" : "1");
    if (pairAsked && fetchTexels && !wide) defines.emplace_back("CAUSTIC_PAIR_BVH", "1");
    // Path regeneration (integrator/path.comp): on by default where the lanes of a work group
    // run in lock step on the CPU (llvmpipe, whatever CAUSTIC_FETCH_TEXELS says);
    // $CAUSTIC_REGENERATE = 1 or 0 forces it. Unmeasured on NVIDIA, so off there.
    if (regeneratesPaths()) defines.emplace_back("CAUSTIC_REGENERATE", "1");
    // The mesh walk's newest stack entries in variables (geometry/bvh.glsl,
    // CAUSTIC_REGISTER_STACK, for every form of the trees): 2 on llvmpipe, where the memory
    // stack's every push and pop is a per-lane store or load (binary walk, mesh-knot at 128 x 128
    // x 8 spp: 8: 1.11x, 4: 1.08x, 12: 1.09x, 16: 1.0x; the 4-wide walk 2.2x, session 13). Since
    // the scene is read with image loads (no helper calls that clobbered every vector register),
    // 2 beats 8 (knot 1.03-1.06x in three runs, textured-gltf 1.04x, gltf-cutouts 1.02x,
    // textured-mesh 1.02x; session 18): fewer vectors held live, fewer spills. Off elsewhere,
    // unmeasured on NVIDIA.
    // $CAUSTIC_REGISTER_STACK = N (1-32) or 0 sets it.
    int registerStack = onLlvmpipe() ? 2 : 0;
    if (const char* env = std::getenv("CAUSTIC_REGISTER_STACK"); env && *env) registerStack = std::clamp(std::atoi(env), 0, 32);
    if (registerStack > 0) defines.emplace_back("CAUSTIC_REGISTER_STACK", std::to_string(registerStack));
    // The buffer textures read as image buffers (scene/buffers.glsl, CAUSTIC_IMAGE_LOADS): on
    // llvmpipe, whose texel fetches are calls (docs/performance.md, session 18); unmeasured on
    // NVIDIA, so off there. $CAUSTIC_IMAGE_LOADS = 1 or 0 forces it (with the buffer textures only).
    bool imageLoads = onLlvmpipe();
    if (const char* env = std::getenv("CAUSTIC_IMAGE_LOADS"); env && *env) imageLoads = std::strcmp(env, "0") != 0;
    if (imageLoads && fetchTexels && imageUnitsForTexelViews()) defines.emplace_back("CAUSTIC_IMAGE_LOADS", "1");
    // The mesh walks' statistics (geometry/bvh.glsl, CAUSTIC_WALK_STATS; Renderer::walkStats,
    // printed by caustic-bench): a benchmark aid, on only where $CAUSTIC_WALK_STATS is set (and not 0). Counts do
    // not move with the machine's load as timings do (docs/performance.md, session 20).
    if (const char* env = std::getenv("CAUSTIC_WALK_STATS"); env && *env && std::strcmp(env, "0") != 0)
        defines.emplace_back("CAUSTIC_WALK_STATS", "1");
    return defines;
}

// Units: the views' images reach IMAGE_UNIT_TEXELS + TEXUNIT_LAST; image uniforms of the
// integrator: the film's IMAGE_UNIT_TEXELS plus one per view (TEXUNIT_1..TEXUNIT_LAST).
bool imageUnitsForTexelViews() {
    GLint units = 0, computeImages = 0;
    glGetIntegerv(GL_MAX_IMAGE_UNITS, &units);
    glGetIntegerv(GL_MAX_COMPUTE_IMAGE_UNIFORMS, &computeImages);
    return units > IMAGE_UNIT_TEXELS + TEXUNIT_LAST && computeImages >= IMAGE_UNIT_TEXELS + TEXUNIT_LAST;
}

bool regeneratesPaths() {
    if (const char* env = std::getenv("CAUSTIC_REGENERATE"); env && *env) return std::strcmp(env, "0") != 0;
    return onLlvmpipe();
}

std::string defaultShaderDir() {
    if (const char* env = std::getenv("CAUSTIC_SHADER_DIR"); env && *env) return env;
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        for (fs::path candidate : {exe.parent_path() / ".." / "shaders", exe.parent_path() / "shaders"})
            if (fs::exists(candidate / "integrator", ec)) return candidate.lexically_normal().string();
    }
#ifdef CAUSTIC_SOURCE_SHADER_DIR
    return CAUSTIC_SOURCE_SHADER_DIR;
#else
    return "shaders";
#endif
}

}  // namespace caustic
