#!/usr/bin/env python3
"""Writes copies of shaders/ with one cost removed each, for profiling the integrator on the GPU
machine (tests/gpu_machine/run.sh variants): each variant is rendered by caustic-bench with
CAUSTIC_SHADER_DIR pointing at it, so the difference in samples/s is what that part costs.
Variants change the image (they are not correct renderers); they exist only for measurement.

    shader_variants.py OUT_DIR
"""
import os
import shutil
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shaders")

LAMBERT_SAMPLE = ("BsdfSample s;\n    s.wi = lambertSample(wo, u.xy); s.pdf = lambertPdf(wo, s.wi);"
                  " s.f = lambertEval(m.albedo.rgb, wo, s.wi); s.flags = 0u; return s;")

# name -> [(file, old, new)]
PATCHES = {
    "no-nee": [("integrator/path.glsl", "bool useLights = strategy != STRATEGY_BSDF_ONLY && frame.counts.y > 0u;",
                "bool useLights = false;")],
    "lambert-only": [
        ("bsdf/bsdf.glsl", "vec3 bsdfEval(GpuMaterial m, vec3 wo, vec3 wi) {",
         "vec3 bsdfEval(GpuMaterial m, vec3 wo, vec3 wi) {\n    return lambertEval(m.albedo.rgb, wo, wi);"),
        ("bsdf/bsdf.glsl", "float bsdfPdf(GpuMaterial m, vec3 wo, vec3 wi) {",
         "float bsdfPdf(GpuMaterial m, vec3 wo, vec3 wi) {\n    return lambertPdf(wo, wi);"),
        ("bsdf/bsdf.glsl", "BsdfSample s = bsdfInvalidSample();", LAMBERT_SAMPLE + "\n    s = bsdfInvalidSample();"),
    ],
    "no-textures": [
        ("bsdf/material.glsl", "    normalTexel = vec3(0.0, 0.0, 1.0);\n", "    normalTexel = vec3(0.0, 0.0, 1.0);\n    return m;\n"),
        ("bsdf/material.glsl", "vec3 shadingNormalAt(GpuMaterial m, SurfacePoint s, vec3 ng, vec3 normalTexel) {",
         "vec3 shadingNormalAt(GpuMaterial m, SurfacePoint s, vec3 ng, vec3 normalTexel) {\n    return ng;"),
    ],
    "no-aov-images": [
        ("integrator/film.glsl", "px.albedo = imageLoad(albedoImage, ip);", "px.albedo = vec4(0.0);"),
        ("integrator/film.glsl", "px.normal = imageLoad(normalImage, ip);", "px.normal = vec4(0.0);"),
        ("integrator/film.glsl", "imageStore(albedoImage, ip, px.albedo);", ""),
        ("integrator/film.glsl", "imageStore(normalImage, ip, px.normal);", ""),
    ],
    # The texture slots' loop kept a loop (a bound the compiler cannot see: frame.geometry.z is 0).
    "texture-loop-not-unrolled": [("bsdf/material.glsl", "for (uint slot = 0u; slot < 3u; ++slot) {",
                                   "for (uint slot = 0u; slot < 3u + frame.geometry.z; ++slot) {")],
    # One bilinear lookup instead of two blended (no trilinear).
    "texture-bilinear-only": [("bsdf/texture.glsl", "    vec4 a = textureBilinear(textureLevel(t, l0), uv);\n",
                               "    vec4 a = textureBilinear(textureLevel(t, l0), uv);\n    return a;\n")],
    "small-stack": [("geometry/bvh.glsl", "#else\nconst int BVH_STACK_SIZE = 76;\n", "#else\nconst int BVH_STACK_SIZE = 40;\n")],
}
PATCHES["all-of-them"] = [p for name in ["no-nee", "lambert-only", "no-textures", "no-aov-images", "small-stack"]
                          for p in PATCHES[name]]


def main():
    out = sys.argv[1]
    shutil.rmtree(out, ignore_errors=True)
    for name, patches in [("base", [])] + list(PATCHES.items()):
        target = os.path.join(out, name)
        shutil.copytree(ROOT, target)
        for rel, old, new in patches:
            path = os.path.join(target, rel)
            with open(path) as f:
                text = f.read()
            if old not in text:
                sys.exit(f"shader_variants.py: {name}: '{old[:40]}...' not found in {rel}")
            with open(path, "w") as f:
                f.write(text.replace(old, new, 1))
    print(out)


if __name__ == "__main__":
    main()
