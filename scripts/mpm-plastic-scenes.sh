#!/bin/sh
# The plastic/elastic step ratio of the thesis scenes (issue 33 item 4, docs/mpm.md):
# each plastic scene's first FRAMES frames, as written and with its `plasticity`
# lines removed (the same particles, grid and steps, elastic), alternating, REPEATS
# times; prints each run's particle-steps/s from the mpm test harness (no surfaces,
# no previews). The elastic copies sit beside the scenes (their mesh paths are
# relative) and are removed at the end.
# Usage: scripts/mpm-plastic-scenes.sh [REPEATS] [SCENE:FRAMES ...]
set -e
cd "$(dirname "$0")/.."
REPEATS=${1:-2}
[ $# -gt 0 ] && shift
RUNS=${*:-assets/scenes/mpm-container-n0.toml:1 assets/scenes/mpm-snow-drop.toml:3 assets/scenes/mpm-bullet-walls.toml:2 assets/scenes/mpm-watermelon.toml:5}
cargo test -q --release -p perifrac-sim --test mpm --no-run 2>/dev/null
copies=""
trap 'rm -f $copies' EXIT
rate() {
    MPM_SCENE="$PWD/$1" MPM_SCENE_FRAMES="$2" cargo test -q --release -p perifrac-sim --test mpm \
        scene_run -- --ignored --nocapture 2>/dev/null | grep -o '[0-9.e+]* particle-steps/s' | cut -d' ' -f1
}
for run in $RUNS; do
    scene=${run%%:*}
    frames=${run##*:}
    elastic="${scene%.toml}.elastic-copy.toml"
    grep -v '^plasticity *=' "$scene" > "$elastic"
    copies="$copies $elastic"
    for r in $(seq "$REPEATS"); do
        p=$(rate "$scene" "$frames")
        e=$(rate "$elastic" "$frames")
        echo "$(basename "$scene" .toml) repeat $r: plastic $p, elastic $e particle-steps/s, ratio $(awk "BEGIN { printf \"%.2f\", $e / $p }")"
    done
done
