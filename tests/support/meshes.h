// Small closed meshes written as OBJ files for tests (shared vertices, consistent winding, outward
// normals), and a temporary folder that cleans up after itself.
#pragma once

#include "renderer/mesh.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <unistd.h>

namespace caustic::test {

struct TempDir {
    std::filesystem::path path;
    TempDir() {
        char pattern[] = "/tmp/caustic-test-XXXXXX";
        path = mkdtemp(pattern);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    std::string file(const std::string& name) const { return (path / name).string(); }
};

// A UV sphere of radius 1 (renderer/mesh.h's makeUvSphere) as an OBJ file.
inline void writeObjSphere(const std::string& path, int rings, int segments) {
    const Mesh m = makeUvSphere(static_cast<std::uint32_t>(rings), static_cast<std::uint32_t>(segments));
    std::ofstream f(path);
    for (const glm::vec3& p : m.positions) f << "v " << p.x << " " << p.y << " " << p.z << "\n";
    for (const glm::uvec3& t : m.triangles) f << "f " << t.x + 1 << " " << t.y + 1 << " " << t.z + 1 << "\n";
}

// A torus around +y with radii R (ring) and r (tube).
inline void writeObjTorus(const std::string& path, double R, double r, int nu, int nv) {
    std::ofstream f(path);
    const double pi = std::numbers::pi;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const double u = 2 * pi * i / nu, v = 2 * pi * j / nv;
            f << "v " << (R + r * std::cos(v)) * std::cos(u) << " " << r * std::sin(v) << " "
              << (R + r * std::cos(v)) * std::sin(u) << "\n";
        }
    auto id = [&](int i, int j) { return 1 + ((i + nu) % nu) * nv + ((j + nv) % nv); };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            f << "f " << id(i, j) << " " << id(i, j + 1) << " " << id(i + 1, j + 1) << "\n";
            f << "f " << id(i, j) << " " << id(i + 1, j + 1) << " " << id(i + 1, j) << "\n";
        }
}

// The square [-1, 1]^2 in the z = 0 plane facing +z, as two triangles.
inline void writeObjQuad(const std::string& path) {
    std::ofstream f(path);
    f << "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n";
}

}  // namespace caustic::test
