#!/bin/sh
# The integral-based MPM's bonds against plain MLS-MPM, side by side, on the first
# 0.03 s (228 steps) of assets/scenes/integral-boards-fig5.6.toml: `OLD` and `NEW` are
# two builds of `perifrac` (cargo build --release -p perifrac, at two commits). Each
# repeat runs the boards plain (NEW, the bonds tables taken out: the default
# fixed-corotated stress), with the bonds by OLD, with the bonds by NEW, one after the
# other. Prints the run's total and the bonds' stage ("spb bonds" of the manifest's
# timings) in seconds.
# Usage: scripts/bench-integral-bonds.sh OLD NEW [REPEATS]
set -e
OLD=$1
NEW=$2
REPEATS=${3:-3}
HERE=$(cd "$(dirname "$0")/.." && pwd)
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
short() {
    sed -e 's/^duration = .*/duration = 0.03/' -e 's/^surface = .*/surface = "none"\npreview = false\nusd = false/' \
        "$HERE/assets/scenes/integral-boards-fig5.6.toml"
}
short >"$WORK/bonds.toml"
short | grep -v -e '^bonds = ' -e '^\[materials\..*\.mpm\]' >"$WORK/plain.toml"
for r in $(seq "$REPEATS"); do
    for run in plain old new; do
        case $run in
            plain) bin=$NEW scene=plain ;;
            old) bin=$OLD scene=bonds ;;
            new) bin=$NEW scene=bonds ;;
        esac
        rm -rf "$WORK/out"
        "$bin" run "$WORK/$scene.toml" -o "$WORK/out" >/dev/null 2>&1
        python3 -c "
import json
t = json.load(open('$WORK/out/manifest.json'))['timings']
print('$r $run', round(t['total'], 2), round(t['stages'].get('spb bonds', 0.0), 2))"
    done
done
