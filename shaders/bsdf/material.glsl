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
// at the hit divided by |cos| (world length).
GpuMaterial materialAtSurface(GpuMaterial m, SurfacePoint s, float coneWidth) {
    float uvWidth = coneWidth * s.uvPerLength;
    if (m.textures.x != 0u) {
        uint t = m.textures.x - 1u;
        m.albedo.rgb = textureSampleLod(t, s.uv, materialTextureLod(t, uvWidth)).rgb;
    }
    if (m.textures.z != 0u) {
        uint t = m.textures.z - 1u;
        m.params.x = textureSampleLod(t, s.uv, materialTextureLod(t, uvWidth)).r;
    }
    return m;
}

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

vec3 shadingNormalAt(GpuMaterial m, SurfacePoint s, vec3 ng, float coneWidth) {
    if (m.textures.y == 0u) return ng;
    uint t = m.textures.y - 1u;
    vec3 tn = textureSampleLod(t, s.uv, materialTextureLod(t, coneWidth * s.uvPerLength)).rgb * 2.0 - 1.0;
    return applyNormalMap(ng, s.dpdu, s.dpdv, tn);
}

#endif
