#!/usr/bin/env bash
# Reads a cache's preview movies with decoders we did not write: Pillow for the
# animated PNG (preview/movie.png) and, where ffmpeg's ffprobe is installed, the MP4
# (preview/movie.mp4). See docs/previews.md.
#
#   scripts/movie-check.sh OUT FRAMES FPS
#
# Pillow goes into the virtual environment of scripts/dcc-check.sh ($PERIFRAC_DCC_VENV,
# default target/dcc-venv), made on first use. Exit code 0: all checks passed; 77:
# Pillow cannot be installed here (pip's message is printed); else a check failed.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
out="${1:?usage: scripts/movie-check.sh OUT FRAMES FPS}"
frames="${2:?usage: scripts/movie-check.sh OUT FRAMES FPS}"
fps="${3:?usage: scripts/movie-check.sh OUT FRAMES FPS}"
venv="${PERIFRAC_DCC_VENV:-$here/../target/dcc-venv}"
python="${PYTHON:-python3}"
# One maker of the environment at a time, as scripts/dcc/venv.sh.
mkdir -p "$(dirname "$venv")"
exec 9>"$venv.lock"
flock 9
if [ ! -x "$venv/bin/python" ]; then
  "$python" -m venv "$venv"
fi
if ! "$venv/bin/python" -c "import PIL" 2>/dev/null; then
  if ! "$venv/bin/pip" install -q pillow; then
    echo "SKIPPED: pip could not install Pillow on this platform" >&2
    exit 77
  fi
fi
flock -u 9
"$venv/bin/python" "$here/dcc/movie_check.py" "$out" "$frames" "$fps"
