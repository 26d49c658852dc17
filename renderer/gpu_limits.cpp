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

GpuLimits queryGpuLimits(bool texelFetching) {
    GpuLimits limits;
    GLint texture = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &texture);
    GLint64 block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
    limits.maxTextureSize = texture;
    limits.maxStorageBlockSize = block;
    if (texelFetching) {
        GLint texels = 0;
        glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &texels);
        limits.maxTextureBufferTexels = texels;
    }
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
    // texel: the bytes of a texel of the buffer texture that views it (renderer_dispatch.cpp, bindScene), 0
    // for a buffer read only as a storage buffer.
    const struct {
        const char* what;
        double size;
        double texel;
    } buffers[] = {
        {"primitives", sizeOf(c.primitives), 16},
        {"materials", sizeOf(c.materials), 16},
        {"lights", sizeOf(c.lights), 16},
        {"light tree", sizeOf(c.lightTree.nodes), 16},
        {"light and environment sampling tables", tableBytes, 4},
        {"BVH nodes", sizeOf(c.bvhNodes), 16},
        {"4-wide BVH nodes", sizeOf(c.wideNodes), 16},
        {"top-level BVH entries", sizeOf(c.tlasRefs), 4},
        {"mesh instances", sizeOf(c.instances), 16},
        {"mesh triangles", sizeOf(c.triangles), 16},
        {"mesh vertices", sizeOf(c.vertices), 16},
        {"texture texels", sizeOf(c.texels), 0},
        {"textures", sizeOf(c.textures), 0},
    };
    for (const auto& b : buffers) {
        if (b.size > double(limits.maxStorageBlockSize)) {
            return std::string("the scene's ") + b.what + " need " + bytes(b.size) +
                   " of GPU storage; this GPU allows " + bytes(double(limits.maxStorageBlockSize)) +
                   " per buffer (GL_MAX_SHADER_STORAGE_BLOCK_SIZE)";
        }
        // Read through a buffer texture (llvmpipe), texels past the limit would read as zeros.
        if (limits.maxTextureBufferTexels > 0 && b.texel > 0 && b.size / b.texel > double(limits.maxTextureBufferTexels)) {
            return std::string("the scene's ") + b.what + " need " + std::to_string(std::int64_t(b.size / b.texel)) +
                   " texels of a buffer texture; this GPU allows " + std::to_string(limits.maxTextureBufferTexels) +
                   " (GL_MAX_TEXTURE_BUFFER_SIZE)";
        }
    }
    return {};
}

}  // namespace caustic
