#!/usr/bin/env python3
"""Reads jit_profile.sh's folder: the disassembled JIT code and the sampled instruction addresses.
Prints the functions (split at `ret`) and the loops (a backward branch and the code it spans) with
their share of all samples, hottest first. A loop's share includes its inner loops' but not the
helpers it calls (texel fetches are calls to the small functions listed first).
    jit_loops.py DIR [ROWS]"""
import bisect
import collections
import re
import sys


def main():
    d = sys.argv[1]
    rows = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    counts = collections.Counter()
    for line in open(f"{d}/ips.txt"):
        c, ip = line.split()
        counts[int(ip, 16)] += int(c)
    total = sum(counts.values()) or 1
    code = []
    for line in open(f"{d}/jit0.asm"):
        m = re.match(r"\s*([0-9a-f]+):\s+((?:[0-9a-f]{2} )+)\s*(.*)", line)
        if m:
            code.append((int(m.group(1), 16), m.group(3)))
    addrs = [a for a, _ in code]
    print(f"{total} samples, {100 * sum(counts.get(a, 0) for a in addrs) / total:.1f} % in the first JIT region")
    functions, current = [], []
    for a, ins in code:
        current.append(a)
        if ins.startswith("ret"):
            functions.append(current)
            current = []
    functions.append(current)
    ranked = sorted(((sum(counts.get(a, 0) for a in f), f[0], f[-1], len(f)) for f in functions if f), reverse=True)
    print("functions:")
    for c, s, e, n in ranked[:8]:
        print(f"  {100 * c / total:6.2f} %  {s:x}-{e:x}  {n} instructions")
    loops = []
    for i, (a, ins) in enumerate(code):
        m = re.match(r"j\w+\s+(?:0x)?([0-9a-f]+)$", ins)
        if m:
            target = int(m.group(1), 16)
            if addrs[0] <= target < a:
                lo = bisect.bisect_left(addrs, target)
                loops.append((sum(counts.get(addrs[k], 0) for k in range(lo, i + 1)), target, a, i - lo + 1))
    print("loops:")
    for c, s, e, n in sorted(loops, reverse=True)[:rows]:
        print(f"  {100 * c / total:6.2f} %  {s:x}-{e:x}  {n} instructions")


if __name__ == "__main__":
    main()
