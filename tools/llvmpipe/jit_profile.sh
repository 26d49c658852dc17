#!/usr/bin/env bash
# Where llvmpipe spends a render's time, down to the JIT code's loops (a profiling aid, never a
# test; docs/performance.md, "How to measure"). Runs caustic-bench with the given arguments,
# records it with perf after a warm-up, dumps the JIT code's executable mappings from
# /proc/PID/mem, disassembles them and prints the functions (the kernel and the texture-fetch
# helpers) and the hottest loops (backward branches) with their share of the samples.
#   tools/llvmpipe/jit_profile.sh OUT_DIR [caustic-bench arguments...]
# WARM (s, default 5) and SECS (s, default 8) set the warm-up and the recording time; the render
# must outlast both (e.g. --size 256 --samples 64). Needs perf (linux-perf) and objdump (binutils).
set -euo pipefail
out=$1; shift
here=$(cd "$(dirname "$0")" && pwd)
bench=${CAUSTIC_BENCH:-$here/../../build/caustic-bench}
mkdir -p "$out"
"$bench" "$@" > "$out/bench.txt" 2>&1 &
pid=$!
sleep "${WARM:-5}"
perf record -o "$out/perf.data" -F 4000 -p "$pid" -- sleep "${SECS:-8}" 2> /dev/null
python3 - "$pid" "$out" <<'PY'
import sys
pid, out = sys.argv[1], sys.argv[2]
regions = []
for line in open(f"/proc/{pid}/maps"):
    f = line.split()
    if "x" in f[1] and len(f) < 6:  # anonymous executable mappings: the JIT code
        start, end = (int(x, 16) for x in f[0].split("-"))
        regions.append((start, end))
with open(f"/proc/{pid}/mem", "rb") as mem, open(f"{out}/regions.txt", "w") as listing:
    for i, (start, end) in enumerate(regions):
        mem.seek(start)
        open(f"{out}/jit{i}.bin", "wb").write(mem.read(end - start))
        listing.write(f"{i} {start:x} {end:x}\n")
PY
wait "$pid"
perf script -i "$out/perf.data" -F ip 2> /dev/null | sort | uniq -c | sort -rn > "$out/ips.txt"
start=$(awk 'NR == 1 {print $2}' "$out/regions.txt")
objdump -D -b binary -mi386:x86-64 --adjust-vma="0x$start" "$out/jit0.bin" > "$out/jit0.asm"
python3 "$here/jit_loops.py" "$out"
