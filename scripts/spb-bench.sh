#!/bin/sh
# SPB-MPM against plain MLS-MPM on the same scene (issue 32, docs/mpm.md): the scene
# as written and the scene without its `energy_release_rate` lines, interleaved,
# REPEATS times each, surfaces and previews off. Prints, from each run's manifest,
# the steps, the particle-steps per second and the share of the step spent in the
# peridynamic stages ("spb bonds": states, failure and bond forces; "spb erosion":
# Φ, the released energy on the grid and the joins), and from its last frame how many
# particles are peridynamic.
# Usage: scripts/spb-bench.sh [REPEATS] [SCENE] [FRAMES]
set -e
cd "$(dirname "$0")/.."
REPEATS=${1:-2}
SCENE=${2:-assets/scenes/spb-net-ball-fig6.6.toml}
FRAMES=${3:-}
cargo build -q --release -p perifrac
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
sed 's/^surface = .*/surface = "none"\npreview = false/' "$SCENE" > "$out/spb.toml"
grep -v '^energy_release_rate\|^erosion_release_rate' "$out/spb.toml" > "$out/plain.toml"
for r in $(seq "$REPEATS"); do
    for kind in spb plain; do
        target/release/perifrac run "$out/$kind.toml" -o "$out/run" --force --quiet \
            ${FRAMES:+--frames "$FRAMES"}
        python3 - "$out/run" "$kind" "$r" <<'PY'
import json, os, struct, sys
run, kind, repeat = sys.argv[1:]
m = json.load(open(os.path.join(run, "manifest.json")))
stages = m["timings"]["stages"]
total = sum(stages.values())
pd = stages.get("spb bonds", 0.0) + stages.get("spb erosion", 0.0)
frames = sorted(os.listdir(os.path.join(run, "particles")))
data = open(os.path.join(run, "particles", frames[-1]), "rb").read()
end = data.index(b"end_header\n") + 11
head = data[:end].decode().splitlines()
n = int(next(l for l in head if l.startswith("element vertex")).split()[2])
names = [l.split()[2] for l in head if l.startswith("property")]
members = 0
if "region" in names:
    k, w = names.index("region"), len(names)
    values = struct.unpack("<" + "f" * (w * n), data[end:end + 4 * w * n])
    members = sum(1 for i in range(n) if values[i * w + k] == 1.0)
print(f"{kind} repeat {repeat}: {m['steps']} steps, {n} particles, "
      f"{n * m['steps'] / total:.3e} particle-steps/s, peridynamic stages "
      f"{100 * pd / total:.1f}% (bonds {100 * stages.get('spb bonds', 0) / total:.1f}%, "
      f"erosion {100 * stages.get('spb erosion', 0) / total:.1f}%), "
      f"{members} peridynamic particles ({100 * members / n:.1f}%) at the end")
PY
    done
done
