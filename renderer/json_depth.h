// Nesting depth of JSON text, checked before it is parsed: every recursive walk over a parsed
// value (error messages, writers, nlohmann's own dump) then stays shallow. Used by the scene
// loader and by the glTF reader (renderer/scene_io.cpp, renderer/mesh_import_gltf.cpp).
#pragma once

#include <cstddef>
#include <string_view>

namespace caustic {

// The offset of the first '[' or '{' that opens level limit + 1, or npos. A linear scan that skips
// strings (and their escapes); everything else about the syntax is the parser's job.
inline std::size_t jsonTooDeepAt(std::string_view text, int limit) {
    int depth = 0;
    bool inString = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\') ++i;
            else if (c == '"') inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > limit) return i;
        } else if (c == ']' || c == '}') {
            --depth;  // unbalanced input goes negative; the parser reports it
        }
    }
    return std::string_view::npos;
}

}  // namespace caustic
