#!/usr/bin/env python3
"""A/B benchmark of caustic configurations on llvmpipe (a benchmark, never a test).

Runs caustic-bench once per configuration per round, interleaved (A B A B ...), and prints per
scene the median of M samples per CPU second and its ratio to the first configuration. On a shared
or virtual machine a single run can be 10-25 % off, and even interleaved medians of 3-12 rounds
of the same pair of configurations have ranged from 0.90x to 1.08x (docs/performance.md). So it also prints, per configuration, the median of
the per-round ratios with a bootstrap 90 % interval: decide on that interval, not on one median.

    tools/llvmpipe/ab.py [--rounds 3] [--size 128] [--spp 8] [--max-depth 7]
                         --config NAME=BENCH[:SHADER_DIR[:VAR=VALUE...]] ... scene.json ...

BENCH is a caustic-bench binary (keep a copy of the old one before rebuilding); SHADER_DIR, when
given, is the shader tree it reads (CAUSTIC_SHADER_DIR, e.g. `git archive REV shaders | tar -x`);
VAR=VALUE are further environment variables (CAUSTIC_REGISTER_STACK=4, CAUSTIC_FETCH_TEXELS=0, ...).
"""
import argparse
import collections
import os
import random
import statistics
import subprocess
import sys


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--size", default="128")
    ap.add_argument("--spp", default="8")
    ap.add_argument("--max-depth", default="7")
    ap.add_argument("--config", action="append", required=True)
    ap.add_argument("scenes", nargs="+")
    args = ap.parse_args()
    configs = []
    for c in args.config:
        name, spec = c.split("=", 1)
        parts = spec.split(":")
        env = dict(os.environ)
        if len(parts) > 1 and parts[1]:
            env["CAUSTIC_SHADER_DIR"] = parts[1]
        for kv in parts[2:]:
            k, v = kv.split("=", 1)
            env[k] = v
        configs.append((name, parts[0], env))
    rates = collections.defaultdict(list)
    for _ in range(args.rounds):
        for name, bench, env in configs:
            cmd = [bench, "--size", args.size, "--samples", args.spp, "--max-depth", args.max_depth] + args.scenes
            r = subprocess.run(cmd, env=env, capture_output=True, text=True)
            if r.returncode != 0 or "failed" in r.stderr:
                sys.exit("ab.py: %s: %s" % (name, r.stderr.strip()[:400]))
            for line in r.stdout.splitlines():
                if "FALLBACK" in line or "INCOMPLETE" in line:
                    sys.exit("ab.py: %s: %s" % (name, line))
                f = line.split()
                if len(f) > 10 and f[0].endswith(".json"):
                    rates[(f[0], name)].append(float(f[10]))
    names = [n for n, _, _ in configs]
    for scene in dict.fromkeys(k[0] for k in rates):
        base = statistics.median(rates[(scene, names[0])])
        cells = ["%s %.3f (%.3fx)" % (n, statistics.median(rates[(scene, n)]), statistics.median(rates[(scene, n)]) / base)
                 for n in names]
        print("%-28s %s" % (scene, "   ".join(cells)))
        # The same ratio from each round's own pair of runs (they ran back to back, so a slow spell
        # of the machine hits both), with a bootstrap 90 % interval of its median: an interval
        # that contains 1 says the rounds could not tell the configurations apart.
        for n in names[1:]:
            ratios = [b / a for a, b in zip(rates[(scene, names[0])], rates[(scene, n)])]
            lo, hi = bootstrap_interval(ratios)
            print("%-28s   %s / %s per round: median %.3fx, 90 %% interval [%.3f, %.3f] over %d rounds"
                  % ("", n, names[0], statistics.median(ratios), lo, hi, len(ratios)))


def bootstrap_interval(values, resamples=4000, seed=1):
    """The 5th and 95th percentiles of the median of `values` resampled with replacement."""
    rng = random.Random(seed)
    medians = sorted(statistics.median(rng.choices(values, k=len(values))) for _ in range(resamples))
    return medians[int(0.05 * resamples)], medians[int(0.95 * resamples) - 1]


if __name__ == "__main__":
    main()
