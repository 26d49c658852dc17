// The per-dispatch constants (GpuFrame) and the packed tables buffer.
#include "renderer/gpu_scene.h"

#include "renderer/camera.h"
#include "renderer/gpu_materials.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <utility>

namespace caustic {

namespace {
// The tables in the order they are packed.
std::array<const std::vector<float>*, 9> packedTables(const CompiledScene& c) {
    return {&c.lightCdf, &c.envMap.marginalCdf, &c.envMap.conditionalCdf, &c.meshLightCdf, &c.envMap.marginalGuide,
            &c.envMap.conditionalGuide, &c.aperture.marginalCdf, &c.aperture.conditionalCdf, &c.aperture.mask};
}
}  // namespace

TableOffsets tableOffsets(const CompiledScene& c) {
    std::array<std::size_t, 10> at{};
    const auto tables = packedTables(c);
    for (std::size_t i = 0; i < tables.size(); ++i) at[i + 1] = at[i] + tables[i]->size();
    TableOffsets o;
    o.tables = glm::uvec4(at[0], at[1], at[2], at[3]);
    o.guides = glm::uvec2(at[4], at[5]);
    o.aperture = std::uint32_t(at[6]);
    o.total = at[9];
    return o;
}

std::vector<float> packTables(const CompiledScene& c) {
    std::vector<float> out;
    out.reserve(tableOffsets(c).total);
    for (const std::vector<float>* t : packedTables(c)) out.insert(out.end(), t->begin(), t->end());
    return out;
}

static bool hasFogOrVolumes(const Scene& scene, const CompiledScene& compiled) {
    const Environment& env = scene.environment;
    if (env.mediumSigmaA != glm::vec3(0.0f) || env.mediumSigmaS != glm::vec3(0.0f)) return true;
    return std::any_of(compiled.materials.begin(), compiled.materials.end(),
                       [](const gpu::GpuMaterial& m) { return m.info.x == MAT_VOLUME; });
}

gpu::GpuFrame makeFrame(const Scene& scene, const CompiledScene& compiled, std::uint32_t strategy) {
    gpu::GpuFrame f{};
    const Camera& c = scene.camera;
    const int w = scene.render.width, h = scene.render.height;
    const CameraFrame cam = cameraFrame(c, w, h);  // renderer/camera.h, in double, rounded here
    f.camPosition = glm::vec4(c.position, 0);
    f.camRight = glm::vec4(glm::vec3(cam.right * cam.tanX), 0);
    f.camUp = glm::vec4(glm::vec3(cam.up * cam.tanY), 0);
    f.camForward = glm::vec4(glm::vec3(cam.forward), 0);
    f.image = glm::uvec4(w, h, 0, scene.render.seed);
    f.counts = glm::uvec4(compiled.primitives.size(), compiled.lights.size(), scene.render.maxDepth, strategy);
    f.dispatch = glm::uvec4(1, compiled.envLightIndex + 1, 0, 0);
    const Environment& env = scene.environment;
    std::uint32_t envType = env.type == EnvironmentType::Constant ? ENV_CONSTANT
                            : env.type == EnvironmentType::Sky    ? ENV_SKY
                            : env.type == EnvironmentType::Map    ? ENV_MAP
                                                                  : ENV_NONE;
    f.envInfo = glm::uvec4(envType, compiled.envMap.width, compiled.envMap.height, compiled.envMap.tableScale);
    const float rot = glm::radians(env.rotation);
    f.envMap = glm::vec4(std::cos(rot), std::sin(rot), env.intensity, 0);
    f.camLens = glm::vec4(c.apertureRadius, static_cast<float>(cam.focalDistance), c.squeeze, glm::radians(c.bladeRotationDegrees));
    const std::uint32_t filter = scene.render.filter == PixelFilter::Tent       ? FILTER_TENT
                                 : scene.render.filter == PixelFilter::Gaussian ? FILTER_GAUSSIAN
                                                                                : FILTER_BOX;
    f.camInfo = glm::uvec4(std::max(c.blades, 0), filter, c.lens.empty() ? 0u : 1u, 0);
    f.geometry = glm::uvec4(compiled.tlasNodeCount, compiled.instances.size(), 0, 0);
    const RenderSettings& r = scene.render;
    const std::uint32_t selection = r.lightSelection == LightSelection::Power     ? LIGHT_SELECT_POWER
                                    : r.lightSelection == LightSelection::Uniform ? LIGHT_SELECT_UNIFORM
                                                                                  : LIGHT_SELECT_TREE;
    const std::uint32_t rr = r.russianRoulette == RussianRoulette::Original ? RR_ORIGINAL
                             : r.russianRoulette == RussianRoulette::Mitsuba ? RR_MITSUBA
                             : r.russianRoulette == RussianRoulette::Pbrt    ? RR_PBRT
                                                                             : RR_OFF;
    f.sampling = glm::uvec4(r.sampler == SamplerType::Independent ? SAMPLER_INDEPENDENT : SAMPLER_SOBOL, selection, rr,
                            compiled.lightTree.nodes.size());
    f.envSelect = glm::vec4(compiled.envImportance, 0, 0, 0);
    // Glass splitting's probe sees what lies beyond the glass with no medium on the way
    // (integrator/path.glsl), so it is off where the scene has fog or a volume boundary.
    const bool media = hasFogOrVolumes(scene, compiled);
    // w: the point and spot lights, which equiangular sampling in media aims at (integrator/medium.glsl).
    const auto deltaLights = std::count_if(compiled.lights.begin(), compiled.lights.end(), [](const gpu::GpuLight& l) {
        return l.info.x == LIGHT_POINT || l.info.x == LIGHT_SPOT;
    });
    f.options = glm::uvec4(r.glassSplit && !media ? OPTION_GLASS_SPLIT : 0u, 0, 0, std::uint32_t(deltaLights));
    const GpuMediumRows fog = gpuMedium(env.mediumSigmaA, env.mediumSigmaS, env.mediumAnisotropy);
    f.mediumA = fog.a;
    f.mediumS = fog.s;
    // The ray offset's floor (geometry/intersect.glsl): the largest coordinate magnitude of the
    // scene and the camera, at most 1, so a scene of size 1 or more keeps the floor 1 and a
    // scene scaled down keeps its offsets in proportion (issue 12: the Cornell box at 1e-4 was 22%
    // darker with a fixed floor). In double: bounds may reach 1e19 and beyond.
    double extent = 0.0;
    for (const glm::vec3& v : {compiled.boundsMin, compiled.boundsMax, c.position})
        for (int k = 0; k < 3; ++k)
            if (std::isfinite(v[k])) extent = std::max(extent, std::abs(double(v[k])));
    f.rayOffset = glm::vec4(static_cast<float>(std::clamp(extent, 1e-30, 1.0)), 0, 0, 0);
    const TableOffsets offsets = tableOffsets(compiled);
    f.tables = offsets.tables;
    f.envGuide = glm::uvec4(offsets.guides, compiled.envMap.marginalGuideLog2, compiled.envMap.conditionalGuideLog2);
    f.aperture = glm::uvec4(offsets.aperture, compiled.aperture.width, compiled.aperture.height,
                            compiled.aperture.width > 0 ? 1u : 0u);
    f.envRadiance = glm::vec4(env.radiance * env.intensity, 0);
    f.envHorizon = glm::vec4(env.horizon * env.intensity, 0);
    f.envZenith = glm::vec4(env.zenith * env.intensity, 0);
    return f;
}

}  // namespace caustic
