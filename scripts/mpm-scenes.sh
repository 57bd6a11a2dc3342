#!/bin/sh
# Runs the MPM scenes after Lyu's Table 7.1 (assets/scenes/mpm-*.toml) without
# surfaces or previews and prints each one's wall time, steps, throughput and what
# its last frame holds (mean and max ε^p, the range of J, each body's mean velocity).
# Usage: scripts/mpm-scenes.sh [FRAMES] [SCENE...]  (FRAMES empty or "all": to the end)
set -e
cd "$(dirname "$0")/.."
FRAMES=${1:-all}
[ $# -gt 0 ] && shift
SCENES=${*:-assets/scenes/mpm-*.toml}
cargo test -q --release -p perifrac-sim --test mpm --no-run 2>/dev/null
for scene in $SCENES; do
    if [ "$FRAMES" = all ]; then unset MPM_SCENE_FRAMES; else export MPM_SCENE_FRAMES="$FRAMES"; fi
    MPM_SCENE="$PWD/$scene" cargo test -q --release -p perifrac-sim --test mpm scene_run -- --ignored --nocapture \
        | sed "s/^test scene_run ... //" | grep -v "^running\|^$\|test result\|^ok$"
done
