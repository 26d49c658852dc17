#version 450 core
// Test kernel for material textures and surface attributes (bsdf/material.glsl, the same file the
// integrator includes).
//   u_mode 0: results[i] = textureSampleLod(u_texture, u_uv[i], u_lod) for the uv in inputs[i].xy.
//   u_mode 1: for primitive u_prim and the world point inputs[i].xyz on it: results[i] =
//             (shading normal of material u_material there, uv.x); the geometric normal is in
//             inputs[i].w's sign convention: the front normal computed here.
#include "bsdf/material.glsl"
#include "geometry/intersect.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = BINDING_TEST_OUTPUT) buffer Results { vec4 results[]; };
layout(std430, binding = 12) readonly buffer Inputs { vec4 inputs[]; };
uniform uint u_mode;
uniform uint u_count;
uniform uint u_texture;
uniform float u_lod;
uniform uint u_prim;
uniform uint u_material;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    if (u_mode == 0u) {
        results[i] = textureSampleLod(u_texture, inputs[i].xy, u_lod);
    } else {
        GpuPrimitive prim = primitives[u_prim];
        vec3 p = inputs[i].xyz;
        vec3 ng = prim.info.x == PRIM_SPHERE ? sphereNormal(prim, p) : normalize(cross(prim.b.xyz, prim.c.xyz));
        SurfacePoint sp = primitiveSurface(prim, p);
        vec3 normalTexel;
        GpuMaterial m = materialAtSurface(materials[u_material], sp, 0.0, normalTexel);
        vec3 ns = shadingNormalAt(m, sp, ng, normalTexel);
        results[2u * i] = vec4(ns, sp.uv.x);
        results[2u * i + 1u] = vec4(ng, sp.uv.y);
    }
}
