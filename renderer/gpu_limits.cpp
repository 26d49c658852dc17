#include "renderer/gpu_limits.h"

#include <glad/gl.h>

#include <cstdio>
#include <vector>

namespace caustic {
namespace {

std::string bytes(double n) {
    char buf[48];
    if (n >= 1024.0 * 1024 * 1024) std::snprintf(buf, sizeof buf, "%.2f GiB", n / (1024.0 * 1024 * 1024));
    else if (n >= 1024.0 * 1024) std::snprintf(buf, sizeof buf, "%.1f MiB", n / (1024.0 * 1024));
    else if (n >= 1024.0) std::snprintf(buf, sizeof buf, "%.1f KiB", n / 1024.0);
    else std::snprintf(buf, sizeof buf, "%.0f bytes", n);
    return buf;
}

template <class T>
double sizeOf(const std::vector<T>& v) { return double(v.size()) * double(sizeof(T)); }

}  // namespace

GpuLimits queryGpuLimits() {
    GpuLimits limits;
    GLint texture = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &texture);
    GLint64 block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
    limits.maxTextureSize = texture;
    limits.maxStorageBlockSize = block;
    return limits;
}

std::string gpuLimitProblem(const Scene& scene, const CompiledScene& c, const GpuLimits& limits) {
    const std::int64_t side = limits.maxTextureSize;
    const EnvironmentMap& env = c.envMap;
    if (side > 0 && (env.width > side || env.height > side)) {
        // An error rather than a silent downsampling: the map's sampling table and its texels
        // must agree, and a quietly blurred sky is a wrong image too (docs/reliability.md).
        return "environment.file: " + scene.environment.file + ": the map is " + std::to_string(env.width) + " x " +
               std::to_string(env.height) + " pixels; this GPU's textures may be at most " + std::to_string(side) +
               " per side (GL_MAX_TEXTURE_SIZE); resample the map";
    }
    if (side > 0 && (scene.render.width > side || scene.render.height > side)) {
        return "render: " + std::to_string(scene.render.width) + " x " + std::to_string(scene.render.height) +
               " pixels; this GPU's textures may be at most " + std::to_string(side) + " per side (GL_MAX_TEXTURE_SIZE)";
    }
    if (limits.maxStorageBlockSize <= 0) return {};
    const double tableBytes = double(tableOffsets(c).total) * sizeof(float);   // packTables' size, not packed here
    const struct {
        const char* what;
        double size;
    } buffers[] = {
        {"primitives", sizeOf(c.primitives)},
        {"materials", sizeOf(c.materials)},
        {"lights", sizeOf(c.lights)},
        {"light tree", sizeOf(c.lightTree.nodes)},
        {"light and environment sampling tables", tableBytes},
        {"BVH nodes", sizeOf(c.bvhNodes)},
        {"4-wide BVH nodes", sizeOf(c.wideNodes)},
        {"top-level BVH entries", sizeOf(c.tlasRefs)},
        {"mesh instances", sizeOf(c.instances)},
        {"mesh triangles", sizeOf(c.triangles)},
        {"mesh vertices", sizeOf(c.vertices)},
        {"texture texels", sizeOf(c.texels)},
        {"textures", sizeOf(c.textures)},
    };
    for (const auto& b : buffers) {
        if (b.size > double(limits.maxStorageBlockSize)) {
            return std::string("the scene's ") + b.what + " need " + bytes(b.size) +
                   " of GPU storage; this GPU allows " + bytes(double(limits.maxStorageBlockSize)) +
                   " per buffer (GL_MAX_SHADER_STORAGE_BLOCK_SIZE)";
        }
    }
    return {};
}

}  // namespace caustic
