#include "renderer/integrator_config.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <cstdio>

namespace caustic {

namespace {

// $name as a boolean: "0" is false, any other non-empty value true; unset or empty: nullopt.
std::optional<bool> envFlag(const char* name) {
    const char* v = std::getenv(name);
    if (!v || !*v) return std::nullopt;
    return std::strcmp(v, "0") != 0;
}

// Constants of the defaults, with the reasons (figures: docs/performance.md).
// A dispatch aims at this long: long enough to amortise its overhead, short enough that the
// driver never queues seconds of work (NVIDIA's drops a long queue).
constexpr double kDispatchSeconds = 0.05;
// With path regeneration a dispatch needs several samples per pixel for a lane whose path ended
// to have another to start, and the more it holds the less its lanes idle at the end: llvmpipe
// runs a dispatch on the CPU, with no watchdog, so batch dispatches there aim at a second.
constexpr double kRegeneratingDispatchSeconds = 1.0;
// The 4-wide walk's entries held in variables on llvmpipe: 2 beats 1, 4 and 8 there (fewer
// vectors live, fewer spills, since the scene is read by image loads).
constexpr int kRegisterStack = 2;

}  // namespace

IntegratorConfig IntegratorConfig::fromEnvironment(std::vector<std::string>* warnings) {
    IntegratorConfig c;
    auto warn = [&](const char* name, const char* value, const char* expected) {
        if (warnings) warnings->push_back(std::string("$") + name + "=" + value + " ignored (expected " + expected + ")");
    };
    if (const char* v = std::getenv("CAUSTIC_DEFAULTS"); v && *v) {
        if (std::strcmp(v, "llvmpipe") == 0) c.defaults = IntegratorDefaults::Llvmpipe;
        else if (std::strcmp(v, "nvidia") == 0) c.defaults = IntegratorDefaults::Nvidia;
        else warn("CAUSTIC_DEFAULTS", v, "llvmpipe or nvidia");
    }
    c.fetchTexels = envFlag("CAUSTIC_FETCH_TEXELS");
    c.wideTree = envFlag("CAUSTIC_WIDE_BVH");
    if (const char* v = std::getenv("CAUSTIC_REGISTER_STACK"); v && *v) {
        char* end = nullptr;
        const long n = std::strtol(v, &end, 10);
        if (end != v && *end == '\0' && n >= 1 && n <= 32) c.registerStack = static_cast<int>(n);
        else warn("CAUSTIC_REGISTER_STACK", v, "an integer from 1 to 32");
    }
    c.imageLoads = envFlag("CAUSTIC_IMAGE_LOADS");
    c.specialize = envFlag("CAUSTIC_SPECIALIZE");
    c.bakeGeometry = envFlag("CAUSTIC_BAKE_GEOMETRY");
    c.regenerate = envFlag("CAUSTIC_REGENERATE");
    if (const char* v = std::getenv("CAUSTIC_DISPATCH_SECONDS"); v && *v) {
        char* end = nullptr;
        const double s = std::strtod(v, &end);
        if (end != v && *end == '\0' && std::isfinite(s) && s > 0.0 && s <= 60.0) c.dispatchSeconds = s;
        else warn("CAUSTIC_DISPATCH_SECONDS", v, "seconds in (0, 60]");
    }
    c.walkStats = envFlag("CAUSTIC_WALK_STATS").value_or(false);
    c.compileTimes = envFlag("CAUSTIC_COMPILE_TIMES").value_or(false);
    if (const char* v = std::getenv("CAUSTIC_PROGRAM_CACHE")) c.programCache = v;
    return c;
}

ResolvedIntegratorConfig resolveIntegratorConfig(const IntegratorConfig& c) {
    ResolvedIntegratorConfig r;
    r.llvmpipeDefaults = c.defaults == IntegratorDefaults::Detect ? onLlvmpipe()
                                                                   : c.defaults == IntegratorDefaults::Llvmpipe;
    const bool lp = r.llvmpipeDefaults;
    // llvmpipe runs 8 invocations as the lanes of one SIMD register; a storage-buffer load is a
    // loop over the lanes with a bounds check each, a texel fetch one gather (scene/buffers.glsl).
    r.fetchTexels = c.fetchTexels.value_or(lp);
    // The 4-wide tree: half the steps of the binary one, each testing four boxes, which llvmpipe
    // pays for whatever a step does. It is read through a buffer texture only.
    r.wideTree = c.wideTree.value_or(lp) && r.fetchTexels;
    r.registerStack = r.wideTree ? std::clamp(c.registerStack.value_or(kRegisterStack), 1, 32) : 0;
    // Image loads: llvmpipe calls a helper for each texel fetch of a non-8-bit format, which spills
    // the caller's vectors; an image load is generated in line. They need an image unit per view.
    r.imageLoads = c.imageLoads.value_or(lp) && r.fetchTexels && imageUnitsForTexelViews();
    // Specialisation: on llvmpipe code a scene does not use still costs its full time.
    r.specialize = c.specialize.value_or(lp);
    r.bakeGeometry = c.bakeGeometry;
    // Regeneration: pays where a work group's lanes run in lock step on the CPU; unmeasured on
    // NVIDIA, so off there.
    r.regenerate = c.regenerate.value_or(lp);
    r.dispatchSeconds = c.dispatchSeconds.value_or(r.regenerate ? kRegeneratingDispatchSeconds : kDispatchSeconds);
    r.walkStats = c.walkStats;
    r.compileTimes = c.compileTimes;
    return r;
}

ShaderDefines ResolvedIntegratorConfig::defines() const {
    ShaderDefines d;
    if (fetchTexels) d.emplace_back("CAUSTIC_FETCH_TEXELS", "1");
    if (wideTree) {
        d.emplace_back("CAUSTIC_WIDE_BVH", "1");
        d.emplace_back("CAUSTIC_REGISTER_STACK", std::to_string(registerStack));
    }
    if (regenerate) d.emplace_back("CAUSTIC_REGENERATE", "1");
    if (imageLoads) d.emplace_back("CAUSTIC_IMAGE_LOADS", "1");
    if (walkStats) d.emplace_back("CAUSTIC_WALK_STATS", "1");
    return d;
}

std::string ResolvedIntegratorConfig::describe() const {
    std::string s = llvmpipeDefaults ? "llvmpipe defaults:" : "NVIDIA defaults:";
    s += fetchTexels ? " texel fetches" : " storage buffers";
    if (imageLoads) s += ", image loads";
    s += wideTree ? ", 4-wide walk (" + std::to_string(registerStack) + " held)" : ", binary walk";
    s += specialize ? ", specialised" : ", general program";
    if (bakeGeometry) s += *bakeGeometry ? ", baking forced on" : ", baking forced off";
    if (regenerate) s += ", regeneration";
    char buf[48];
    std::snprintf(buf, sizeof buf, ", %g s dispatches", dispatchSeconds);
    s += buf;
    if (walkStats) s += ", walk statistics";
    return s;
}

}  // namespace caustic
