// The struct layouts in shaders/shared/layout.h must mean the same to the GLSL compiler as to
// C++: compare the offsets the driver reports for the integrator program with offsetof, for
// every member of every shared struct (GpuPrimitive, GpuMaterial, GpuTexture, GpuLight,
// GpuLightNode, GpuBvhNode, GpuInstance, GpuTriangle, GpuVertex, GpuFrame), and each array's
// stride with sizeof. The integrator uses every buffer, so its program reports them all.
#include "shaders/shared/layout.h"
#include "tests/gpu/gl_fixture.h"

#include <glad/gl.h>

#include <catch2/catch.hpp>

#include <cstddef>

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
#define CHECK_MEMBER(array, Type, member) \
    CHECK(resourceOffset(p, GL_BUFFER_VARIABLE, array "[0]." #member) == GLint(offsetof(Type, member)))
    CHECK_MEMBER("primitives", GpuPrimitive, a);
    CHECK_MEMBER("primitives", GpuPrimitive, b);
    CHECK_MEMBER("primitives", GpuPrimitive, c);
    CHECK_MEMBER("primitives", GpuPrimitive, info);
    CHECK(arrayStride(p, "primitives[0].a") == GLint(sizeof(GpuPrimitive)));
    CHECK_MEMBER("materials", GpuMaterial, albedo);
    CHECK_MEMBER("materials", GpuMaterial, emission);
    CHECK_MEMBER("materials", GpuMaterial, params);
    CHECK_MEMBER("materials", GpuMaterial, info);
    CHECK_MEMBER("materials", GpuMaterial, eta);
    CHECK_MEMBER("materials", GpuMaterial, k);
    CHECK_MEMBER("materials", GpuMaterial, textures);
    CHECK_MEMBER("materials", GpuMaterial, sheen);
    CHECK_MEMBER("textures", GpuTexture, info);
    CHECK(arrayStride(p, "textures[0].info") == GLint(sizeof(GpuTexture)));
    CHECK(arrayStride(p, "materials[0].albedo") == GLint(sizeof(GpuMaterial)));
    CHECK_MEMBER("lights", GpuLight, p0);
    CHECK_MEMBER("lights", GpuLight, p1);
    CHECK_MEMBER("lights", GpuLight, p2);
    CHECK_MEMBER("lights", GpuLight, color);
    CHECK_MEMBER("lights", GpuLight, info);
    CHECK_MEMBER("lights", GpuLight, tree);
    CHECK(arrayStride(p, "lights[0].p0") == GLint(sizeof(GpuLight)));
    CHECK_MEMBER("lightTree", GpuLightNode, boundsMin);
    CHECK_MEMBER("lightTree", GpuLightNode, boundsMax);
    CHECK_MEMBER("lightTree", GpuLightNode, axis);
    CHECK_MEMBER("lightTree", GpuLightNode, info);
    CHECK(arrayStride(p, "lightTree[0].boundsMin") == GLint(sizeof(GpuLightNode)));
    // The geometry: a BVH node's vec3 is followed by a scalar (std430 packs it into the vec3's
    // fourth word, as the C++ struct does).
    CHECK_MEMBER("bvhNodes", GpuBvhNode, boundsMin);
    CHECK_MEMBER("bvhNodes", GpuBvhNode, rightOrFirst);
    CHECK_MEMBER("bvhNodes", GpuBvhNode, boundsMax);
    CHECK_MEMBER("bvhNodes", GpuBvhNode, countAndAxis);
    CHECK(arrayStride(p, "bvhNodes[0].boundsMin") == GLint(sizeof(GpuBvhNode)));
    CHECK_MEMBER("instances", GpuInstance, worldToObject0);
    CHECK_MEMBER("instances", GpuInstance, worldToObject1);
    CHECK_MEMBER("instances", GpuInstance, worldToObject2);
    CHECK_MEMBER("instances", GpuInstance, objectToWorld0);
    CHECK_MEMBER("instances", GpuInstance, objectToWorld1);
    CHECK_MEMBER("instances", GpuInstance, objectToWorld2);
    CHECK_MEMBER("instances", GpuInstance, info);
    CHECK_MEMBER("instances", GpuInstance, info2);
    CHECK_MEMBER("instances", GpuInstance, info3);
    CHECK(arrayStride(p, "instances[0].worldToObject0") == GLint(sizeof(GpuInstance)));
    CHECK_MEMBER("triangles", GpuTriangle, p0);
    CHECK_MEMBER("triangles", GpuTriangle, p1);
    CHECK_MEMBER("triangles", GpuTriangle, p2);
    CHECK_MEMBER("triangles", GpuTriangle, v);
    CHECK(arrayStride(p, "triangles[0].p0") == GLint(sizeof(GpuTriangle)));
    CHECK_MEMBER("vertices", GpuVertex, normalU);
    CHECK_MEMBER("vertices", GpuVertex, tangentV);
    CHECK(arrayStride(p, "vertices[0].normalU") == GLint(sizeof(GpuVertex)));
#undef CHECK_MEMBER
#define CHECK_FRAME(member) CHECK(resourceOffset(p, GL_UNIFORM, "frame." #member) == GLint(offsetof(GpuFrame, member)))
    CHECK_FRAME(camPosition);
    CHECK_FRAME(camRight);
    CHECK_FRAME(camUp);
    CHECK_FRAME(camForward);
    CHECK_FRAME(image);
    CHECK_FRAME(counts);
    CHECK_FRAME(dispatch);
    CHECK_FRAME(envInfo);
    CHECK_FRAME(envRadiance);
    CHECK_FRAME(envHorizon);
    CHECK_FRAME(envZenith);
    CHECK_FRAME(envMap);
    CHECK_FRAME(camLens);
    CHECK_FRAME(camInfo);
    CHECK_FRAME(geometry);
    CHECK_FRAME(sampling);
    CHECK_FRAME(envSelect);
    CHECK_FRAME(rayOffset);
    CHECK_FRAME(options);
    CHECK_FRAME(tables);
#undef CHECK_FRAME
}
