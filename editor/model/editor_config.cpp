#include "editor/model/editor_config.h"

#include "renderer/file_util.h"
#include "renderer/scene_io.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace caustic::editor {


std::string editorConfigDir() {
    if (const char* d = std::getenv("CAUSTIC_EDITOR_HOME"); d && *d) return d;
    if (const char* x = std::getenv("XDG_CONFIG_HOME"); x && *x) return (fs::path(x) / "caustic").string();
    if (const char* h = std::getenv("HOME"); h && *h) return (fs::path(h) / ".config" / "caustic").string();
    return (fs::temp_directory_path() / "caustic").string();
}

void RecentFiles::add(const std::string& file) {
    remove(file);
    m_files.insert(m_files.begin(), file);
    if (m_files.size() > kMax) m_files.resize(kMax);
}

void RecentFiles::remove(const std::string& file) {
    m_files.erase(std::remove(m_files.begin(), m_files.end(), file), m_files.end());
}

bool RecentFiles::load(const std::string& listFile) {
    m_files.clear();
    std::ifstream in(listFile);
    if (!in) return false;
    std::string line;
    while (std::getline(in, line) && m_files.size() < kMax)
        if (!line.empty() && std::find(m_files.begin(), m_files.end(), line) == m_files.end()) m_files.push_back(line);
    return true;
}

bool RecentFiles::save(const std::string& listFile, std::string* error) const {
    std::error_code ec;
    fs::create_directories(fs::path(listFile).parent_path(), ec);
    std::string text;
    for (const std::string& f : m_files) text += f + "\n";
    return writeFileAtomically(listFile, text, error);
}

Autosave Autosave::in(const std::string& dir) {
    return {(fs::path(dir) / "autosave.json").string(), (fs::path(dir) / "autosave.owner").string()};
}

bool Autosave::write(const Scene& scene, const std::string& owner, std::string* error) const {
    std::error_code ec;
    fs::create_directories(fs::path(scenePath).parent_path(), ec);
    // The owner first: a crash between the two writes leaves a scene with a stale owner at worst.
    return writeFileAtomically(ownerPath, owner + "\n", error) && saveScene(scene, scenePath, error);
}

bool Autosave::exists() const { return fs::exists(scenePath); }

std::optional<std::pair<Scene, std::string>> Autosave::read(std::string* error) const {
    SceneLoadResult loaded = loadScene(scenePath);
    if (!loaded) {
        if (error) *error = loaded.error;
        return std::nullopt;
    }
    std::string owner;
    if (std::optional<std::string> text = readTextFile(ownerPath, nullptr)) {
        owner = *text;
        while (!owner.empty() && (owner.back() == '\n' || owner.back() == '\r')) owner.pop_back();
    }
    return std::make_pair(std::move(*loaded.scene), owner);
}

void Autosave::remove() const {
    if (frozen) return;
    std::error_code ec;
    fs::remove(scenePath, ec);
    fs::remove(ownerPath, ec);
}

Autosave::Found Autosave::recover() {
    Found found;
    std::string error;
    found.recovered = read(&error);
    if (found.recovered) return found;
    // Moved aside under the first free name; an earlier unreadable autosave is never replaced.
    const fs::path dir = fs::path(scenePath).parent_path();
    constexpr int kMaxUnreadable = 1000;
    std::error_code ec;
    for (int n = 1; n <= kMaxUnreadable && found.keptAs.empty(); ++n) {
        const fs::path scene = dir / ("autosave.unreadable-" + std::to_string(n) + ".json");
        const fs::path owner = dir / ("autosave.unreadable-" + std::to_string(n) + ".owner");
        if (fs::symlink_status(scene, ec).type() != fs::file_type::not_found ||
            fs::symlink_status(owner, ec).type() != fs::file_type::not_found)
            continue;
        fs::rename(scenePath, scene, ec);
        if (ec) break;
        found.keptAs = scene.string();
        if (fs::exists(ownerPath, ec)) fs::rename(ownerPath, owner, ec);
    }
    found.message = "the autosave " + scenePath + " could not be read, so it is not offered back: " + error + "\n";
    if (!found.keptAs.empty()) {
        found.message += "It is kept as " + found.keptAs + "; the editor goes on without it.";
    } else {
        frozen = true;
        found.message += "It could not be moved aside" + (ec ? " (" + ec.message() + ")" : std::string()) +
                         ", so it stays where it is: this session does not autosave (save your work) or remove it.";
    }
    return found;
}

}  // namespace caustic::editor
