#include "editor/model/camera_views.h"

#include "renderer/file_util.h"
#include "renderer/scene_io.h"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace fs = std::filesystem;
using nlohmann::json;

namespace caustic::editor {
namespace {

json vec(glm::vec3 v) { return json::array({v.x, v.y, v.z}); }
glm::vec3 vec(const json& j) { return {j.at(0).get<float>(), j.at(1).get<float>(), j.at(2).get<float>()}; }

json cameraJson(const Camera& c) {
    json j = {{"position", vec(c.position)},
              {"look_at", vec(c.lookAt)},
              {"up", vec(c.up)},
              {"fov", c.fovDegrees},
              {"fov_axis", static_cast<int>(c.fovAxis)},
              {"roll", c.rollDegrees},
              {"aperture_radius", c.apertureRadius},
              {"focal_distance", c.focalDistance},
              {"squeeze", c.squeeze},
              {"blades", c.blades},
              {"blade_rotation", c.bladeRotationDegrees}};
    if (c.focusPoint) j["focus_point"] = vec(*c.focusPoint);
    return j;
}

Camera cameraFromJson(const json& j) {
    Camera c;
    c.position = vec(j.at("position"));
    c.lookAt = vec(j.at("look_at"));
    c.up = vec(j.at("up"));
    c.fovDegrees = j.at("fov").get<float>();
    const int axis = j.value("fov_axis", 0);
    c.fovAxis = static_cast<FovAxis>(axis >= 0 && axis <= 3 ? axis : 0);
    c.rollDegrees = j.value("roll", 0.0f);
    c.apertureRadius = j.value("aperture_radius", 0.0f);
    c.focalDistance = j.value("focal_distance", 0.0f);
    c.squeeze = j.value("squeeze", 1.0f);
    c.blades = j.value("blades", 0);
    c.bladeRotationDegrees = j.value("blade_rotation", 0.0f);
    if (j.contains("focus_point")) c.focusPoint = vec(j.at("focus_point"));
    return c;
}

const std::vector<CameraView> kNone;

}  // namespace

std::string CameraViews::key(const std::string& scenePath) {
    if (scenePath.empty()) return {};
    std::error_code ec;
    const fs::path p = fs::absolute(scenePath, ec).lexically_normal();
    return ec ? scenePath : p.string();
}

bool CameraViews::load(const std::string& file, std::string* error) {
    std::error_code ec;
    if (!fs::exists(file, ec)) return true;
    const std::optional<std::string> text = readTextFile(file, error);
    if (!text) return false;
    try {
        const json j = json::parse(*text);
        std::map<std::string, std::vector<CameraView>> views;
        for (const auto& [scene, list] : j.at("scenes").items())
            for (const json& v : list) {
                CameraView view{v.at("name").get<std::string>(), cameraFromJson(v.at("camera"))};
                if (!checkEntity(view.camera, "camera").empty()) continue;   // the scene reader would refuse it
                views[scene].push_back(std::move(view));
            }
        m_views = std::move(views);
    } catch (const std::exception& e) {
        if (error) *error = file + ": " + e.what();
        return false;
    }
    return true;
}

bool CameraViews::save(const std::string& file, std::string* error) const {
    json scenes = json::object();
    for (const auto& [scene, list] : m_views) {
        if (scene.empty() || list.empty()) continue;   // an untitled scene's views are not kept
        json a = json::array();
        for (const CameraView& v : list) a.push_back({{"name", v.name}, {"camera", cameraJson(v.camera)}});
        scenes[scene] = a;
    }
    return writeFileAtomically(file, json{{"scenes", scenes}}.dump(2) + "\n", error);
}

const std::vector<CameraView>& CameraViews::of(const std::string& scenePath) const {
    const auto it = m_views.find(key(scenePath));
    return it == m_views.end() ? kNone : it->second;
}

void CameraViews::store(const std::string& scenePath, const std::string& name, const Camera& camera) {
    std::vector<CameraView>& list = m_views[key(scenePath)];
    for (CameraView& v : list)
        if (v.name == name) {
            v.camera = camera;
            return;
        }
    list.push_back({name, camera});
}

bool CameraViews::remove(const std::string& scenePath, const std::string& name) {
    const auto it = m_views.find(key(scenePath));
    if (it == m_views.end()) return false;
    return std::erase_if(it->second, [&](const CameraView& v) { return v.name == name; }) > 0;
}

const CameraView* CameraViews::find(const std::string& scenePath, const std::string& name) const {
    for (const CameraView& v : of(scenePath))
        if (v.name == name) return &v;
    return nullptr;
}

void CameraViews::carry(const std::string& from, const std::string& to) {
    const std::string a = key(from), b = key(to);
    if (a == b) return;
    const auto it = m_views.find(a);
    if (it == m_views.end() || it->second.empty()) return;
    m_views[b] = it->second;
}

std::string CameraViews::nextName(const std::string& scenePath) const {
    for (int i = 1;; ++i) {
        const std::string n = "view " + std::to_string(i);
        if (!find(scenePath, n)) return n;
    }
}

}  // namespace caustic::editor
