#include "editor/model/viewport_math.h"

#include "renderer/camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace caustic::editor {
namespace {

// The camera's basis (with roll) as the renderer sees it, in float.
struct Basis { glm::vec3 forward, right, up; };
Basis basisOf(const Camera& c) {
    const CameraFrame f = cameraFrame(c, 1.0);  // the basis does not depend on the aspect
    return {glm::vec3(f.forward), glm::vec3(f.right), glm::vec3(f.up)};
}

constexpr float kInf = std::numeric_limits<float>::infinity();

// Ray parameters are in world units because the object-space direction is not renormalised.
float hitUnitSphere(glm::vec3 o, glm::vec3 d) {
    const float a = glm::dot(d, d), b = glm::dot(o, d), c = glm::dot(o, o) - 1.0f;
    const float disc = b * b - a * c;
    if (disc < 0.0f || a == 0.0f) return kInf;
    const float s = std::sqrt(disc);
    float t = (-b - s) / a;
    if (t <= 1e-5f) t = (-b + s) / a;
    return t > 1e-5f ? t : kInf;
}

float hitUnitQuad(glm::vec3 o, glm::vec3 d) {
    if (std::abs(d.z) < 1e-12f) return kInf;
    const float t = -o.z / d.z;
    if (t <= 1e-5f) return kInf;
    const glm::vec3 p = o + t * d;
    return std::abs(p.x) <= 1.0f && std::abs(p.y) <= 1.0f ? t : kInf;
}

float hitUnitBox(glm::vec3 o, glm::vec3 d) {
    float t0 = -kInf, t1 = kInf;
    for (int i = 0; i < 3; ++i) {
        if (std::abs(d[i]) < 1e-12f) {
            if (std::abs(o[i]) > 1.0f) return kInf;
            continue;
        }
        float a = (-1.0f - o[i]) / d[i], b = (1.0f - o[i]) / d[i];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
    }
    if (t0 > t1) return kInf;
    if (t0 > 1e-5f) return t0;
    return t1 > 1e-5f ? t1 : kInf;
}

float hitTransformed(const glm::mat4& m, const Ray& ray, float (*hit)(glm::vec3, glm::vec3)) {
    const float det = glm::determinant(m);
    if (!std::isfinite(det) || std::abs(det) < 1e-20f) return kInf;
    const glm::mat4 inv = glm::inverse(m);
    return hit(glm::vec3(inv * glm::vec4(ray.origin, 1.0f)), glm::vec3(inv * glm::vec4(ray.direction, 0.0f)));
}

float hitSphere(glm::vec3 centre, float radius, const Ray& ray) {
    return hitUnitSphere((ray.origin - centre) / radius, ray.direction / radius);
}

constexpr float kPointLightPickRadius = 0.05f;   // world units: a point light's clickable size

// World bounds of the box [lo, hi] under m: its 8 corners transformed.
std::pair<glm::vec3, glm::vec3> boundsOfBox(const glm::mat4& m, glm::vec3 boxLo, glm::vec3 boxHi) {
    glm::vec3 lo(kInf), hi(-kInf);
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 c((i & 1) ? boxHi.x : boxLo.x, (i & 2) ? boxHi.y : boxLo.y, (i & 4) ? boxHi.z : boxLo.z);
        const glm::vec3 p = glm::vec3(m * glm::vec4(c, 1.0f));
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    return {lo, hi};
}

std::pair<glm::vec3, glm::vec3> boundsOfUnitCube(const glm::mat4& m, bool flatZ) {
    glm::vec3 lo(kInf), hi(-kInf);
    for (int i = 0; i < 8; ++i) {
        glm::vec3 c((i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, (i & 4) ? 1.0f : -1.0f);
        if (flatZ) c.z = 0.0f;
        const glm::vec3 p = glm::vec3(m * glm::vec4(c, 1.0f));
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    return {lo, hi};
}

}  // namespace

Ray cameraRay(const Camera& camera, int width, int height, glm::vec2 pixel, const LensCamera* lens) {
    if (lens && !camera.lens.empty())
        if (const auto r = lensPixelRay(camera, *lens, glm::dvec2(pixel), width, height))
            return {glm::vec3(r->origin), glm::vec3(r->direction)};
    const CameraFrame f = cameraFrame(camera, width, height);
    return {camera.position, glm::vec3(f.pixelDirection(glm::dvec2(pixel), width, height))};
}

std::optional<PickHit> pick(const Scene& scene, const Ray& ray) {
    std::optional<PickHit> best;
    auto consider = [&](EntityRef ref, float t) {
        if (t < kInf && (!best || t < best->distance)) best = PickHit{ref, t};
    };
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        const Object& o = scene.objects[i];
        if (o.shape == Shape::Mesh) continue;   // meshes are picked in the Outliner (no CPU triangles here yet)
        auto hit = o.shape == Shape::Sphere ? hitUnitSphere : o.shape == Shape::Quad ? hitUnitQuad : hitUnitBox;
        consider({EntityKind::Object, static_cast<int>(i)}, hitTransformed(o.transform.toMatrix(), ray, hit));
    }
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const Light& l = scene.lights[i];
        const EntityRef ref{EntityKind::Light, static_cast<int>(i)};
        switch (l.type) {
            case LightType::Rect: consider(ref, hitTransformed(l.transform.toMatrix(), ray, hitUnitQuad)); break;
            case LightType::Sphere: consider(ref, hitSphere(l.position, l.radius, ray)); break;
            case LightType::Point:
            case LightType::Spot: consider(ref, hitSphere(l.position, kPointLightPickRadius, ray)); break;
        }
    }
    return best;
}

