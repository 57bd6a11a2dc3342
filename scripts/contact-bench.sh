#!/usr/bin/env bash
# Figures of docs/contact.md (issue 12): the demo with particle contact (its share of
# the step time), the deformable-ball demo against the rigid-ball demo (broken bonds,
# fragments, the ball's exit speed), without surfaces or previews.
#
#   scripts/contact-bench.sh [PERIFRAC] [OUT]
#
# PERIFRAC defaults to target/release/perifrac. The elastic-wall throughput A/B of
# docs/contact.md is `perifrac bench throughput --particles 30000 --steps 20`, run
# alternately with the binary before and after, repeated.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${1:-$here/target/release/perifrac}"
out="${2:-$(mktemp -d)}"
mkdir -p "$out"
for name in demo demo-deformable-ball; do
  sed -e 's/^surface = "embedded"/surface = "none"/' \
      -e 's/^checkpoint_every = 10/checkpoint_every = 0\npreview = false/' \
      -e "s#\.\./meshes#$here/assets/meshes#" \
      "$here/assets/scenes/$name.toml" > "$out/$name.toml"
  "$bin" run "$out/$name.toml" -o "$out/$name" --quiet
done
PYTHONPATH="$here/scripts" python3 - "$out" <<'PY'
import json, sys, os
out = sys.argv[1]
from cache_ply import particles as ply
for name in ['demo', 'demo-deformable-ball']:
    d = os.path.join(out, name)
    m = json.load(open(os.path.join(d, 'manifest.json')))
    t = m['timings']
    stages = t['stages']
    step = sum(stages.values()) + t['integrate_contact']
    contact = stages.get('particle contact', 0.0)
    last = max(int(f[:4]) for f in os.listdir(os.path.join(d, 'particles')))
    p = ply(os.path.join(d, 'particles', f'{last:04}.ply'))
    body = 'material'
    wall = [r for r in p if r[body] == 0]
    frags = {}
    for r in wall:
        frags[r['fragment']] = frags.get(r['fragment'], 0) + 1
    big = sum(1 for c in frags.values() if c >= 10)
    damaged = sum(1 for r in wall if r['damage'] > 0.3) / len(wall)
    ball = [r for r in p if r[body] == 1]
    if ball:
        speed = sum(r['vz'] for r in ball) / len(ball)
        ball_z = sum(r['z'] for r in ball) / len(ball)
    else:
        c = m['collider_centers']
        speed = (c[-1][1][2] - c[-2][1][2]) / (m['frame_times'][-1] - m['frame_times'][-2])
        ball_z = c[-1][1][2]
    print(f"{name}: {m['steps']} steps, dt {m['dt']:.3e} s, step time {step:.1f} s (total {t['total']:.1f} s), "
          f"particle contact {contact:.1f} s = {100 * contact / step:.1f}% of the step time; "
          f"broken bonds {m['broken_bonds']}, wall fragments of >= 10 particles {big}, "
          f"wall particles with damage > 0.3: {100 * damaged:.1f}%; ball at z = {ball_z:.3f} m moving at {speed:.1f} m/s")
PY
