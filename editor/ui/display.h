// The viewport's display pass on the GPU: tone maps the renderer's accumulation texture into an
// RGBA8 texture for ImGui (shaders/display/tonemap.comp), and keeps a lookdev snapshot of it.
#pragma once

#include "renderer/tonemap.h"

#include <memory>
#include <string>
#include <utility>

namespace caustic::editor {

class Display {
public:
    // Compiles shaders/display/tonemap.comp from shaderDir; null with *error on failure.
    static std::unique_ptr<Display> create(const std::string& shaderDir, std::string* error);
    ~Display();
    Display(const Display&) = delete;
    Display& operator=(const Display&) = delete;

    void update(unsigned accumulationTexture, int width, int height, ToneMap op, float exposureEv);
    unsigned texture() const { return m_texture; }
    int width() const { return m_width; }
    int height() const { return m_height; }

    // F5: uses `from`'s program (a fresh compile) and gives it this one's to delete; the image
    // and the snapshot stay.
    void takeProgram(Display& from) { std::swap(m_program, from.m_program); }

    void takeSnapshot();   // copies the current display image
    void dropSnapshot();   // another scene: the snapshot belongs to the last one
    bool hasSnapshot() const { return m_snapshot != 0; }
    unsigned snapshotTexture() const { return m_snapshot; }

private:
    Display() = default;
    unsigned m_program = 0, m_texture = 0, m_snapshot = 0;
    unsigned m_retired = 0;   // the texture before the last resize, deleted at the next update
    int m_width = 0, m_height = 0;
};

}  // namespace caustic::editor