std::optional<std::pair<glm::vec3, glm::vec3>> entityBounds(const Scene& scene, EntityRef ref,
                                                            const MeshBoundsLookup& meshBounds) {
    const size_t i = static_cast<size_t>(ref.index);
    if (ref.kind == EntityKind::Object && ref.index >= 0 && i < scene.objects.size()) {
        const Object& o = scene.objects[i];
        if (o.shape == Shape::Mesh) {   // its extent lives in the file: ask the lookup
            const auto local = meshBounds ? meshBounds(o) : std::nullopt;
            if (!local) return std::nullopt;
            return boundsOfBox(o.transform.toMatrix(), local->first, local->second);
        }
        return boundsOfUnitCube(o.transform.toMatrix(), o.shape == Shape::Quad);
    }
    if (ref.kind == EntityKind::Light && ref.index >= 0 && i < scene.lights.size()) {
        const Light& l = scene.lights[i];
        if (l.type == LightType::Rect) return boundsOfUnitCube(l.transform.toMatrix(), true);
        const float r = l.type == LightType::Sphere ? l.radius : 0.25f;
        return std::make_pair(l.position - glm::vec3(r), l.position + glm::vec3(r));
    }
    return std::nullopt;
}

std::optional<std::pair<glm::vec3, glm::vec3>> sceneBounds(const Scene& scene, const MeshBoundsLookup& meshBounds) {
    std::optional<std::pair<glm::vec3, glm::vec3>> all;
    auto add = [&](EntityRef ref) {
        auto b = entityBounds(scene, ref, meshBounds);
        if (!b || !std::isfinite(b->first.x) || !std::isfinite(b->second.x)) return;
        if (!all) all = b;
        else all = std::make_pair(glm::min(all->first, b->first), glm::max(all->second, b->second));
    };
    for (size_t i = 0; i < scene.objects.size(); ++i) add({EntityKind::Object, static_cast<int>(i)});
    for (size_t i = 0; i < scene.lights.size(); ++i) add({EntityKind::Light, static_cast<int>(i)});
    return all;
}

Camera orbit(const Camera& c, float yawDegrees, float pitchDegrees) {
    Camera out = c;
    const glm::vec3 up = glm::normalize(c.up);
    glm::vec3 offset = c.position - c.lookAt;
    // Yaw about the camera's up axis, then pitch about its right axis, never over the pole.
    offset = glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(yawDegrees), up) * glm::vec4(offset, 0.0f));
    const glm::vec3 right = glm::normalize(glm::cross(-offset, up));
    const float current = glm::degrees(std::asin(std::clamp(glm::dot(glm::normalize(offset), up), -1.0f, 1.0f)));
    const float target = std::clamp(current + pitchDegrees, -89.0f, 89.0f);
    offset = glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(-(target - current)), right) * glm::vec4(offset, 0.0f));
    out.position = c.lookAt + offset;
    return out;
}

Camera pan(const Camera& c, float dx, float dy) {
    const Basis b = basisOf(c);
    const float distance = glm::length(c.lookAt - c.position);
    const float scale = 2.0f * distance * std::tan(glm::radians(c.fovDegrees) * 0.5f);
    const glm::vec3 move = (-dx * b.right + dy * b.up) * scale;
    Camera out = c;
    out.position += move;
    out.lookAt += move;
    return out;
}

Camera dolly(const Camera& c, float factor) {
    Camera out = c;
    const glm::vec3 offset = c.position - c.lookAt;
    const float d = glm::length(offset);
    const float nd = std::max(d * factor, 1e-3f);
    out.position = c.lookAt + offset * (nd / d);
    return out;
}

Camera fly(const Camera& c, glm::vec3 localMove) {
    const Basis b = basisOf(c);
    const glm::vec3 move = localMove.x * b.right + localMove.y * b.up + localMove.z * b.forward;
    Camera out = c;
    out.position += move;
    out.lookAt += move;
    return out;
}

