#!/usr/bin/env bash
# Opens a cache the way the tools artists use would, and checks what they would see:
# Pixar's USD library (PyPI usd-core: the validator, and every time sample of
# cache.usd against the PLY and glTF files), meshio (tets/tets.pvd), and Blender
# itself (PyPI bpy, headless: File > Import > USD and glTF). See docs/usd.md.
#
#   scripts/dcc-check.sh OUT [--rests-on-colliders]
#
# --rests-on-colliders: the scene's particles rest on its mesh colliders at the last frame
# (checked in usd-core and in Blender).
#
# The Python packages go into a virtual environment, $PERIFRAC_DCC_VENV (default
# target/dcc-venv), made on first use. Exit code 0: all checks passed; 77: the wheels
# cannot be installed on this platform (pip's message is printed); else a check failed.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
out="${1:?usage: scripts/dcc-check.sh OUT [--rests-on-colliders]}"
shift
options=("$@")
venv="${PERIFRAC_DCC_VENV:-$here/../target/dcc-venv}"
python="${PYTHON:-python3}"
if [ ! -x "$venv/bin/python" ]; then
  "$python" -m venv "$venv"
fi
# usd-core, meshio and numpy install wherever CPython does; bpy only where Blender ships
# a wheel for this Python (5.0: CPython 3.11 on x86-64/arm64 Linux, macOS, Windows).
if ! "$venv/bin/python" -c "import pxr, meshio, numpy" 2>/dev/null; then
  if ! "$venv/bin/pip" install -q usd-core meshio numpy; then
    echo "SKIPPED: pip could not install usd-core/meshio on this platform" >&2
    exit 77
  fi
fi
"$venv/bin/python" "$here/dcc/usd_check.py" "$out" ${options[@]+"${options[@]}"}
if ! "$venv/bin/python" -c "import bpy" 2>/dev/null; then
  if ! "$venv/bin/pip" install -q bpy; then
    echo "SKIPPED (Blender import only): pip could not install bpy for $("$venv/bin/python" -V) on this platform" >&2
    exit 77
  fi
fi
"$venv/bin/python" "$here/dcc/blender_check.py" "$out" ${options[@]+"${options[@]}"}
