// Saved camera views (issue 15): named cameras an artist stores and recalls (a recall is one
// undoable camera edit). They are the editor's own state, not the scene's: kept in
// <config>/views.json (editor_config.h editorConfigDir), by the scene file's absolute path.
// Why not in the scene file: a view is a navigation bookmark, not part of the image (batch mode
// renders the scene's one camera and would ignore them), and the scene format is shared with batch
// mode, the farm and the schema-generated docs, which an editor convenience should not widen.
// Save As carries a scene's views to its new path. No ImGui, no GL: unit-tested.
#pragma once

#include "renderer/scene.h"

#include <map>
#include <string>
#include <vector>

namespace caustic::editor {

struct CameraView {
    std::string name;
    Camera camera;
    bool operator==(const CameraView&) const = default;
};

class CameraViews {
public:
    // Reads the views file (a missing file is no views; a broken one is reported in *error and
    // ignored; a view whose camera the scene reader would refuse is skipped).
    bool load(const std::string& file, std::string* error);
    // Writes atomically (renderer/file_util.h).
    bool save(const std::string& file, std::string* error) const;

    // The views of the scene at `scenePath` ("" for an untitled scene, whose views last only for
    // the session's memory of it).
    const std::vector<CameraView>& of(const std::string& scenePath) const;
    // Stores (or, under an existing name, replaces) a view.
    void store(const std::string& scenePath, const std::string& name, const Camera& camera);
    bool remove(const std::string& scenePath, const std::string& name);
    const CameraView* find(const std::string& scenePath, const std::string& name) const;
    // Save As: the views of `from` are also those of `to` (kept under both).
    void carry(const std::string& from, const std::string& to);
    // A free name: "view 1", "view 2", ...
    std::string nextName(const std::string& scenePath) const;

private:
    static std::string key(const std::string& scenePath);
    std::map<std::string, std::vector<CameraView>> m_views;
};

}  // namespace caustic::editor
