// Opening a scene without freezing the window (docs/editor.md, "Opening scenes"): the JSON is
// parsed and validated at once (a broken file is refused before anything changes), then every mesh
// file of the new scene that the renderer does not hold yet is imported on the MeshLoader's worker;
// the new scene is adopted only when all of them are ready, and a mesh that fails fails the open.
// This is the bookkeeping of one such open; no GL, no ImGui (unit-tested in tests/editor/).
#pragma once

#include "editor/model/mesh_loader.h"
#include "renderer/scene.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace caustic::editor {

// One mesh file of a scene: its meshCacheKey (the path compileScene imports) and the first object
// that uses it (for messages).
struct SceneMeshFile {
    std::string key;
    int objectIndex = -1;
    std::string objectName;
};

// The distinct mesh files of `scene` (keys resolved against scene.sourcePath), in object order.
std::vector<SceneMeshFile> sceneMeshFiles(const Scene& scene);

class PendingOpen {
public:
    // `scene` is the parsed scene (its sourcePath set: mesh keys resolve against it), `file` what
    // the user opened (or the owner of a recovered autosave), `recovered`: adopt it as unsaved.
    // `held` says whether the renderer already holds a key, unchanged: those are not imported.
    PendingOpen(Scene scene, std::string file, bool recovered, const std::function<bool(const std::string&)>& held);

    // The keys to import (in order); give each request's id to requested().
    std::vector<std::string> toImport() const;
    void requested(std::size_t index, std::uint64_t id);
    std::vector<std::uint64_t> ids() const;   // the requests still outstanding

    // Takes a loader result; false when it is not one of this open's requests.
    bool take(const MeshLoadResult& result);
    bool ready() const;    // every mesh imported (true at once when nothing had to be)
    bool failed() const { return !m_error.empty(); }
    // "<object where>.file: <importer's message>" of the first mesh that failed.
    const std::string& error() const { return m_error; }
    // "opening scene.json: importing 2 of 3 meshes ..." while importing.
    std::string status() const;
    // The imported meshes by key (insert them into the MeshCache before adopting the scene).
    std::vector<std::pair<std::string, std::shared_ptr<const MeshCacheEntry>>> meshes() const;
    std::vector<double> seconds() const;   // worker seconds of each mesh imported so far

    Scene scene;
    std::string file;
    bool recovered = false;
    // Set by the caller: the scene being replaced, as it was when the open started.
    std::uint64_t generation = 0;   // EditorState::generation()
    std::uint64_t revision = 0;     // EditorState::history.revision()

private:
    struct Need {
        SceneMeshFile mesh;
        std::uint64_t id = 0;
        std::shared_ptr<const MeshCacheEntry> entry;
        double seconds = 0.0;
        bool done = false;
    };
    std::vector<Need> m_needs;
    std::string m_error;
};

}  // namespace caustic::editor
