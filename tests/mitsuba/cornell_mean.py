"""The image mean of Mitsuba 3's own cornell_box() scene, for tests/data/cornell-box-128-reference.json.

Mitsuba's scene as its mi.cornell_box() returns it, with three changes that make it the integral
caustic computes for scenes/cornell-box.json (tests/gpu/test_cornell_reference.cpp):
  - the film is 128 x 128 with a box pixel filter (cornell_box() uses a Gaussian; the image mean
    is the same for any normalised filter up to the border, the box makes it exact);
  - the path integrator's max_depth is caustic's max_depth + 1 (Mitsuba counts the camera ray's
    segment as a bounce: its max_depth 1 is emission seen directly, caustic's 0);
  - nothing else: Russian roulette changes the noise, not the mean.
The mean over all pixels and channels of several independent renders (different seeds) is
printed with its standard error (the spread of the renders' means over sqrt(renders)).

Run with the venv tests/variance/run.sh makes (Mitsuba 3 and the LLVM variant):
    .deps/bench-venv/bin/python tests/mitsuba/cornell_mean.py [--depth 10] [--spp 1024] [--renders 8]
"""
import argparse
import json
import math
import time

import mitsuba as mi
import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--depth", type=int, default=10, help="caustic's max_depth (Mitsuba's is one more)")
    ap.add_argument("--spp", type=int, default=1024, help="samples per pixel per render")
    ap.add_argument("--renders", type=int, default=8, help="independent renders (seeds 0, 1, ...)")
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    args = ap.parse_args()
    mi.set_variant(args.variant)
    desc = mi.cornell_box()
    desc["integrator"]["max_depth"] = args.depth + 1
    film = desc["sensor"]["film"]
    film["width"] = film["height"] = args.size
    film["rfilter"] = {"type": "box"}
    desc["sensor"]["sampler"] = {"type": "independent", "sample_count": args.spp}
    scene = mi.load_dict(desc)
    means = []
    t0 = time.time()
    for seed in range(args.renders):
        img = mi.TensorXf(mi.render(scene, spp=args.spp, seed=seed))
        a = np.array(img)[:, :, :3]
        means.append(a.reshape(-1, 3).mean(axis=0).tolist())
    n = len(means)
    mean = [sum(m[c] for m in means) / n for c in range(3)]
    se = [math.sqrt(sum((m[c] - mean[c]) ** 2 for m in means) / (n - 1) / n) for c in range(3)]
    print(json.dumps({
        "mean": [round(v, 9) for v in mean],
        "standard_error": [float("%.3g" % v) for v in se],
        "caustic_max_depth": args.depth, "mitsuba_max_depth": args.depth + 1,
        "size": args.size, "spp_per_render": args.spp, "renders": n,
        "mitsuba": mi.__version__, "variant": args.variant, "seconds": round(time.time() - t0, 1),
    }, indent=2))


if __name__ == "__main__":
    main()
