#!/usr/bin/env python3
"""caustic's participating media against Mitsuba 3.9.1's `volpath` (a comparison and a figure maker,
not a ctest: it needs Mitsuba, see tests/variance/run.sh for the venv and Debian's libllvm19).

Four scenes written for both (box filter, caustic max_depth N = Mitsuba N + 1, 96 x 96):
  absorbing-glass  a smooth glass sphere (ior 1.5) whose interior only absorbs, under a constant sky
  volume-sphere    a chromatic, forward-scattering (g 0.5) medium behind an index-matched boundary
                   (caustic `volume`, Mitsuba `null` BSDF + interior), sky 0.3 and a rectangle light
  milky-glass      a glass sphere (ior 1.5) with a scattering, back-scattering (g -0.3) interior,
                   sky 0.3 and the rectangle light
  subsurface       the surface material's subsurface (a random walk, smooth interface of ior 1.4, colour
                   [0.8, 0.5, 0.25], mean free path 0.1 x [1, 0.6, 0.3], g 0.2) against Mitsuba's dielectric
                   with the interior the mapping gives (van de Hulst's relation inverted, written here
                   again), no depth limit in Mitsuba (the walk has none in caustic), sky 0.3 and the light;
                   Mitsuba's `volpathmis` (spectral MIS, as caustic's free flight): its `volpath` samples
                   one channel's extinction for all three, whose weights have a heavy tail in a medium
                   this chromatic (it reads 2-5 % low at 512 spp)
  fog-spot         the scene's fog (camera inside; Mitsuba: the sensor's medium and every shape's
                   exterior) lit by a spot light (linear-in-angle falloff, Mitsuba's) over a floor
                   with a sphere on it
Each renderer renders each scene with 4 seeds. Prints per scene both image means (R, G, B) and their
ratio, and how many of the 12 x 12 blocks of 8 x 8 pixels differ by more than 4 combined standard
errors (each block's error from its spread over the seeds); fails (exit 1) when a mean differs by
more than --tolerance (default 1 %) or more than 3 % of the blocks (of 432 block-channel pairs per
scene; a t statistic with 3 + 3 degrees of freedom exceeds 4 about 1 % of the time). Writes
docs/figures/media-mitsuba.png (a row per scene: caustic, Mitsuba, |difference| x 4).

Usage: <venv>/bin/python tests/mitsuba/media_scenes.py [--spp N] [--only NAME] [--caustic BIN]
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
W = H = 96
SEEDS = 4
BLOCK = 8
MAX_DEPTH = 64  # caustic's; Mitsuba's is one more


def mi_rgb(v):
    return {"type": "rgb", "value": list(v)}


def mi_medium(sigma_a, sigma_s, g):
    """A Mitsuba homogeneous medium from per-channel coefficients: sigma_t = sigma_a + sigma_s given as a
    reflectance times `scale` (Mitsuba reads an rgb sigma_t as a colour in [0, 1]), albedo sigma_s / sigma_t."""
    st = [a + s for a, s in zip(sigma_a, sigma_s)]
    scale = max(st)
    return {"type": "homogeneous", "sigma_t": mi_rgb([x / scale for x in st]), "scale": scale,
            "albedo": mi_rgb([s / t if t > 0 else 0.0 for s, t in zip(sigma_s, st)]),
            "phase": {"type": "hg", "g": g}}


def mi_camera(cam, medium=None):
    c = {"type": "perspective", "fov": cam["fov"], "fov_axis": "x",
         "to_world": mi.ScalarTransform4f().look_at(origin=cam["position"], target=cam["look_at"], up=[0, 1, 0]),
         "film": {"type": "hdrfilm", "width": W, "height": H, "rfilter": {"type": "box"}},
         "sampler": {"type": "independent", "sample_count": 1}}
    if medium:
        c["medium"] = {"type": "ref", "id": medium}
    return c


CAM = {"position": [0, 0.3, 4.5], "look_at": [0, 0, 0], "fov": 40, "fov_axis": "x"}
# A rectangle light 2.5 above, facing down: caustic's canonical quad faces +z, Mitsuba's rectangle too.
LIGHT_Y = 2.5
LIGHT_SCALE = 0.5
LIGHT_RADIANCE = [12.0, 11.0, 9.0]


def caustic_light():
    return {"name": "light", "shape": "quad", "material": "black", "emission": LIGHT_RADIANCE,
            "transform": {"translate": [0, LIGHT_Y, 0], "rotate": [90, 0, 0], "scale": [LIGHT_SCALE, LIGHT_SCALE, 1]}}


def mi_light():
    return {"type": "rectangle",
            "to_world": mi.ScalarTransform4f().translate([0, LIGHT_Y, 0]) @ mi.ScalarTransform4f().rotate([1, 0, 0], 90)
            @ mi.ScalarTransform4f().scale([LIGHT_SCALE, LIGHT_SCALE, 1]),
            "bsdf": {"type": "diffuse", "reflectance": mi_rgb([0, 0, 0])},
            "emitter": {"type": "area", "radiance": mi_rgb(LIGHT_RADIANCE)}}


def scene_absorbing_glass():
    colour, depth = [0.8, 0.45, 0.1], 1.0
    c = {"camera": CAM, "materials": [{"name": "amber", "type": "dielectric", "ior": 1.5, "transmission_color": colour,
                                      "transmission_depth": depth}],
         "objects": [{"name": "ball", "shape": "sphere", "material": "amber"}],
         "environment": {"type": "constant", "radiance": [1, 1, 1]}}
    sigma = [-math.log(x) / depth for x in colour]
    m = {"env": {"type": "constant", "radiance": mi_rgb([1, 1, 1])},
         "ball": {"type": "sphere", "bsdf": {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0},
                  "interior": mi_medium(sigma, [0, 0, 0], 0.0)}}
    return c, m


VOL_A, VOL_S = [0.1, 0.3, 0.6], [2.0, 1.2, 0.5]


def scene_volume_sphere():
    c = {"camera": CAM,
         "materials": [{"name": "smoke", "type": "volume", "sigma_a": VOL_A, "sigma_s": VOL_S, "anisotropy": 0.5},
                       {"name": "black", "type": "diffuse", "albedo": [0, 0, 0]}],
         "objects": [{"name": "ball", "shape": "sphere", "material": "smoke"}, caustic_light()],
         "environment": {"type": "constant", "radiance": [0.3, 0.3, 0.3]}}
    m = {"env": {"type": "constant", "radiance": mi_rgb([0.3, 0.3, 0.3])}, "light": mi_light(),
         "ball": {"type": "sphere", "bsdf": {"type": "null"}, "interior": mi_medium(VOL_A, VOL_S, 0.5)}}
    return c, m


def scene_milky_glass():
    # OpenPBR's parameters for caustic (depth 1: sigma_s = scatter, sigma_t = -ln(colour)); the same
    # coefficients for Mitsuba.
    scatter, colour = [0.9, 0.7, 0.5], [0.25, 0.3, 0.35]
    st = [-math.log(x) for x in colour]
    sa = [t - s for t, s in zip(st, scatter)]
    assert min(sa) >= 0
    c = {"camera": CAM,
         "materials": [{"name": "milk", "type": "dielectric", "ior": 1.5, "transmission_color": colour,
                        "transmission_depth": 1.0, "transmission_scatter": scatter,
                        "transmission_scatter_anisotropy": -0.3},
                       {"name": "black", "type": "diffuse", "albedo": [0, 0, 0]}],
         "objects": [{"name": "ball", "shape": "sphere", "material": "milk"}, caustic_light()],
         "environment": {"type": "constant", "radiance": [0.3, 0.3, 0.3]}}
    m = {"env": {"type": "constant", "radiance": mi_rgb([0.3, 0.3, 0.3])}, "light": mi_light(),
         "ball": {"type": "sphere", "bsdf": {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0},
                  "interior": mi_medium(sa, scatter, -0.3)}}
    return c, m


def single_scattering_albedo(colour, g):
    """van de Hulst's relation A = (1 - s)(1 - 0.139 s) / (1 + 1.17 s), s = sqrt((1 - a) / (1 - a g)),
    solved for the single-scattering albedo a (docs/materials.md, "Transmission and subsurface")."""
    b = 1.139 + 1.17 * colour
    s = (b - math.sqrt(b * b - 4 * 0.139 * (1 - colour))) / (2 * 0.139)
    return (1 - s * s) / (1 - s * s * g)


def scene_subsurface():
    colour, radius, scale, g = [0.8, 0.5, 0.25], 0.1, [1.0, 0.6, 0.3], 0.2
    c = {"camera": CAM,
         "materials": [{"name": "sss", "type": "surface", "base_color": colour, "specular_roughness": 0,
                        "specular_ior": 1.4, "subsurface_weight": 1, "subsurface_color": colour,
                        "subsurface_radius": radius, "subsurface_radius_scale": scale,
                        "subsurface_scatter_anisotropy": g},
                       {"name": "black", "type": "diffuse", "albedo": [0, 0, 0]}],
         "objects": [{"name": "ball", "shape": "sphere", "material": "sss"}, caustic_light()],
         "environment": {"type": "constant", "radiance": [0.3, 0.3, 0.3]}}
    st = [1 / (radius * k) for k in scale]
    alb = [single_scattering_albedo(x, g) for x in colour]
    m = {"env": {"type": "constant", "radiance": mi_rgb([0.3, 0.3, 0.3])}, "light": mi_light(),
         "ball": {"type": "sphere", "bsdf": {"type": "dielectric", "int_ior": 1.4, "ext_ior": 1.0},
                  "interior": mi_medium([t * (1 - a) for t, a in zip(st, alb)], [t * a for t, a in zip(st, alb)], g)}}
    return c, m, None, -1, "volpathmis"


FOG_A, FOG_S = [0.01, 0.012, 0.015], [0.12, 0.13, 0.15]


def scene_fog_spot():
    spot_pos, spot_target = [1.5, 3.0, 1.0], [0.0, -1.0, 0.0]
    c = {"camera": CAM,
         "materials": [{"name": "grey", "type": "diffuse", "albedo": [0.6, 0.6, 0.6]},
                       {"name": "orange", "type": "diffuse", "albedo": [0.8, 0.4, 0.1]}],
         "objects": [{"name": "floor", "shape": "quad", "material": "grey",
                      "transform": {"translate": [0, -1, 0], "rotate": [-90, 0, 0], "scale": [4, 4, 1]}},
                     {"name": "ball", "shape": "sphere", "material": "orange",
                      "transform": {"translate": [-0.4, -0.5, 0], "scale": 0.5}}],
         "lights": [{"name": "spot", "type": "spot", "color": [40, 36, 30], "position": spot_pos,
                     "direction": [t - p for t, p in zip(spot_target, spot_pos)], "inner_angle": 12,
                     "outer_angle": 22, "falloff": "linear_angle"}],
         "environment": {"type": "none", "medium_sigma_a": FOG_A, "medium_sigma_s": FOG_S, "medium_anisotropy": 0.4}}
    fog = {"type": "ref", "id": "fog"}
    m = {"fog": mi_medium(FOG_A, FOG_S, 0.4),
         "floor": {"type": "rectangle", "to_world": mi.ScalarTransform4f().translate([0, -1, 0]) @
                   mi.ScalarTransform4f().rotate([1, 0, 0], -90) @ mi.ScalarTransform4f().scale([4, 4, 1]),
                   "bsdf": {"type": "diffuse", "reflectance": mi_rgb([0.6, 0.6, 0.6])}, "exterior": fog},
         "ball": {"type": "sphere", "center": [-0.4, -0.5, 0], "radius": 0.5,
                  "bsdf": {"type": "diffuse", "reflectance": mi_rgb([0.8, 0.4, 0.1])}, "exterior": fog},
         "spot": {"type": "spot", "intensity": mi_rgb([40, 36, 30]), "cutoff_angle": 22, "beam_width": 12,
                  "to_world": mi.ScalarTransform4f().look_at(origin=spot_pos, target=spot_target, up=[0, 0, 1])}}
    return c, m, "fog"


SCENES = {"absorbing-glass": scene_absorbing_glass, "volume-sphere": scene_volume_sphere,
          "milky-glass": scene_milky_glass, "subsurface": scene_subsurface, "fog-spot": scene_fog_spot}


CAUSTIC = os.path.join(ROOT, "build", "caustic")


def render_caustic(name, c, spp, seed, out_dir):
    scene = dict(c)
    scene["version"] = 1
    scene["render"] = {"width": W, "height": H, "samples": spp, "max_depth": MAX_DEPTH, "seed": seed}
    scene["camera"] = dict(c["camera"])
    path = os.path.join(out_dir, f"{name}-{seed}.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    subprocess.run([CAUSTIC, "--scene", path, "--exr", "--output", out_dir], check=True, stdout=subprocess.DEVNULL)
    return np.array(mi.Bitmap(os.path.join(out_dir, f"{name}-{seed}.exr")).convert(
        mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False))


def render_mitsuba(m, medium, spp, seed, max_depth=MAX_DEPTH + 1, integrator="volpath"):
    scene = {"type": "scene", "integrator": {"type": integrator, "max_depth": max_depth},
             "sensor": mi_camera(CAM, medium)}
    scene.update(m)
    return np.array(mi.render(mi.load_dict(scene), seed=seed, spp=spp))


def blocks(img):
    return img.reshape(H // BLOCK, BLOCK, W // BLOCK, BLOCK, 3).mean(axis=(1, 3))


def main():
    global CAUSTIC
    parser = argparse.ArgumentParser()
    parser.add_argument("--spp", type=int, default=512)
    parser.add_argument("--tolerance", type=float, default=0.01)
    parser.add_argument("--only", default=None)
    parser.add_argument("--caustic", default=CAUSTIC, help="the caustic binary (default: build/caustic)")
    args = parser.parse_args()
    CAUSTIC = args.caustic
    mi.set_variant("llvm_ad_rgb")
    ok = True
    rows = []
    print(f"{'scene':16s} {'caustic mean (R, G, B)':>26s} {'Mitsuba mean':>26s} {'ratio':>26s} {'blocks > 4 se':>14s}")
    with tempfile.TemporaryDirectory() as tmp:
        for name, make in SCENES.items():
            if args.only and name != args.only:
                continue
            made = make()
            c, m = made[0], made[1]
            medium = made[2] if len(made) > 2 else None
            depth = made[3] if len(made) > 3 else MAX_DEPTH + 1
            integrator = made[4] if len(made) > 4 else "volpath"
            a = np.stack([render_caustic(name, c, args.spp, s, tmp) for s in range(SEEDS)])
            b = np.stack([render_mitsuba(m, medium, args.spp, 1000 + s, depth, integrator) for s in range(SEEDS)])
            ma, mb = a.mean(axis=(0, 1, 2)), b.mean(axis=(0, 1, 2))
            ratio = ma / mb
            ba, bb = np.stack([blocks(x) for x in a]), np.stack([blocks(x) for x in b])
            diff = ba.mean(0) - bb.mean(0)
            se = np.sqrt(ba.var(0, ddof=1) / SEEDS + bb.var(0, ddof=1) / SEEDS)
            outliers = int(np.sum(np.abs(diff) > 4.0 * se + 1e-6))
            total = diff.size
            good = bool(np.all(np.abs(ratio - 1.0) <= args.tolerance)) and outliers <= 0.03 * total
            ok = ok and good
            print(f"{name:16s} {np.array2string(ma, precision=4):>26s} {np.array2string(mb, precision=4):>26s} "
                  f"{np.array2string(ratio, precision=4):>26s} {outliers:>6d} / {total:<4d} {'' if good else 'FAIL'}")
            ia, ib = a.mean(0), b.mean(0)
            rows.append(np.concatenate([ia, ib, np.abs(ia - ib) * 4.0], axis=1))
    if rows and not args.only:
        fig = np.concatenate(rows, axis=0)
        out = os.path.join(ROOT, "docs", "figures")
        os.makedirs(out, exist_ok=True)
        mi.Bitmap(np.clip(fig, 0, 1).astype(np.float32)).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8,
                                                                   srgb_gamma=True).write(
            os.path.join(out, "media-mitsuba.png"))
        print("wrote docs/figures/media-mitsuba.png")
    print("means within %.1f %% per channel and blocks within noise: %s" % (100 * args.tolerance, "yes" if ok else "NO"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
