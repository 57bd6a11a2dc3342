"""Where a shot's fragments are at a frame (docs/rigid.md, "Where it stands"): per
fragment of particles/NNNN.ply, the speed of its centre of mass, its distance from the
origin in x–z (the wall's place in the demo) and its lowest point.

    python3 scripts/shot_end.py OUT/particles/0079.ply [more frames]
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
from cache_ply import particles  # noqa: E402

for path in sys.argv[1:]:
    frags = {}
    for p in particles(path):
        frags.setdefault(int(p['fragment']), []).append(p)
    rows = []
    for q in frags.values():
        m = len(q)
        v = [sum(p[k] for p in q) / m for k in ('vx', 'vy', 'vz')]
        x = [sum(p[k] for p in q) / m for k in ('x', 'y', 'z')]
        rows.append((m, math.sqrt(sum(a * a for a in v)), x, min(p['y'] for p in q)))
    n = len(rows)
    speed = sorted(r[1] for r in rows)
    moving = [r for r in rows if r[1] > 0.05]
    airborne = [r for r in rows if r[3] > 0.02]
    dist = sorted(math.hypot(r[2][0], r[2][2]) for r in rows)
    sizes = [r[0] for r in rows]
    largest = sorted(rows, key=lambda r: -r[0])[:5]
    print(f"{path}: {n} fragments ({sum(s > 100 for s in sizes)} > 100 particles, "
          f"{sum(9 <= s <= 100 for s in sizes)} of 9-100, {sum(2 <= s <= 8 for s in sizes)} of 2-8, "
          f"{sum(s == 1 for s in sizes)} single)")
    print(f"  fragment speed median {speed[n // 2]:.2f}, 90th percentile {speed[int(0.9 * n)]:.2f}, "
          f"fastest {speed[-1]:.1f} m/s; moving > 5 cm/s: {len(moving)}; lowest point 2 cm or "
          f"more above the ground: {len(airborne)}")
    print(f"  distance median {dist[n // 2]:.2f} m, 90th percentile {dist[int(0.9 * n)]:.2f} m, "
          f"farthest {dist[-1]:.1f} m; the five largest: "
          + ", ".join(f"{r[0]} at {r[1]:.2f} m/s" for r in largest))
