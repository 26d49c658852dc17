#include "renderer/shader_loader.h"

#include "renderer/program_cache.h"

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

unsigned compileComputeProgram(const ShaderSource& source, const std::string& entryName, std::string* error,
                               bool printTimes) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    const auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
    // Built before, with this source and driver: its binary (renderer/program_cache.h).
    if (const unsigned cached = loadCachedProgram(source.text)) {
        if (printTimes)
            std::fprintf(stderr, "caustic: %s: %zu bytes of source, loaded from the program cache in %.0f ms\n",
                         entryName.c_str(), source.text.size(), ms(Clock::now() - t0));
        return cached;
    }
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
    glProgramParameteri(program, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
    glLinkProgram(program);
    glDeleteShader(shader);
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (printTimes) {
        std::fprintf(stderr, "caustic: %s: %zu bytes of source, compiled in %.0f ms, linked in %.0f ms\n",
                     entryName.c_str(), source.text.size(), ms(t1 - t0), ms(Clock::now() - t1));
    }
    if (!ok) {
        *error = "shader " + entryName + " failed to link:\n" + mapShaderLog(infoLog(program, true), source);
        glDeleteProgram(program);
        return 0;
    }
    storeCachedProgram(program, source.text);
    return program;
}

bool onLlvmpipe() {
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return renderer && std::strstr(renderer, "llvmpipe") != nullptr;
}

// Units: the views' images reach IMAGE_UNIT_TEXELS + TEXUNIT_LAST; image uniforms of the
// integrator: the film's IMAGE_UNIT_TEXELS plus one per view (TEXUNIT_1..TEXUNIT_LAST).
bool imageUnitsForTexelViews() {
    GLint units = 0, computeImages = 0;
    glGetIntegerv(GL_MAX_IMAGE_UNITS, &units);
    glGetIntegerv(GL_MAX_COMPUTE_IMAGE_UNIFORMS, &computeImages);
    return units > IMAGE_UNIT_TEXELS + TEXUNIT_LAST && computeImages >= IMAGE_UNIT_TEXELS + TEXUNIT_LAST;
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
