// The scene as the GPU sees it: storage buffers whose element layouts live in shared/layout.h.
// Included by the integrator and by every test kernel, so that they read the same data.
#ifndef SCENE_BUFFERS_GLSL
#define SCENE_BUFFERS_GLSL
#include "../shared/layout.h"
#include "features.glsl"

layout(std140, binding = BINDING_FRAME_UBO) uniform FrameBlock { GpuFrame frame; };
layout(std430, binding = BINDING_PRIMITIVES) readonly buffer PrimitiveBuffer { GpuPrimitive primitives[]; };
// The primitives as the ray tests read them: spheres as in primitives[], quads in plane form
// (a = (N, N.corner), b = (U, U.corner), c = (V, V.corner) with N = e1 x e2, U = (e2 x N) / N.N,
// V = (N x e1) / N.N: the quad's (alpha, beta) are U.p - b.w and V.p - c.w), computed once on the
// CPU instead of per ray (renderer/renderer.cpp, primitiveHitRecords).
layout(std430, binding = BINDING_PRIMITIVE_HITS) readonly buffer PrimitiveHitBuffer { GpuPrimitive primitiveHits[]; };
layout(std430, binding = BINDING_MATERIALS) readonly buffer MaterialBuffer { GpuMaterial materials[]; };
layout(std430, binding = BINDING_LIGHTS) readonly buffer LightBuffer { GpuLight lights[]; };
// The CDF tables, one after another (offsets in frame.tables):
//   lightCdf(i): probability of choosing a light with index <= i (the last entry is 1);
//   envMarginalCdf(j), envConditionalCdf(k): the environment map's sampling tables;
//   meshLightCdf(k): per emissive mesh instance, the CDF over its triangles' areas;
//   then the environment map's guide tables (offsets in frame.envGuide; lights/environment.glsl).
layout(std430, binding = BINDING_TABLES) readonly buffer TableBuffer { float sceneTables[]; };
// sceneTable(i) reads entry i (a buffer texture with CAUSTIC_FETCH_TEXELS, below).
#define lightCdf(i) sceneTable(frame.tables.x + (i))
#define envMarginalCdf(i) sceneTable(frame.tables.y + (i))
#define envConditionalCdf(i) sceneTable(frame.tables.z + (i))
#define meshLightCdf(i) sceneTable(frame.tables.w + (i))
// The environment map and its sampling tables (see EnvironmentMap in renderer/gpu_scene.h).
layout(binding = TEXUNIT_ENV_MAP) uniform sampler2D envMapTexture;
// Material textures: every texture's mip chain in one buffer (RGBA as two packHalf2x16 words),
// found through its GpuTexture descriptor (shaders/bsdf/texture.glsl reads them).
layout(std430, binding = BINDING_TEXELS) readonly buffer TexelBuffer { uvec2 texels[]; };
layout(std430, binding = BINDING_TEXTURES) readonly buffer TextureBuffer { GpuTexture textures[]; };
// The BSDF tables (BSDF_TABLE_* offsets; computed by bsdf/ggx_albedo.comp and bsdf/surface_albedo.comp from the BSDF code; renderer/bsdf_tables.h).
layout(std430, binding = BINDING_BSDF_TABLES) readonly buffer BsdfTableBuffer { float bsdfTables[]; };
// Geometry: BVH nodes (the top level first), top-level leaf entries, mesh instances, triangles
// (object space, each mesh's in its BVH's leaf order) and vertices.
layout(std430, binding = BINDING_BVH_NODES) readonly buffer BvhNodeBuffer { GpuBvhNode bvhNodes[]; };
layout(std430, binding = BINDING_TLAS_REFS) readonly buffer TlasRefBuffer { uint tlasRefs[]; };
layout(std430, binding = BINDING_INSTANCES) readonly buffer InstanceBuffer { GpuInstance instances[]; };
layout(std430, binding = BINDING_TRIANGLES) readonly buffer TriangleBuffer { GpuTriangle triangles[]; };
layout(std430, binding = BINDING_VERTICES) readonly buffer VertexBuffer { GpuVertex vertices[]; };
// COUNTER_* words (shared/layout.h).
layout(std430, binding = BINDING_COUNTERS) buffer CounterBuffer { uint counters[]; };

