// Ray-primitive intersection (spheres, quads) and the scene queries (closest hit with the
// surface attributes shading needs, any hit), through the two-level BVH of bvh.glsl.
#ifndef GEOMETRY_INTERSECT_GLSL
#define GEOMETRY_INTERSECT_GLSL
#include "../lib/math.glsl"
#include "../scene/buffers.glsl"
#include "surface.glsl"

struct Ray { vec3 o; vec3 d; };

// Rays traced by this invocation (closest-hit and any-hit queries), for the rays/s figure.
uint g_rayCount = 0u;

struct Hit {
    float t;
    vec3 p;        // world position
    vec3 ng;       // unit geometric normal (front side, not flipped towards the ray)
    vec3 ns;       // unit shading normal (interpolated for meshes), on the side of ng
    uint material;
    uint light;    // light index + 1, 0: not a light
    uint flags;    // PRIM_FLAG_*
    // What hitSurface needs to derive the texture attributes, only when a material has textures
    // (computing them at every hit cost the integrator a third of its speed on an H100).
    uint ref;      // the top-level entry (TraceHit::ref)
    uint triangle; // instances: the index into triangles[]
    vec2 bary;     // instances: the barycentrics (b1, b2)
};

// The unit sphere in object space; p.abc are the rows of the affine world-to-object matrix.
bool intersectSphere(GpuPrimitive s, Ray r, float tMax, out float tHit) {
    vec3 o = vec3(dot(s.a, vec4(r.o, 1.0)), dot(s.b, vec4(r.o, 1.0)), dot(s.c, vec4(r.o, 1.0)));
    vec3 d = vec3(dot(s.a.xyz, r.d), dot(s.b.xyz, r.d), dot(s.c.xyz, r.d));
    float a = dot(d, d);
    float b = dot(o, d);
    // c computed as |o|^2 - 1 loses precision far away; the closest-approach form below is the
    // "Ray Tracing Gems" ch. 7 (Haines et al. 2019) rearrangement: disc = r^2 - |o - (o.d)d/|d|^2|^2.
    vec3 perp = o - (b / a) * d;
    float disc = a * (1.0 - dot(perp, perp));
    if (disc < 0.0) return false;
    float c = dot(o, o) - 1.0;
    float q = -(b + (b >= 0.0 ? 1.0 : -1.0) * sqrt(disc));
    float t0 = c / q, t1 = q / a;
    if (t0 > t1) { float tmp = t0; t0 = t1; t1 = tmp; }
    if (t0 > 0.0 && t0 < tMax) { tHit = t0; return true; }
    if (t1 > 0.0 && t1 < tMax) { tHit = t1; return true; }
    return false;
}

vec3 sphereNormal(GpuPrimitive s, vec3 p) {
    vec3 po = vec3(dot(s.a, vec4(p, 1.0)), dot(s.b, vec4(p, 1.0)), dot(s.c, vec4(p, 1.0)));
    // Normals transform with the inverse transpose: (W2O)^T * n_object.
    return normalize(s.a.xyz * po.x + s.b.xyz * po.y + s.c.xyz * po.z);
}

// A quad in plane form (scene/buffers.glsl, primitiveHits): one division, no cross products.
bool intersectQuadPlane(GpuPrimitive q, Ray r, float tMax, out float tHit) {
    float denom = dot(q.a.xyz, r.d);
    if (abs(denom) < 1e-20) return false;
    float t = (q.a.w - dot(q.a.xyz, r.o)) / denom;
    if (!(t > 0.0 && t < tMax)) return false;
    vec3 p = r.o + t * r.d;
    float alpha = dot(q.b.xyz, p) - q.b.w;
    float beta = dot(q.c.xyz, p) - q.c.w;
    if (alpha < 0.0 || alpha > 1.0 || beta < 0.0 || beta > 1.0) return false;
    tHit = t;
    return true;
}

bool intersectQuad(GpuPrimitive q, Ray r, float tMax, out float tHit) {
    vec3 n = cross(q.b.xyz, q.c.xyz);
    float denom = dot(n, r.d);
    if (abs(denom) < 1e-20) return false;
    float t = dot(n, q.a.xyz - r.o) / denom;
    if (!(t > 0.0 && t < tMax)) return false;
    vec3 hp = r.o + t * r.d - q.a.xyz;
    vec3 w = n / dot(n, n);
    float alpha = dot(w, cross(hp, q.c.xyz));
    float beta = dot(w, cross(q.b.xyz, hp));
    if (alpha < 0.0 || alpha > 1.0 || beta < 0.0 || beta > 1.0) return false;
    tHit = t;
    return true;
}

// The shape tests a scene-specialised program keeps (scene/features.glsl): a scene of quads
// alone never runs the sphere test, and the other way round.
bool primitiveIsSphere(GpuPrimitive prim) {
    if (!HAS_SHAPE(PRIM_SPHERE)) return false;
    if (!HAS_SHAPE(PRIM_QUAD)) return true;
    return prim.info.x == PRIM_SPHERE;
}

