#include "editor/ui/display.h"

#include "renderer/shader_loader.h"

#include <glad/gl.h>

#include <cmath>

namespace caustic::editor {

std::unique_ptr<Display> Display::create(const std::string& shaderDir, std::string* error) {
    ShaderLoader loader(shaderDir);
    ShaderSource source;
    if (!loader.load("display/tonemap.comp", {}, &source, error)) return nullptr;
    const unsigned program = compileComputeProgram(source, "display/tonemap.comp", error);
    if (!program) return nullptr;
    std::unique_ptr<Display> d(new Display());
    d->m_program = program;
    return d;
}

Display::~Display() {
    const unsigned textures[3] = {m_texture, m_snapshot, m_retired};
    glDeleteTextures(3, textures);
    glDeleteProgram(m_program);
}

void Display::update(unsigned accumulationTexture, int width, int height, ToneMap op, float exposureEv) {
    if (!accumulationTexture || width <= 0 || height <= 0) return;
    // The texture replaced at the last resize: this frame's UI no longer draws it.
    if (m_retired) glDeleteTextures(1, &m_retired);
    m_retired = 0;
    if (width != m_width || height != m_height) {
        // The UI drew this frame's image with the current texture before this update; deleting it
        // now would free its name for the next texture made this frame (ImGui's font atlas grows
        // on demand), and the viewport would show that instead for a frame. It goes next frame.
        m_retired = m_texture;
        glCreateTextures(GL_TEXTURE_2D, 1, &m_texture);
        glTextureStorage2D(m_texture, 1, GL_RGBA8, width, height);
        // Nearest when magnified: a reduced-resolution preview shows its pixels honestly, and 1:1
        // stays exact.
        glTextureParameteri(m_texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(m_texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        m_width = width;
        m_height = height;
    }
    glUseProgram(m_program);
    glBindTextureUnit(0, accumulationTexture);
    glBindImageTexture(0, m_texture, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glProgramUniform1f(m_program, 0, std::exp2(exposureEv));
    glProgramUniform1i(m_program, 1, op == ToneMap::Aces ? 0 : 1);
    glDispatchCompute(static_cast<GLuint>(width + 7) / 8, static_cast<GLuint>(height + 7) / 8, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glUseProgram(0);
}

void Display::takeSnapshot() {
    if (!m_texture) return;
    if (m_snapshot) glDeleteTextures(1, &m_snapshot);
    glCreateTextures(GL_TEXTURE_2D, 1, &m_snapshot);
    glTextureStorage2D(m_snapshot, 1, GL_RGBA8, m_width, m_height);
    glTextureParameteri(m_snapshot, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(m_snapshot, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glCopyImageSubData(m_texture, GL_TEXTURE_2D, 0, 0, 0, 0, m_snapshot, GL_TEXTURE_2D, 0, 0, 0, 0, m_width, m_height, 1);
}

void Display::dropSnapshot() {
    if (m_snapshot) glDeleteTextures(1, &m_snapshot);
    m_snapshot = 0;
}

}  // namespace caustic::editor
