#include "renderer/bsdf_tables.h"

#include "renderer/shader_loader.h"
#include "shaders/shared/layout.h"

#include <glad/gl.h>

namespace caustic {

static_assert(BSDF_TABLE_DIELECTRIC == GGX_ALBEDO_TABLE_SIZE * GGX_ALBEDO_TABLE_SIZE);
static_assert(BSDF_TABLE_DIELECTRIC_AVG ==
              BSDF_TABLE_DIELECTRIC + GGX_ALBEDO_TABLE_SIZE * GGX_ALBEDO_TABLE_SIZE * SURFACE_TABLE_IOR);
static_assert(BSDF_TABLE_SHEEN == BSDF_TABLE_DIELECTRIC_AVG + GGX_ALBEDO_TABLE_SIZE * SURFACE_TABLE_IOR);
static_assert(BSDF_TABLE_FLOATS == BSDF_TABLE_SHEEN + GGX_ALBEDO_TABLE_SIZE * GGX_ALBEDO_TABLE_SIZE);

namespace {

unsigned loadKernel(const std::string& shaderDir, const char* name, std::string* error) {
    ShaderLoader loader(shaderDir);
    ShaderSource source;
    if (!loader.load(name, {}, &source, error)) return 0;
    return compileComputeProgram(source, name, error);
}

}  // namespace

bool computeBsdfTables(const std::string& shaderDir, unsigned buffer, std::string* error) {
    const unsigned ggx = loadKernel(shaderDir, "bsdf/ggx_albedo.comp", error);
    if (!ggx) return false;
    const unsigned surface = loadKernel(shaderDir, "bsdf/surface_albedo.comp", error);
    if (!surface) {
        glDeleteProgram(ggx);
        return false;
    }
    constexpr int N = GGX_ALBEDO_TABLE_SIZE;
    glNamedBufferData(buffer, GLsizeiptr(sizeof(float)) * BSDF_TABLE_FLOATS, nullptr, GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_BSDF_TABLES, buffer);
    glUseProgram(ggx);
    glDispatchCompute((N + 7) / 8, (N + 7) / 8, 1);
    glUseProgram(surface);
    for (unsigned pass = 0; pass < 2; ++pass) {
        glProgramUniform1ui(surface, glGetUniformLocation(surface, "u_pass"), pass);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glDispatchCompute((N + 7) / 8, (N + 7) / 8, SURFACE_TABLE_IOR + 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
    glDeleteProgram(ggx);
    glDeleteProgram(surface);
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