bool intersectPrimitive(GpuPrimitive prim, Ray r, float tMax, out float t) {
    if (primitiveIsSphere(prim)) return intersectSphere(prim, r, tMax, t);
    return intersectQuad(prim, r, tMax, t);
}

// What the traversal calls: the primitive's hit record (quads in plane form).
bool intersectPrimitiveT(uint index, vec3 o, vec3 d, float tMax, out float t) {
    Ray r;
    r.o = o;
    r.d = d;
    GpuPrimitive rec = loadPrimitiveHit(index);
    if (primitiveIsSphere(rec)) return intersectSphere(rec, r, tMax, t);
    return intersectQuadPlane(rec, r, tMax, t);
}

#include "bvh.glsl"

// What shading needs of ray r's closest hit th (traceScene's record).
Hit hitAttributes(Ray r, TraceHit th) {
    Hit hit;
    hit.t = th.t;
    hit.p = r.o + th.t * r.d;
    if (!HAS_MESHES || (th.ref & TLAS_REF_INSTANCE) == 0u) {
        GpuPrimitive prim = loadPrimitive(th.ref);
        hit.ng = primitiveIsSphere(prim) ? sphereNormal(prim, hit.p) : normalizeScaled(cross(prim.b.xyz, prim.c.xyz));
        hit.ns = hit.ng;
        hit.material = prim.info.y;
        hit.light = prim.info.z;
        hit.flags = prim.info.w;
    } else {
        GpuInstance inst = loadInstance(th.ref & ~TLAS_REF_INSTANCE);
        GpuTriangle tri = loadTriangle(th.triangle);
        hit.ng = normalize(instanceNormalToWorld(inst, cross(tri.p1.xyz - tri.p0.xyz, tri.p2.xyz - tri.p0.xyz)));
        hit.material = triangleMaterial(inst, tri);
        hit.light = inst.light;
        hit.flags = inst.flags;
        hit.ns = triangleShadingNormal(inst, tri, th.bary, hit.ng);
    }
    hit.ref = th.ref;
    hit.triangle = th.triangle;
    hit.bary = th.bary;
    return hit;
}

// Closest hit with t in (0, tMax), with everything shading needs.
bool sceneIntersect(Ray r, float tMax, out Hit hit) {
    ++g_rayCount;
    TraceHit th;
    if (!traceScene(r.o, r.d, tMax, false, th)) return false;
    hit = hitAttributes(r, th);
    return true;
}

// Texture coordinates and tangents at a hit (for materials with textures).
SurfacePoint hitSurface(Hit hit) {
    if (!HAS_MESHES || (hit.ref & TLAS_REF_INSTANCE) == 0u) return primitiveSurface(loadPrimitive(hit.ref), hit.p);
    return triangleSurface(loadInstance(hit.ref & ~TLAS_REF_INSTANCE), loadTriangle(hit.triangle), hit.bary);
}

// Any hit with t in (0, tMax): shadow rays, early exit.
bool sceneOccluded(Ray r, float tMax) {
    ++g_rayCount;
    TraceHit th;
    return traceScene(r.o, r.d, tMax, true, th);
}

// Offsets a ray origin off the surface on the side of `dir`, so secondary rays do not re-hit their
// own surface. The error of a computed hit point grows with the magnitude of the numbers it was
// computed from, so the offset is relative to the hit's largest coordinate (about 840 to 1700
// float spacings of it), as in Waechter and Binder 2019, "A Fast and Robust Method for Avoiding
// Self-Intersection" (Ray Tracing Gems, ch. 6). Near the origin the hit's own magnitude says
// little (a point near 0 computed as o + t d carries the error of o and t d), so it needs a floor.
// Waechter and Binder switch to a fixed offset (1/65536) below 1/32, which assumes a scene of size
// about 1, as did the fixed floor used here before, which made a Cornell box scaled by 1e-4
// render 22% darker (its light sits 1e-6 below the ceiling). Here the
// floor is the scene's own scale (frame.rayOffset.x: its largest coordinate and the camera's, at
// most 1; renderer/gpu_scene.cpp, makeFrame), so scaling a whole scene scales its offsets and
// scenes of size 1 or more offset exactly as before.
vec3 offsetRayOrigin(vec3 p, vec3 ng, vec3 dir) {
    float eps = 1e-4 * max(frame.rayOffset.x, maxComponent(abs(p)));
    return p + (dot(ng, dir) >= 0.0 ? eps : -eps) * ng;
}

// The shadow ray between two surface points, each offset off its own surface, as a segment:
// d = target - origin unnormalised, so the segment ends at t = 1 whatever the offsets did to its
// length (a fixed fraction of the distance is not safe: the offsets can shorten a grazing segment
// by more than that and make the light occlude itself).
Ray segmentRay(vec3 p, vec3 ngP, vec3 q, vec3 ngQ) {
    Ray r;
    vec3 dir = q - p;
    r.o = offsetRayOrigin(p, ngP, dir);
    vec3 target = dot(ngQ, ngQ) > 0.0 ? offsetRayOrigin(q, ngQ, -dir) : q;
    r.d = target - r.o;
    return r;
}
#endif
