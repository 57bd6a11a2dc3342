#!/usr/bin/env bash
# Figures of docs/embedded.md ("Defects of the split mesh", issue 13 item 4): inverted
# tets of the split tet mesh per frame and their worst volume, the longest crack-
# triangle edge of the smoothed surface in λ, what the smoothing backed off, the cracks'
# zig-zag before and after smoothing; and the tilted planar cut's distance from its plane
# after smoothing (surface/tests/embedded.rs).
#
#   scripts/crack-quality.sh [full|reduced] [OUT]
#
# `full` runs the demo scene as shipped (assets/scenes/demo.toml); `reduced` (the
# default) the same scene with λ = 0.02 m and 10 frames, a few minutes on 2 cores.
# Both without previews or USD.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
size="${1:-reduced}"
out="${2:-$here/out/crack-quality-$size}"
mkdir -p "$out"
cd "$here"
cargo build --release -q -p perifrac --no-default-features
cargo build --release -q -p perifrac-surface --no-default-features --example crack_quality
target="$(cargo metadata --format-version 1 --no-deps | python3 -c 'import json,sys; print(json.load(sys.stdin)["target_directory"])')"
scene="$out/demo-$size.toml"
edits=(-e 's/^checkpoint_every = 10/checkpoint_every = 0\npreview = false\nusd = false/')
if [[ "$size" == reduced ]]; then
  edits+=(-e 's/^name = "demo"/name = "demo-reduced"/'
          -e 's/^fps = 7500.0 .*/fps = 2500.0/'
          -e 's/^resolution = 0.016 .*/resolution = 0.02/')
elif [[ "$size" != full ]]; then
  echo "usage: scripts/crack-quality.sh [full|reduced] [OUT]" >&2
  exit 2
fi
sed "${edits[@]}" assets/scenes/demo.toml > "$scene"
"$target/release/perifrac" run "$scene" -o "$out/cache" --quiet --force
"$target/release/examples/crack_quality" "$out/cache"
cargo test -q --release -p perifrac-surface --no-default-features --test embedded -- \
  --nocapture --test-threads 1 2>&1 | grep -E "cut"
