// The viewport's display transform: the accumulation image (rgb = sum of samples, a = sample
// count) -> mean * 2^exposure -> tone curve -> sRGB, into an RGBA8 image the UI draws. The same
// formulas as renderer/tonemap.cpp (toSrgb8), which batch mode and the editor's "write image"
// use, so what the viewport shows is what a saved PNG holds (up to the final rounding).
#version 450 core
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform sampler2D accumulation;
layout(binding = 0, rgba8) uniform writeonly image2D displayImage;
layout(location = 0) uniform float exposureScale;   // 2^exposure
layout(location = 1) uniform int toneMap;           // 0 = ACES (Narkowicz 2015), 1 = Reinhard 2002

// Narkowicz 2015, "ACES Filmic Tone Mapping Curve".
vec3 toneAces(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}
// Reinhard et al. 2002, eq. 3.
vec3 toneReinhard(vec3 x) { return x / (1.0 + x); }
// IEC 61966-2-1.
vec3 srgbEncode(vec3 v) {
    v = clamp(v, 0.0, 1.0);
    return mix(1.055 * pow(v, vec3(1.0 / 2.4)) - 0.055, 12.92 * v, lessThanEqual(v, vec3(0.0031308)));
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(displayImage);
    if (p.x >= size.x || p.y >= size.y) return;
    vec4 acc = texelFetch(accumulation, p, 0);
    vec3 mean = acc.a > 0.0 ? acc.rgb / acc.a : vec3(0.0);
    vec3 x = max(mean * exposureScale, vec3(0.0));
    vec3 t = toneMap == 0 ? toneAces(x) : toneReinhard(x);
    imageStore(displayImage, p, vec4(srgbEncode(t), 1.0));
}
