#!/usr/bin/env bash
# Renders docs/gallery/*.png: one representative frame (960×540) of each gallery scene,
# simulated with a limited frame count so each takes a few minutes on 2 cores.
# Usage: scripts/gallery.sh [OUT_DIR]   (caches go to OUT_DIR, default out/gallery)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-$root/out/gallery}"
cargo build --release -q -p perifrac --manifest-path "$root/Cargo.toml"
bin="$root/target/release/perifrac"
# Every image is the default view (framed on the action, the projectile's side).
# scene, frames to simulate, the frame shown, more render options
while read -r scene frames shown options; do
  "$bin" run "$root/assets/scenes/$scene.toml" -o "$out/$scene" --frames "$frames" --force --quiet
  # shellcheck disable=SC2086 # the options are words
  "$bin" render "$out/$scene" --frame "$shown" --size 960x540 --quiet $options
  cp "$out/$scene/preview/frame_$(printf '%04d' "$shown").png" "$root/docs/gallery/$scene.png"
  echo "docs/gallery/$scene.png: frame $shown of $frames"
done <<'LIST'
demo 30 20
jello-bullet 14 14
plastic-wall 16 16
glass-wall 12 12
thin-sheet-tear 8 9
bar-twist 8 9
figure-stretch 23 24
membrane-foil-fig4-heated 100 101 --color-by quantity
mpm-watermelon 10 11
LIST
# The demo's dailies movie (animated PNG, every frame at playback_fps), small enough
# for the README to link.
"$bin" render "$out/demo" --size 480x270 --movie --overlay --quiet
cp "$out/demo/preview/movie.png" "$root/docs/gallery/demo-movie.png"
echo "docs/gallery/demo-movie.png: the demo's $(ls "$out/demo/preview"/0*.png | wc -l) frames"
# The demo as a finished shot (5 s, the pieces rigid once they stop breaking): its
# movie, the camera following the shot, and a still of the pieces flying (frame 33,
# 0.13 s).
"$bin" run "$root/assets/scenes/demo-shot.toml" -o "$out/demo-shot" --force --quiet
"$bin" render "$out/demo-shot" --size 480x270 --movie --overlay --quiet
cp "$out/demo-shot/preview/movie.png" "$root/docs/gallery/demo-shot-movie.png"
echo "docs/gallery/demo-shot-movie.png: the demo shot's $(ls "$out/demo-shot/preview"/0*.png | wc -l) frames"
"$bin" render "$out/demo-shot" --frame 33 --size 960x540 --quiet
cp "$out/demo-shot/preview/frame_0033.png" "$root/docs/gallery/demo-shot.png"
echo "docs/gallery/demo-shot.png: frame 33 of the demo shot"
# Its last frame, on its largest piece at rest (the pieces lie up to 81 m apart).
last=$(ls "$out/demo-shot/particles" | tail -n 1)
last=${last%.ply}
"$bin" render "$out/demo-shot" --frame "$((10#$last))" --camera largest --size 960x540 --quiet
cp "$out/demo-shot/preview/frame_$last.png" "$root/docs/gallery/demo-shot-end.png"
echo "docs/gallery/demo-shot-end.png: frame $last of the demo shot, its largest piece"
# The same demo cache surfaced by the OpenVDB method instead (a copy, so the embedded
# crack surfaces stay as they are; `surface` replaces the copy's embedded surfaces).
rm -rf "$out/demo-vdb"
cp -r "$out/demo" "$out/demo-vdb"
"$bin" surface "$out/demo-vdb" --method vdb --quiet
"$bin" render "$out/demo-vdb" --frame 20 --size 960x540 --quiet
cp "$out/demo-vdb/preview/frame_0020.png" "$root/docs/gallery/demo-vdb.png"
echo "docs/gallery/demo-vdb.png: frame 20 of the demo, vdb method"
