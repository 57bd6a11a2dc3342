#!/usr/bin/env bash
# Issue 13, item 5: the fastest wall particle of the demo per frame, against the ball's
# 50 m/s, with how many particles exceed 100 m/s (2x) and how many of those are
# fragments of one particle. Runs the demo without surfaces or previews.
#
#   scripts/debris-speed.sh [PERIFRAC] [OUT] [LATTICE] [SEED] [chen]
#
# PERIFRAC defaults to target/release/perifrac; LATTICE ("rotated", "aligned" or
# "unstructured", or "" for the scene's default) sets the wall's `lattice` key; SEED the
# scene's seed (which turns the lattice; default 0). With `chen`, the glass is Chen's
# tension-only glass with the default contact (the demo without its
# critical_compression, ball friction and [contact] table), the unbounded case of
# docs/lattice.md.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${1:-$here/target/release/perifrac}"
out="${2:-$(mktemp -d)}"
lattice="${3:-}"
seed="${4:-0}"
variant="${5:-}"
mkdir -p "$out"
sed -e 's/^surface = "embedded"/surface = "none"/' \
    -e 's/^checkpoint_every = 10/checkpoint_every = 0\npreview = false/' \
    -e "s/^gravity = \(.*\)/gravity = \1\nseed = $seed/" \
    "$here/assets/scenes/demo.toml" > "$out/demo.toml"
if [ "$variant" = chen ]; then
  sed -i -e '/^critical_compression = /d' -e '/^friction = 0.5 /d' \
      -e '/^\[contact\]/,/^distance = /d' "$out/demo.toml"
fi
if [ -n "$lattice" ]; then
  sed -i "s/^horizon = 1.45 .*/horizon = 1.45\nlattice = \"$lattice\"/" "$out/demo.toml"
fi
"$bin" run "$out/demo.toml" -o "$out/demo" --quiet --force
PYTHONPATH="$here/scripts" python3 - "$out/demo" <<'PY'
import os, sys
d = sys.argv[1]
from cache_ply import particles as ply
for f in sorted(os.listdir(os.path.join(d, 'particles'))):
    p = ply(os.path.join(d, 'particles', f))
    size = {}
    for r in p:
        size[r['fragment']] = size.get(r['fragment'], 0) + 1
    speeds = [((r['vx'] ** 2 + r['vy'] ** 2 + r['vz'] ** 2) ** 0.5, r['fragment']) for r in p]
    top = max(s for s, _ in speeds)
    fast = [g for s, g in speeds if s > 100.0]
    lone = sum(1 for g in fast if size[g] == 1)
    print(f"{f}: max {top:.1f} m/s ({top / 50:.2f}x), {len(fast)} over 100 m/s ({lone} alone), "
          f"{len(size)} fragments ({sum(1 for c in size.values() if c == 1)} of one particle)")
PY
