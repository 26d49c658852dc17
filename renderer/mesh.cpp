#include "renderer/mesh.h"

#include <cmath>
#include <string>

namespace caustic {

namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const glm::vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }
bool finite(const glm::vec4& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

}  // namespace

std::string MeshValidation::summary() const {
    std::string s;
    auto add = [&s](std::size_t n, const char* what) {
        if (n == 0) return;
        if (!s.empty()) s += ", ";
        s += std::to_string(n) + " " + what;
    };
    add(droppedOutOfRange, "triangles with out-of-range indices dropped");
    add(droppedNonFinite, "triangles with non-finite vertices dropped");
    add(droppedDegenerate, "degenerate (zero-area) triangles dropped");
    add(fixedNormals, "invalid normals recomputed");
    add(fixedUvs, "non-finite UVs set to 0");
    add(droppedNormals ? 1 : 0, "normal array of the wrong size dropped");
    add(droppedUvs ? 1 : 0, "UV array of the wrong size dropped");
    add(droppedTangents ? 1 : 0, "invalid tangent array dropped");
    return s;
}

std::vector<glm::vec3> computeVertexNormals(const std::vector<glm::vec3>& positions,
                                            const std::vector<glm::uvec3>& triangles) {
    std::vector<glm::vec3> n(positions.size(), glm::vec3(0.0f));
    const std::size_t nv = positions.size();
    for (const glm::uvec3& t : triangles) {
        if (t.x >= nv || t.y >= nv || t.z >= nv) continue;
        // The unnormalised cross product weighs each face by its area.
        const glm::vec3 fn = glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x]);
        if (!finite(fn)) continue;
        n[t.x] += fn;
        n[t.y] += fn;
        n[t.z] += fn;
    }
    for (glm::vec3& v : n) {
        const float len = glm::length(v);
        v = len > 0.0f && std::isfinite(len) ? v / len : glm::vec3(0.0f, 0.0f, 1.0f);
    }
    return n;
}

MeshValidation validateMesh(Mesh& mesh) {
    MeshValidation r;
    const std::size_t nv = mesh.positions.size();

    std::vector<glm::uvec3> kept;
    kept.reserve(mesh.triangles.size());
    for (const glm::uvec3& t : mesh.triangles) {
        if (t.x >= nv || t.y >= nv || t.z >= nv) {
            ++r.droppedOutOfRange;
            continue;
        }
        const glm::vec3 &a = mesh.positions[t.x], &b = mesh.positions[t.y], &c = mesh.positions[t.z];
        if (!finite(a) || !finite(b) || !finite(c)) {
            ++r.droppedNonFinite;
            continue;
        }
        const glm::vec3 cr = glm::cross(b - a, c - a);
        // Exactly zero (or overflowing) area only: thin slivers are legitimate geometry, and the
        // watertight intersection test handles them.
        if (t.x == t.y || t.y == t.z || t.x == t.z || (cr.x == 0.0f && cr.y == 0.0f && cr.z == 0.0f) ||
            !finite(cr)) {
            ++r.droppedDegenerate;
            continue;
        }
        kept.push_back(t);
    }
    mesh.triangles.swap(kept);

    if (!mesh.normals.empty() && mesh.normals.size() != nv) {
        mesh.normals.clear();
        r.droppedNormals = true;
    }
    if (!mesh.uvs.empty() && mesh.uvs.size() != nv) {
        mesh.uvs.clear();
        r.droppedUvs = true;
    }
    if (!mesh.tangents.empty()) {
        bool ok = mesh.tangents.size() == nv;
        for (std::size_t i = 0; ok && i < nv; ++i) ok = finite(mesh.tangents[i]);
        if (!ok) {
            mesh.tangents.clear();
            r.droppedTangents = true;
        }
    }

    std::vector<glm::vec3> smooth;
    for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
        glm::vec3& n = mesh.normals[i];
        const float len = glm::length(n);
        if (finite(n) && len > 0.0f && std::isfinite(len)) {
            n /= len;
            continue;
        }
        if (smooth.empty()) smooth = computeVertexNormals(mesh.positions, mesh.triangles);
        n = smooth[i];
        ++r.fixedNormals;
    }
    for (glm::vec2& uv : mesh.uvs) {
        if (!finite(uv)) {
            uv = glm::vec2(0.0f);
            ++r.fixedUvs;
        }
    }
    return r;
}

Mesh makeUvSphere(std::uint32_t rings, std::uint32_t segments, const std::function<float(float, float)>& radius) {
    constexpr float kPi = 3.14159265358979f;
    auto r = [&](float theta, float phi) { return radius ? radius(theta, phi) : 1.0f; };
    Mesh m;
    m.name = "uv sphere";
    m.positions.push_back({0.0f, r(0.0f, 0.0f), 0.0f});
    for (std::uint32_t i = 1; i < rings; ++i) {
        const float th = kPi * static_cast<float>(i) / static_cast<float>(rings);
        for (std::uint32_t j = 0; j < segments; ++j) {
            const float ph = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(segments);
            const float rr = r(th, ph);
            m.positions.push_back({rr * std::sin(th) * std::cos(ph), rr * std::cos(th), rr * std::sin(th) * std::sin(ph)});
        }
    }
    const auto south = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back({0.0f, -r(kPi, 0.0f), 0.0f});
    auto v = [segments](std::uint32_t i, std::uint32_t j) { return 1 + (i - 1) * segments + (j % segments); };
    for (std::uint32_t j = 0; j < segments; ++j) m.triangles.push_back({0u, v(1, j + 1), v(1, j)});
    for (std::uint32_t i = 1; i + 1 < rings; ++i)
        for (std::uint32_t j = 0; j < segments; ++j) {
            m.triangles.push_back({v(i, j), v(i, j + 1), v(i + 1, j + 1)});
            m.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i + 1, j)});
        }
    for (std::uint32_t j = 0; j < segments; ++j) m.triangles.push_back({south, v(rings - 1, j), v(rings - 1, j + 1)});
    return m;
}

}  // namespace caustic
