// The on-disk program cache (renderer/program_cache.h): a program compiled once is loaded from its
// binary the next time (a hit), works as the compiled one does, and a damaged or foreign file is
// a miss that compiles and rewrites it; another source never finds it.
#include "renderer/program_cache.h"
#include "renderer/shader_loader.h"
#include "tests/gpu/gl_fixture.h"
#include "tests/support/meshes.h"  // TempDir

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

using namespace caustic;
namespace fs = std::filesystem;

namespace {

// Writes `value` into a one-word buffer; returns what the program wrote there.
std::uint32_t runWriter(unsigned program) {
    GLuint buffer = 0;
    glCreateBuffers(1, &buffer);
    const std::uint32_t zero = 0;
    glNamedBufferData(buffer, sizeof zero, &zero, GL_DYNAMIC_READ);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer);
    glUseProgram(program);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::uint32_t out = 0;
    glGetNamedBufferSubData(buffer, 0, sizeof out, &out);
    glDeleteBuffers(1, &buffer);
    return out;
}

ShaderSource writer(std::uint32_t value) {
    return {"#version 450\nlayout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer B { uint v; };\n"
            "void main() { v = " + std::to_string(value) + "u; }\n",
            {"writer.comp"}};
}

// The process's cache folder for the test's lifetime (useProgramCache).
struct CacheDir {
    test::TempDir dir;
    std::string old = programCacheDir();
    CacheDir() { useProgramCache(dir.path.string()); }
    ~CacheDir() { useProgramCache(old.empty() ? std::string("off") : old); }
    std::vector<fs::path> files() const {
        std::vector<fs::path> out;
        for (const auto& e : fs::directory_iterator(dir.path)) out.push_back(e.path());
        return out;
    }
};

}  // namespace

TEST_CASE("program cache: a program compiled once is loaded from its binary next time, and works", "[gpu][programs]") {
    test::glContext();
    GLint formats = 0;
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
    REQUIRE(formats > 0);   // llvmpipe and NVIDIA both have one: the cache is in use on both
    CacheDir cache;
    std::string error;
    const std::uint64_t hits0 = programCacheHits();
    const unsigned first = compileComputeProgram(writer(42), "writer.comp", &error);
    REQUIRE(first);
    CHECK(programCacheHits() == hits0);
    REQUIRE(cache.files().size() == 1);
    CHECK(runWriter(first) == 42u);

    const unsigned second = compileComputeProgram(writer(42), "writer.comp", &error);
    REQUIRE(second);
    CHECK(programCacheHits() == hits0 + 1);
    CHECK(runWriter(second) == 42u);

    // Another source: a miss, its own file; it writes its own value.
    const unsigned other = compileComputeProgram(writer(7), "writer.comp", &error);
    REQUIRE(other);
    CHECK(programCacheHits() == hits0 + 1);
    CHECK(cache.files().size() == 2);
    CHECK(runWriter(other) == 7u);

    // A damaged file (its binary's bytes garbled, then cut short): a miss that compiles, works,
    // and writes the file again, which then hits.
    const fs::path file = cache.files()[0];
    for (const std::uintmax_t keep : {fs::file_size(file), std::uintmax_t(40)}) {
        {
            std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
            f.seekp(40);
            const std::string junk(256, '\x5a');
            f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
        }
        fs::resize_file(file, keep);
        for (std::uint32_t value : {42u, 7u}) {
            const unsigned p = compileComputeProgram(writer(value), "writer.comp", &error);
            REQUIRE(p);
            CHECK(runWriter(p) == value);
            glDeleteProgram(p);
        }
        while (glGetError() != GL_NO_ERROR) {
        }
    }
    const std::uint64_t before = programCacheHits();
    for (std::uint32_t value : {42u, 7u}) {
        const unsigned p = compileComputeProgram(writer(value), "writer.comp", &error);
        REQUIRE(p);
        CHECK(runWriter(p) == value);
        glDeleteProgram(p);
    }
    CHECK(programCacheHits() == before + 2);   // both files valid again

    // Off: nothing is read or written.
    useProgramCache("off");
    const unsigned off = compileComputeProgram(writer(9), "writer.comp", &error);
    REQUIRE(off);
    CHECK(runWriter(off) == 9u);
    CHECK(cache.files().size() == 2);
    for (unsigned p : {first, second, other, off}) glDeleteProgram(p);
}
