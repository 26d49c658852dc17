#include "editor/model/focus_overlay.h"

#include "renderer/camera.h"

#include <cmath>

namespace caustic::editor {

double focusDistance(const Camera& camera, double aspect) { return cameraFrame(camera, aspect).focalDistance; }

bool focusEdited(const Camera& before, const Camera& after) {
    return before.focalDistance != after.focalDistance || before.focusPoint != after.focusPoint ||
           before.apertureRadius != after.apertureRadius;
}

std::vector<FocusCell> inFocusCells(const Scene& scene, int cols, int rows, float band,
                                    const std::function<std::optional<float>(const Ray&)>& extraHit) {
    std::vector<FocusCell> out;
    const int w = scene.render.width, h = scene.render.height;
    if (cols <= 0 || rows <= 0 || w <= 0 || h <= 0) return out;
    const CameraFrame frame = cameraFrame(scene.camera, double(w) / double(h));
    const double focus = frame.focalDistance;
    const glm::vec3 forward(frame.forward);
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < cols; ++x) {
            const glm::vec2 pixel((float(x) + 0.5f) * float(w) / float(cols), (float(y) + 0.5f) * float(h) / float(rows));
            const Ray ray = cameraRay(scene.camera, w, h, pixel);
            std::optional<float> t;
            if (const auto hit = pick(scene, ray)) t = hit->distance;
            if (extraHit)
                if (const auto m = extraHit(ray); m && (!t || *m < *t)) t = m;
            if (!t) continue;
            const double depth = double(*t) * double(glm::dot(ray.direction, forward));
            if (std::abs(depth - focus) <= double(band) * focus) out.push_back({x, y});
        }
    return out;
}

}  // namespace caustic::editor
