// Material textures: every texture's mip chain lives in one storage buffer (texels[], RGBA as four
// halves) and is found through its GpuTexture descriptor (offset, width, height, levels), so any
// number of textures of any size work without bindless textures (not on Mesa llvmpipe 22) and
// nothing is resized into a fixed square. Filtering is manual: bilinear within a level, linear
// between the two levels around the requested level of detail (trilinear), with each axis
// repeating (scene textures, glTF REPEAT), clamped to the edge or mirrored (glTF samplers).
// Texture coordinates: u to the right, v up; the image's top row is v = 1.
// The mip chain is built on the CPU in linear space (renderer/gpu_scene.cpp addTexture; albedo
// maps are decoded from sRGB there).
#ifndef BSDF_TEXTURE_GLSL
#define BSDF_TEXTURE_GLSL
#include "../lib/math.glsl"
#include "../scene/buffers.glsl"

struct TextureLevel { uint offset; ivec2 size; uvec2 wrap; };

uint textureLevels(GpuTexture t) { return t.info.w & 255u; }

TextureLevel textureLevel(GpuTexture t, uint level) {
    TextureLevel l;
    l.offset = t.info.x;
    l.wrap = uvec2((t.info.w >> 8) & 3u, (t.info.w >> 10) & 3u);
    uint w = t.info.y, h = t.info.z;
    for (uint i = 0u; i < level; ++i) {
        l.offset += w * h;
        w = max(1u, w >> 1);
        h = max(1u, h >> 1);
    }
    l.size = ivec2(w, h);
    return l;
}

// One texel coordinate of an axis of n texels, wrapped by mode (TEXTURE_WRAP_*).
int textureWrapCoord(int x, int n, uint mode) {
    if (mode == TEXTURE_WRAP_CLAMP) return clamp(x, 0, n - 1);
    if (mode == TEXTURE_WRAP_MIRROR) {
        int p = ((x % (2 * n)) + 2 * n) % (2 * n);
        return p < n ? p : 2 * n - 1 - p;
    }
    return ((x % n) + n) % n;
}

vec4 textureTexel(TextureLevel l, ivec2 xy) {
    ivec2 p = ivec2(textureWrapCoord(xy.x, l.size.x, l.wrap.x), textureWrapCoord(xy.y, l.size.y, l.wrap.y));
    uvec2 h = texels[l.offset + uint(p.y * l.size.x + p.x)];
    return vec4(unpackHalf2x16(h.x), unpackHalf2x16(h.y));
}

vec4 textureBilinear(TextureLevel l, vec2 uv) {
    vec2 x = vec2(uv.x, 1.0 - uv.y) * vec2(l.size) - 0.5;
    vec2 x0 = floor(x);
    vec2 t = x - x0;
    // Keep the integer coordinates small so that the modulo stays exact far from [0, 1]: by the
    // wrap's period (n repeating, 2n mirrored) or, clamped, just outside the texture.
    vec2 n = vec2(l.size);
    vec2 period = vec2(l.wrap.x == TEXTURE_WRAP_MIRROR ? 2.0 : 1.0, l.wrap.y == TEXTURE_WRAP_MIRROR ? 2.0 : 1.0) * n;
    vec2 reduced = mod(x0, period);
    ivec2 i0 = ivec2(l.wrap.x == TEXTURE_WRAP_CLAMP ? clamp(x0.x, -1.0, n.x) : reduced.x,
                     l.wrap.y == TEXTURE_WRAP_CLAMP ? clamp(x0.y, -1.0, n.y) : reduced.y);
    vec4 a = textureTexel(l, i0), b = textureTexel(l, i0 + ivec2(1, 0));
    vec4 c = textureTexel(l, i0 + ivec2(0, 1)), d = textureTexel(l, i0 + ivec2(1, 1));
    return mix(mix(a, b, t.x), mix(c, d, t.x), t.y);
}

// Trilinear lookup of texture `index` (0-based) at level of detail `lod` (0 = full resolution).
vec4 textureSampleLod(uint index, vec2 uv, float lod) {
    GpuTexture t = textures[index];
    float maxLevel = float(textureLevels(t) - 1u);
    lod = clamp(lod, 0.0, maxLevel);
    uint l0 = uint(floor(lod));
    float f = lod - float(l0);
    vec4 a = textureBilinear(textureLevel(t, l0), uv);
    if (f <= 0.0 || l0 + 1u > textureLevels(t) - 1u) return a;
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
