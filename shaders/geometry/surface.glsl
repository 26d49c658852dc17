// Surface attributes at a hit that materials need: texture coordinates and the position's
// derivatives along them (tangents for normal maps), and the local texture scale for levels of
// detail.
//   quad:     (u, v) = the quad's (alpha, beta) parameters along its two edges; dpdu, dpdv = edges;
//   sphere:   u = phi / 2pi + 1/2 with phi = atan(x, -z), v = 1 - theta / pi with theta from +y,
//             in object space (the same angles as the environment map); dpdu, dpdv from those;
//   triangle: the vertices' UVs interpolated; dpdu, dpdv solved from the triangle's UV layout
//             (PBRT 4th ed. sec. 6.5.3), or the mesh's tangent for dpdu when it has one.
#ifndef GEOMETRY_SURFACE_GLSL
#define GEOMETRY_SURFACE_GLSL
#include "../lib/math.glsl"
#include "../scene/buffers.glsl"

struct SurfacePoint {
    vec2 uv;
    vec3 dpdu;        // world-space derivatives of the position (tangents, not normalised)
    vec3 dpdv;
    float uvPerLength;  // texture units per world length (geometric mean of the two directions)
};

SurfacePoint primitiveSurface(GpuPrimitive prim, vec3 p) {
    SurfacePoint s;
    if (prim.info.x == PRIM_QUAD) {
        vec3 n = cross(prim.b.xyz, prim.c.xyz);
        vec3 w = n / dot(n, n);
        vec3 hp = p - prim.a.xyz;
        s.uv = vec2(dot(w, cross(hp, prim.c.xyz)), dot(w, cross(prim.b.xyz, hp)));
        s.dpdu = prim.b.xyz;
        s.dpdv = prim.c.xyz;
    } else {
        vec3 po = vec3(dot(prim.a, vec4(p, 1.0)), dot(prim.b, vec4(p, 1.0)), dot(prim.c, vec4(p, 1.0)));
        po = normalize(po);
        float theta = acos(clamp(po.y, -1.0, 1.0));
        float phi = atan(po.x, -po.z);
        s.uv = vec2(phi / (2.0 * PI) + 0.5, 1.0 - theta / PI);
        float st = sin(theta), ct = cos(theta), sp = sin(phi), cp = cos(phi);
        // Object to world: the inverse of the world-to-object rows a, b, c.
        mat3 o2w = inverse(transpose(mat3(prim.a.xyz, prim.b.xyz, prim.c.xyz)));
        s.dpdu = o2w * (2.0 * PI * vec3(st * cp, 0.0, st * sp));
        s.dpdv = o2w * (-PI * vec3(ct * sp, -st, -ct * cp));
    }
    s.uvPerLength = inversesqrt(max(length(s.dpdu) * length(s.dpdv), 1e-30));
    return s;
}

// The material of a mesh triangle: the object's, or (info2.z != 0) the model file's own, whose
// slot the triangle carries in p0.w.
uint triangleMaterial(GpuInstance inst, GpuTriangle tri) {
    return inst.material + (inst.fileMaterials != 0u ? floatBitsToUint(tri.p0.w) : 0u);
}

vec3 instanceDirectionToWorld(GpuInstance inst, vec3 v) {
    return vec3(dot(inst.objectToWorld0.xyz, v), dot(inst.objectToWorld1.xyz, v), dot(inst.objectToWorld2.xyz, v));
}

// Normals go with the inverse transpose: (world-to-object)^T n.
vec3 instanceNormalToWorld(GpuInstance inst, vec3 n) {
    return inst.worldToObject0.xyz * n.x + inst.worldToObject1.xyz * n.y + inst.worldToObject2.xyz * n.z;
}

// The interpolated shading normal at barycentrics (b1, b2) (world, unit, on the side of the
// geometric normal ng), or ng where the mesh has no normals.
vec3 triangleShadingNormal(GpuInstance inst, GpuTriangle tri, vec2 b, vec3 ng) {
    GpuVertex v0 = loadVertex(tri.v.x), v1 = loadVertex(tri.v.y), v2 = loadVertex(tri.v.z);
    vec3 nObj = (1.0 - b.x - b.y) * v0.normalU.xyz + b.x * v1.normalU.xyz + b.y * v2.normalU.xyz;
    vec3 ns = dot(nObj, nObj) > 0.0 ? normalize(instanceNormalToWorld(inst, nObj)) : ng;
    return dot(ns, ng) < 0.0 ? -ns : ns;
}

// The texture coordinates of triangle `tri` at barycentrics (b1, b2) (triangleSurface's uv alone).
vec2 triangleUv(GpuTriangle tri, vec2 b) {
    GpuVertex v0 = loadVertex(tri.v.x), v1 = loadVertex(tri.v.y), v2 = loadVertex(tri.v.z);
    return (1.0 - b.x - b.y) * vec2(v0.normalU.w, v0.tangentV.w) + b.x * vec2(v1.normalU.w, v1.tangentV.w) +
           b.y * vec2(v2.normalU.w, v2.tangentV.w);
}

// The triangle's surface at barycentrics (b1, b2) (p = (1-b1-b2) p0 + b1 p1 + b2 p2).
SurfacePoint triangleSurface(GpuInstance inst, GpuTriangle tri, vec2 b) {
    GpuVertex v0 = loadVertex(tri.v.x), v1 = loadVertex(tri.v.y), v2 = loadVertex(tri.v.z);
    float b0 = 1.0 - b.x - b.y;
    vec2 uv0 = vec2(v0.normalU.w, v0.tangentV.w), uv1 = vec2(v1.normalU.w, v1.tangentV.w),
         uv2 = vec2(v2.normalU.w, v2.tangentV.w);
    SurfacePoint s;
    s.uv = b0 * uv0 + b.x * uv1 + b.y * uv2;
    vec3 e1 = tri.p1.xyz - tri.p0.xyz, e2 = tri.p2.xyz - tri.p0.xyz;
    vec2 d1 = uv1 - uv0, d2 = uv2 - uv0;
    float det = d1.x * d2.y - d1.y * d2.x;
    vec3 dpdu, dpdv;
    if (abs(det) > 1e-12) {
        dpdu = (d2.y * e1 - d1.y * e2) / det;
        dpdv = (-d2.x * e1 + d1.x * e2) / det;
    } else {  // no usable UVs: any frame around the normal
        vec3 n = normalizeScaled(cross(e1, e2));
        buildOnb(n, dpdu, dpdv);
    }
    vec3 t = b0 * v0.tangentV.xyz + b.x * v1.tangentV.xyz + b.y * v2.tangentV.xyz;
    if (dot(t, t) > 0.0) dpdu = t * length(dpdu);
    s.dpdu = instanceDirectionToWorld(inst, dpdu);
    s.dpdv = instanceDirectionToWorld(inst, dpdv);
    s.uvPerLength = inversesqrt(max(length(s.dpdu) * length(s.dpdv), 1e-30));
    return s;
}

#endif
