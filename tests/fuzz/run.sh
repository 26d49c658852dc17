#!/usr/bin/env bash
# Builds the libFuzzer harnesses (clang, -fsanitize=fuzzer,address,undefined, in build-fuzz/) and
# runs each for a number of executions (default 1,000,000), from seed corpora made of scenes/,
# assets/, Debian's assimp-testmodels and tests/fuzz/seeds/. docs/reliability.md has the figures.
#
#   tests/fuzz/run.sh                        every harness, 10^6 executions each, one after another
#   tests/fuzz/run.sh --runs 100000 mesh     one harness (scene scene_override hdr mesh mesh_common mesh_open image
#                                            sheet part)
#
# Needs clang and its sanitizer runtimes (Debian: clang libclang-rt-14-dev); the normal build and
# test suite do not. Corpora grow in build-fuzz/corpus/<harness>/ (kept between runs), crashes go
# to build-fuzz/artifacts/, each run's log to build-fuzz/logs/<harness>.log; the last line of each
# summary gives executions, coverage (libFuzzer's "cov": edges of caustic's code; Assimp and
# OpenImageIO are not instrumented) and features.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${CAUSTIC_FUZZ_BUILD_DIR:-$root/build-fuzz}"
runs=1000000
harnesses=()
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) runs="$2"; shift 2 ;;
    -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
    *) harnesses+=("$1"); shift ;;
  esac