// Reading the hot scene data: loadPrimitive, loadBvhNode, loadTriangle, loadVertex, loadTlasRef,
// loadInstance, loadMaterial, loadLight, sceneTable, bsdfTable (and loadLightNode in
// lights/light_select.glsl). With CAUSTIC_FETCH_TEXELS (the renderer defines it on llvmpipe;
// renderer/shader_loader.h, integratorDefines) they read buffer textures over the same buffers
// (TEXUNIT_*, RGBA32UI: one texel per 16 bytes) instead of indexing the storage buffers. Why:
// llvmpipe runs 8 invocations as the lanes of one SIMD register, and turns every storage-buffer
// load into a loop over the 8 lanes, each lane's load of each 32-bit component behind its own
// bounds-check branch; a texel fetch is one gather per texel, without branches. Integer texels
// are bit exact (floats are reinterpreted, never converted). docs/performance.md has the figures.
layout(binding = TEXUNIT_PRIMITIVES) uniform usamplerBuffer primitiveTexels;
layout(binding = TEXUNIT_BVH_NODES) uniform usamplerBuffer bvhNodeTexels;
layout(binding = TEXUNIT_TRIANGLES) uniform usamplerBuffer triangleTexels;
layout(binding = TEXUNIT_TLAS_REFS) uniform usamplerBuffer tlasRefTexels;
layout(binding = TEXUNIT_INSTANCES) uniform usamplerBuffer instanceTexels;
layout(binding = TEXUNIT_MATERIALS) uniform usamplerBuffer materialTexels;
layout(binding = TEXUNIT_PRIMITIVE_HITS) uniform usamplerBuffer primitiveHitTexels;
// The meshes' 4-wide BVHs (GpuWideBvhNode, 4 texels each), read only by texel fetches: the 4-wide
// traversal (CAUSTIC_WIDE_BVH, geometry/bvh.glsl) is a configuration for llvmpipe, where the
// buffer textures are used anyway.
layout(binding = TEXUNIT_WIDE_NODES) uniform usamplerBuffer wideNodeTexels;
layout(binding = TEXUNIT_VERTICES) uniform usamplerBuffer vertexTexels;
layout(binding = TEXUNIT_TABLES) uniform usamplerBuffer tableTexels;
layout(binding = TEXUNIT_LIGHTS) uniform usamplerBuffer lightTexels;
layout(binding = TEXUNIT_LIGHT_TREE) uniform usamplerBuffer lightNodeTexels;
layout(binding = TEXUNIT_BSDF_TABLES) uniform usamplerBuffer bsdfTableTexels;
// The meshes' pair BVHs (renderer/bvh.h, buildPairBvh), read only by texel fetches: the pair walk
// (CAUSTIC_PAIR_BVH, geometry/bvh.glsl) is llvmpipe's configuration.
layout(binding = TEXUNIT_PAIR_NODES) uniform usamplerBuffer pairNodeTexels;

#ifdef CAUSTIC_FETCH_TEXELS
#define FETCH_U4(tex, i) texelFetch(tex, int(i))
#define FETCH_F4(tex, i) uintBitsToFloat(texelFetch(tex, int(i)))
#define sceneTable(i) uintBitsToFloat(texelFetch(tableTexels, int(i)).x)
#define bsdfTable(i) uintBitsToFloat(texelFetch(bsdfTableTexels, int(i)).x)
#else
#define sceneTable(i) sceneTables[i]
#define bsdfTable(i) bsdfTables[i]
#endif

#ifdef CAUSTIC_FETCH_TEXELS
GpuPrimitive fetchPrimitive(usamplerBuffer tex, uint i) {
    GpuPrimitive p;
    p.a = FETCH_F4(tex, 4u * i);
    p.b = FETCH_F4(tex, 4u * i + 1u);
    p.c = FETCH_F4(tex, 4u * i + 2u);
    p.info = FETCH_U4(tex, 4u * i + 3u);
    return p;
}
#endif

