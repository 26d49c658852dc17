// Surface attributes a material needs (texture coordinates, tangents) and the textured material
// at a hit: albedo maps replace the albedo (diffuse models) or tint (others), roughness maps'
// first channel replaces params.x (GGX alpha, Oren-Nayar sigma or EON r), normal maps perturb the
// shading normal in the tangent frame of the geometric normal.
// primitiveSurface derives the attributes for the analytic primitives:
//   quad:   (u, v) = the quad's (alpha, beta) parameters along its two edges; dpdu, dpdv = edges;
//   sphere: u = phi / 2pi + 1/2 with phi = atan(x, -z), v = 1 - theta / pi with theta from +y,
//           in object space (the same angles as the environment map); dpdu, dpdv from those.
// Meshes fill the same SurfacePoint from their vertex UVs and tangents.
// Levels of detail come from a ray cone (Akenine-Moeller et al. 2019, "Texture Level of Detail
// Strategies for Real-Time Ray Tracing", Ray Tracing Gems ch. 20): the caller passes the cone's
// width at the hit; it is converted to texture units with the local uv-per-length scale.
#ifndef BSDF_MATERIAL_GLSL
#define BSDF_MATERIAL_GLSL
#include "texture.glsl"
#include "../geometry/surface.glsl"

// The material with its albedo and roughness textures applied; coneWidth = the ray cone's width
// at the hit divided by |cos| (world length). The slots are visited by one loop with one texture
// lookup in it, rather than one lookup per slot: the integrator inlines everything, and three
// inlined trilinear lookups cost registers on NVIDIA (docs/performance.md, "The integrator profile (H100)").
// The normal map's value (slot y) is returned in `normalTexel` (tangent space, in [-1, 1]; z = 1
// without a normal map) for shadingNormalAt.
GpuMaterial materialAtSurface(GpuMaterial m, SurfacePoint s, float coneWidth, out vec3 normalTexel) {
    float uvWidth = coneWidth * s.uvPerLength;
    normalTexel = vec3(0.0, 0.0, 1.0);
    for (uint slot = 0u; slot < 3u; ++slot) {
        uint tex = m.textures[slot];
        if (tex == 0u) continue;
        vec4 v = textureSampleLod(tex - 1u, s.uv, materialTextureLod(tex - 1u, uvWidth));
        if (slot == 0u) m.albedo.rgb = v.rgb;
        else if (slot == 1u) normalTexel = (v.rgb * 2.0 - 1.0) * vec3(m.emission.w, m.emission.w, 1.0);  // w: its scale
        else if (m.info.x == MAT_SURFACE) {
            // Perceptual roughness (squared: alpha), and with a baked glTF metallic-roughness
            // texture the metalness in G.
            m.params.x = v.r * v.r;
            if ((m.info.y & MAT_FLAG_METAL_TEXTURE) != 0u) m.albedo.w = v.g;
        } else m.params.x = v.r;
    }
    return m;
}

// The emission texture's factor at uv (1 without one): level 0, bilinear, for a ray that hits the
// surface and for a light sample on it alike (lights/lights.glsl), so that both strategies of
// multiple importance sampling estimate the same emitted radiance (a level of detail from the hit's
// ray cone would give the BSDF strategy a blurred copy of what light sampling sees).
vec3 emissionTexel(GpuMaterial m, vec2 uv) {
    if (CAUSTIC_EMISSION_TEXTURES == 0u || m.textures.w == 0u) return vec3(1.0);
    return textureSampleLod(m.textures.w - 1u, uv, 0.0).rgb;
}

// The radiance material m emits at texture coordinates uv.
vec3 materialEmission(GpuMaterial m, vec2 uv) { return m.emission.rgb * emissionTexel(m, uv); }

// The shading normal on the front side of ng (unit geometric normal, not flipped): perturbed by
// the normal map (tangent space: x along dpdu, y along the bitangent on dpdv's side, z = ng;
// stored as (n + 1) / 2), or ng itself.
vec3 applyNormalMap(vec3 ng, vec3 dpdu, vec3 dpdv, vec3 tangentNormal) {
    vec3 t = dpdu - ng * dot(ng, dpdu);
    vec3 b;
    if (dot(t, t) < 1e-24) buildOnb(ng, t, b);
    else t = normalize(t);
    b = cross(ng, t);
    if (dot(b, dpdv) < 0.0) b = -b;
    vec3 n = t * tangentNormal.x + b * tangentNormal.y + ng * tangentNormal.z;
    return dot(n, n) > 0.0 ? normalize(n) : ng;
}

// normalTexel: from materialAtSurface.
vec3 shadingNormalAt(GpuMaterial m, SurfacePoint s, vec3 ng, vec3 normalTexel) {
    if (m.textures.y == 0u) return ng;
    return applyNormalMap(ng, s.dpdu, s.dpdv, normalTexel);
}

#endif
