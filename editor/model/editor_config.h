// The editor's files in its config folder: where that folder is, the recent-files list and the
// autosave (the saved camera views are in camera_views.h, the preferences in preferences.h).
#pragma once

#include "renderer/scene.h"

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace caustic::editor {

// $CAUSTIC_EDITOR_HOME, else $XDG_CONFIG_HOME/caustic, else $HOME/.config/caustic.
std::string editorConfigDir();

class RecentFiles {
public:
    static constexpr std::size_t kMax = 10;
    void add(const std::string& file);             // most recent first, no duplicates
    void remove(const std::string& file);
    const std::vector<std::string>& files() const { return m_files; }
    bool load(const std::string& listFile);        // one path per line; missing file = empty
    bool save(const std::string& listFile, std::string* error) const;

private:
    std::vector<std::string> m_files;
};

// The autosave: the scene as JSON plus the path of the file it belongs to, written atomically.
// A clean exit removes it; one found at start-up is offered back (the editor crashed or was killed).
struct Autosave {
    std::string scenePath;   // <dir>/autosave.json
    std::string ownerPath;   // <dir>/autosave.owner: the original file ("" when untitled)
    // Set by recover() when an unreadable autosave could not be moved aside: it stays where it is,
    // and this session neither writes over it nor removes it (remove() does nothing).
    bool frozen = false;

    static Autosave in(const std::string& dir);
    bool write(const Scene& scene, const std::string& owner, std::string* error) const;
    bool exists() const;
    // The recovered scene and its owner; nullopt with *error when it cannot be read.
    std::optional<std::pair<Scene, std::string>> read(std::string* error) const;
    void remove() const;

    // What start-up does with an autosave it finds. When it reads, `recovered` holds the scene and
    // its owner. When it does not (a truncated or hand-broken file), the user's data is kept: the
    // file is moved aside to <dir>/autosave.unreadable-<n>.json (its owner file beside it, as
    // autosave.unreadable-<n>.owner; n the first free number), so the next autosave does not
    // write over it and a clean exit does not remove it, and `message` says which file could not
    // be read, what is wrong with it and where it is now. If it cannot be moved, it stays and
    // `frozen` is set.
    struct Found {
        std::optional<std::pair<Scene, std::string>> recovered;
        std::string message;       // non-empty when the autosave could not be read
        std::string keptAs;        // where the unreadable autosave is now
    };
    Found recover();
};

}  // namespace caustic::editor
