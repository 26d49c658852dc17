// Material textures: every texture's mip chain lives in one storage buffer (texels[], RGBA as four
// halves) and is found through its GpuTexture descriptor (offset, width, height, levels), so any
// number of textures of any size work without bindless textures (not on Mesa llvmpipe 22) and
// nothing is resized into a fixed square. Filtering is manual: bilinear within a level, linear
// between the two levels around the requested level of detail (trilinear), repeat wrapping.
// Texture coordinates: u to the right, v up; the image's top row is v = 1.
// The mip chain is built on the CPU in linear space (renderer/gpu_scene.cpp addTexture; albedo
// maps are decoded from sRGB there).
#ifndef BSDF_TEXTURE_GLSL
#define BSDF_TEXTURE_GLSL
#include "../lib/math.glsl"
#include "../scene/buffers.glsl"

struct TextureLevel { uint offset; ivec2 size; };

TextureLevel textureLevel(GpuTexture t, uint level) {
    TextureLevel l;
    l.offset = t.info.x;
    uint w = t.info.y, h = t.info.z;
    for (uint i = 0u; i < level; ++i) {
        l.offset += w * h;
        w = max(1u, w >> 1);
        h = max(1u, h >> 1);
    }
    l.size = ivec2(w, h);
    return l;
}

vec4 textureTexel(TextureLevel l, ivec2 xy) {
    ivec2 p = ((xy % l.size) + l.size) % l.size;  // repeat
    uvec2 h = texels[l.offset + uint(p.y * l.size.x + p.x)];
    return vec4(unpackHalf2x16(h.x), unpackHalf2x16(h.y));
}

vec4 textureBilinear(TextureLevel l, vec2 uv) {
    vec2 x = vec2(uv.x, 1.0 - uv.y) * vec2(l.size) - 0.5;
    vec2 x0 = floor(x);
    vec2 t = x - x0;
    // Keep the integer coordinates small so that the modulo stays exact far from [0, 1].
    ivec2 i0 = ivec2(mod(x0, vec2(l.size)));
    vec4 a = textureTexel(l, i0), b = textureTexel(l, i0 + ivec2(1, 0));
    vec4 c = textureTexel(l, i0 + ivec2(0, 1)), d = textureTexel(l, i0 + ivec2(1, 1));
    return mix(mix(a, b, t.x), mix(c, d, t.x), t.y);
}

// Trilinear lookup of texture `index` (0-based) at level of detail `lod` (0 = full resolution).
vec4 textureSampleLod(uint index, vec2 uv, float lod) {
    GpuTexture t = textures[index];
    float maxLevel = float(t.info.w - 1u);
    lod = clamp(lod, 0.0, maxLevel);
    uint l0 = uint(floor(lod));
    float f = lod - float(l0);
    vec4 a = textureBilinear(textureLevel(t, l0), uv);
    if (f <= 0.0 || l0 + 1u > t.info.w - 1u) return a;
    return mix(a, textureBilinear(textureLevel(t, l0 + 1u), uv), f);
}

// The level of detail for a footprint of `uvWidth` texture-coordinate units (1 = the whole
// texture): log2 of the number of level-0 texels it spans.
float materialTextureLod(uint index, float uvWidth) {
    GpuTexture t = textures[index];
    float texels = uvWidth * sqrt(float(t.info.y) * float(t.info.z));
    return texels > 1.0 ? log2(texels) : 0.0;
}

#endif
