#!/usr/bin/env python3
"""caustic's absorbing dielectrics (transmission_color / transmission_depth) against Mitsuba 3.9.1
(a comparison and a figure maker, not a ctest: it needs Mitsuba, see tests/variance/run.sh for the
venv and Debian's libllvm19).

Two unit spheres under a constant white environment (radiance 1; clear glass there would give
exactly 1 in every pixel, so what is not 1 is the absorption), box filter, caustic max_depth N =
Mitsuba N + 1:
  1. smooth glass, ior 1.5, amber (colour [0.8, 0.45, 0.1] at depth 1)
  2. rough glass (GGX alpha 0.2), ior 1.5, green bottle glass (colour [0.3, 0.7, 0.35] at depth 1)
Mitsuba: `dielectric` / `roughdielectric` (GGX) with an interior `homogeneous` medium of albedo 0
and sigma_t = -ln(colour) / depth per channel, integrator `volpath`.
Prints per sphere both means (R, G, B) and their ratio per channel, and fails (exit 1) when a
channel's means differ by more than --tolerance (relative, default 1 %). Writes
docs/figures/absorption-mitsuba.png (caustic top, Mitsuba middle, |difference| x 4 bottom).

Usage: <venv>/bin/python tests/mitsuba/absorption_spheres.py [--spp N]
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import mitsuba as mi

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
W, H = 256, 128
XS = [-1.15, 1.15]
CAM = {"position": [0, 0, 8], "look_at": [0, 0, 0], "fov": 36, "fov_axis": "x"}
MAX_DEPTH = 31  # caustic's; Mitsuba's is one more
SPHERES = [
    {"name": "amber", "colour": [0.8, 0.45, 0.1], "depth": 1.0, "alpha": 0.0},
    {"name": "green", "colour": [0.3, 0.7, 0.35], "depth": 1.0, "alpha": 0.2},
]


def render_caustic(spp, out_dir):
    mats = []
    for s in SPHERES:
        m = {"name": s["name"], "type": "dielectric", "ior": 1.5, "transmission_color": s["colour"],
             "transmission_depth": s["depth"]}
        if s["alpha"] > 0:
            m["roughness"] = s["alpha"]
        mats.append(m)
    scene = {
        "version": 1, "camera": CAM,
        "render": {"width": W, "height": H, "samples": spp, "max_depth": MAX_DEPTH},
        "materials": mats,
        "objects": [{"name": s["name"], "shape": "sphere", "material": s["name"],
                     "transform": {"translate": [x, 0, 0]}} for s, x in zip(SPHERES, XS)],
        "environment": {"type": "constant", "radiance": [1, 1, 1]},
    }
    path = os.path.join(out_dir, "absorption-spheres.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    subprocess.run([os.path.join(ROOT, "build", "caustic"), "--scene", path, "--exr", "--output", out_dir], check=True,
                   stdout=subprocess.DEVNULL)
    return np.array(mi.Bitmap(os.path.join(out_dir, "absorption-spheres.exr")).convert(
        mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False))


def render_mitsuba(spp):
    scene = {
        "type": "scene",
        "integrator": {"type": "volpath", "max_depth": MAX_DEPTH + 1},
        "sensor": {"type": "perspective", "fov": CAM["fov"], "fov_axis": "x",
                   "to_world": mi.ScalarTransform4f().look_at(origin=CAM["position"], target=CAM["look_at"], up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": W, "height": H, "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent", "sample_count": spp}},
        "env": {"type": "constant", "radiance": {"type": "rgb", "value": 1.0}},
    }
    for i, (s, x) in enumerate(zip(SPHERES, XS)):
        sigma = [-math.log(c) / s["depth"] for c in s["colour"]]
        scale = max(sigma)  # Mitsuba reads an rgb sigma_t as a reflectance in [0, 1]: times `scale`
        if s["alpha"] > 0:
            bsdf = {"type": "roughdielectric", "distribution": "ggx", "alpha": s["alpha"], "int_ior": 1.5, "ext_ior": 1.0}
        else:
            bsdf = {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0}
        scene[f"sphere{i}"] = {"type": "sphere", "center": [x, 0, 0], "radius": 1.0, "bsdf": bsdf,
                               "interior": {"type": "homogeneous", "albedo": {"type": "rgb", "value": 0.0},
                                            "sigma_t": {"type": "rgb", "value": [x / scale for x in sigma]},
                                            "scale": scale}}
    return np.array(mi.render(mi.load_dict(scene)))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--spp", type=int, default=256)
    parser.add_argument("--tolerance", type=float, default=0.01)
    args = parser.parse_args()
    mi.set_variant("llvm_ad_rgb")
    with tempfile.TemporaryDirectory() as tmp:
        a = render_caustic(args.spp, tmp)
    b = render_mitsuba(args.spp)
    half = math.tan(math.radians(CAM["fov"] / 2)) * CAM["position"][2]
    ok = True
    print(f"{'sphere':8s} {'caustic mean (R, G, B)':>28s} {'Mitsuba mean':>28s} {'ratio per channel':>28s}")
    for s, x in zip(SPHERES, XS):
        # The sphere's pixel square: its centre's image x, +- its radius in pixels (the corners
        # see the environment, 1 in both).
        cx = (x / half * 0.5 + 0.5) * W
        r = W / (2 * half)
        cols = slice(int(cx - r), int(cx + r))
        rows = slice(int(H / 2 - r), int(H / 2 + r))
        ma, mb = a[rows, cols].reshape(-1, 3).mean(0), b[rows, cols].reshape(-1, 3).mean(0)
        ratio = ma / mb
        ok = ok and bool(np.all(np.abs(ratio - 1.0) <= args.tolerance))
        print(f"{s['name']:8s} {np.array2string(ma, precision=4):>28s} {np.array2string(mb, precision=4):>28s} "
              f"{np.array2string(ratio, precision=4):>28s}")
    fig = np.concatenate([a, b, np.abs(a - b) * 4.0], axis=0)
    out = os.path.join(ROOT, "docs", "figures")
    os.makedirs(out, exist_ok=True)
    mi.Bitmap(np.clip(fig, 0, 1).astype(np.float32)).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8,
                                                               srgb_gamma=True).write(
        os.path.join(out, "absorption-mitsuba.png"))
    print("wrote docs/figures/absorption-mitsuba.png")
    print("within %.1f %% per channel: %s" % (100 * args.tolerance, "yes" if ok else "NO"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
