#!/usr/bin/env python3
"""The variance benchmark (a benchmark, never a test): how much noise each sample carries.

For every scene of the suite (scenes.py) and every configuration, renders K independent images
(seeds 1..K) of N samples per pixel and reports, against a converged reference:
  var/spp  the mean over pixels and channels of the per-pixel variance of one image times N: the
           variance one sample contributes, were samples independent (for a quasi-Monte Carlo
           sampler it is the variance of the N-sample estimate times N, so it falls with N);
  relMSE   the mean over the K images of mean((img - ref)^2 / (ref^2 + 0.01)) (the usual
           relative MSE with a small epsilon against dark pixels);
  time     seconds per image (caustic: the render time its summary prints, without start-up and
           shader compilation; Mitsuba: mi.render after a warm-up render, the seed passed as an
           opaque value so no kernel is compiled again);
  eff      relMSE x time (lower is better): equal-time quality, since for unbiased estimators
           relMSE falls as 1/time.
The caustic configurations: "default" (Sobol sampler, light tree, the default Russian roulette),
"indep" (the independent sampler, otherwise default), "uniform" (uniform light selection,
otherwise default), "power" (power selection), "nosplit" (no glass splitting), and, with --rr, every Russian roulette rule.
Mitsuba 3 (llvm_ad_rgb, its path integrator and independent sampler) renders the same scenes.
The reference is caustic's default configuration at --ref-spp samples per pixel (kept in --out).

Usage: tests/variance/run.sh [--spp 16] [--k 8] [--ref-spp 1024] [--scenes a,b] [--rr] [--no-mitsuba]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scenes as suite_mod  # noqa: E402

ROOT = suite_mod.ROOT


def read_exr(mi, path):
    return np.array(mi.Bitmap(path), dtype=np.float64)[..., :3]


def caustic_images(exe, scene_file, spp, seeds, sets, outdir, mi):
    """Renders one image per seed in one process (--sweep); returns (images, seconds per image)."""
    cmd = [exe, "--scene", scene_file, "--samples", str(spp), "--exr", "--output", outdir,
           "--sweep", "render.seed=" + ",".join(str(s) for s in seeds)]
    for s in sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError("caustic failed: %s\n%s" % (" ".join(cmd), r.stderr))
    times = [float(t) for t in re.findall(r" spp in ([0-9.]+) s", r.stderr)]
    files = [l for l in r.stdout.split() if l.endswith(".exr")]
    if len(files) != len(seeds):
        raise RuntimeError("expected %d images, got %s" % (len(seeds), files))
    return [read_exr(mi, f) for f in files], float(np.median(times))


def caustic_reference(exe, scene_file, spp, sets, outdir, mi):
    cmd = [exe, "--scene", scene_file, "--samples", str(spp), "--exr", "--output", outdir, "--seed", "1000"] + \
          [a for s in sets for a in ("--set", s)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError("caustic failed: %s\n%s" % (" ".join(cmd), r.stderr))
    return read_exr(mi, [l for l in r.stdout.split() if l.endswith(".exr")][0])


def mitsuba_images(mi, dr, scene, spp, seeds):
    s = mi.load_dict(suite_mod.to_mitsuba(mi, scene, spp))
    np.array(mi.render(s, spp=spp, seed=dr.opaque(mi.UInt32, 12345)))  # warm-up (kernel compile)
    images, times = [], []
    for seed in seeds:
        t0 = time.perf_counter()
        img = np.array(mi.render(s, spp=spp, seed=dr.opaque(mi.UInt32, seed)), dtype=np.float64)[..., :3]
        times.append(time.perf_counter() - t0)
        images.append(img)
    return images, float(np.median(times))


def stats(images, spp, ref):
    a = np.stack(images)
    var = float(np.mean(np.var(a, axis=0, ddof=1))) * spp
    rel = float(np.mean([np.mean((im - ref) ** 2 / (ref ** 2 + 0.01)) for im in images]))
    return var, rel, float(np.mean(a))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--k", type=int, default=8, help="independent images per configuration")
    ap.add_argument("--ref-spp", type=int, default=1024)
    ap.add_argument("--scenes", default="", help="comma-separated subset of: " + ",".join(suite_mod.suite()))
    ap.add_argument("--rr", action="store_true", help="also every Russian roulette rule")
    ap.add_argument("--configs", default="default,indep,uniform", help="caustic configurations")
    ap.add_argument("--no-mitsuba", action="store_true")
    ap.add_argument("--caustic", default=os.path.join(ROOT, "build", "caustic"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "variance"))
    ap.add_argument("--json", default="", help="also write the table as JSON here")
    args = ap.parse_args()

    import drjit as dr
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")

    configs = {
        "default": [],
        "indep": ["render.sampler=independent"],
        "uniform": ["render.light_selection=uniform"],
        "power": ["render.light_selection=power"],
        "nosplit": ["render.glass_split=false"],
    }
    chosen = [c for c in args.configs.split(",") if c]
    if args.rr:
        for rule in ("original", "mitsuba", "pbrt", "off"):
            configs["rr-" + rule] = ["render.russian_roulette=" + rule]
            chosen.append("rr-" + rule)
    suite = suite_mod.suite()
    names = [n for n in args.scenes.split(",") if n] or list(suite)
    os.makedirs(args.out, exist_ok=True)
    seeds = list(range(1, args.k + 1))
    rows = []
    print("machine: %s; %d spp x %d seeds, reference %d spp" % (os.uname().nodename, args.spp, args.k, args.ref_spp))
    print("%-11s %-12s %12s %10s %9s %10s %8s" % ("scene", "renderer", "var/spp", "relMSE", "time s", "eff", "mean"))
    for name in names:
        scene = suite[name]
        sdir = os.path.join(args.out, name)
        os.makedirs(sdir, exist_ok=True)
        if scene.get("cornell") or scene.get("file"):
            scene_file = scene.get("file") or os.path.join(ROOT, "scenes", "cornell-box.json")
            base = ["render.width=%d" % scene["width"], "render.height=%d" % scene["height"],
                    "render.max_depth=%d" % scene["max_depth"], "render.filter=box"]
        else:
            scene_file = os.path.join(sdir, name + ".json")
            with open(scene_file, "w") as f:
                json.dump(suite_mod.to_caustic(scene), f, indent=1)
            base = []
        ref_file = os.path.join(sdir, "reference-%d.npy" % args.ref_spp)
        if os.path.exists(ref_file):
            ref = np.load(ref_file)
        else:
            ref = caustic_reference(args.caustic, scene_file, args.ref_spp, base, tempfile.mkdtemp(dir=sdir), mi)
            np.save(ref_file, ref)
        results = {}
        for c in chosen:
            imgs, t = caustic_images(args.caustic, scene_file, args.spp, seeds, base + configs[c],
                                     tempfile.mkdtemp(dir=sdir), mi)
            results["caustic " + c] = stats(imgs, args.spp, ref) + (t,)
        if not args.no_mitsuba:
            imgs, t = mitsuba_images(mi, dr, scene, args.spp, seeds)
            results["mitsuba"] = stats(imgs, args.spp, ref) + (t,)
        for who, (var, rel, mean, t) in results.items():
            print("%-11s %-12s %12.5g %10.5g %9.3f %10.4g %8.4f" % (name, who.replace("caustic ", "c:"), var, rel, t,
                                                                       rel * t, mean))
            rows.append({"scene": name, "renderer": who, "var_per_spp": var, "relmse": rel, "seconds": t,
                         "mean": mean, "spp": args.spp, "k": args.k})
        if "mitsuba" in results and "caustic default" in results:
            m, d = results["mitsuba"], results["caustic default"]
            print("%-11s ratios caustic default / Mitsuba: variance %.3f, relMSE %.3f, equal-time relMSE %.3f, mean %.4f"
                  % (name, d[0] / m[0], d[1] / m[1], (d[1] * d[3]) / (m[1] * m[3]), d[2] / m[2]))
        sys.stdout.flush()
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