Camera frameBounds(const Camera& c, glm::vec3 lo, glm::vec3 hi, float aspect) {
    const glm::vec3 centre = 0.5f * (lo + hi);
    const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
    // The smaller half-angle of the view must hold the bounding sphere.
    const CameraFrame f = cameraFrame(c, double(aspect));
    const float halfFov = float(std::atan(std::min(f.tanX, f.tanY)));
    const float distance = radius / std::sin(halfFov) * 1.1f;
    Camera out = c;
    const glm::vec3 dir = glm::normalize(c.position - c.lookAt);
    out.lookAt = centre;
    out.position = centre + dir * distance;
    return out;
}

// The rolled up vector: the gizmo's view turns with the rendered image.
glm::mat4 viewMatrix(const Camera& c) { return glm::lookAt(c.position, c.lookAt, basisOf(c).up); }

glm::mat4 projectionMatrix(const Camera& c, int width, int height, float zNear, float zFar) {
    const CameraFrame f = cameraFrame(c, width, height);
    return glm::perspective(float(2.0 * std::atan(f.tanY)), float(f.tanX / f.tanY), zNear, zFar);
}

Transform transformFromMatrix(const glm::mat4& m) {
    Transform t;
    t.translate = glm::vec3(m[3]);
    glm::vec3 cols[3] = {glm::vec3(m[0]), glm::vec3(m[1]), glm::vec3(m[2])};
    glm::vec3 s(glm::length(cols[0]), glm::length(cols[1]), glm::length(cols[2]));
    if (glm::determinant(glm::mat3(m)) < 0.0f) s.x = -s.x;
    for (int i = 0; i < 3; ++i) cols[i] = s[i] != 0.0f ? cols[i] / s[i] : glm::vec3(0.0f);
    t.scale = s;
    // R = Rz(c) Ry(b) Rx(a); cols[col][row]. R[2][0] (row 2, column 0) = -sin b.
    const float sb = std::clamp(-cols[0][2], -1.0f, 1.0f);
    const float b = std::asin(sb);
    float a = 0.0f, c = 0.0f;
    if (std::abs(sb) < 0.99999f) {
        a = std::atan2(cols[1][2], cols[2][2]);   // R[2][1], R[2][2]
        c = std::atan2(cols[0][1], cols[0][0]);   // R[1][0], R[0][0]
    } else {
        // Gimbal lock: only a - c (b = +90) or a + c (b = -90) is defined; put it all in a.
        a = sb > 0.0f ? std::atan2(cols[1][0], cols[1][1]) : std::atan2(-cols[1][0], cols[1][1]);
    }
    t.rotate = glm::degrees(glm::vec3(a, b, c));
    return t;
}

glm::vec3 snapTo(glm::vec3 v, float step) {
    if (step <= 0.0f) return v;
    return glm::round(v / step) * step;
}

GizmoOps gizmoOpsFor(const Scene& scene, EntityRef ref) {
    if (ref.kind == EntityKind::Object) return {true, true, true};
    if (ref.kind == EntityKind::Light && ref.index >= 0 && static_cast<size_t>(ref.index) < scene.lights.size()) {
        switch (scene.lights[static_cast<size_t>(ref.index)].type) {
            case LightType::Rect: return {true, true, true};
            case LightType::Spot: return {true, true, false};
            default: return {true, false, false};
        }
    }
    return {false, false, false};
}

glm::mat4 lightGizmoMatrix(const Light& light) {
    if (light.type == LightType::Rect) return light.transform.toMatrix();
    glm::mat4 m(1.0f);
    if (light.type == LightType::Spot) {
        // Any orthonormal frame with z along the direction: the spot has no roll.
        const float len = glm::length(light.direction);
        const glm::vec3 z = len > 0.0f ? light.direction / len : glm::vec3(0.0f, -1.0f, 0.0f);
        const glm::vec3 helper = std::abs(z.y) < 0.99f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
        const glm::vec3 x = glm::normalize(glm::cross(helper, z));
        m[0] = glm::vec4(x, 0.0f);
        m[1] = glm::vec4(glm::cross(z, x), 0.0f);
        m[2] = glm::vec4(z, 0.0f);
    }
    m[3] = glm::vec4(light.position, 1.0f);
    return m;
}

Light lightFromGizmo(const Light& light, const glm::mat4& m) {
    Light l = light;
    if (l.type == LightType::Rect) {
        l.transform = transformFromMatrix(m);
        return l;
    }
    l.position = glm::vec3(m[3]);
    if (l.type == LightType::Spot) {
        const glm::vec3 z(m[2]);
        const float len = glm::length(z);
        const float oldLen = glm::length(light.direction);
        // A turn about the spot's own axis (or rounding) leaves the direction as it was.
        if (len > 0.0f && std::isfinite(len) &&
            (oldLen <= 0.0f || glm::length(z / len - light.direction / oldLen) > 1e-6f))
            l.direction = z / len;
    }
    return l;
}