done
[ ${#harnesses[@]} -gt 0 ] || harnesses=(scene scene_override hdr mesh mesh_common mesh_open image sheet part)
command -v clang++ >/dev/null || { echo "run.sh: clang++ not found (apt-get install clang libclang-rt-14-dev)" >&2; exit 1; }

cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCAUSTIC_FUZZ=ON -DCAUSTIC_WITH_OIDN=OFF >&2
targets=()
for h in "${harnesses[@]}"; do targets+=("caustic_fuzz_$h"); done
cmake --build "$build" -j "${CAUSTIC_JOBS:-$(nproc)}" --target "${targets[@]}" >&2

models=/usr/share/assimp/models
fz="$root/tests/fuzz"
mkdir -p "$build/artifacts" "$build/logs"

# Seeds, copied in once (libFuzzer adds what it finds beside them).
seed() {  # seed <harness> <prefix> <file>...: each file becomes one seed, <prefix> in front
  local h="$1" prefix="$2"; shift 2
  local dir="$build/corpus/$h"; mkdir -p "$dir"
  for f in "$@"; do
    local out="$dir/seed-$(printf '%s' "$f" | md5sum | cut -c1-16)"
    [ -e "$out" ] || { printf '%s' "$prefix" | cat - "$f" > "$out"; }
  done
}
ext_of() { local e="${1##*.}"; printf '%s' "${e,,}"; }
seed_with_ext() {  # seed_with_ext <harness> <max bytes> <file>...: "<extension>\n" in front
  local h="$1" max="$2"; shift 2
  for f in "$@"; do
    [ "$(stat -c %s "$f")" -le "$max" ] || continue
    seed "$h" "$(ext_of "$f")"$'\n' "$f"
  done
}
for h in "${harnesses[@]}"; do
  case "$h" in
    scene) seed scene "" "$root"/scenes/*.json ;;
    scene_override) seed scene_override "$(cat "$fz/seeds/overrides.txt")"$'\n\n' "$root"/scenes/*.json ;;
    hdr) seed hdr "" "$fz"/seeds/hdr/* "$root/assets/sky.hdr" ;;
    mesh)
      mapfile -t files < <(find "$models" -type f \( -iname '*.obj' -o -iname '*.ply' -o -iname '*.stl' -o -iname '*.off' \
        -o -iname '*.gltf' -o -iname '*.glb' -o -iname '*.dae' -o -iname '*.3ds' -o -iname '*.fbx' -o -iname '*.x' \
        -o -iname '*.ac' -o -iname '*.nff' -o -iname '*.lwo' -o -iname '*.amf' -o -iname '*.md5mesh' -o -iname '*.smd' \
        -o -iname '*.ogex' -o -iname '*.ase' -o -iname '*.ms3d' -o -iname '*.md2' -o -iname '*.mdl' -o -iname '*.xgl' \
        -o -iname '*.3mf' -o -iname '*.raw' -o -iname '*.cob' -o -iname '*.b3d' -o -iname '*.dxf' -o -iname '*.x3d' \
        -o -iname '*.irrmesh' -o -iname '*.q3o' -o -iname '*.csm' -o -iname '*.ter' -o -iname '*.hmp' \) | sort)
      seed_with_ext mesh 65536 "${files[@]}" "$root/assets/knot.obj" ;;
    mesh_common)  # the formats of caustic_fuzz_mesh_common (tests/fuzz/CMakeLists.txt)
      mapfile -t files < <(find "$models" -type f \( -iname '*.obj' -o -iname '*.ply' -o -iname '*.stl' -o -iname '*.off' \
        -o -iname '*.gltf' -o -iname '*.glb' -o -iname '*.fbx' \) | sort)
      seed_with_ext mesh_common 65536 "${files[@]}" "$root/assets/knot.obj" ;;
    mesh_open)  # the same without FBX
      mapfile -t files < <(find "$models" -type f \( -iname '*.obj' -o -iname '*.ply' -o -iname '*.stl' -o -iname '*.off' \
        -o -iname '*.gltf' -o -iname '*.glb' \) | sort)
      seed_with_ext mesh_open 65536 "${files[@]}" "$root/assets/knot.obj" ;;
    image)
      mapfile -t files < <(find "$models" -type f \( -iname '*.png' -o -iname '*.jpg' -o -iname '*.bmp' -o -iname '*.tga' \
        -o -iname '*.dds' -o -iname '*.tif' -o -iname '*.exr' -o -iname '*.hdr' \) | sort)
      seed_with_ext image 65536 "${files[@]}" "$fz"/seeds/image/* "$root/assets/sky.hdr" ;;
    sheet) seed sheet "" "$fz"/seeds/sheet/* ;;
    part) seed part "" "$fz"/seeds/part/* ;;
    *) echo "run.sh: no harness '$h'" >&2; exit 2 ;;
  esac
done

# Per harness: the longest input and extra options. Time-outs are per input (a hang is an input
# that takes longer than 10 s); rss_limit_mb is above the largest image the readers accept
# (16384 x 8192 x 4 floats = 2 GiB).
declare -A max_len=([scene]=8192 [scene_override]=8192 [hdr]=16384 [mesh]=65536 [mesh_common]=65536 [mesh_open]=65536 [image]=65536 [sheet]=8192 [part]=16384)
# The image harness's resident memory grows in steps over a long run under AddressSanitizer (1.3
# GB after 12,000 inputs, 2.5 GB after 81,000: the sanitizer allocator keeps what the largest
# images took; LeakSanitizer finds 62 bytes lost, in OpenImageIO) without anything leaking, so its
# limit is higher, and the allocator is asked to give freed memory back every second.
# Per-input time-outs: 10 s, but 30 s for images. A 551-byte TIFF declaring a large image takes
# 1.3 s under the sanitizers on a quiet machine, and twice on 2026-12-02 such an input passed 10 s
# while the machine was loaded (the fuzzer at low priority beside the sanitizer suite). That is a
# time-out with no hang behind it, and it ended the run.
declare -A timeout=([scene]=10 [scene_override]=10 [hdr]=10 [mesh]=10 [mesh_common]=10 [mesh_open]=10 [image]=30 [sheet]=10 [part]=30)
declare -A rss_limit=([scene]=4096 [scene_override]=4096 [hdr]=4096 [mesh]=4096 [mesh_common]=4096 [mesh_open]=4096 [image]=8192 [sheet]=4096 [part]=8192)
# Mesh and image inputs reach Assimp and OpenImageIO, which allocate what a corrupt header
# declares (64 GB for one glTF accessor): a normal build gets std::bad_alloc and refuses the file,
# but under AddressSanitizer a failed throwing new always aborts; Assimp's importers also crash
# on their own (docs/reliability.md). The mesh harness runs in libFuzzer's fork mode, which
# records such inputs (and any crash or time-out) under artifacts/ and goes on; each recorded
# crash must be looked at (the summary counts them). The image harness runs in the normal mode
# (each fork-mode job restarts OpenImageIO, 100x slower); CAUSTIC_FUZZ_IMAGE_FORK=1 forks it too.
# CAUSTIC_FUZZ_FORK_JOBS: parallel fork-mode jobs (default 1; -runs counts all of them together).
fork="-fork=${CAUSTIC_FUZZ_FORK_JOBS:-1} -ignore_ooms=1 -ignore_crashes=1 -ignore_timeouts=1"
declare -A extra=([scene]="-dict=$fz/scene.dict" [scene_override]="-dict=$fz/scene.dict" [hdr]="" [mesh]="$fork" [mesh_common]="$fork" [mesh_open]="$fork" [image]="${CAUSTIC_FUZZ_IMAGE_FORK:+$fork}" [sheet]="-dict=$fz/sheet.dict" [part]="-dict=$fz/part.dict")
summary=()
for h in "${harnesses[@]}"; do
  log="$build/logs/$h.log"
  echo "== $h: $runs executions (log: $log)" >&2
  # ScratchDir (fuzz_common.h) writes the inputs for path-taking readers under TMPDIR.
  set +e
  # Leaks: the suppressions of the sanitizer suite (third-party code only, reasons in the file).
  ( cd "$build" && TMPDIR="${TMPDIR:-/tmp}" ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1:allocator_release_to_os_interval_ms=1000:${ASAN_OPTIONS:-}" \
    LSAN_OPTIONS="suppressions=$root/tests/sanitize/lsan.supp:print_suppressions=0:${LSAN_OPTIONS:-}" \
    "$build/tests/fuzz/caustic_fuzz_$h" -runs="$runs" -max_len="${max_len[$h]}" -timeout="${timeout[$h]}" -rss_limit_mb="${rss_limit[$h]}" \
      -malloc_limit_mb=4096 -print_final_stats=1 -artifact_prefix="$build/artifacts/$h-" ${extra[$h]} \
      "$build/corpus/$h" ) > "$log" 2>&1
  rc=$?
  set -e
  done_line="$(grep -E '^#[0-9]+.*DONE' "$log" | tail -1 || true)"
  execs="$(grep -E 'stat::number_of_executed_units' "$log" | awk '{print $2}' || true)"
  # Fork mode has no final stats: its last status line ("#<executions>: cov: ... crash: n") instead.
  [ -n "$execs" ] || { done_line="$(grep -E '^#[0-9]+: cov' "$log" | tail -1 || true)"; execs="${done_line%%:*}"; execs="${execs#\#}"; }
  summary+=("$h: rc=$rc executions=${execs:-?} ${done_line:-(no DONE line: see the log)}")
  [ $rc -eq 0 ] || { echo "!! $h failed (rc $rc): tail of $log" >&2; tail -40 "$log" >&2; }
done
printf '%s\n' "${summary[@]}"
