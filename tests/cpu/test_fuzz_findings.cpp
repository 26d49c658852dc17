// Regression tests for what the fuzz harnesses (tests/fuzz, docs/reliability.md "Fuzzing") found
// in caustic's own code; each failed before its fix. Findings in the image module (OpenImageIO)
// are covered by the image harness's smoke run and its seeds (tests/fuzz/seeds/image/).
#include "renderer/hdr_file.h"
#include "renderer/mesh_import.h"
#include "tests/support/meshes.h"

#include <catch2/catch.hpp>

#include <fstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

using namespace caustic;

namespace {

const char* const kHdrHead = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";

// Assimp's cube.ply header (assimp-testmodels PLY/cube.ply): 8 vertices, 6 quads.
const char* const kPlyCubeHeader =
    "ply\nformat ascii 1.0\nelement vertex 8\nproperty float32 x\nproperty float32 y\nproperty float32 z\n"
    "element face 6\nproperty list uint8 int32 vertex_index\n";

// Imports the file in a forked child that must finish within `seconds` (an abort or a hang
// fails the test instead of ending or stalling the suite); true when the child reported an
// import error containing `expected`.
bool importFailsInChild(const std::string& file, const std::string& expected, unsigned seconds) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::alarm(seconds);
        const MeshImportResult r = importMeshFile(file);
        ::_exit(!r.ok() && r.error.rfind(file, 0) == 0 && r.error.find(expected) != std::string::npos ? 0 : 1);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    INFO("child status " << status << (WIFSIGNALED(status) ? " (killed by a signal)" : ""));
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace

TEST_CASE("fuzz findings: a truncated PLY file that trips an assertion inside Assimp is refused, not fatal",
          "[fuzz][mesh]") {
    // Debian's Assimp aborted the process (TriangulateProcess.cpp:238: numOut != pMesh->mNumFaces).
    test::TempDir dir;
    const std::string file = dir.file("truncated.ply");
    std::ofstream(file, std::ios::binary) << kPlyCubeHeader << "end_header\n0 ";
    CHECK(importFailsInChild(file, "cannot import", 60));
}

TEST_CASE("fuzz findings: a PLY header without end_header is refused instead of hanging Assimp", "[fuzz][mesh]") {
    test::TempDir dir;
    const std::string file = dir.file("no-end.ply");
    std::ofstream(file, std::ios::binary) << kPlyCubeHeader << "d_heNaNader\n0 0 0\n0 0 1\n0 1 1\n0 1 0\n4 0 1 2 3\n";
    CHECK(importFailsInChild(file, "the PLY header has no end_header line", 60));
    // The word glued to the data that follows hung it as well (found by fuzz_mesh).
    std::ofstream(file, std::ios::binary | std::ios::trunc) << kPlyCubeHeader << "end_header22e-16 0.5\n0 0 0\n";
    CHECK(importFailsInChild(file, "the PLY header has no end_header line", 60));
}

TEST_CASE("fuzz findings: a short HDR file declaring a large image is refused before its pixels are allocated",
          "[fuzz][image]") {
    // 16384x8192 is inside the size limit; 64 bytes cannot hold it in any encoding (run-length at
    // best: 4 + 4 * 2 * 130 bytes a row, 8192 rows). The reader
    // allocated (and cleared) 1.6 GB before it found the file truncated at row 0.
    test::TempDir dir;
    const std::string file = dir.file("short.hdr");
    std::ofstream(file, std::ios::binary) << kHdrHead << "-Y 8192 +X 16384\n" << std::string(64, '\x02');
    ImageData img;
    std::string error;
    CHECK_FALSE(readRadianceHdr(file, &img, &error));
    CHECK(error == file + ": truncated: declares 16384x8192 pixels, which need at least 8552448 bytes, but the file "
                          "has 64 after the header");
    CHECK(img.pixels.capacity() == 0);
}

TEST_CASE("fuzz findings: an HDR file exactly as long as its densest encoding still reads", "[fuzz][image]") {
    // 200 pixels a row, each component in two runs (127 + 73): 4 + 4 * 2 * 2 = 20 bytes a row, the
    // lower bound the reader now checks before allocating.
    test::TempDir dir;
    const std::string file = dir.file("dense.hdr");
    std::string rows;
    for (int y = 0; y < 3; ++y) {
        rows += std::string{2, 2, 0, char(200)};
        for (const int value : {128, 64, 32, 129}) rows += std::string{char(128 + 127), char(value), char(128 + 73), char(value)};
    }
    std::ofstream(file, std::ios::binary) << kHdrHead << "-Y 3 +X 200\n" << rows;
    ImageData img;
    std::string error;
    REQUIRE(readRadianceHdr(file, &img, &error));
    CHECK(img.width == 200);
    CHECK(img.height == 3);
    // RGBE (128, 64, 32, e = 129): value = mantissa * 2^(129 - 136).
    CHECK(img.pixels[0] == 1.0f);
    CHECK(img.pixels[599 * 3 + 2] == 0.25f);
}
