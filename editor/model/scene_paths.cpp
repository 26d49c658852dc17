#include "editor/model/scene_paths.h"

#include <filesystem>

namespace fs = std::filesystem;

namespace caustic::editor {

std::string sceneFolderOf(const std::string& sceneFile) {
    std::error_code ec;
    const fs::path folder = sceneFile.empty() ? fs::current_path(ec) : fs::absolute(fs::path(sceneFile), ec).parent_path();
    return folder.lexically_normal().string();
}

std::string rebasePath(const std::string& file, const std::string& fromFolder, const std::string& toFolder) {
    if (file.empty() || fs::path(file).is_absolute() || fromFolder == toFolder) return file;
    const fs::path target = (fs::path(fromFolder) / file).lexically_normal();
    const fs::path rel = target.lexically_relative(fs::path(toFolder));
    // No relative path between them (another root): the absolute one still names the file.
    return rel.empty() ? target.string() : rel.string();
}

void rebasePaths(Object& o, const std::string& from, const std::string& to) { o.file = rebasePath(o.file, from, to); }

void rebasePaths(Material& m, const std::string& from, const std::string& to) {
    m.albedoTexture = rebasePath(m.albedoTexture, from, to);
    m.normalTexture = rebasePath(m.normalTexture, from, to);
    m.roughnessTexture = rebasePath(m.roughnessTexture, from, to);
}

void rebasePaths(Environment& e, const std::string& from, const std::string& to) { e.file = rebasePath(e.file, from, to); }

void rebaseScenePaths(Scene& scene, const std::string& from, const std::string& to) {
    if (from == to) return;
    for (Object& o : scene.objects) rebasePaths(o, from, to);
    for (Material& m : scene.materials) rebasePaths(m, from, to);
    rebasePaths(scene.environment, from, to);
}

std::string suggestSaveAsName(const std::string& folder, const std::string& currentFile) {
    const std::string stem = currentFile.empty() ? "scene" : fs::path(currentFile).stem().string();
    std::error_code ec;
    for (int i = currentFile.empty() ? 1 : 2; i < 100000; ++i) {
        // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) about
        // "-" + std::to_string(i) inlined into operator+.
        std::string name = stem;
        if (i != 1) name.append("-").append(std::to_string(i));
        name.append(".json");
        if (!fs::exists(fs::path(folder) / name, ec)) return name;
    }
    return stem + "-copy.json";   // a folder with 100000 of them: the overwrite prompt still asks
}

}  // namespace caustic::editor
