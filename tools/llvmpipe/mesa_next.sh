#!/usr/bin/env bash
# caustic-bench on a newer llvmpipe than Debian 12's (a benchmarking aid, never a test;
# docs/performance.md). Makes (once) a minimal Debian sid root with sid's Mesa (at the
# time of writing 26.2.6 with LLVM 22; Debian 12's backports stop at 25.0.7 with LLVM 15), binds
# this checkout and the machine's /tmp into it at the same paths, copies the three Debian 12
# libraries that sid no longer has (libassimp.so.5, libdraco.so.7, libminizip.so.1), and writes
# ROOT/bench: a wrapper that runs a caustic-bench built here (Debian 12's glibc is older than sid's,
# so the binary runs there unchanged) on sid's Mesa. Prints the wrapper's path.
#   tools/llvmpipe/mesa_next.sh [ROOT]        (default /tmp/caustic-mesa-next; needs root, debootstrap)
# The wrapper runs $CAUSTIC_NEXT_BENCH if set (a copy of an older build, as ab.py's configurations
# use), else this checkout's build/caustic-bench; paths under the checkout and /tmp mean the same
# inside. With the benchmarks:
#   ab.py --config mesa25=build/caustic-bench --config mesa26=ROOT/bench scenes/mesh-knot.json
#   compare.py --bench ROOT/bench ...      (caustic on the newer Mesa against Mitsuba)
# ROOT holds this checkout and /tmp through bind mounts: `mesa_next.sh --unmount [ROOT]` undoes
# them, and must come before deleting ROOT (else rm -r would go through them).
set -euo pipefail
checkout=$(cd "$(dirname "$0")/../.." && pwd)
if [ "${1:-}" = --unmount ]; then
    root=$(realpath -m "${2:-/tmp/caustic-mesa-next}")
    for m in tmp "${checkout#/}" dev proc; do
        if mountpoint -q "$root/$m"; then umount "$root/$m"; fi
    done
    echo "unmounted; $root can be deleted" >&2
    exit 0
fi
root=$(realpath -m "${1:-/tmp/caustic-mesa-next}")  # the wrapper names it, from any folder
mirror=$(sed -n 's/^URIs: *//p' /etc/apt/sources.list.d/debian.sources 2>/dev/null | head -1)
mirror=${mirror:-http://deb.debian.org/debian}
command -v debootstrap > /dev/null || apt-get install -y -q debootstrap > /dev/null
if [ ! -x "$root/usr/bin/apt-get" ]; then
    debootstrap --variant=minbase sid "$root" "$mirror" >&2
fi
cp /etc/resolv.conf "$root/etc/resolv.conf" 2>/dev/null || true
mountpoint -q "$root/proc" || mount -t proc proc "$root/proc"
mountpoint -q "$root/dev" || mount --bind /dev "$root/dev"
mkdir -p "$root$checkout"
mountpoint -q "$root$checkout" || mount --bind "$checkout" "$root$checkout"
mountpoint -q "$root/tmp" || mount --bind /tmp "$root/tmp"
if ! chroot "$root" dpkg -s mesa-libgallium > /dev/null 2>&1; then
    # A mirror's snapshot of sid may be older than its Release file's Valid-Until.
    chroot "$root" apt-get -q -o Acquire::Check-Valid-Until=false update >&2
    chroot "$root" apt-get install -y -q --no-install-recommends libegl1 libegl-mesa0 libgl1-mesa-dri \
        mesa-libgallium libpng16-16t64 libjpeg62-turbo zlib1g libstdc++6 >&2
fi
mkdir -p "$root/opt/debian12-libs"
for lib in libassimp.so.5 libdraco.so.7 libminizip.so.1; do
    cp -L "/lib/x86_64-linux-gnu/$lib" "$root/opt/debian12-libs/"
done
cat > "$root/bench" << EOF
#!/usr/bin/env bash
# caustic-bench on sid's Mesa (written by tools/llvmpipe/mesa_next.sh)
bench=\${CAUSTIC_NEXT_BENCH:-$checkout/build/caustic-bench}
exec chroot "$root" /usr/bin/env LD_LIBRARY_PATH=/opt/debian12-libs /bin/bash -c 'cd "\$0" && exec "\$@"' "\$PWD" "\$bench" "\$@"
EOF
chmod +x "$root/bench"
version=$("$root/bench" --size 8 --samples 1 2>&1 | sed -n 's/^# Mesa | //p' | head -1)
echo "Mesa in $root: ${version:-unknown, no renderer line from the wrapper}" >&2
echo "$root/bench"
