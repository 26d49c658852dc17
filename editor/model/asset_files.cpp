#include "editor/model/asset_files.h"

#include "renderer/mesh_import.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <set>

namespace fs = std::filesystem;

namespace caustic::editor {

namespace {

std::string lowerExtension(const std::string& path) {
    std::string e = fs::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return e;
}

}  // namespace

bool isAssetFile(AssetKind kind, const std::string& path) {
    const std::string e = lowerExtension(path);
    switch (kind) {
        case AssetKind::Texture:
            for (const char* x : {".png", ".jpg", ".jpeg", ".exr", ".hdr", ".tga", ".bmp", ".tif", ".tiff"})
                if (e == x) return true;
            return false;
        case AssetKind::Mesh: return !e.empty() && isMeshFileExtensionSupported(path);
        case AssetKind::EnvironmentMap: return e == ".hdr" || e == ".exr";
        case AssetKind::Lens: return e == ".lens";
    }
    return false;
}

std::string assetsFolderFor(const std::string& sceneFolder) {
    if (const char* env = std::getenv("CAUSTIC_ASSETS_DIR"); env && *env) return fs::absolute(env).lexically_normal().string();
    std::error_code ec;
    for (const fs::path& p : {fs::path(sceneFolder) / "assets", fs::path(sceneFolder) / ".." / "assets"})
        if (fs::is_directory(p, ec)) return fs::absolute(p, ec).lexically_normal().string();
    return {};
}

std::string pathForScene(const std::string& file, const std::string& sceneFolder) {
    std::error_code ec;
    const fs::path abs = fs::absolute(file, ec).lexically_normal();
    if (ec) return file;
    const fs::path folder = fs::path(sceneFolder).lexically_normal();
    if (abs.root_name() != folder.root_name()) return abs.string();
    const fs::path rel = abs.lexically_relative(folder);
    return rel.empty() ? abs.string() : rel.string();
}

std::vector<AssetFile> listAssetFiles(AssetKind kind, const std::string& sceneFolder, const std::string& assetsFolder,
                                      int maxDepth, std::size_t maxFiles) {
    std::vector<AssetFile> out;
    std::set<std::string> seen;
    auto scan = [&](const std::string& root, const char* rootName) {
        if (root.empty()) return;
        std::error_code ec;
        const fs::path base = fs::absolute(root, ec).lexically_normal();
        if (ec || !fs::is_directory(base, ec)) return;
        std::vector<AssetFile> found;
        fs::recursive_directory_iterator it(base, fs::directory_options::skip_permission_denied, ec), end;
        for (; !ec && it != end && out.size() + found.size() < maxFiles; it.increment(ec)) {
            const std::string name = it->path().filename().string();
            std::error_code e2;
            const bool dir = it->is_directory(e2);
            if (!name.empty() && name[0] == '.') {
                if (dir) it.disable_recursion_pending();
                continue;
            }
            if (dir) {
                if (it.depth() + 1 >= maxDepth) it.disable_recursion_pending();
                continue;
            }
            if (!isAssetFile(kind, name)) continue;
            const fs::path abs = it->path().lexically_normal();
            if (!seen.insert(abs.string()).second) continue;
            found.push_back({rootName, abs.lexically_relative(base).string(), pathForScene(abs.string(), sceneFolder), abs.string()});
        }
        std::sort(found.begin(), found.end(), [](const AssetFile& a, const AssetFile& b) { return a.display < b.display; });
        out.insert(out.end(), found.begin(), found.end());
    };
    scan(sceneFolder, "scene folder");
    scan(assetsFolder, "assets");
    return out;
}

}  // namespace caustic::editor
