#!/bin/sh
# The plastic/elastic step ratio of the thesis scenes (issue 33 item 4, docs/mpm.md):
# each plastic scene's first FRAMES frames, REPEATS times; from the manifest's stage
# timers, the step's cost over what it costs without its plasticity stage (the
# projection onto the yield surface and the hardening; the stress, transfers and grid
# are what an elastic step of the same scene does). The scene without its
# `plasticity` is not the comparison: it moves otherwise (an elastic watermelon
# bounces the bullet back), so its grid and its transfers cost otherwise.
# BINARIES (default: this tree's release build) lists perifrac binaries to compare;
# each repeat runs them one after the other, so a change is measured side by side.
# Usage: [BINARIES="OLD NEW"] scripts/mpm-plastic-scenes.sh [REPEATS] [SCENE:FRAMES ...]
set -e
cd "$(dirname "$0")/.."
REPEATS=${1:-2}
[ $# -gt 0 ] && shift
RUNS=${*:-assets/scenes/mpm-container-n0.toml:1 assets/scenes/mpm-container-n0.5.toml:1 assets/scenes/mpm-container-n1.toml:1 assets/scenes/mpm-snow-drop.toml:3 assets/scenes/mpm-bullet-walls.toml:2 assets/scenes/mpm-watermelon.toml:5}
if [ -z "$BINARIES" ]; then
    cargo build -q --release -p perifrac
    BINARIES=target/release/perifrac
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for run in $RUNS; do
    scene=${run%%:*}
    frames=${run##*:}
    for r in $(seq "$REPEATS"); do
        for bin in $BINARIES; do
            "$bin" run "$scene" -o "$out/run" --frames "$frames" --force --quiet
            python3 - "$out/run/manifest.json" "$(basename "$scene" .toml)" "$r" "$bin" <<'EOF'
import json, sys
m = json.load(open(sys.argv[1]))
stages = m["timings"]["stages"]
total = sum(stages.values())
plastic = stages.get("plasticity", 0.0)
print(f"{sys.argv[2]} repeat {sys.argv[3]} ({sys.argv[4]}): {m['steps']} steps, "
      f"{1e3 * total / m['steps']:.1f} ms a step, plasticity {100 * plastic / total:.0f}% of it: "
      f"plastic/elastic {total / (total - plastic):.2f}")
EOF
        done
    done
done
