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
// With CAUSTIC_IMAGE_LOADS (llvmpipe's default with the buffer textures) the same views are read
// as image buffers (imageLoad, image unit IMAGE_UNIT_TEXELS + the texture unit): Mesa 25's
// llvmpipe calls a helper function for every texel fetch of a format other than 8-bit unorm, and
// the call makes LLVM spill and reload the caller's live vectors around it; an image load is
// generated in line (the same loads, a bounds check instead of the call). Bit-identical results;
// docs/performance.md (session 18) has the figures.
// `format` is the unit's TEXUNIT_*_FORMAT (shared/layout.h, where the views' formats are kept).
// (Not pasted from the unit's name: Mesa's GLSL preprocessor expands an argument before pasting.)
#ifdef CAUSTIC_IMAGE_LOADS
#define SCENE_TEXELS(unit, format, name) \
    layout(binding = IMAGE_UNIT_TEXELS + unit, format) uniform readonly restrict uimageBuffer name
#define FETCH_U4(tex, i) imageLoad(tex, int(i))
#else
#define SCENE_TEXELS(unit, format, name) layout(binding = unit) uniform usamplerBuffer name
#define FETCH_U4(tex, i) texelFetch(tex, int(i))
#endif
#define FETCH_F4(tex, i) uintBitsToFloat(FETCH_U4(tex, i))
SCENE_TEXELS(TEXUNIT_PRIMITIVES, TEXUNIT_PRIMITIVES_FORMAT, primitiveTexels);
SCENE_TEXELS(TEXUNIT_BVH_NODES, TEXUNIT_BVH_NODES_FORMAT, bvhNodeTexels);
SCENE_TEXELS(TEXUNIT_TRIANGLES, TEXUNIT_TRIANGLES_FORMAT, triangleTexels);
SCENE_TEXELS(TEXUNIT_TLAS_REFS, TEXUNIT_TLAS_REFS_FORMAT, tlasRefTexels);
SCENE_TEXELS(TEXUNIT_INSTANCES, TEXUNIT_INSTANCES_FORMAT, instanceTexels);
SCENE_TEXELS(TEXUNIT_MATERIALS, TEXUNIT_MATERIALS_FORMAT, materialTexels);
SCENE_TEXELS(TEXUNIT_PRIMITIVE_HITS, TEXUNIT_PRIMITIVE_HITS_FORMAT, primitiveHitTexels);
// The meshes' 4-wide BVHs (GpuWideBvhNode, 4 texels each), read only through these views: the
// 4-wide traversal (CAUSTIC_WIDE_BVH, geometry/bvh.glsl) is a configuration for llvmpipe, where
// the views are used anyway.
SCENE_TEXELS(TEXUNIT_WIDE_NODES, TEXUNIT_WIDE_NODES_FORMAT, wideNodeTexels);
SCENE_TEXELS(TEXUNIT_VERTICES, TEXUNIT_VERTICES_FORMAT, vertexTexels);
SCENE_TEXELS(TEXUNIT_TABLES, TEXUNIT_TABLES_FORMAT, tableTexels);
SCENE_TEXELS(TEXUNIT_LIGHTS, TEXUNIT_LIGHTS_FORMAT, lightTexels);
SCENE_TEXELS(TEXUNIT_LIGHT_TREE, TEXUNIT_LIGHT_TREE_FORMAT, lightNodeTexels);
SCENE_TEXELS(TEXUNIT_BSDF_TABLES, TEXUNIT_BSDF_TABLES_FORMAT, bsdfTableTexels);
// The meshes' pair BVHs (renderer/bvh.h, buildPairBvh), read only by texel fetches: the pair walk
// (CAUSTIC_PAIR_BVH, geometry/bvh.glsl) is llvmpipe's configuration.
SCENE_TEXELS(TEXUNIT_PAIR_NODES, TEXUNIT_PAIR_NODES_FORMAT, pairNodeTexels);
// The meshes' 8-wide BVHs (renderer/bvh.h, buildWide8Bvh; six texels a node), read only by texel
// fetches: the 8-wide walk (CAUSTIC_WIDE_BVH=8, geometry/bvh.glsl) is on request only.
SCENE_TEXELS(TEXUNIT_WIDE8_NODES, TEXUNIT_WIDE8_NODES_FORMAT, wide8NodeTexels);
#undef SCENE_TEXELS

#ifdef CAUSTIC_FETCH_TEXELS
#define sceneTable(i) uintBitsToFloat(FETCH_U4(tableTexels, i).x)
#define bsdfTable(i) uintBitsToFloat(FETCH_U4(bsdfTableTexels, i).x)
#else
#define sceneTable(i) sceneTables[i]
#define bsdfTable(i) bsdfTables[i]
#endif

#ifdef CAUSTIC_FETCH_TEXELS
// A GpuPrimitive's four texels (a macro: an image cannot be a function's parameter without
// repeating its qualifiers).
#define FETCH_PRIMITIVE(tex, i) \
    GpuPrimitive(FETCH_F4(tex, 4u * (i)), FETCH_F4(tex, 4u * (i) + 1u), FETCH_F4(tex, 4u * (i) + 2u), \
                 FETCH_U4(tex, 4u * (i) + 3u))
#endif

GpuPrimitive loadPrimitive(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    return FETCH_PRIMITIVE(primitiveTexels, i);
#else
    return primitives[i];
#endif
}

GpuPrimitive loadPrimitiveHit(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    return FETCH_PRIMITIVE(primitiveHitTexels, i);
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
    return FETCH_U4(tlasRefTexels, i).x;
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
