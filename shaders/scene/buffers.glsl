// The scene as the GPU sees it: storage buffers whose element layouts live in shared/layout.h.
// Included by the integrator and by every test kernel, so that they read the same data.
#ifndef SCENE_BUFFERS_GLSL
#define SCENE_BUFFERS_GLSL
#include "../shared/layout.h"

layout(std140, binding = BINDING_FRAME_UBO) uniform FrameBlock { GpuFrame frame; };
layout(std430, binding = BINDING_PRIMITIVES) readonly buffer PrimitiveBuffer { GpuPrimitive primitives[]; };
layout(std430, binding = BINDING_MATERIALS) readonly buffer MaterialBuffer { GpuMaterial materials[]; };
layout(std430, binding = BINDING_LIGHTS) readonly buffer LightBuffer { GpuLight lights[]; };
// The CDF tables, one after another (offsets in frame.tables):
//   lightCdf(i): probability of choosing a light with index <= i (the last entry is 1);
//   envMarginalCdf(j), envConditionalCdf(k): the environment map's sampling tables;
//   meshLightCdf(k): per emissive mesh instance, the CDF over its triangles' areas.
layout(std430, binding = BINDING_TABLES) readonly buffer TableBuffer { float sceneTables[]; };
#define lightCdf(i) sceneTables[frame.tables.x + (i)]
#define envMarginalCdf(i) sceneTables[frame.tables.y + (i)]
#define envConditionalCdf(i) sceneTables[frame.tables.z + (i)]
#define meshLightCdf(i) sceneTables[frame.tables.w + (i)]
// The environment map and its sampling tables (see EnvironmentMap in renderer/gpu_scene.h).
layout(binding = TEXUNIT_ENV_MAP) uniform sampler2D envMapTexture;
// Material textures: every texture's mip chain in one buffer (RGBA as two packHalf2x16 words),
// found through its GpuTexture descriptor (shaders/bsdf/texture.glsl reads them).
layout(std430, binding = BINDING_TEXELS) readonly buffer TexelBuffer { uvec2 texels[]; };
layout(std430, binding = BINDING_TEXTURES) readonly buffer TextureBuffer { GpuTexture textures[]; };
// The directional albedo of the F = 1 GGX lobe (computed by bsdf/ggx_albedo.comp from microfacet.glsl; renderer/bsdf_tables.h).
layout(std430, binding = BINDING_BSDF_TABLES) readonly buffer BsdfTableBuffer { float ggxAlbedoTable[]; };
// Geometry: BVH nodes (the top level first), top-level leaf entries, mesh instances, triangles
// (object space, each mesh's in its BVH's leaf order) and vertices.
layout(std430, binding = BINDING_BVH_NODES) readonly buffer BvhNodeBuffer { GpuBvhNode bvhNodes[]; };
layout(std430, binding = BINDING_TLAS_REFS) readonly buffer TlasRefBuffer { uint tlasRefs[]; };
layout(std430, binding = BINDING_INSTANCES) readonly buffer InstanceBuffer { GpuInstance instances[]; };
layout(std430, binding = BINDING_TRIANGLES) readonly buffer TriangleBuffer { GpuTriangle triangles[]; };
layout(std430, binding = BINDING_VERTICES) readonly buffer VertexBuffer { GpuVertex vertices[]; };
// COUNTER_* words (shared/layout.h).
layout(std430, binding = BINDING_COUNTERS) buffer CounterBuffer { uint counters[]; };

#endif
