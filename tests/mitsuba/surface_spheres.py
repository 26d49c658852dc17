#!/usr/bin/env python3
"""caustic's layered `surface` material against Mitsuba 3.9.1 on a row of spheres (a benchmark and
a figure maker, not a ctest: it needs Mitsuba from .deps/bench-venv, see tests/variance/run.sh).

Four unit spheres under a constant white environment (radiance 1, no floor: each pixel is the
sphere's directional albedo at that point's view angle, times 1, plus the light that bounces off
the sphere, which is none for a convex object), box filter, caustic max_depth N = Mitsuba N + 1:
  1. diffuse base only (specular_weight 0)        vs `diffuse`: the same model
  2. metal, F82 tint white = Schlick, alpha 0.25  vs `principled` metallic 1: the same Fresnel,
                                                     Smith separable (Mitsuba) vs height-correlated
  3. plastic: GGX specular alpha 0.09 over Lambert vs `roughplastic` (GGX, nonlinear false):
                                                     a different layering by design
  4. diffuse + clear coat, coat alpha 0.01         vs `principled` clearcoat 1: Disney's GTR1 coat
                                                     at a quarter weight, by design different
Prints per sphere the mean of each renderer and the per-pixel relative RMS difference, and writes
docs/figures/surface-mitsuba.png (caustic top, Mitsuba middle, |difference| x 4 bottom).

Usage: .deps/bench-venv/bin/python tests/mitsuba/surface_spheres.py [--spp N]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import mitsuba as mi

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
W, H = 384, 96
XS = [-3.3, -1.1, 1.1, 3.3]
CAM = {"position": [0, 0, 12], "look_at": [0, 0, 0], "fov": 38, "fov_axis": "x"}

CAUSTIC = [
    {"name": "diffuse", "type": "surface", "base_color": [0.8, 0.4, 0.2], "specular_weight": 0},
    {"name": "metal", "type": "surface", "base_color": [0.9, 0.6, 0.3], "metalness": 1, "specular_roughness": 0.5},
    {"name": "plastic", "type": "surface", "base_color": [0.2, 0.3, 0.8], "specular_roughness": 0.3,
     "specular_ior": 1.5},
    {"name": "coat", "type": "surface", "base_color": [0.8, 0.1, 0.1], "specular_weight": 0, "coat_weight": 1,
     "coat_roughness": 0.1, "coat_ior": 1.5},
]
MITSUBA = [
    {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.8, 0.4, 0.2]}},
    {"type": "principled", "base_color": {"type": "rgb", "value": [0.9, 0.6, 0.3]}, "metallic": 1.0, "roughness": 0.5},
    {"type": "roughplastic", "distribution": "ggx", "alpha": 0.09, "int_ior": 1.5, "ext_ior": 1.0,
     "diffuse_reflectance": {"type": "rgb", "value": [0.2, 0.3, 0.8]}, "nonlinear": False},
    {"type": "principled", "base_color": {"type": "rgb", "value": [0.8, 0.1, 0.1]}, "metallic": 0.0,
     "specular": 0.0, "roughness": 1.0, "clearcoat": 1.0, "clearcoat_gloss": 0.909},
]


def render_caustic(spp, out_dir):
    scene = {
        "version": 1, "camera": CAM,
        "render": {"width": W, "height": H, "samples": spp, "max_depth": 15},
        "materials": CAUSTIC,
        "objects": [{"name": m["name"], "shape": "sphere", "material": m["name"],
                     "transform": {"translate": [x, 0, 0]}} for m, x in zip(CAUSTIC, XS)],
        "environment": {"type": "constant", "radiance": [1, 1, 1]},
    }
    path = os.path.join(out_dir, "surface-spheres.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    subprocess.run([os.path.join(ROOT, "build", "caustic"), "--scene", path, "--exr", "--output", out_dir], check=True,
                   stdout=subprocess.DEVNULL)
    return np.array(mi.Bitmap(os.path.join(out_dir, "surface-spheres.exr")).convert(
        mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False))


def render_mitsuba(spp):
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 16},
        "sensor": {"type": "perspective", "fov": CAM["fov"], "fov_axis": "x",
                   "to_world": mi.ScalarTransform4f().look_at(origin=CAM["position"], target=CAM["look_at"], up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": W, "height": H, "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent", "sample_count": spp}},
        "env": {"type": "constant", "radiance": {"type": "rgb", "value": 1.0}},
    }
    for i, (bsdf, x) in enumerate(zip(MITSUBA, XS)):
        scene[f"sphere{i}"] = {"type": "sphere", "center": [x, 0, 0], "radius": 1.0, "bsdf": bsdf}
    return np.array(mi.render(mi.load_dict(scene)))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--spp", type=int, default=256)
    args = parser.parse_args()
    mi.set_variant("llvm_ad_rgb")
    with tempfile.TemporaryDirectory() as tmp:
        a = render_caustic(args.spp, tmp)
    b = render_mitsuba(args.spp)
    # Pixel columns of each sphere: its centre's image x, +- its radius in pixels.
    half = np.tan(np.radians(CAM["fov"] / 2)) * CAM["position"][2]
    names = [m["name"] for m in CAUSTIC]
    print(f"{'sphere':10s} {'caustic mean (R, G, B)':>30s} {'Mitsuba mean':>30s} {'ratio':>8s} {'pixel rel. RMS':>14s}")
    for name, x in zip(names, XS):
        cx = (x / half * 0.5 + 0.5) * W
        r = W / (2 * half)
        cols = slice(int(cx - 0.75 * r), int(cx + 0.75 * r))
        rows = slice(int(H / 2 - 0.75 * r), int(H / 2 + 0.75 * r))
        pa, pb = a[rows, cols], b[rows, cols]
        ma, mb = pa.reshape(-1, 3).mean(0), pb.reshape(-1, 3).mean(0)
        rel = np.sqrt(np.mean((pa - pb) ** 2)) / max(1e-6, float(pb.mean()))
        print(f"{name:10s} {np.array2string(ma, precision=4):>30s} {np.array2string(mb, precision=4):>30s} "
              f"{float(ma.mean() / mb.mean()):8.4f} {rel:14.4f}")
    fig = np.concatenate([a, b, np.abs(a - b) * 4.0], axis=0)
    out = os.path.join(ROOT, "docs", "figures")
    os.makedirs(out, exist_ok=True)
    mi.Bitmap(np.clip(fig, 0, 1).astype(np.float32)).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8,
                                                               srgb_gamma=True).write(
        os.path.join(out, "surface-mitsuba.png"))
    print("wrote docs/figures/surface-mitsuba.png")


if __name__ == "__main__":
    sys.exit(main())
