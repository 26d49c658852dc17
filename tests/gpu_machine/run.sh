#!/usr/bin/env bash
# Runs on the GPU machine (the device tool), from the repository root, with .gpu/ carried:
# unpacks the payload, installs GLVND, then runs the whole benchmark and the GPU tests in one go
# and leaves the results in $OUT (bench.txt, gpu-tests.txt, images). Never more than a few
# seconds of GPU work queued at once: the renderer paces its dispatches.
#   run.sh [quick|variants|compare]
# A plain or quick run also benchmarks the 1M-triangle mesh scene that make_mesh_scene.py writes.
# variants: only the integrator profile: caustic-bench on each copy of the shaders written by
# shader_variants.py (pack.sh puts them in .gpu/variants), plus the driver's program binaries.
# compare: only caustic against Mitsuba 3's cuda_ad_rgb in one interleaved run (compare.py: the
# Cornell box and mesh-knot at 1024 x 1024, caustic max depth 7 = Mitsuba max_depth 8, 64 spp,
# 3 repetitions; caustic as it runs on NVIDIA by default, and scene-specialised, and specialised
# with buffer textures: the binary, the 4-wide and the 8-wide nodes), results in $OUT/compare.txt and
# compare.json. Needs .gpu/mitsuba.tar.xz
# (pack_mitsuba.sh), carried in a second call (it does not fit beside the payload):
#   call 1: carry [".gpu/payload.tar.xz", ".gpu/debs"], run.sh quick (or nothing: just unpacks)
#   call 2: carry [".gpu/mitsuba.tar.xz"], run.sh compare (git-ignored paths from call 1 stay)
# (Not part of a plain run, which with the GPU tests already takes several minutes: each call
# stays well inside the 10 minutes a command may run.)
set -uo pipefail
OUT=${OUT:-/tmp/caustic-gpu-out}
mkdir -p "$OUT" /tmp/caustic-gpu
tar -C /tmp/caustic-gpu -xJf .gpu/payload.tar.xz
for f in .gpu/debs/*.deb; do dpkg -x "$f" /; done
ldconfig
export LD_LIBRARY_PATH=/tmp/caustic-gpu/lib
export CAUSTIC_SHADER_DIR=$PWD/shaders
if [ -f /usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json ]; then
  export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
fi
# The test binary names its data by the path of the checkout it was built in.
src=$(cat /tmp/caustic-gpu/source-dir.txt)
if [ "$src" != "$PWD" ] && [ ! -e "$src" ]; then mkdir -p "$(dirname "$src")" && ln -s "$PWD" "$src"; fi
B=/tmp/caustic-gpu/bin
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv > "$OUT/nvidia-smi.txt" 2>&1
nproc > "$OUT/nproc.txt"
mkdir -p "$OUT/images"
scenes="scenes/cornell-box.json scenes/veach-mis.json scenes/materials-diffuse.json scenes/materials-metals.json
  scenes/materials-rough-glass.json scenes/dof.json scenes/sky-spheres.json scenes/mesh-knot.json"
compare() {
  mkdir -p /tmp/caustic-gpu/mitsuba
  tar -C /tmp/caustic-gpu/mitsuba -xJf .gpu/mitsuba.tar.xz
  PYTHONPATH=/tmp/caustic-gpu/mitsuba timeout 420 python3 tests/gpu_machine/compare.py --variant cuda_ad_rgb \
    --size 1024 --spp 64 --mitsuba-spp 64 --max-depth 7 --reps 3 --bench $B/caustic-bench \
    --config general --config specialised:CAUSTIC_SPECIALIZE=1 \
    --config specialised-texels:CAUSTIC_SPECIALIZE=1:CAUSTIC_FETCH_TEXELS=1 \
    --config specialised-texels-4wide:CAUSTIC_SPECIALIZE=1:CAUSTIC_FETCH_TEXELS=1:CAUSTIC_WIDE_BVH=1 \
    --json "$OUT/compare.json" cornell mesh-knot 2>&1 | tee "$OUT/compare.txt"
}
if [ "${1:-}" = compare ]; then
  compare
  exit 0
fi
if [ "${1:-}" = variants ]; then
  mkdir -p "$OUT/programs"
  for v in .gpu/variants/*; do
    name=$(basename "$v")
    echo "## variant $name"
    CAUSTIC_SHADER_DIR=$PWD/$v timeout 60 $B/caustic-bench --size 1024 --samples 32 --repeat 3 \
      --dump-program "$OUT/programs/$name.bin" scenes/cornell-box.json scenes/mesh-knot.json 2>&1 | tail -2
  done | tee "$OUT/variants.txt"
  for d in 1 2 4; do
    echo "## base, max depth $d"
    timeout 60 $B/caustic-bench --size 1024 --samples 32 --repeat 3 --max-depth $d scenes/cornell-box.json 2>&1 | tail -1
  done | tee -a "$OUT/variants.txt"
  exit 0
fi
{
  echo "## caustic-bench --size 1024 --samples 64 --max-depth 8 --repeat 3 --rays --oidn"
  timeout 300 $B/caustic-bench --size 1024 --samples 64 --max-depth 8 --repeat 3 --rays --oidn --out "$OUT/images" $scenes 2>&1
  echo "rc=$?"
  # Issue 16's mesh goal: two instances of a 1M-triangle mesh (make_mesh_scene.py; ~1 s to write),
  # diffuse rays per second in the integrator (Mrays/s) and alone (--rays).
  python3 tests/gpu_machine/make_mesh_scene.py /tmp/caustic-gpu/big-mesh > /dev/null
  echo "## 1M-triangle mesh: caustic-bench --size 1024 --samples 64 --max-depth 7 --repeat 3 --rays"
  timeout 120 $B/caustic-bench --size 1024 --samples 64 --max-depth 7 --repeat 3 --rays /tmp/caustic-gpu/big-mesh/mesh-big.json 2>&1
  # The same through buffer textures, with the binary and the 4-wide nodes (the two walks).
  for wide in 0 1; do
    echo "## 1M-triangle mesh, CAUSTIC_FETCH_TEXELS=1 CAUSTIC_WIDE_BVH=$wide"
    CAUSTIC_FETCH_TEXELS=1 CAUSTIC_WIDE_BVH=$wide timeout 90 $B/caustic-bench --size 1024 --samples 64 --max-depth 7 \
      --repeat 2 --rays /tmp/caustic-gpu/big-mesh/mesh-big.json 2>&1 | tail -2
  done
  echo "## the editor's frames: caustic-bench --size 1024 --interactive 300"
  timeout 120 $B/caustic-bench --size 1024 --samples 16 --repeat 1 --interactive 300 scenes/cornell-box.json scenes/mesh-knot.json 2>&1 | grep "^interactive"
  echo "## the editor's frames: caustic-bench --size 2048 --interactive 300"
  timeout 120 $B/caustic-bench --size 2048 --samples 4 --repeat 1 --interactive 300 scenes/cornell-box.json 2>&1 | grep "^interactive"
} | tee "$OUT/bench.txt"
if [ "${1:-}" != quick ]; then
  { timeout 200 $B/caustic_gpu_tests 2>&1; echo "rc=$?"; } > "$OUT/gpu-tests.txt"
  # The traversal configurations the renderer does not use on NVIDIA by default, tested there too.
  { CAUSTIC_SPECIALIZE=1 CAUSTIC_FETCH_TEXELS=1 timeout 100 $B/caustic_gpu_tests "[geometry],[integrator]" 2>&1;
    echo "rc=$?"; } > "$OUT/gpu-tests-specialised-texels.txt"
fi
cat "$OUT/nvidia-smi.txt"
tail -5 "$OUT/bvh-bench.txt" "$OUT/gpu-tests.txt" 2>/dev/null
