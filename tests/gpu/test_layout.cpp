// The struct layouts in shaders/shared/layout.h must mean the same to the GLSL compiler as to
// C++: compare the offsets the driver reports for the integrator program with offsetof, for
// every member of every shared struct that a buffer holds (generated from the structs' row
// lists, so a new member is checked without a line here), and each array's stride with sizeof.
// The integrator uses every buffer, so its program reports them all. (GpuWideBvhNode is read
// only through a buffer texture: its rows are its texels, which the row count checks.)
#include "shaders/shared/layout.h"
#include "tests/gpu/gl_fixture.h"

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <cstddef>
#include <string>

using namespace caustic;

namespace {

GLint resourceOffset(GLuint program, GLenum interface, const char* name) {
    GLuint index = glGetProgramResourceIndex(program, interface, name);
    INFO(name);
    REQUIRE(index != GL_INVALID_INDEX);
    const GLenum prop = GL_OFFSET;
    GLint offset = -1;
    glGetProgramResourceiv(program, interface, index, 1, &prop, 1, nullptr, &offset);
    return offset;
}

GLint arrayStride(GLuint program, const char* name) {
    GLuint index = glGetProgramResourceIndex(program, GL_BUFFER_VARIABLE, name);
    REQUIRE(index != GL_INVALID_INDEX);
    const GLenum prop = GL_TOP_LEVEL_ARRAY_STRIDE;
    GLint stride = -1;
    glGetProgramResourceiv(program, GL_BUFFER_VARIABLE, index, 1, &prop, 1, nullptr, &stride);
    return stride;
}

}  // namespace

TEST_CASE("shared structs have the same layout in GLSL and C++", "[gpu][layout]") {
    auto renderer = test::makeRenderer();
    const GLuint p = renderer->program();
    using namespace caustic::gpu;
    // Every member of every row list (shared/layout.h): its offset as the driver reports it for the
    // storage buffer LAYOUT_ARRAY (or the frame's uniform block) against offsetof, and the array's
    // stride against sizeof. LAYOUT_ARRAY and LAYOUT_TYPE are defined around each expansion.
#define LAYOUT_MEMBER(n)                                                                             \
    {                                                                                                \
        const std::string name = std::string(LAYOUT_ARRAY) + "[0]." #n;                              \
        CHECK(resourceOffset(p, GL_BUFFER_VARIABLE, name.c_str()) == GLint(offsetof(LAYOUT_TYPE, n))); \
        CHECK(arrayStride(p, name.c_str()) == GLint(sizeof(LAYOUT_TYPE)));                           \
    }
#define LAYOUT_MEMBER2(a, b) LAYOUT_MEMBER(a) LAYOUT_MEMBER(b)
#define LAYOUT_MEMBER4(a, b, c, d) LAYOUT_MEMBER(a) LAYOUT_MEMBER(b) LAYOUT_MEMBER(c) LAYOUT_MEMBER(d)
#define LAYOUT_CHECK(ROWS) ROWS(LAYOUT_MEMBER, LAYOUT_MEMBER, LAYOUT_MEMBER2, LAYOUT_MEMBER4)
#define LAYOUT_ARRAY "primitives"
#define LAYOUT_TYPE GpuPrimitive
    LAYOUT_CHECK(GPU_PRIMITIVE_ROWS)
#undef LAYOUT_ARRAY
#undef LAYOUT_TYPE
#define LAYOUT_ARRAY "materials"
#define LAYOUT_TYPE GpuMaterial
    LAYOUT_CHECK(GPU_MATERIAL_ROWS)
#undef LAYOUT_ARRAY
#undef LAYOUT_TYPE
#define LAYOUT_ARRAY "textures"
#define LAYOUT_TYPE GpuTexture
    LAYOUT_CHECK(GPU_TEXTURE_ROWS)
#undef LAYOUT_ARRAY
#undef LAYOUT_TYPE
#define LAYOUT_ARRAY "lights"
#define LAYOUT_TYPE GpuLight
    LAYOUT_CHECK(GPU_LIGHT_ROWS)
#undef LAYOUT_ARRAY
#undef LAYOUT_TYPE
#define LAYOUT_ARRAY "lightTree"
#define LAYOUT_TYPE GpuLightNode
    LAYOUT_CHECK(GPU_LIGHT_NODE_ROWS)
#undef LAYOUT_ARRAY
#undef LAYOUT_TYPE
    // A BVH node's vec3 is followed by a scalar (std430 packs it into the vec3's fourth word, as
    // the C++ struct does).
#define LAYOUT_ARRAY "bvhNodes"
#define LAYOUT_TYPE GpuBvhNode
    LAYOUT_CHECK(GPU_BVH_NODE_ROWS)
#undef LAYOUT_ARRAY
#undef LAYOUT_TYPE
#define LAYOUT_ARRAY "instances"
#define LAYOUT_TYPE GpuInstance
    LAYOUT_CHECK(GPU_INSTANCE_ROWS)
#undef LAYOUT_ARRAY
#undef LAYOUT_TYPE
#define LAYOUT_ARRAY "triangles"
#define LAYOUT_TYPE GpuTriangle
    LAYOUT_CHECK(GPU_TRIANGLE_ROWS)
#undef LAYOUT_ARRAY
#undef LAYOUT_TYPE
#define LAYOUT_ARRAY "vertices"
#define LAYOUT_TYPE GpuVertex
    LAYOUT_CHECK(GPU_VERTEX_ROWS)
#undef LAYOUT_ARRAY
#undef LAYOUT_TYPE
#undef LAYOUT_CHECK
#undef LAYOUT_MEMBER4
#undef LAYOUT_MEMBER2
#undef LAYOUT_MEMBER
    // The frame's uniform block (std140; its rows are vec4s, so std140 is std430 is C++).
#define FRAME_MEMBER(n) CHECK(resourceOffset(p, GL_UNIFORM, "frame." #n) == GLint(offsetof(GpuFrame, n)));
#define FRAME_MEMBER2(a, b) FRAME_MEMBER(a) FRAME_MEMBER(b)
#define FRAME_MEMBER4(a, b, c, d) FRAME_MEMBER(a) FRAME_MEMBER(b) FRAME_MEMBER(c) FRAME_MEMBER(d)
    GPU_FRAME_ROWS(FRAME_MEMBER, FRAME_MEMBER, FRAME_MEMBER2, FRAME_MEMBER4)
#undef FRAME_MEMBER4
#undef FRAME_MEMBER2
#undef FRAME_MEMBER
}
