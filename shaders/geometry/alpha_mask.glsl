// Alpha cut-outs (glTF 2.0 section 3.9.5, alphaMode MASK; the scene file's "alpha_mode": "mask"):
// the any-hit test traversal (geometry/bvh.glsl) asks of every triangle a ray hits before it
// accepts the hit, so camera, bounce and shadow rays all pass through the holes, and what lies
// behind is found by the same walk. A point is cut out when its alpha, the albedo (base colour)
// texture's A at the triangle's interpolated UV (KHR_texture_transform is already in the UVs:
// renderer/mesh_import.cpp) with the texture's wrap modes, is below the material's cutoff
// (GpuMaterial::info.z; the glTF base colour factor's alpha is folded into it: alpha * factor <
// cutoff <=> alpha < cutoff / factor). Without a texture the alpha is 1, so only a cutoff above 1
// cuts (everything).
//   Level of detail: always level 0, bilinear. Traversal has no ray cone, and a cut-out is a
//   threshold of the alpha, which mip filtering would blur into a different shape (thinner
//   leaves at a distance); what the pixel filter integrates over the full-resolution mask is the
//   antialiased edge.
//   Cost: nothing in a program specialised for a scene without masks (CAUSTIC_ALPHA_MASK 0:
//   scene/features.glsl; llvmpipe executes both sides of every branch, so the code must be
//   compiled out, not skipped); elsewhere one flag test per triangle hit of an instance without
//   masked materials (PRIM_FLAG_ALPHA_MASK), and for masked ones two material texels, three
//   vertex UVs and four texels.
#ifndef GEOMETRY_ALPHA_MASK_GLSL
#define GEOMETRY_ALPHA_MASK_GLSL
#include "../scene/buffers.glsl"
#include "../bsdf/texture.glsl"
#include "surface.glsl"

// The material's info (x: MAT_*, y: MAT_FLAG_*, z: cutoff bits) and texture slots, without the
// other texels of loadMaterial (their rows: GPU_MATERIAL_ROW_* in shared/layout.h).
uvec4 alphaMaskMaterialInfo(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    return FETCH_U4(materialTexels, GPU_ROW_COUNT(GPU_MATERIAL_ROWS) * i + GPU_MATERIAL_ROW_INFO);
#else
    return materials[i].info;
#endif
}
uint alphaMaskAlbedoTexture(uint i) {
#ifdef CAUSTIC_FETCH_TEXELS
    return FETCH_U4(materialTexels, GPU_ROW_COUNT(GPU_MATERIAL_ROWS) * i + GPU_MATERIAL_ROW_TEXTURES).x;
#else
    return materials[i].textures.x;
#endif
}

// Whether the material's mask keeps (does not cut out) the point at uv.
bool alphaMaskKeepsMaterial(uint material, vec2 uv) {
    uvec4 info = alphaMaskMaterialInfo(material);
    if ((info.y & MAT_FLAG_ALPHA_MASK) == 0u) return true;
    uint tex = alphaMaskAlbedoTexture(material);
    float alpha = tex != 0u ? textureSampleLod(tex - 1u, uv, 0.0).a : 1.0;
    return alpha >= uintBitsToFloat(info.z);
}

// Whether a hit on triangle `tri` of instance `inst` at barycentrics b counts (false: cut out).
bool alphaMaskKeeps(GpuInstance inst, GpuTriangle tri, vec2 b) {
    if (CAUSTIC_ALPHA_MASK == 0u || (inst.flags & PRIM_FLAG_ALPHA_MASK) == 0u) return true;
    return alphaMaskKeepsMaterial(triangleMaterial(inst, tri), triangleUv(tri, b));
}

#endif
