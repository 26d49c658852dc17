// Mesh edits that wait for a background import (docs/editor.md, "Importing meshes"): "Import
// mesh" and a change of a mesh object's file. The file is imported and its BVH built on the
// MeshLoader's worker (editor/model/mesh_loader.h); once per frame, finish() takes what is ready,
// inserts it into the renderer's MeshCache and only then applies the edit, so the viewport keeps
// rendering the old scene meanwhile and the compile that follows imports nothing. A failed import
// shows the importer's message (file and reason) and changes nothing.
//
// Opening a scene goes the same way (docs/editor.md, "Opening scenes"): openScene() takes a scene
// already parsed and validated, imports the mesh files the renderer does not hold on the same
// worker, and adopts the scene only when all are ready; a mesh that fails fails the open and the
// current scene stays.
#pragma once

#include "editor/model/mesh_loader.h"
#include "editor/model/scene_open.h"
#include "editor/model/viewport_math.h"

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace caustic::editor {

struct EditorUi;

class MeshImports {
public:
    MeshImports();   // the worker wakes the frame loop (glfwPostEmptyEvent) when a mesh is ready

    // Adds a mesh object for file once it is imported.
    void importFile(EditorUi& ui, const std::string& file);
    // Gives object objectIndex (a mesh) the model file `file` once it is imported.
    void setObjectFile(EditorUi& ui, int objectIndex, const std::string& file);
    // Opens `scene` (parsed from `file`; for a recovered autosave, `file` is the file it belongs
    // to and the scene is adopted as unsaved): its mesh files that the renderer does not hold,
    // unchanged, are imported in the background and the scene is adopted once all are ready (at
    // once when none has to be). Replaces an open still in progress. If the current scene was
    // edited meanwhile, the unsaved-changes prompt asks before it is replaced.
    void openScene(EditorUi& ui, Scene scene, const std::string& file, bool recovered);
    // Applies the edits whose meshes are ready and adopts an opened scene whose meshes are (UI
    // thread, once per frame, before rendering).
    void finish(EditorUi& ui);
    // Mesh files the current scene uses that the renderer does not hold as they are on disk (a
    // file changed on disk since it was imported, say) are imported again in the background;
    // true while any is, and the caller holds its scene updates meanwhile (renderFrame), so that
    // no compile ever imports on the UI thread. A file that fails is not retried until it changes
    // again: the compile then reports it.
    bool refreshing(EditorUi& ui);
    // An import is queued, running, or ready and not yet applied.
    bool pending() const { return !m_edits.empty() || !m_refresh.empty(); }
    // A scene is being opened (its meshes import).
    bool opening() const { return m_open != nullptr; }
    // "opening scene.json: importing 1 of 2 meshes ..." and/or "importing knot.obj ..." (the
    // files in progress), or "" when none.
    std::string status() const;
    // Worker seconds (import + BVH) of each import finished this session, for the script report.
    const std::vector<double>& importSeconds() const { return m_seconds; }
    // The same for the meshes of opened scenes.
    const std::vector<double>& openSeconds() const { return m_openSeconds; }

private:
    struct Edit {
        std::uint64_t id = 0;
        std::uint64_t generation = 0;   // EditorState::generation() when requested
        std::string file;               // as requested (absolute or relative to the working folder)
        std::string objectName;         // setObjectFile: the object (by name: indices move)
    };
    void apply(EditorUi& ui, const Edit& edit, const MeshLoadResult* result);
    void finishOpen(EditorUi& ui);
    void dropOpen();

    std::vector<Edit> m_edits;
    std::map<std::string, std::uint64_t> m_refresh;   // refreshing(): key -> loader request
    std::map<std::string, std::filesystem::file_time_type> m_refreshFailed;   // key -> the file time that failed
    std::vector<double> m_seconds, m_openSeconds;
    std::shared_ptr<PendingOpen> m_open;   // the scene being opened, or null
    MeshLoader m_loader;                // last: destroyed (joined) first
};

// Local bounds of a mesh object from the renderer's imported copy (for "frame selection").
MeshBoundsLookup meshBoundsLookup(const EditorUi& ui);

}  // namespace caustic::editor
