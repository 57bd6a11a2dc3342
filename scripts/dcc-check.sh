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
# target/dcc-venv), made on first use by scripts/dcc/venv.sh. Exit code 0: all checks
# passed; 77: the wheels cannot be installed on this platform (pip's message is
# printed); else a check failed.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
out="${1:?usage: scripts/dcc-check.sh OUT [--rests-on-colliders]}"
shift
options=("$@")
python="$("$here/dcc/venv.sh")"
"$python" "$here/dcc/usd_check.py" "$out" ${options[@]+"${options[@]}"}
python="$("$here/dcc/venv.sh" --bpy)"
"$python" "$here/dcc/blender_check.py" "$out" ${options[@]+"${options[@]}"}
