// The scene as the GPU sees it: storage buffers whose element layouts live in shared/layout.h.
// Included by the integrator and by every test kernel, so that they read the same data.
#ifndef SCENE_BUFFERS_GLSL
#define SCENE_BUFFERS_GLSL
#include "../shared/layout.h"

layout(std140, binding = BINDING_FRAME_UBO) uniform FrameBlock { GpuFrame frame; };
layout(std430, binding = BINDING_PRIMITIVES) readonly buffer PrimitiveBuffer { GpuPrimitive primitives[]; };
layout(std430, binding = BINDING_MATERIALS) readonly buffer MaterialBuffer { GpuMaterial materials[]; };
layout(std430, binding = BINDING_LIGHTS) readonly buffer LightBuffer { GpuLight lights[]; };
// lightCdf[i] = probability of choosing a light with index <= i; the last entry is 1.
layout(std430, binding = BINDING_LIGHT_CDF) readonly buffer LightCdfBuffer { float lightCdf[]; };
// The environment map and its sampling tables (see EnvironmentMap in renderer/gpu_scene.h).
layout(binding = TEXUNIT_ENV_MAP) uniform sampler2D envMapTexture;
layout(std430, binding = BINDING_ENV_MARGINAL) readonly buffer EnvMarginalBuffer { float envMarginalCdf[]; };
layout(std430, binding = BINDING_ENV_CONDITIONAL) readonly buffer EnvConditionalBuffer { float envConditionalCdf[]; };
// Material textures: every texture's mip chain in one buffer (RGBA as two packHalf2x16 words),
// found through its GpuTexture descriptor (shaders/bsdf/texture.glsl reads them).
layout(std430, binding = BINDING_TEXELS) readonly buffer TexelBuffer { uvec2 texels[]; };
layout(std430, binding = BINDING_TEXTURES) readonly buffer TextureBuffer { GpuTexture textures[]; };
// The directional albedo of the F = 1 GGX lobe (renderer/gpu_scene.cpp ggxAlbedoTable).
layout(std430, binding = BINDING_BSDF_TABLES) readonly buffer BsdfTableBuffer { float ggxAlbedoTable[]; };
// COUNTER_* words (shared/layout.h).
layout(std430, binding = BINDING_COUNTERS) buffer CounterBuffer { uint counters[]; };

#endif
