"""caustic against Mitsuba 3, interleaved in one run (a benchmark, never a test).

On a machine shared with other work the load changes from minute to minute, so the two
renderers are measured in turns, A B A B ...: each repetition runs caustic-bench once over the
scenes (its own warm-up inside) and then times Mitsuba's render of each scene in this process
(warmed up once at the start). Prints every measurement with the load average before it, then
per scene the medians and their ratio, both in samples per wall-clock second and in samples per
CPU second of the renderer's process (all its threads; on a loaded machine that moves less with
the load than the wall clock; on the GPU machine only the wall clock means anything).

  compare.py [--variant llvm_ad_rgb] [--size 256] [--spp 16] [--mitsuba-spp 64] [--max-depth 7]
             [--reps 5] [--bench build/caustic-bench] [--config LABEL[:VAR=VALUE...]]... [--json FILE]
             [scene ...]

--config: a caustic configuration, measured in its turn in every repetition: the label, then
environment variables for caustic-bench (CAUSTIC_SHADER_DIR=... for another shader tree,
CAUSTIC_SPECIALIZE=0, CAUSTIC_FETCH_TEXELS=0, CAUSTIC_WIDE_BVH=0), or CAUSTIC_BENCH=PATH for
another caustic-bench binary (another commit's build); repeatable. Default: one, "caustic", as is.

Scenes: cornell (scenes/cornell-box.json and Mitsuba's cornell_box()), mesh-knot. On the GPU
machine run.sh calls it with --variant cuda_ad_rgb and the 1024 x 1024 settings.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "llvmpipe"))
import mitsuba_bench  # noqa: E402
from ab import bootstrap_interval  # noqa: E402

CAUSTIC_FILES = {"cornell": "scenes/cornell-box.json", "mesh-knot": "scenes/mesh-knot.json"}


def caustic_run(bench, scenes, size, spp, max_depth, extra, env):
    """One caustic-bench process over the scenes: {scene: (M samples/s, M samples per CPU s)}."""
    files = [os.path.join(ROOT, CAUSTIC_FILES[s]) for s in scenes]
    cmd = [bench, "--size", str(size), "--samples", str(spp), "--max-depth", str(max_depth), "--repeat", "1"] + extra + files
    r = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ, **env))
    if r.returncode != 0:
        sys.exit("compare.py: %s failed (%d):\n%s" % (" ".join(cmd), r.returncode, r.stderr))
    rates = {}
    for line in r.stdout.splitlines():
        for s in scenes:
            f = os.path.basename(CAUSTIC_FILES[s])
            if line.startswith(f + " "):
                if "INCOMPLETE" in line:
                    sys.exit("compare.py: caustic-bench says the image is incomplete:\n" + line)
                if "FALLBACK" in line:
                    sys.exit("compare.py: caustic-bench rendered with the general program (the scene's failed to "
                             "build):\n" + line + "\n" + r.stderr)
                f = line.split()
                # (an older caustic-bench has no CPU-time columns)
                rates[s] = (float(f[6]), float(f[10]) if len(f) > 10 and f[10] != "INCOMPLETE:" else float("nan"))
    if set(rates) != set(scenes):
        sys.exit("compare.py: caustic-bench printed no row for %s:\n%s" % (sorted(set(scenes) - set(rates)), r.stdout))
    return rates


def machine_summary():
    """The CPU the ratio was measured on: its model, CPU count and widest vector ISA. The knot's
    ratio moves with it by about 1.25x (docs/performance.md: Mitsuba's LLVM back end
    and Embree use AVX-512 where llvmpipe gains nothing from it), so every run prints it."""
    model, flags = "unknown CPU", set()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                key, _, value = line.partition(":")
                if key.strip() == "model name" and model == "unknown CPU":
                    model = value.strip()
                elif key.strip() == "flags" and not flags:
                    flags = set(value.split())
    except OSError:
        pass
    isa = "AVX-512" if "avx512f" in flags else "AVX2" if "avx2" in flags else "AVX" if "avx" in flags else "SSE"
    return "%s, %d CPUs, %s" % (model, os.cpu_count() or 0, isa)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--spp", type=int, default=16, help="caustic's samples per measurement")
    ap.add_argument("--mitsuba-spp", type=int, default=64)
    ap.add_argument("--max-depth", type=int, default=7, help="caustic's; Mitsuba's max_depth is one more")
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--bench", default=os.path.join(ROOT, "build", "caustic-bench"))
    ap.add_argument("--bench-arg", action="append", default=[], help="passed to caustic-bench (repeatable)")
    ap.add_argument("--config", action="append", default=[], help="LABEL[:VAR=VALUE...] (repeatable)")
    ap.add_argument("--json", default="")
    ap.add_argument("scenes", nargs="*", default=["cornell", "mesh-knot"])
    args = ap.parse_args()
    import drjit as dr
    import mitsuba as mi
    mi.set_variant(args.variant)
    mscenes = {}
    for s in args.scenes:
        mscenes[s] = mi.load_dict(mitsuba_bench.scene_dict(mi, s, args.size, args.mitsuba_spp, args.max_depth))
        mi.render(mscenes[s], spp=args.mitsuba_spp, seed=0)
        dr.sync_thread()
    configs = []
    for c in args.config or ["caustic"]:
        label, *assignments = c.split(":")
        configs.append((label, dict(a.split("=", 1) for a in assignments)))
    names = [label for label, _ in configs] + ["mitsuba"]
    rows = {s: {n: {"wall": [], "cpu": []} for n in names} for s in args.scenes}
    loads = []
    machine = machine_summary()
    print("machine: %s; Mitsuba %s (drjit %s), %s" % (machine, mi.__version__, dr.__version__, args.variant), flush=True)
    print("rep  %-22s %-10s %12s %14s  load(1 min)" % ("renderer", "scene", "Msamples/s", "Msamples/cpu-s"), flush=True)
    for rep in range(args.reps):
        for label, env in configs:
            load = os.getloadavg()[0]
            loads.append(load)
            env = dict(env)
            bench = env.pop("CAUSTIC_BENCH", args.bench)
            rates = caustic_run(bench, args.scenes, args.size, args.spp, args.max_depth, args.bench_arg, env)
            for s in args.scenes:
                rows[s][label]["wall"].append(rates[s][0])
                rows[s][label]["cpu"].append(rates[s][1])
                print("%3d  %-22s %-10s %12.3f %14.3f  %.2f" % (rep, label, s, rates[s][0], rates[s][1], load), flush=True)
        for s in args.scenes:
            load = os.getloadavg()[0]
            loads.append(load)
            t0, c0 = time.perf_counter(), time.process_time()
            img = mi.render(mscenes[s], spp=args.mitsuba_spp, seed=rep + 1)
            dr.eval(img)
            dr.sync_thread()
            n = args.mitsuba_spp * args.size * args.size * 1e-6
            rate, cpu = n / (time.perf_counter() - t0), n / max(time.process_time() - c0, 1e-9)
            rows[s]["mitsuba"]["wall"].append(rate)
            rows[s]["mitsuba"]["cpu"].append(cpu)
            print("%3d  %-22s %-10s %12.3f %14.3f  %.2f" % (rep, "mitsuba " + args.variant, s, rate, cpu, load), flush=True)
    print("\nmedians of %d: M samples/s (wall) and M samples per CPU second; ratio: over Mitsuba's; load %.1f-%.1f"
          % (args.reps, min(loads), max(loads)))
    print("%-10s %-22s %10s %8s %10s %8s" % ("scene", "renderer", "wall", "ratio", "cpu", "ratio"))
    summary = {}
    for s in args.scenes:
        mw = statistics.median(rows[s]["mitsuba"]["wall"])
        mc = statistics.median(rows[s]["mitsuba"]["cpu"])
        summary[s] = {}
        for n in names:
            w, c = statistics.median(rows[s][n]["wall"]), statistics.median(rows[s][n]["cpu"])
            summary[s][n] = {"wall": w, "cpu": c, "ratio": w / mw, "ratio_cpu": c / mc, "runs": rows[s][n]}
            print("%-10s %-22s %10.3f %8.3f %10.3f %8.3f" % (s, n, w, w / mw, c, c / mc))
    # Each repetition's own ratio (caustic's run and Mitsuba's render of the same repetition ran
    # minutes apart at most), with a bootstrap 90 % interval of the median: how sure the ratio is.
    print("\nper repetition: median ratio over Mitsuba and its bootstrap 90 % interval")
    for s in args.scenes:
        for n in names[:-1]:
            for key in ("wall", "cpu"):
                ratios = [a / b for a, b in zip(rows[s][n][key], rows[s]["mitsuba"][key])]
                lo, hi = bootstrap_interval(ratios)
                print("%-10s %-22s %-5s %.3f [%.3f, %.3f]" % (s, n, key, statistics.median(ratios), lo, hi))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"machine": machine, "variant": args.variant, "size": args.size, "max_depth": args.max_depth, "load": [min(loads), max(loads)],
                       "scenes": summary}, f, indent=1)


if __name__ == "__main__":
    main()
