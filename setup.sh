#!/usr/bin/env bash
# caustic's one set-up script. On a fresh Debian 12 machine it installs what is missing (a second
# run skips what is there), builds in Release what the mode runs, and then:
#   ./setup.sh          builds only build/caustic, renders scenes/cornell-box.json headless and
#                       prints the image's path
#   ./setup.sh test     builds everything and runs every test (ctest), as CI does
#   ./setup.sh build    only installs and builds everything
# Downloaded and generated third-party files go to .deps/ (git-ignored).
set -euo pipefail
cd "$(dirname "$0")"
mode=${1:-render}
case "$mode" in render|test|build) ;; *) echo "usage: $0 [render|test|build]" >&2; exit 2 ;; esac

log() { printf '== %s\n' "$*" >&2; }
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

# 1. Debian packages (docs/dependencies.md says why each one and where from).
packages=(
  build-essential cmake ninja-build pkg-config python3 python3-venv
  libglm-dev nlohmann-json3-dev catch2
  libopenimageio-dev openimageio-tools libopenexr-dev
  libgl-dev libopengl-dev libegl-dev libegl-mesa0 libgl1-mesa-dri
  libglfw3-dev xvfb xauth
  libassimp-dev assimp-testmodels libpng-dev libjpeg-dev
  fonts-dejavu-core
  chromium
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  log "installing ${#missing[@]} Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# 1b. Mesa 25 from Debian's bookworm-backports (its llvmpipe is caustic's GPU where there is none).
# Debian 12's own Mesa 22.3 runs both sides of every branch and every loop body at least once for
# all 8 lanes of a SIMD group, whether or not a lane takes it; Mesa 25's llvmpipe jumps over code no
# lane of the group needs. Measured on 22 scenes: 0.98x on the Cornell box, 1.4-3.8x on the other
# 21 (docs/performance.md, "Why llvmpipe's defaults are what they are"). The same packages Debian 12 installs, from Debian's own
# archive, signed with the same key. CAUSTIC_STOCK_MESA=1 keeps Debian 12's Mesa (everything works
# on it, slower); a machine that is not Debian 12 keeps its own.
mesa_packages=(libegl-mesa0 libgl1-mesa-dri libglx-mesa0 libgbm1 mesa-libgallium)
if [ "${CAUSTIC_STOCK_MESA:-0}" != 1 ] && grep -qs '^VERSION_CODENAME=bookworm$' /etc/os-release &&
   ! dpkg --compare-versions "$(dpkg-query -W -f='${Version}' libgl1-mesa-dri 2>/dev/null || echo 0)" ge 25; then
  added=""
  if ! grep -rqs 'bookworm-backports' /etc/apt/sources.list /etc/apt/sources.list.d/; then
    # The archive the machine already uses for bookworm (a local mirror stays local).
    mirror=$(grep -rhoEs 'https?://[^ ]+/debian/?( |$)' /etc/apt/sources.list /etc/apt/sources.list.d/ |
             head -n 1 | tr -d ' ' || true)
    mirror=${mirror:-http://deb.debian.org/debian}
    added=/etc/apt/sources.list.d/caustic-bookworm-backports.list
    log "adding $mirror bookworm-backports to apt's sources (for Mesa 25)"
    echo "deb $mirror bookworm-backports main" | $SUDO tee "$added" >/dev/null
  fi
  log "installing Mesa 25 from bookworm-backports: ${mesa_packages[*]}"
  export DEBIAN_FRONTEND=noninteractive
  # Best effort: without it everything works on Debian 12's Mesa, only slower. A source that
  # cannot be fetched is removed again, so that it does not fail every later apt-get update.
  if ! { $SUDO apt-get update -q && $SUDO apt-get install -y -q --no-install-recommends -t bookworm-backports "${mesa_packages[@]}"; }; then
    log "WARNING: Mesa 25 could not be installed from bookworm-backports; keeping Debian 12's Mesa (slower llvmpipe)"
    if [ -n "$added" ]; then $SUDO rm -f "$added" && $SUDO apt-get update -q || true; fi
  fi
fi

# 2. glad2 (the OpenGL loader generator) in its own venv: PyPI's glad (v1) shares its module name.
venv=.deps/venv
if ! "$venv/bin/python" -c 'import glad, sys; sys.exit(0 if glad.__version__ == "2.0.8" else 1)' 2>/dev/null; then
  log "creating $venv with glad2==2.0.8"
  rm -rf "$venv"
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q --disable-pip-version-check glad2==2.0.8
fi

# 2b. Dear ImGui (docking) and ImGuizmo for the editor, from the imgui-bundle 1.93.0 sdist on PyPI
# (docs/dependencies.md): download once, check the sha256, extract only the needed files
# into .deps/imgui (cmake/imgui.cmake builds them). The stamp file makes a repeat run skip this.
imgui_sdist=imgui_bundle-1.93.0.tar.gz
imgui_sha=10ad1dab8258a6787b4f07bb926b08d0efc648a7906242568c8dd778c5e719bf
imgui_dir=.deps/imgui
if [ "$(cat "$imgui_dir/.stamp" 2>/dev/null)" != "$imgui_sha" ]; then
  mkdir -p .deps/downloads
  if ! echo "$imgui_sha  .deps/downloads/$imgui_sdist" | sha256sum -c --status 2>/dev/null; then
    log "downloading $imgui_sdist (PyPI sdist, 54 MB)"
    rm -f ".deps/downloads/$imgui_sdist"
    "$venv/bin/pip" download -q --disable-pip-version-check --no-deps -d .deps/downloads \
      --no-binary imgui-bundle imgui-bundle==1.93.0
    echo "$imgui_sha  .deps/downloads/$imgui_sdist" | sha256sum -c --status ||
      { echo "setup.sh: $imgui_sdist: sha256 mismatch" >&2; exit 1; }
  fi
  log "extracting Dear ImGui and ImGuizmo into $imgui_dir"
  rm -rf "$imgui_dir" && mkdir -p "$imgui_dir"
  src=imgui_bundle-1.93.0/external
  im=$src/hello_imgui/hello_imgui/external/imgui   # plain upstream docking (not the bundle's fork)
  # Flattened to .deps/imgui/imgui/{*.cpp,backends/} and .deps/imgui/imguizmo/.
  tar -xzf ".deps/downloads/$imgui_sdist" -C "$imgui_dir" \
    --transform 's,^.*/external/imgui/,imgui/,;s,^.*/ImGuizmo/ImGuizmo/src/,imguizmo/,;s,^.*/ImGuizmo/ImGuizmo/LICENSE,imguizmo/LICENSE,' \
    $im/LICENSE.txt $im/imconfig.h $im/imgui.h $im/imgui_internal.h $im/imgui.cpp $im/imgui_draw.cpp \
    $im/imgui_tables.cpp $im/imgui_widgets.cpp $im/imgui_demo.cpp $im/imstb_rectpack.h \
    $im/imstb_textedit.h $im/imstb_truetype.h \
    $im/backends/imgui_impl_glfw.cpp $im/backends/imgui_impl_glfw.h \
    $im/backends/imgui_impl_opengl3.cpp $im/backends/imgui_impl_opengl3.h \
    $im/backends/imgui_impl_opengl3_loader.h \
    $src/ImGuizmo/ImGuizmo/LICENSE $src/ImGuizmo/ImGuizmo/src/ImGuizmo.h $src/ImGuizmo/ImGuizmo/src/ImGuizmo.cpp
  echo "$imgui_sha" > "$imgui_dir/.stamp"
fi

# 2c. Intel Open Image Denoise 2.5.1 (--oidn): the libraries from the pyoidn wheel, the headers
# from the mitsuba-oidn sdist (docs/dependencies.md), sha256-checked, only the needed files,
# into .deps/oidn/{lib,include} (a CMake prefix). config.h is made from config.h.in: version
# 2.5.1, no API namespace, shared libraries. Python's zipfile extracts the wheel (no unzip needed).
oidn_whl=pyoidn-2.5.1.0-py3-none-manylinux2014_x86_64.whl
oidn_whl_sha=32ad13368f8de1ef63001942ad05b02a00cd732d1206d97f352d3a3f606d823e
oidn_sdist=mitsuba_oidn-0.1.2.tar.gz
oidn_sdist_sha=baa03e305e92709aa62fb27347ce28f00ce683df0f93d58b6056cea18909e506
oidn_dir=.deps/oidn
if [ "$(cat "$oidn_dir/.stamp" 2>/dev/null)" != "$oidn_whl_sha $oidn_sdist_sha" ]; then
  mkdir -p .deps/downloads
  fetch() {  # file sha256 pip-arguments...
    local file=$1 sha=$2; shift 2
    if ! echo "$sha  .deps/downloads/$file" | sha256sum -c --status 2>/dev/null; then
      log "downloading $file (PyPI)"
      rm -f ".deps/downloads/$file"
      "$venv/bin/pip" download -q --disable-pip-version-check --no-deps -d .deps/downloads "$@"
      echo "$sha  .deps/downloads/$file" | sha256sum -c --status ||
        { echo "setup.sh: $file: sha256 mismatch" >&2; exit 1; }
    fi
  }
  fetch "$oidn_whl" "$oidn_whl_sha" --only-binary pyoidn --platform manylinux2014_x86_64 pyoidn==2.5.1.0
  fetch "$oidn_sdist" "$oidn_sdist_sha" --no-binary mitsuba-oidn mitsuba-oidn==0.1.2
  log "extracting Open Image Denoise into $oidn_dir"
  rm -rf "$oidn_dir" && mkdir -p "$oidn_dir/include"
  python3 - ".deps/downloads/$oidn_whl" "$oidn_dir" <<'PY'
import os, sys, zipfile
wheel, dest = sys.argv[1], sys.argv[2]
keep = ("libOpenImageDenoise.so", "libOpenImageDenoise.so.2", "libOpenImageDenoise.so.2.5.1",
        "libOpenImageDenoise_core.so.2.5.1", "libOpenImageDenoise_device_cpu.so.2.5.1",
        "libOpenImageDenoise_device_cuda.so.2.5.1", "libtbb.so.12")
with zipfile.ZipFile(wheel) as z:
    for info in z.infolist():
        name = info.filename
        if not name.startswith("pyoidn/oidn/lib/") or name.endswith("/"):
            continue
        rel = name[len("pyoidn/oidn/"):]
        if not (os.path.basename(rel) in keep or rel.startswith("lib/cmake/")):
            continue
        target = os.path.join(dest, rel)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        with z.open(info) as src, open(target, "wb") as out:
            out.write(src.read())
PY
  inc=mitsuba_oidn-0.1.2/ext/oidn/include/OpenImageDenoise
  tar -xzf ".deps/downloads/$oidn_sdist" -C "$oidn_dir/include" --strip-components=4 \
    $inc/oidn.h $inc/oidn.hpp $inc/config.h.in
  sed -e 's/@OIDN_VERSION_MAJOR@/2/g; s/@OIDN_VERSION_MINOR@/5/g; s/@OIDN_VERSION_PATCH@/1/g' \
      -e 's/@OIDN_VERSION_NUMBER@/20501/g; s/@OIDN_VERSION_NOTE@//g' \
      -e 's|^#cmakedefine OIDN_API_NAMESPACE.*|/* #undef OIDN_API_NAMESPACE */|' \
      -e 's|^#cmakedefine OIDN_STATIC_LIB|/* #undef OIDN_STATIC_LIB */|' \
      -e 's|^\( *\)#cmakedefine OIDN_DEVICE_METAL|\1/* #undef OIDN_DEVICE_METAL */|' \
      -e 's|^\( *\)#cmakedefine \(OIDN_[A-Z_]*\)|\1#define \2|' \
      "$oidn_dir/include/OpenImageDenoise/config.h.in" > "$oidn_dir/include/OpenImageDenoise/config.h"
  echo "$oidn_whl_sha $oidn_sdist_sha" > "$oidn_dir/.stamp"
fi

# 2d. The render farm (app/farm, docs/farm.md): its own venv, .deps/farm-venv, with Ray, tqdm,
# numpy, flip-evaluator and the OpenEXR bindings from PyPI, and Playwright for the test that opens
# the report in Debian's chromium (installed above; Playwright's own browser download is never
# used). Versions are pinned; the stamp makes a repeat run skip the install, and a changed pin is
# installed into the existing venv (pip keeps what already matches). The package itself is
# installed editable (no dependencies) whenever the venv does not point at this checkout.
farm_venv=.deps/farm-venv
farm_pins="ray==2.60.0 tqdm==4.70.1 numpy==2.4.6 flip-evaluator==1.7 playwright==1.65.2 OpenEXR==3.5.3"
if [ "$(cat "$farm_venv/.stamp" 2>/dev/null)" != "$farm_pins" ]; then
  if [ ! -x "$farm_venv/bin/python" ]; then
    log "creating $farm_venv"
    rm -rf "$farm_venv"
    python3 -m venv "$farm_venv"
  fi
  log "installing into $farm_venv: $farm_pins (about 700 MB the first time)"
  "$farm_venv/bin/pip" install -q --disable-pip-version-check $farm_pins
  echo "$farm_pins" > "$farm_venv/.stamp"
fi
if [ "$("$farm_venv/bin/python" -c 'import caustic_farm, os; print(os.path.dirname(os.path.dirname(caustic_farm.__file__)))' 2>/dev/null)" != "$PWD/app/farm" ]; then
  log "installing app/farm (caustic-farm) into $farm_venv"
  "$farm_venv/bin/pip" install -q --disable-pip-version-check --no-deps -e app/farm
fi

# 3. Configure and build (Release).
# Always configure (quick when nothing changed; recovers from an interrupted first configure).
log "configuring build/"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >&2
# The render needs only the program (its shaders are read from the source tree); the tests need
# every target.
if [ "$mode" = render ]; then
  log "building build/caustic"
  cmake --build build -j "$(nproc)" --target caustic >&2
else
  log "building"
  cmake --build build -j "$(nproc)" >&2
fi

# 4. Render, or test.
case "$mode" in
  render)
    log "rendering scenes/cornell-box.json"
    build/caustic --scene scenes/cornell-box.json --output renders
    ;;
  test)
    log "running the tests"
    cd build && ctest --output-on-failure -j 2
    ;;
esac
