// compileScene's analytic lights: rectangles and spheres, their power for light selection, and
// the checks that keep their areas within what a float holds.
#include "renderer/gpu_scene_builder.h"

namespace caustic::scene_compile {

void Builder::addLight(gpu::GpuLight l, float power, int primitive, const LightBounds& bounds) {
    if (primitive >= 0) {
        out.primitives[primitive].info.z = static_cast<std::uint32_t>(out.lights.size() + 1);
        l.info.z = static_cast<std::uint32_t>(primitive);
        if (out.materials[out.primitives[primitive].info.y].textures.w != 0u) l.info.y |= LIGHT_FLAG_EMISSION_TEXTURE;
    }
    out.lights.push_back(l);
    out.lightPower.push_back(power);
    out.lightBounds.push_back(bounds);
}

bool Builder::lightAreaFits(double area, const std::string& where) {
    if (area >= kMinLightArea && area <= kMaxLightArea) return true;
    *error = where + ": the emitter's area (" + formatShort(area) +
             ") is outside what the renderer's 32-bit floats handle (1e-30 to 1e30 square units); scale it";
    return false;
}

glm::vec3 Builder::emissionTextureMean(std::uint32_t material) {
    const std::uint32_t slot = out.materials[material].textures.w;
    if (slot == 0) return glm::vec3(1.0f);
    if (auto found = emissionMeans.find(material); found != emissionMeans.end()) return found->second;
    const gpu::GpuTexture& t = out.textures[slot - 1];
    const size_t n = size_t(t.info.y) * size_t(t.info.z);
    glm::dvec3 sum(0.0);
    for (size_t i = 0; i < n && t.info.x + i < out.texels.size(); ++i) {
        const glm::uvec2 h = out.texels[t.info.x + i];
        sum += glm::dvec3(glm::unpackHalf2x16(h.x).x, glm::unpackHalf2x16(h.x).y, glm::unpackHalf2x16(h.y).x);
    }
    const glm::vec3 mean = glm::max(glm::vec3(sum / double(std::max<size_t>(n, 1))), glm::vec3(1e-3f));
    emissionMeans.emplace(material, mean);
    return mean;
}

bool Builder::addRectLight(std::uint32_t prim, glm::vec3 radiance, bool twoSided, const std::string& where) {
    const auto& p = out.primitives[prim];
    gpu::GpuLight l{};
    const double areaD = glm::length(glm::cross(glm::dvec3(glm::vec3(p.b)), glm::dvec3(glm::vec3(p.c))));
    if (!lightAreaFits(areaD, where)) return false;
    const float area = static_cast<float>(areaD);
    l.p0 = p.a;
    l.p1 = glm::vec4(glm::vec3(p.b), area);
    l.p2 = p.c;
    l.color = glm::vec4(radiance, 0);
    l.info = glm::uvec4(LIGHT_RECT, twoSided ? LIGHT_FLAG_TWO_SIDED : 0u, 0, 0);
    LightBounds bounds;
    const glm::vec3 o(p.a), u(p.b), v(p.c);
    bounds.boundsMin = glm::min(glm::min(o, o + u), glm::min(o + v, o + u + v));
    bounds.boundsMax = glm::max(glm::max(o, o + u), glm::max(o + v, o + u + v));
    const glm::vec3 n = glm::cross(u, v);
    bounds.axis = glm::length(n) > 0.0f ? n / glm::length(n) : glm::vec3(0, 0, 1);
    bounds.cosThetaO = twoSided ? -1.0f : 1.0f;
    const float y = luminance(radiance * emissionTextureMean(p.info.y));
    bounds.intensity = saturatedPower(areaD * y);
    addLight(l, saturatedPower(kPi * areaD * y * (twoSided ? 2.0 : 1.0)), static_cast<int>(prim), bounds);
    return true;
}

bool Builder::addSphereLight(std::uint32_t prim, const glm::mat4& m, glm::vec3 radiance, const std::string& where,
                    bool twoSided) {
    glm::mat3 lin(m);
    float sx = glm::length(lin[0]), sy = glm::length(lin[1]), sz = glm::length(lin[2]);
    float tol = 1e-4f * std::max({sx, sy, sz});
    if (std::abs(sx - sy) > tol || std::abs(sx - sz) > tol || std::abs(glm::dot(lin[0], lin[1])) > tol * sx ||
        std::abs(glm::dot(lin[0], lin[2])) > tol * sx || std::abs(glm::dot(lin[1], lin[2])) > tol * sx) {
        *error = where + ": an emissive sphere must be uniformly scaled (it is sampled as a sphere light)";
        return false;
    }
    if (!lightAreaFits(4.0 * kPi * double(sx) * sx, where)) return false;
    gpu::GpuLight l{};
    l.p0 = glm::vec4(glm::vec3(m[3]), sx);
    l.color = glm::vec4(radiance, 0);
    l.info = glm::uvec4(LIGHT_SPHERE, twoSided ? LIGHT_FLAG_TWO_SIDED : 0u, 0, 0);
    LightBounds bounds;
    bounds.boundsMin = glm::vec3(m[3]) - sx;
    bounds.boundsMax = glm::vec3(m[3]) + sx;
    const float y = luminance(radiance * emissionTextureMean(out.primitives[prim].info.y));
    bounds.intensity = saturatedPower(kPi * double(sx) * sx * y);
    addLight(l, saturatedPower(kPi * 4.0 * kPi * double(sx) * sx * y), static_cast<int>(prim), bounds);
    return true;
}

}  // namespace caustic::scene_compile
