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
// renderer/integrator_config.h) they read buffer textures over the same buffers
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
// docs/performance.md has the figures.
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
// The meshes' 4-wide BVHs (GpuWideBvhNode, 4 texels each), read only through this view: the
// 4-wide walk (geometry/walk_wide4.glsl) is llvmpipe's, where the views are used anyway.
SCENE_TEXELS(TEXUNIT_WIDE_NODES, TEXUNIT_WIDE_NODES_FORMAT, wideNodeTexels);
SCENE_TEXELS(TEXUNIT_VERTICES, TEXUNIT_VERTICES_FORMAT, vertexTexels);
SCENE_TEXELS(TEXUNIT_TABLES, TEXUNIT_TABLES_FORMAT, tableTexels);
SCENE_TEXELS(TEXUNIT_LIGHTS, TEXUNIT_LIGHTS_FORMAT, lightTexels);
SCENE_TEXELS(TEXUNIT_LIGHT_TREE, TEXUNIT_LIGHT_TREE_FORMAT, lightNodeTexels);
SCENE_TEXELS(TEXUNIT_BSDF_TABLES, TEXUNIT_BSDF_TABLES_FORMAT, bsdfTableTexels);
#undef SCENE_TEXELS

#ifdef CAUSTIC_FETCH_TEXELS
#define sceneTable(i) uintBitsToFloat(FETCH_U4(tableTexels, i).x)
#define bsdfTable(i) uintBitsToFloat(FETCH_U4(bsdfTableTexels, i).x)
#else
#define sceneTable(i) sceneTables[i]
#define bsdfTable(i) bsdfTables[i]
#endif

// The loaders, generated from each struct's row list (shared/layout.h): with buffer textures, a
// struct's rows are its texels, read one after the other from the view named by GPU_TEXELS.
#define GPU_LOAD_V4(n) s.n = FETCH_F4(GPU_TEXELS, t); ++t;
#define GPU_LOAD_U4(n) s.n = FETCH_U4(GPU_TEXELS, t); ++t;
#define GPU_LOAD_V3U(v, u) { uvec4 w = FETCH_U4(GPU_TEXELS, t); ++t; s.v = uintBitsToFloat(w.xyz); s.u = w.w; }
#define GPU_LOAD_UUUU(a, b, c, d) \
    { uvec4 w = FETCH_U4(GPU_TEXELS, t); ++t; s.a = w.x; s.b = w.y; s.c = w.z; s.d = w.w; }
#ifdef CAUSTIC_FETCH_TEXELS
#define GPU_TEXEL_LOADER(Type, ROWS, name, buffer)                                                 \
    Type name(uint i) {                                                                            \
        Type s;                                                                                    \
        uint t = GPU_ROW_COUNT(ROWS) * i;                                                          \
        ROWS(GPU_LOAD_V4, GPU_LOAD_U4, GPU_LOAD_V3U, GPU_LOAD_UUUU)                                \
        return s;                                                                                  \
    }
#else
#define GPU_TEXEL_LOADER(Type, ROWS, name, buffer) Type name(uint i) { return buffer[i]; }
#endif
#define GPU_TEXELS primitiveTexels
GPU_TEXEL_LOADER(GpuPrimitive, GPU_PRIMITIVE_ROWS, loadPrimitive, primitives)
#undef GPU_TEXELS
#define GPU_TEXELS primitiveHitTexels
GPU_TEXEL_LOADER(GpuPrimitive, GPU_PRIMITIVE_ROWS, loadPrimitiveHit, primitiveHits)
#undef GPU_TEXELS
#define GPU_TEXELS bvhNodeTexels
GPU_TEXEL_LOADER(GpuBvhNode, GPU_BVH_NODE_ROWS, loadBvhNode, bvhNodes)
#undef GPU_TEXELS
#define GPU_TEXELS triangleTexels
GPU_TEXEL_LOADER(GpuTriangle, GPU_TRIANGLE_ROWS, loadTriangle, triangles)
#undef GPU_TEXELS
#define GPU_TEXELS vertexTexels
GPU_TEXEL_LOADER(GpuVertex, GPU_VERTEX_ROWS, loadVertex, vertices)
#undef GPU_TEXELS
#define GPU_TEXELS instanceTexels
GPU_TEXEL_LOADER(GpuInstance, GPU_INSTANCE_ROWS, loadInstance, instances)
#undef GPU_TEXELS
#define GPU_TEXELS lightTexels
GPU_TEXEL_LOADER(GpuLight, GPU_LIGHT_ROWS, loadLight, lights)
#undef GPU_TEXELS
#define GPU_TEXELS materialTexels
GPU_TEXEL_LOADER(GpuMaterial, GPU_MATERIAL_ROWS, loadMaterial, materials)
#undef GPU_TEXELS

uint loadTlasRef(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    return FETCH_U4(tlasRefTexels, i).x;
#else
    return tlasRefs[i];
#endif
}

#endif
