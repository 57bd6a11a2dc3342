#!/usr/bin/env bash
# Instructions a step costs in two perifrac binaries, counted by valgrind's callgrind
# (deterministic, unlike wall time on a shared machine): the elastic wall of
# assets/scenes/elastic-wall.toml run for 0.001 s and 0.004 s on one thread, one frame
# each, no checkpoints or previews; the difference of the two runs' counts is the cost
# of the extra steps, set-up and file writing cancelling out.
#
#   scripts/instructions-ab.sh BEFORE AFTER [OUT]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
before="$1"
after="$2"
out="${3:-$(mktemp -d)}"
mkdir -p "$out"
for d in 0.001 0.004; do
  sed -e "s/^duration = 0.4 .*/duration = $d/" \
      -e "s/^fps = 60.0 .*/fps = $(python3 -c "print(1 / $d)")/" \
      -e 's/^checkpoint_every = 10/checkpoint_every = 0\npreview = false/' \
      "$here/assets/scenes/elastic-wall.toml" > "$out/wall-$d.toml"
done
count() { # binary duration name
  valgrind --tool=callgrind --callgrind-out-file="$out/cg-$3-$2.out" \
    "$1" run "$out/wall-$2.toml" -o "$out/run-$3-$2" --threads 1 --quiet --force \
    2>&1 | grep -o 'Collected : [0-9]*' | grep -o '[0-9]*$'
}
steps() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['steps'])" "$1"; }
b1=$(count "$before" 0.001 before); a1=$(count "$after" 0.001 after)
b4=$(count "$before" 0.004 before); a4=$(count "$after" 0.004 after)
n=$(( $(steps "$out/run-before-0.004/manifest.json") - $(steps "$out/run-before-0.001/manifest.json") ))
python3 - "$b1" "$b4" "$a1" "$a4" "$n" <<'PY'
import sys
b1, b4, a1, a4, n = map(int, sys.argv[1:])
before, after = (b4 - b1) / n, (a4 - a1) / n
print(f"{n} steps: {before / 1e6:.2f} M instructions a step before, {after / 1e6:.2f} M after "
      f"({100 * (after / before - 1):+.3f}%)")
PY
