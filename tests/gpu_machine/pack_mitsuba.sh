#!/usr/bin/env bash
# Packs Mitsuba 3 for the GPU machine into .gpu/mitsuba.tar.xz (git-ignored): the PyPI wheels of
# mitsuba 3.9.1 and drjit 1.5.0 for that machine's Python (Ubuntu 24.04: CPython 3.12), trimmed to
# the cuda_ad_rgb and scalar_rgb variants and the plugins tests/gpu_machine/mitsuba_bench.py's
# scenes use, so that it fits a device call's carry (64 MiB) on its own. That machine reaches no
# registry: pip runs here. run.sh unpacks it and runs compare.py with the cuda_ad_rgb variant.
#   tests/gpu_machine/pack_mitsuba.sh [python-version]     (default 3.12)
# The plugin list was found by running mitsuba_bench.py on a copy trimmed the same way (with the
# llvm_ad_rgb variant, on this machine) until no plugin was missing.
set -euo pipefail
cd "$(dirname "$0")/../.."
py=${1:-3.12}
pip=.deps/bench-venv/bin/pip
[ -x "$pip" ] || pip="python3 -m pip"
rm -rf .gpu/mitsuba-wheels .gpu/mitsuba-stage
mkdir -p .gpu/mitsuba-wheels .gpu/mitsuba-stage
$pip download -q --disable-pip-version-check --only-binary=:all: --no-deps --python-version "$py" \
  --platform manylinux_2_17_x86_64 --platform manylinux2014_x86_64 --platform manylinux_2_28_x86_64 \
  mitsuba==3.9.1 drjit==1.5.0 -d .gpu/mitsuba-wheels
for w in .gpu/mitsuba-wheels/*.whl; do python3 -m zipfile -e "$w" .gpu/mitsuba-stage/; done
rm -rf .gpu/mitsuba-stage/*.dist-info
m=.gpu/mitsuba-stage/mitsuba
# Variants: cuda_ad_rgb (measured) and scalar_rgb (the Python layer's scalar types).
# (drjit's llvm/ package stays: drjit imports it whatever the variant.)
find "$m" -maxdepth 1 -name "*.so" \( -name "cuda_*" -o -name "llvm_*" -o -name "scalar_*" \) \
  ! -name "cuda_ad_rgb.*" ! -name "scalar_rgb.*" -delete
rm -rf "$m/include" .gpu/mitsuba-stage/drjit/include
keep="path perspective hdrfilm box gaussian independent diffuse roughconductor rectangle cube obj area envmap
      constant bitmap srgb uniform regular merge d65"
mkdir "$m/plugins-kept"
for p in $keep; do mv "$m/plugins/$p.so" "$m/plugins-kept/"; done
rm -rf "$m/plugins" && mv "$m/plugins-kept" "$m/plugins"
tar -C .gpu/mitsuba-stage -cf - mitsuba drjit | xz -T0 -6 > .gpu/mitsuba.tar.xz
rm -rf .gpu/mitsuba-stage .gpu/mitsuba-wheels
du -sh .gpu/mitsuba.tar.xz >&2
