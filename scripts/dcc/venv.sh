#!/usr/bin/env bash
# Makes (on first use) the Python virtual environment the DCC checks run in,
# $PERIFRAC_DCC_VENV (default target/dcc-venv), with usd-core, meshio and numpy, and
# with bpy when called with --bpy; prints the path of its python.
#
#   scripts/dcc/venv.sh [--bpy]
#
# Exit code 0: ready; 77: the wheels cannot be installed on this platform (pip's
# message is on stderr). usd-core, meshio and numpy install wherever CPython does; bpy
# only where Blender ships a wheel for this Python (5.0: CPython 3.11 on x86-64/arm64
# Linux, macOS, Windows).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
venv="${PERIFRAC_DCC_VENV:-$here/../../target/dcc-venv}"
python="${PYTHON:-python3}"
# Tests run side by side and each calls this: one makes the environment while the
# others wait (two `python -m venv` on one folder removed each other's python).
mkdir -p "$(dirname "$venv")"
exec 9>"$venv.lock"
flock 9
if [ ! -x "$venv/bin/python" ]; then
  "$python" -m venv "$venv" >&2
fi
imports() { "$venv/bin/python" -c "import pxr, meshio, numpy" 2>/dev/null; }
if ! imports; then
  if ! "$venv/bin/pip" install -q usd-core meshio numpy >&2; then
    echo "SKIPPED: pip could not install usd-core/meshio on this platform" >&2
    exit 77
  fi
  # Installed but not importing (a library inside a wheel gone): install them afresh.
  imports || "$venv/bin/pip" install -q --force-reinstall usd-core meshio numpy >&2
fi
if [ "${1:-}" = "--bpy" ] && ! "$venv/bin/python" -c "import bpy" 2>/dev/null; then
  if ! "$venv/bin/pip" install -q bpy >&2; then
    echo "SKIPPED (Blender): pip could not install bpy for $("$venv/bin/python" -V) on this platform" >&2
    exit 77
  fi
fi
echo "$venv/bin/python"