GpuPrimitive loadPrimitive(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    return fetchPrimitive(primitiveTexels, i);
#else
    return primitives[i];
#endif
}

GpuPrimitive loadPrimitiveHit(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    return fetchPrimitive(primitiveHitTexels, i);
#else
    return primitiveHits[i];
#endif
}

GpuBvhNode loadBvhNode(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    uvec4 lo = FETCH_U4(bvhNodeTexels, 2u * i), hi = FETCH_U4(bvhNodeTexels, 2u * i + 1u);
    GpuBvhNode n;
    n.boundsMin = uintBitsToFloat(lo.xyz);
    n.rightOrFirst = lo.w;
    n.boundsMax = uintBitsToFloat(hi.xyz);
    n.countAndAxis = hi.w;
    return n;
#else
    return bvhNodes[i];
#endif
}

GpuTriangle loadTriangle(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    GpuTriangle t;
    t.p0 = FETCH_F4(triangleTexels, 4u * i);
    t.p1 = FETCH_F4(triangleTexels, 4u * i + 1u);
    t.p2 = FETCH_F4(triangleTexels, 4u * i + 2u);
    t.v = FETCH_U4(triangleTexels, 4u * i + 3u);
    return t;
#else
    return triangles[i];
#endif
}

GpuVertex loadVertex(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    GpuVertex v;
    v.normalU = FETCH_F4(vertexTexels, 2u * i);
    v.tangentV = FETCH_F4(vertexTexels, 2u * i + 1u);
    return v;
#else
    return vertices[i];
#endif
}

uint loadTlasRef(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    return texelFetch(tlasRefTexels, int(i)).x;
#else
    return tlasRefs[i];
#endif
}

GpuInstance loadInstance(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    GpuInstance s;
    s.worldToObject0 = FETCH_F4(instanceTexels, 9u * i);
    s.worldToObject1 = FETCH_F4(instanceTexels, 9u * i + 1u);
    s.worldToObject2 = FETCH_F4(instanceTexels, 9u * i + 2u);
    s.objectToWorld0 = FETCH_F4(instanceTexels, 9u * i + 3u);
    s.objectToWorld1 = FETCH_F4(instanceTexels, 9u * i + 4u);
    s.objectToWorld2 = FETCH_F4(instanceTexels, 9u * i + 5u);
    s.info = FETCH_U4(instanceTexels, 9u * i + 6u);
    s.info2 = FETCH_U4(instanceTexels, 9u * i + 7u);
    s.info3 = FETCH_U4(instanceTexels, 9u * i + 8u);
    return s;
#else
    return instances[i];
#endif
}

GpuLight loadLight(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    GpuLight l;
    l.p0 = FETCH_F4(lightTexels, 6u * i);
    l.p1 = FETCH_F4(lightTexels, 6u * i + 1u);
    l.p2 = FETCH_F4(lightTexels, 6u * i + 2u);
    l.color = FETCH_F4(lightTexels, 6u * i + 3u);
    l.info = FETCH_U4(lightTexels, 6u * i + 4u);
    l.tree = FETCH_U4(lightTexels, 6u * i + 5u);
    return l;
#else
    return lights[i];
#endif
}

GpuMaterial loadMaterial(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    GpuMaterial m;
    m.albedo = FETCH_F4(materialTexels, 8u * i);
    m.emission = FETCH_F4(materialTexels, 8u * i + 1u);
    m.params = FETCH_F4(materialTexels, 8u * i + 2u);
    m.info = FETCH_U4(materialTexels, 8u * i + 3u);
    m.eta = FETCH_F4(materialTexels, 8u * i + 4u);
    m.k = FETCH_F4(materialTexels, 8u * i + 5u);
    m.textures = FETCH_U4(materialTexels, 8u * i + 6u);
    m.sheen = FETCH_F4(materialTexels, 8u * i + 7u);
    return m;
#else
    return materials[i];
#endif
}

#endif
