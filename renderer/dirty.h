// What an edit changed, so the renderer redoes only that (architecture: the editor runs a command
// on the Scene, the command reports what it dirtied, and Renderer::update decides).
#pragma once

#include <cstdint>

namespace caustic {

enum Dirty : std::uint32_t {
    kDirtyNone = 0,
    kDirtyCamera = 1u << 0,       // camera only: new frame constants, restart accumulation
    kDirtySettings = 1u << 1,     // render settings (depth, seed, light selection, resolution)
    kDirtyMaterials = 1u << 2,    // material parameters: re-upload materials
    kDirtyTransforms = 1u << 3,   // object/light transforms: refit or rebuild the top level
    kDirtyGeometry = 1u << 4,     // objects added/removed, meshes changed: rebuild what changed
    kDirtyLights = 1u << 5,       // light parameters
    kDirtyEnvironment = 1u << 6,  // environment: rebuild its sampling tables
    // Edits that change nothing on screen, so accumulation goes on (issue 15: they restarted it):
    kDirtyTarget = 1u << 7,       // the target sample count only: render on to it, or stop where it is
    kDirtyUnseen = 1u << 8,       // materials no object uses (added, removed, edited): nothing to redo now;
                                  // the editor hands it over, as a full recompile, with the next edit that restarts
    kDirtyAll = 0xffffffffu,
};

}  // namespace caustic
