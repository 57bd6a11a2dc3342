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
import math, os, sys
d = sys.argv[1]
lam, centre = 0.016, (0.0, 0.2)
from cache_ply import particles as ply
frames = sorted(os.listdir(os.path.join(d, 'particles')))
# Positions in the plate's plane at the last frame would carry the fragments' flight;
# the directions are read where the cracks formed, at the positions of frame 1.
first = ply(os.path.join(d, 'particles', frames[0]))
end = ply(os.path.join(d, 'particles', frames[-1]))
damaged = [(p['x'], p['y']) for p, q in zip(first, end) if q['damage'] >= 0.35]
cell = 2.5 * lam
grid = {}
for i, (x, y) in enumerate(damaged):
    grid.setdefault((math.floor(x / cell), math.floor(y / cell)), []).append(i)
bins = [0] * 12
used = 0
for (x, y) in damaged:
    if math.hypot(x - centre[0], y - centre[1]) < 3 * lam:
        continue
    cx, cy = math.floor(x / cell), math.floor(y / cell)
    near = [damaged[j] for a in (-1, 0, 1) for b in (-1, 0, 1)
            for j in grid.get((cx + a, cy + b), [])
            if math.hypot(damaged[j][0] - x, damaged[j][1] - y) <= cell]
    if len(near) < 6:
        continue
    mx = sum(p[0] for p in near) / len(near)
    my = sum(p[1] for p in near) / len(near)
    sxx = sum((p[0] - mx) ** 2 for p in near)
    syy = sum((p[1] - my) ** 2 for p in near)
    sxy = sum((p[0] - mx) * (p[1] - my) for p in near)
    tr, det = sxx + syy, sxx * syy - sxy * sxy
    root = math.sqrt(max(tr * tr / 4 - det, 0.0))
    big, small = tr / 2 + root, tr / 2 - root
    if small > 0 and big / small < 4:
        continue
    angle = math.degrees(0.5 * math.atan2(2 * sxy, sxx - syy)) % 180.0
    bins[int(((angle + 7.5) % 180.0) // 15.0)] += 1
    used += 1
mean = used / 12
print(f"{len(damaged)} damaged particles, {used} with a crack direction; "
      f"bins (0°, 15°, ... 165°): {bins}")
print(f"largest bin / mean = {max(bins) / mean:.2f}" if used else "no cracks")
PY
