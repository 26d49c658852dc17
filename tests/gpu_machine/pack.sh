#!/usr/bin/env bash
# Packs what the GPU machine needs into .gpu/ (git-ignored) for the device tool's `carry`:
# the benchmarks and the GPU test binary from build/ (Release), the shared libraries they need that
# the GPU machine lacks (Assimp and its dependencies, Open Image Denoise), xz-compressed so they
# fit the 64 MiB a command may carry, and the GLVND packages (libEGL/libGL dispatch), which that
# machine's NVIDIA driver install lacks (docs/dependencies.md, "The NVIDIA machine").
#   tests/gpu_machine/pack.sh        then carry [".gpu"] and run tests/gpu_machine/run.sh there
set -euo pipefail
cd "$(dirname "$0")/../.."
ninja -C build caustic-bench caustic-bvh-bench caustic_gpu_tests >&2
rm -rf .gpu/stage && mkdir -p .gpu/stage/bin .gpu/stage/lib .gpu/debs
cp build/caustic-bench build/caustic-bvh-bench build/tests/caustic_gpu_tests .gpu/stage/bin/
# Every non-system library of the binaries, except glibc, libstdc++/libgcc and the GL/EGL
# dispatch libraries (the driver's own, through GLVND).
ldd .gpu/stage/bin/* | awk '$3 ~ /^\// {print $3}' | sort -u |
  grep -Ev '/(libc|libm|libdl|libpthread|librt|libstdc\+\+|libgcc_s|libEGL|libGL|libGLX|libGLdispatch|libOpenGL)\.so' |
  while read -r lib; do cp -L "$lib" .gpu/stage/lib/; done
# OIDN loads its device modules (CUDA, CPU) from the directory of its core library.
cp -L .deps/oidn/lib/libOpenImageDenoise_device_*.so.* .deps/oidn/lib/libtbb.so.12 .gpu/stage/lib/
pwd > .gpu/stage/source-dir.txt   # the test binary finds its data by this path
tar -C .gpu/stage -cf - bin lib source-dir.txt | xz -T0 -6 > .gpu/payload.tar.xz
rm -rf .gpu/stage
if ! ls .gpu/debs/*.deb >/dev/null 2>&1; then
  (cd .gpu/debs && apt-get download libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
fi
python3 tests/gpu_machine/shader_variants.py .gpu/variants >/dev/null
du -sh .gpu >&2
