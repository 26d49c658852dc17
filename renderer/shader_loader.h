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
// files (through mapShaderLog), prefixed with the entry file.
unsigned compileComputeProgram(const ShaderSource& source, const std::string& entryName,
                               std::string* error);

// Whether the current context's driver is Mesa's llvmpipe (GL_RENDERER), where the integrator's
// configuration differs (integratorDefines, the renderer's specialisation).
bool onLlvmpipe();

// The configuration every program that includes the scene's shaders is built with (the
// integrator, the test kernels, the benchmark's kernels), for the current context's driver: on
// Mesa's llvmpipe CAUSTIC_FETCH_TEXELS (scene data read through buffer textures; why:
// shaders/scene/buffers.glsl). $CAUSTIC_FETCH_TEXELS = 1 or 0 forces it on or off (to test both
// configurations on one driver). The same GLSL source either way.
ShaderDefines integratorDefines();

// Whether this context has image units for every buffer texture's image view (IMAGE_UNIT_TEXELS +
// TEXUNIT_*, shared/layout.h): where CAUSTIC_IMAGE_LOADS may be defined (scene/buffers.glsl).
bool imageUnitsForTexelViews();

// Whether integratorDefines() turns on path regeneration (CAUSTIC_REGENERATE: a lane whose path
// ends starts its pixel's next sample within the same dispatch; integrator/path.comp): by default
// on llvmpipe, $CAUSTIC_REGENERATE = 1 or 0 forces it. It pays only when a dispatch holds several
// samples per pixel, so the renderer then makes its batch dispatches longer.
bool regeneratesPaths();

// Where the shaders are: $CAUSTIC_SHADER_DIR, else <executable dir>/../shaders (build/caustic in
// a checkout), else the source tree's shaders/ recorded at configure time.
std::string defaultShaderDir();

}  // namespace caustic
