// Every run-time choice of how the integrator is built and dispatched, in one struct: which form
// of the meshes' trees the walk reads, how the scene data is read, whether a program is built per
// scene, path regeneration, the dispatch length, and two measuring aids. A program fills one
// IntegratorConfig once (from its defaults, its flags and fromEnvironment) and passes it to
// Renderer::create; nothing below reads the process environment for these choices.
//
// Each choice left unset takes the device's default (resolveIntegratorConfig), chosen per
// back-end from measurements: NVIDIA's on the H100, llvmpipe's on the 2-core VM
// (docs/performance.md, "Why llvmpipe's defaults are what they are"). Which defaults apply is
// detected from the GL renderer's name, or forced (`defaults`) so that one back-end's
// configuration can be run on the other (the tests render NVIDIA's on llvmpipe).
#pragma once

#include "renderer/shader_loader.h"

#include <optional>
#include <string>
#include <vector>

namespace caustic {

enum class IntegratorDefaults {
    Detect,    // from the current context's GL_RENDERER: llvmpipe's on llvmpipe, NVIDIA's elsewhere
    Llvmpipe,  // scene read through image loads, 4-wide walk, one program per scene, regeneration
    Nvidia,    // storage buffers, binary walk, one general program, no regeneration
};

struct IntegratorConfig {
    IntegratorDefaults defaults = IntegratorDefaults::Detect;  // $CAUSTIC_DEFAULTS = llvmpipe | nvidia
    // The scene's hot data read through buffer textures instead of storage buffers
    // (CAUSTIC_FETCH_TEXELS; scene/buffers.glsl). $CAUSTIC_FETCH_TEXELS = 0 | 1.
    std::optional<bool> fetchTexels;
    // The meshes walked in their 4-wide form (geometry/walk_wide4.glsl) instead of the binary one
    // (geometry/walk_binary.glsl); needs fetchTexels. $CAUSTIC_WIDE_BVH = 0 | 1.
    std::optional<bool> wideTree;
    // How many of the 4-wide walk's pending entries it holds in variables (1-32).
    // $CAUSTIC_REGISTER_STACK = N.
    std::optional<int> registerStack;
    // The buffer textures read as image buffers (CAUSTIC_IMAGE_LOADS; scene/buffers.glsl), where
    // the driver has the image units. $CAUSTIC_IMAGE_LOADS = 0 | 1.
    std::optional<bool> imageLoads;
    // One program per scene, keeping only the code the scene uses (scene/features.glsl).
    // $CAUSTIC_SPECIALIZE = 0 | 1.
    std::optional<bool> specialize;
    // The scene's primitives as constants of its program (forces Renderer::setBakeGeometry's
    // choice on or off). $CAUSTIC_BAKE_GEOMETRY = 0 | 1.
    std::optional<bool> bakeGeometry;
    // Path regeneration (integrator/path.comp): a lane whose path ended starts the next sample's.
    // $CAUSTIC_REGENERATE = 0 | 1.
    std::optional<bool> regenerate;
    // How long one dispatch aims to take, in seconds (0, 60]. $CAUSTIC_DISPATCH_SECONDS = S.
    std::optional<double> dispatchSeconds;
    // Measuring aids, off unless asked for: the mesh walks' statistics (Renderer::walkStats;
    // $CAUSTIC_WALK_STATS = 1) and each program's compile and link times on stderr
    // ($CAUSTIC_COMPILE_TIMES = 1).
    bool walkStats = false;
    bool compileTimes = false;
    // Where built programs are kept between runs (renderer/program_cache.h): a folder, or "off".
    // Unset: $XDG_CACHE_HOME/caustic/programs, else ~/.cache/caustic/programs. Process-wide: the
    // program hands it to useProgramCache before it builds. $CAUSTIC_PROGRAM_CACHE = DIR | off.
    std::optional<std::string> programCache;

    // The defaults with the CAUSTIC_* variables above applied: the one place that reads them. A
    // value it cannot read is ignored with a line in `warnings` naming the variable.
    static IntegratorConfig fromEnvironment(std::vector<std::string>* warnings = nullptr);
};

// A configuration with every choice made, for the device it runs on.
struct ResolvedIntegratorConfig {
    bool llvmpipeDefaults = false;  // whose defaults filled the unset choices
    bool fetchTexels = false;
    bool wideTree = false;
    int registerStack = 0;          // 0 without the 4-wide walk
    bool imageLoads = false;
    bool specialize = false;
    std::optional<bool> bakeGeometry;
    bool regenerate = false;
    double dispatchSeconds = 0.05;
    bool walkStats = false;
    bool compileTimes = false;

    // The integrator's defines for this configuration (what path.comp and the test kernels are
    // compiled with, before a scene's own).
    ShaderDefines defines() const;
    // One line naming the choices, for logs and benchmarks ("llvmpipe defaults: texel fetches,
    // image loads, 4-wide walk (2 held), specialised, regeneration, 1 s dispatches").
    std::string describe() const;
};

// Fills the unset choices with the defaults of the device the current GL context runs on (or of
// config.defaults) and drops the ones the device cannot do (image loads without enough image
// units; the 4-wide walk without texel fetches). Needs a current context.
ResolvedIntegratorConfig resolveIntegratorConfig(const IntegratorConfig& config);

}  // namespace caustic
