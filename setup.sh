#!/usr/bin/env bash
# caustic's one set-up script. On a fresh Debian 12 machine it installs what is missing (a second
# run skips what is there), builds build/caustic in Release, and then:
#   ./setup.sh          renders scenes/cornell-box.json headless and prints the image's path
#   ./setup.sh test     runs every test (ctest), as CI does
#   ./setup.sh build    only installs and builds
# Downloaded and generated third-party files go to .deps/ (git-ignored).
set -euo pipefail
cd "$(dirname "$0")"
mode=${1:-render}
case "$mode" in render|test|build) ;; *) echo "usage: $0 [render|test|build]" >&2; exit 2 ;; esac

log() { printf '== %s\n' "$*" >&2; }
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

# 1. Debian packages (shared/docs/dependencies.md says why each one and where from).
packages=(
  build-essential cmake ninja-build pkg-config python3 python3-venv
  libglm-dev nlohmann-json3-dev catch2
  libopenimageio-dev openimageio-tools libopenexr-dev
  libgl-dev libopengl-dev libegl-dev libegl-mesa0 libgl1-mesa-dri
  libglfw3-dev xvfb xauth
  libassimp-dev assimp-testmodels
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

# 2. glad2 (the OpenGL loader generator) in its own venv: PyPI's glad (v1) shares its module name.
venv=.deps/venv
if ! "$venv/bin/python" -c 'import glad, sys; sys.exit(0 if glad.__version__ == "2.0.8" else 1)' 2>/dev/null; then
  log "creating $venv with glad2==2.0.8"
  rm -rf "$venv"
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q --disable-pip-version-check glad2==2.0.8
fi

# 2b. Dear ImGui (docking) and ImGuizmo for the editor, from the imgui-bundle 1.93.0 sdist on PyPI
# (shared/docs/dependencies.md): download once, check the sha256, extract only the needed files
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

# 3. Configure and build (Release).
# Always configure (quick when nothing changed; recovers from an interrupted first configure).
log "configuring build/"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >&2
log "building"
cmake --build build -j "$(nproc)" >&2

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
