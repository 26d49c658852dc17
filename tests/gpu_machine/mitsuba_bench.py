"""Mitsuba 3's samples/s on caustic's benchmark scenes (a benchmark, never a test).

Renders the same scene as caustic-bench does, with Mitsuba 3's `path` integrator, and prints one
row per scene in caustic-bench's units, to put both renderers' figures from one run side by side
(tests/gpu_machine/interleave.sh alternates them on the development machine; run.sh runs it on
the GPU machine with the cuda_ad_rgb variant).

  mitsuba_bench.py [--variant llvm_ad_rgb] [--size 256] [--spp 64] [--max-depth 7] [--repeat 3]
                   [--mode sum|median] [scene ...]

Scenes: `cornell` (Mitsuba's cornell_box(), the same box as scenes/cornell-box.json) and
`mesh-knot` (scenes/mesh-knot.json translated: the two 12 000-triangle knots as OBJ meshes, the
ground quad, Lambert and rough GGX gold, the HDR sky; Mitsuba loads the OBJ into its own mesh).
--max-depth is caustic's (scattering events); Mitsuba's max_depth is one more (it counts the
camera ray's vertex), as in tests/variance. Timing: one warm-up render (kernel compilation),
then --repeat renders of --spp samples each, each timed from the call to mi.render to
dr.sync_thread() after it (the GPU's work finished); the median is reported.
"""
import argparse
import json
import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

# Gold's complex IOR at R, G, B: caustic's "gold" preset (as tests/variance/scenes.py has it).
GOLD = ((0.183, 0.421, 1.373), (3.424, 2.346, 1.770))


def trs(mi, t):
    """caustic's M = T * Rz * Ry * Rx * S (docs/scene-format.md, Transforms) as a Mitsuba transform."""
    T = mi.ScalarTransform4f
    tr = t.get("translate", [0, 0, 0])
    ro = t.get("rotate", [0, 0, 0])
    sc = t.get("scale", 1.0)
    sc = [sc] * 3 if isinstance(sc, (int, float)) else sc
    m = T().translate(tr)
    m = m @ T().rotate([0, 0, 1], ro[2]) @ T().rotate([0, 1, 0], ro[1]) @ T().rotate([1, 0, 0], ro[0])
    return m @ T().scale(sc)


def rgb(v):
    return {"type": "rgb", "value": [float(x) for x in v]}


def from_caustic(mi, path, size, spp, max_depth):
    """The subset of caustic's scene format the mesh benchmark scene uses, as a Mitsuba dict."""
    with open(path) as f:
        s = json.load(f)
    base = os.path.dirname(path)
    T = mi.ScalarTransform4f
    cam = s["camera"]
    if cam.get("fov_axis", "x") != "x":
        sys.exit("%s: camera.fov_axis %r: only 'x' is translated" % (path, cam.get("fov_axis")))
    film = {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": "box"}, "pixel_format": "rgb"}
    d = {"type": "scene", "integrator": {"type": "path", "max_depth": max_depth + 1},
         "sensor": {"type": "perspective", "fov": cam["fov"], "fov_axis": "x",
                    "to_world": T.look_at(origin=cam["position"], target=cam["look_at"], up=cam.get("up", [0, 1, 0])),
                    "film": film, "sampler": {"type": "independent", "sample_count": spp}}}
    mats = {}
    for m in s["materials"]:
        if m["type"] == "diffuse":
            mats[m["name"]] = {"type": "diffuse", "reflectance": rgb(m["albedo"])}
        elif m["type"] == "conductor" and m.get("metal") == "gold":
            mats[m["name"]] = {"type": "roughconductor", "distribution": "ggx", "alpha": m.get("roughness", 0.0),
                               "eta": rgb(GOLD[0]), "k": rgb(GOLD[1])}
        else:
            sys.exit("%s: material %r of type %r is not translated" % (path, m["name"], m["type"]))
    for i, o in enumerate(s["objects"]):
        shape = {"quad": "rectangle", "sphere": "sphere", "mesh": "obj"}.get(o["shape"])
        if shape is None:
            sys.exit("%s: objects[%d]: shape %r is not translated" % (path, i, o["shape"]))
        e = {"type": shape, "to_world": trs(mi, o.get("transform", {})), "bsdf": mats[o["material"]]}
        if shape == "obj":
            e["filename"] = os.path.normpath(os.path.join(base, o["file"]))
        d["obj%d" % i] = e
    env = s.get("environment")
    if env and env["type"] == "map":
        # Mitsuba's equirectangular mapping is caustic's turned by 180 degrees about +y
        # (tests/variance/scenes.py).
        d["env"] = {"type": "envmap", "filename": os.path.normpath(os.path.join(base, env["file"])),
                    "scale": env.get("intensity", 1.0), "to_world": T().rotate([0, 1, 0], 180)}
    elif env:
        sys.exit("%s: environment %r is not translated" % (path, env["type"]))
    return d


def scene_dict(mi, name, size, spp, max_depth):
    if name == "cornell":
        d = mi.cornell_box()
        d["sensor"]["film"].update({"width": size, "height": size, "rfilter": {"type": "box"}})
        d["sensor"]["sampler"] = {"type": "independent", "sample_count": spp}
        d["integrator"] = {"type": "path", "max_depth": max_depth + 1}
        return d
    if name == "mesh-knot":
        return from_caustic(mi, os.path.join(ROOT, "scenes", "mesh-knot.json"), size, spp, max_depth)
    sys.exit("mitsuba_bench.py: unknown scene %r (cornell, mesh-knot)" % name)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--max-depth", type=int, default=7, help="caustic's max depth (Mitsuba's is one more)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default="", help="also write each render's mean radiance here (JSON)")
    ap.add_argument("scenes", nargs="*", default=["cornell", "mesh-knot"])
    args = ap.parse_args()
    import drjit as dr
    import mitsuba as mi
    mi.set_variant(args.variant)
    means = {}
    for name in args.scenes:
        scene = mi.load_dict(scene_dict(mi, name, args.size, args.spp, args.max_depth))
        img = mi.render(scene, spp=args.spp, seed=0)  # warm-up: kernel compilation, Embree/OptiX build
        dr.sync_thread()
        times = []
        for r in range(args.repeat):
            t0 = time.perf_counter()
            img = mi.render(scene, spp=args.spp, seed=r + 1)
            dr.eval(img)
            dr.sync_thread()
            times.append(time.perf_counter() - t0)
        times.sort()
        w = times[len(times) // 2]
        samples = args.spp * args.size * args.size
        import numpy as np
        means[name] = float(np.mean(np.array(img)[..., :3]))
        print("mitsuba %-16s %-12s %4dx%-5d %6d %5d %9.3f %12.3f" % (name, args.variant, args.size, args.size, args.spp,
                                                                      args.max_depth, w, samples / w * 1e-6), flush=True)
    if args.out:
        with open(args.out, "w") as f:
            json.dump(means, f)


if __name__ == "__main__":
    main()
