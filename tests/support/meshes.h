// Small closed meshes written as OBJ files for tests (shared vertices, consistent winding, outward
// normals), and a temporary folder that cleans up after itself.
#pragma once

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

// A UV sphere of radius 1: poles as single vertices, rings of `segments` shared vertices.
inline void writeObjSphere(const std::string& path, int rings, int segments) {
    std::ofstream f(path);
    const double pi = std::numbers::pi;
    f << "v 0 1 0\n";
    for (int r = 1; r < rings; ++r) {
        const double theta = pi * r / rings;
        for (int s = 0; s < segments; ++s) {
            const double phi = 2.0 * pi * s / segments;
            f << "v " << std::sin(theta) * std::cos(phi) << " " << std::cos(theta) << " "
              << -std::sin(theta) * std::sin(phi) << "\n";
        }
    }
    f << "v 0 -1 0\n";
    auto ring = [&](int r, int s) { return 2 + (r - 1) * segments + ((s % segments) + segments) % segments; };
    const int south = 2 + (rings - 1) * segments;
    for (int s = 0; s < segments; ++s) f << "f 1 " << ring(1, s) << " " << ring(1, s + 1) << "\n";
    for (int r = 1; r < rings - 1; ++r)
        for (int s = 0; s < segments; ++s) {
            f << "f " << ring(r, s) << " " << ring(r + 1, s) << " " << ring(r + 1, s + 1) << "\n";
            f << "f " << ring(r, s) << " " << ring(r + 1, s + 1) << " " << ring(r, s + 1) << "\n";
        }
    for (int s = 0; s < segments; ++s) f << "f " << south << " " << ring(rings - 1, s + 1) << " " << ring(rings - 1, s) << "\n";
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
