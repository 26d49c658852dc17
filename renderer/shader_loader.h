// GLSL source assembly: resolves #include "file" (relative to the including file, then to the
// shader root), includes each file once (include guards for free), inserts a table of #defines
// after #version, and emits #line directives so that a compiler message names the real file and
// line, e.g. "bsdf/lambert.glsl:42(7): error: ...".
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace caustic {

using ShaderDefines = std::vector<std::pair<std::string, std::string>>;

struct ShaderSource {
    std::string text;                 // what is handed to glShaderSource
    std::vector<std::string> files;   // source-string number used in #line -> file (root-relative)
};

class ShaderLoader {
public:
    explicit ShaderLoader(std::string rootDir) : m_root(std::move(rootDir)) {}
    const std::string& root() const { return m_root; }

    // entry is relative to the root. On error (missing file, missing include, include cycle is
    // harmless: each file is included once) returns false with a message naming file and line.
    bool load(const std::string& entry, const ShaderDefines& defines, ShaderSource* out,
              std::string* error) const;

private:
    bool appendFile(const std::string& rel, const std::string& includedFrom, int includedAtLine,
                    ShaderSource* out, std::vector<std::string>* seen, std::string* error) const;
    std::string m_root;
};

// Rewrites "0:12(3): error" (Mesa) and "0(12) : error" (NVIDIA) into "file:12(3): error".
std::string mapShaderLog(const std::string& log, const ShaderSource& source);

// Compiles and links a compute program; on failure returns 0 and an error whose lines name the
// files (through mapShaderLog), prefixed with the entry file. With printTimes, its compile and
// link times go to stderr (a measuring aid: on llvmpipe the link runs the GLSL and NIR passes;
// LLVM compiles the program at its first dispatch).
unsigned compileComputeProgram(const ShaderSource& source, const std::string& entryName, std::string* error,
                               bool printTimes = false);

// Whether the current context's driver is Mesa's llvmpipe (GL_RENDERER), whose defaults differ
// (renderer/integrator_config.h).
bool onLlvmpipe();

// Whether this context has image units for every buffer texture's image view (IMAGE_UNIT_TEXELS +
// TEXUNIT_*, shared/layout.h): where CAUSTIC_IMAGE_LOADS may be defined (scene/buffers.glsl).
bool imageUnitsForTexelViews();

// Where the shaders are: $CAUSTIC_SHADER_DIR, else <executable dir>/../shaders (build/caustic in
// a checkout), else the source tree's shaders/ recorded at configure time.
std::string defaultShaderDir();

}  // namespace caustic
