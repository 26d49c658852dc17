#include "renderer/bsdf_tables.h"

#include "renderer/shader_loader.h"
#include "shaders/shared/layout.h"

#include <glad/gl.h>

namespace caustic {

bool computeGgxAlbedoTable(const std::string& shaderDir, unsigned buffer, std::string* error) {
    ShaderLoader loader(shaderDir);
    ShaderSource source;
    if (!loader.load("bsdf/ggx_albedo.comp", {}, &source, error)) return false;
    const unsigned program = compileComputeProgram(source, "bsdf/ggx_albedo.comp", error);
    if (!program) return false;
    constexpr int N = GGX_ALBEDO_TABLE_SIZE;
    glNamedBufferData(buffer, GLsizeiptr(sizeof(float)) * N * N, nullptr, GL_STATIC_DRAW);
    glUseProgram(program);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_BSDF_TABLES, buffer);
    glDispatchCompute((N + 7) / 8, (N + 7) / 8, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
    glDeleteProgram(program);
    return true;
}

std::vector<float> readFloatBuffer(unsigned buffer) {
    GLint64 size = 0;
    glGetNamedBufferParameteri64v(buffer, GL_BUFFER_SIZE, &size);
    std::vector<float> out(size_t(size) / sizeof(float));
    if (!out.empty()) glGetNamedBufferSubData(buffer, 0, GLsizeiptr(out.size() * sizeof(float)), out.data());
    return out;
}

}  // namespace caustic
