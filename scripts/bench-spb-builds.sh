#!/bin/sh
# Two builds of perifrac on an SPB-MPM scene, side by side: `OLD` and `NEW` are two
# `cargo build --release -p perifrac` builds (at two commits). Each repeat runs the
# scene (surfaces, previews and cache.usd off) by OLD, then by NEW, prints each run's
# total of the manifest's stage timings and the stages, and whether every particle
# frame is the same bytes in the two runs.
# Usage: scripts/bench-spb-builds.sh OLD NEW [REPEATS] [SCENE]
set -e
OLD=$1
NEW=$2
REPEATS=${3:-3}
HERE=$(cd "$(dirname "$0")/.." && pwd)
SCENE=${4:-$HERE/assets/scenes/spb-net-ball-fig6.6.toml}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
sed -e 's/^surface = .*/surface = "none"/' -e '/^preview = /d' -e '/^usd = /d' \
    -e 's/^\[output\]/[output]\npreview = false\nusd = false/' "$SCENE" >"$WORK/scene.toml"
for r in $(seq "$REPEATS"); do
    for run in old new; do
        case $run in
            old) bin=$OLD ;;
            new) bin=$NEW ;;
        esac
        "$bin" run "$WORK/scene.toml" -o "$WORK/$run" --force --quiet
        python3 - "$WORK/$run/manifest.json" "$r" "$run" <<'PY'
import json, sys
stages = json.load(open(sys.argv[1]))["timings"]["stages"]
listed = ", ".join(f"{k} {v:.2f}" for k, v in sorted(stages.items()))
print(f"{sys.argv[2]} {sys.argv[3]} {sum(stages.values()):.2f} s ({listed})")
PY
    done
    same=yes
    for f in "$WORK"/old/particles/*.ply; do
        cmp -s "$f" "$WORK/new/particles/$(basename "$f")" || same=no
    done
    echo "$r same bytes: $same"
done
