#!/usr/bin/env bash
# Issue 13: do cracks follow the lattice? A glass plate standing on the ground (the
# demo's wall, 0.4 × 0.4 × 0.05 m, λ = 0.016 m) is hit at its centre by the demo's
# steel ball at a lower speed, so that it cracks radially instead of shattering. At
# the last frame, every damaged particle (damage ≥ 0.35) more than 3λ from the impact
# point gets the direction of the crack through it: the principal axis, in the
# plate's plane, of the damaged particles within 2.5λ, kept where that cloud is
# elongated (eigenvalue ratio ≥ 4). The directions (modulo 180°) go into 12 bins of
# 15°, centred on 0°, 15°, ... (the aligned lattice's axes are 0° and 90°); the script
# prints the bins and the largest over the mean. Cracks without preferred directions
# give under 1.5×.
#
#   scripts/crack-directions.sh [PERIFRAC] [OUT] [LATTICE] [SEED] [SPEED] [HORIZON]
#
# PERIFRAC defaults to target/release/perifrac; LATTICE ("rotated" or "aligned") sets
# the plate's `lattice` key (default: the scene's default, rotated for glass); SEED
# the scene's seed (default 0); SPEED the ball's speed in m/s (default 20); HORIZON
# δ/λ (default the demo's 1.45).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${1:-$here/target/release/perifrac}"
out="${2:-$(mktemp -d)}"
lattice="${3:-}"
seed="${4:-0}"
speed="${5:-20}"
horizon="${6:-1.45}"
mkdir -p "$out"
sed -e 's/^surface = "embedded"/surface = "none"/' \
    -e 's/^checkpoint_every = 10/checkpoint_every = 0\npreview = false/' \
    -e "s/^velocity = \[0.0, 0.0, 50.0\]/velocity = [0.0, 0.0, $speed]/" \
    -e "s/^gravity = \(.*\)/gravity = \1\nseed = $seed/" \
    -e 's/^fps = 7500.0 .*/fps = 2500.0/' \
    -e "s/^horizon = 1.45 .*/horizon = $horizon/" \
    "$here/assets/scenes/demo.toml" > "$out/plate.toml"
if [ -n "$lattice" ]; then
  sed -i "s/^horizon = $horizon/&\nlattice = \"$lattice\"/" "$out/plate.toml"
fi
"$bin" run "$out/plate.toml" -o "$out/plate" --quiet --force
PYTHONPATH="$here/scripts" python3 - "$out/plate" <<'PY'
import sys
from crack_directions import directions, histogram, peak
found = directions(sys.argv[1], (0.0, 0.2))
bins = histogram(found)
print(f"{len(found)} crack directions; bins (0°, 15°, ... 165°): {bins}")
print(f"largest bin / mean = {peak(bins):.2f}" if found else "no cracks")
PY
