#!/usr/bin/env bash
# The variance benchmark in one command (a benchmark, never a test): builds caustic if needed,
# installs Mitsuba 3 (PyPI mitsuba 3.9.1 and numpy, into .deps/bench-venv; its llvm_ad_rgb variant
# needs Debian's libllvm19), then runs tests/variance/variance.py with the arguments given, e.g.
#   tests/variance/run.sh                       # every scene, 16 spp x 8 seeds, 1024-spp references
#   tests/variance/run.sh --scenes cornell,dof --spp 64 --rr
# Results print as a table; --json FILE keeps them. docs/performance.md has the figures.
set -euo pipefail
cd "$(dirname "$0")/../.."
[ -x build/caustic ] || ./setup.sh build
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
if ! dpkg-query -W -f='${Status}' libllvm19 2>/dev/null | grep -q "install ok installed"; then
  echo "== installing libllvm19 (Mitsuba's LLVM back end)" >&2
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends libllvm19
fi
venv=.deps/bench-venv
if ! "$venv/bin/python" -c 'import mitsuba, numpy, sys; sys.exit(0 if mitsuba.__version__ == "3.9.1" else 1)' 2>/dev/null; then
  echo "== creating $venv with mitsuba 3.9.1 and numpy" >&2
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q --disable-pip-version-check mitsuba==3.9.1 numpy
fi
exec "$venv/bin/python" tests/variance/variance.py "$@"
