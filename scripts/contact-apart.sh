#!/usr/bin/env bash
# Figures of docs/contact.md, "Keeping bodies apart" (issue 31, item 7): two binaries
# (before and after) side by side on
#  1. assets/scenes/contact-spheres.toml, every step written as a frame (the scene's
#     own dt): the closest two particles of the two spheres come, in particle
#     spacings l̄ = (sphere volume / particles)^{1/3} (a little above the mean V^{1/3},
#     so the ratio errs low), and the deepest the fronts overlap (max x of the left
#     sphere less min x of the right, in λ); also at a closing speed of c_p/5;
#  2. the demo (sim only: no surfaces, previews or checkpoints): steps and the
#     simulation's wall time, the two binaries alternated REPEATS times.
#
#   scripts/contact-apart.sh OLD NEW [REPEATS] [OUT]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
old="$1"; new="$2"; repeats="${3:-3}"
out="${4:-$(mktemp -d)}"
mkdir -p "$out"
scene="$here/assets/scenes/contact-spheres.toml"
# c_p of the scene's material (E = 1 MPa, ν = 0.45, ρ = 1100): c_p/5 closing.
fifth=$(python3 -c "print(0.2*(1e6*0.55/(1.45*0.1)/1100)**0.5/2)")
for speed in 2.0 "$fifth"; do
  for which in old new; do
    bin=$old; [ "$which" = new ] && bin=$new
    name="spheres-$speed-$which"
    sed -e "s/^velocity = \[2.0, /velocity = [$speed, /" -e "s/^velocity = \[-2.0, /velocity = [-$speed, /" \
        "$scene" > "$out/$name.toml"
    # The scene's steps a frame, then one frame a step at that dt.
    "$bin" run "$out/$name.toml" -o "$out/$name-probe" --quiet --frames 1 --force
    spf=$(python3 -c "import json;m=json.load(open('$out/$name-probe/manifest.json'));print(round(0.002/m['dt']))")
    sed -i -e "s/^fps = 500.0 .*/fps = $((500 * spf)).0/" -e 's/^particles = true/particles = true\npreview = false\ncheckpoint_every = 0/' "$out/$name.toml"
    start=$(date +%s.%N)
    "$bin" run "$out/$name.toml" -o "$out/$name" --quiet --force
    echo "$name: $(python3 -c "print(f'{$(date +%s.%N) - $start:.1f}')") s wall"
  done
done
PYTHONPATH="$here/scripts" python3 - "$out" "$fifth" <<'PY'
import json, os, sys, math
from cache_ply import particles as ply
out, fifth = sys.argv[1], sys.argv[2]
lam, radius = 0.025, 0.1
for speed in ['2.0', fifth]:
    for which in ['old', 'new']:
        d = os.path.join(out, f'spheres-{speed}-{which}')
        m = json.load(open(os.path.join(d, 'manifest.json')))
        frames = sorted(os.listdir(os.path.join(d, 'particles')))
        first = ply(os.path.join(d, 'particles', frames[0]))
        n = [sum(1 for p in first if p['material'] == b) for b in (0, 1)]
        spacing = (4 / 3 * math.pi * radius ** 3 / (0.5 * (n[0] + n[1]))) ** (1 / 3)
        closest, front = math.inf, -math.inf
        for f in frames:
            ps = ply(os.path.join(d, 'particles', f))
            left = [(p['x'], p['y'], p['z']) for p in ps if p['material'] == 0]
            right = [(p['x'], p['y'], p['z']) for p in ps if p['material'] == 1]
            lf, rf = max(p[0] for p in left), min(p[0] for p in right)
            front = max(front, (lf - rf) / lam)
            band = lam
            a = [p for p in left if p[0] > rf - band]
            b = [p for p in right if p[0] < lf + band]
            for p in a:
                for q in b:
                    r = math.dist(p, q)
                    if r < closest:
                        closest = r
        print(f"closing {2 * float(speed):.2f} m/s, {which}: {m['steps']} steps of {m['dt']:.3e} s; "
              f"closest {closest * 1e3:.2f} mm = {closest / spacing:.3f} spacings (l = {spacing * 1e3:.2f} mm); "
              f"deepest front overlap {front:.2f} λ")
PY
for name in demo; do
  sed -e 's/^surface = "embedded"/surface = "none"/' \
      -e 's/^checkpoint_every = 10/checkpoint_every = 0\npreview = false/' \
      "$here/assets/scenes/$name.toml" > "$out/$name.toml"
done
for r in $(seq 1 "$repeats"); do
  for which in old new; do
    bin=$old; [ "$which" = new ] && bin=$new
    start=$(date +%s.%N)
    "$bin" run "$out/demo.toml" -o "$out/demo-$which" --quiet --force
    wall=$(python3 -c "print(f'{$(date +%s.%N) - $start:.1f}')")
    python3 - "$out/demo-$which" "$which" "$r" "$wall" <<'PY'
import json, sys
d, which, r, wall = sys.argv[1:]
m = json.load(open(d + '/manifest.json'))
t = m['timings']
step = sum(t['stages'].values()) + t['integrate_contact']
print(f"demo, repeat {r}, {which}: {m['steps']} steps of {m['dt']:.3e} s; step time {step:.1f} s "
      f"(particle contact {t['stages'].get('particle contact', 0.0):.1f} s), run {wall} s wall")
PY
  done
done