std::vector<std::vector<glm::vec3>> lightOutline(const Light& light, const Camera& camera, float size) {
    std::vector<std::vector<glm::vec3>> lines;
    constexpr int kSegments = 32;
    constexpr float kTwoPi = 6.28318530718f;
    // A circle of radius r about centre c in the plane spanned by unit vectors u and v.
    auto circle = [&](glm::vec3 c, glm::vec3 u, glm::vec3 v, float r) {
        std::vector<glm::vec3> pts;
        for (int i = 0; i <= kSegments; ++i) {
            const float a = kTwoPi * float(i) / kSegments;
            pts.push_back(c + r * (std::cos(a) * u + std::sin(a) * v));
        }
        return pts;
    };
    // Two unit vectors perpendicular to unit n.
    auto basis = [](glm::vec3 n, glm::vec3* u, glm::vec3* v) {
        const glm::vec3 a = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
        *u = glm::normalize(glm::cross(n, a));
        *v = glm::cross(n, *u);
    };
    switch (light.type) {
        case LightType::Rect: {
            const glm::mat4 m = light.transform.toMatrix();
            auto at = [&](float x, float y, float z) { return glm::vec3(m * glm::vec4(x, y, z, 1.0f)); };
            lines.push_back({at(-1, -1, 0), at(1, -1, 0), at(1, 1, 0), at(-1, 1, 0), at(-1, -1, 0)});
            const glm::vec3 centre = at(0, 0, 0);
            const glm::vec3 normal = glm::normalize(glm::vec3(glm::transpose(glm::inverse(m)) * glm::vec4(0, 0, 1, 0)));
            lines.push_back({centre, centre + size * normal});
            break;
        }
        case LightType::Sphere: {
            // The silhouette: the circle perpendicular to the view direction towards the centre.
            glm::vec3 toCamera = camera.position - light.position;
            if (glm::length(toCamera) < 1e-12f) toCamera = glm::vec3(0, 0, 1);
            glm::vec3 u, v;
            basis(glm::normalize(toCamera), &u, &v);
            lines.push_back(circle(light.position, u, v, light.radius));
            break;
        }
        case LightType::Spot: {
            const glm::vec3 d = glm::length(light.direction) > 0.0f ? glm::normalize(light.direction) : glm::vec3(0, -1, 0);
            glm::vec3 u, v;
            basis(d, &u, &v);
            // Past 90 degrees the cone opens backwards: draw the circle at the cone's half-angle
            // capped to 89 degrees (the edges still show where it points).
            const float half = glm::radians(std::min(light.outerAngle, 89.0f));
            const glm::vec3 c = light.position + size * d;
            const float r = size * std::tan(half);
            lines.push_back(circle(c, u, v, r));
            for (const glm::vec3 e : {u, -u, v, -v}) lines.push_back({light.position, c + r * e});
            break;
        }
        case LightType::Point: {
            const float h = 0.25f * size;
            for (const glm::vec3 e : {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)})
                lines.push_back({light.position - h * e, light.position + h * e});
            break;
        }
    }
    return lines;
}

std::vector<OutlineEdge> selectionOutline(const std::vector<int>& shown, int w, int h, const std::function<int(int)>& mark) {
    std::vector<OutlineEdge> out;
    if (w <= 0 || h <= 0 || shown.size() != std::size_t(w) * std::size_t(h)) return out;
    auto markAt = [&](int x, int y) { return x < 0 || y < 0 || x >= w || y >= h ? 0 : (shown[std::size_t(y) * std::size_t(w) + std::size_t(x)] < 0 ? 0 : mark(shown[std::size_t(y) * std::size_t(w) + std::size_t(x)])); };
    auto objectAt = [&](int x, int y) { return x < 0 || y < 0 || x >= w || y >= h ? -1 : shown[std::size_t(y) * std::size_t(w) + std::size_t(x)]; };
    for (int y = 0; y <= h; ++y)
        for (int x = 0; x <= w; ++x) {
            // The edge left of cell (x, y), and the one above it.
            if (y < h && objectAt(x - 1, y) != objectAt(x, y)) {
                const int m = std::max(markAt(x - 1, y), markAt(x, y));
                if (m > 0) out.push_back({glm::vec2(float(x), float(y)), glm::vec2(float(x), float(y + 1)), m});
            }
            if (x < w && objectAt(x, y - 1) != objectAt(x, y)) {
                const int m = std::max(markAt(x, y - 1), markAt(x, y));
                if (m > 0) out.push_back({glm::vec2(float(x), float(y)), glm::vec2(float(x + 1), float(y)), m});
            }
        }
    return out;
}

}  // namespace caustic::editor
