#!/usr/bin/env bash
# Peak memory of `perifrac export usd` against the frames and the particles
# (docs/usd.md): a peridynamics block (a ground and a moving sphere) of 6,702
# particles (0.1 m) and of 43,410 (0.2 m) run for 31 frames, then the same cache made
# 300 and 3,000 frames long (the large block: 300) by repeating its particle files
# (hard links) and manifest entries, each exported under /usr/bin/time -v by each
# binary in turn. Usage: scripts/usd-memory.sh [PERIFRAC_BINARY ...]
set -euo pipefail
bins=("$@")
[ ${#bins[@]} -gt 0 ] || bins=(target/release/perifrac)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cat > "$dir/block.toml" <<'TOML'
[scene]
name = "usd-memory"
duration = 0.001
fps = 30000.0
gravity = [0.0, -9.81, 0.0]

[materials.m]
density = 1000.0
bulk_modulus = 1e5
shear_modulus = 1e5
critical_stretch = 0.05

[[body]]
material = "m"
shape = { type = "box", center = [0.0, 0.0, 0.0], size = [SIZE, SIZE, SIZE] }
resolution = 0.0125

[[collider]]
type = "ground"
height = -0.2

[[collider]]
type = "sphere"
center = [0.3, 0.0, 0.0]
radius = 0.02
velocity = [0.0, 0.0, 1.0]

[output]
preview = false
usd = false
checkpoint_every = 0
TOML
printf '| frames | particles | binary | stage + clips (MB) | peak RSS (MiB) | seconds |\n|---|---|---|---|---|---|\n'
for case in 0.1:30,300,3000 0.2:30,300; do
edge=${case%%:*}
lengths=${case#*:}
sed "s/SIZE/$edge/g" "$dir/block.toml" > "$dir/block_$edge.toml"
rm -rf "$dir/base"
"${bins[0]}" run "$dir/block_$edge.toml" -o "$dir/base" --quiet >/dev/null
base_frames=$(ls "$dir/base/particles" | wc -l)
for frames in ${lengths//,/ }; do
  out="$dir/f$frames"
  mkdir -p "$out/particles"
  cp "$dir/base/scene.toml" "$out/"
  for k in $(seq 1 "$frames"); do
    src=$(( (k - 1) % base_frames + 1 ))
    ln "$dir/base/particles/$(printf %04d "$src").ply" "$out/particles/$(printf %04d "$k").ply"
  done
  python3 - "$dir/base/manifest.json" "$out/manifest.json" "$frames" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
n = int(sys.argv[3])
base = len(m["frame_times"])
m["frame_times"] = [k / m["fps"] for k in range(n)]
for key in ["collider_centers", "collider_rotations"]:
    if m.get(key):
        m[key] = [m[key][k % base] for k in range(n)]
m["files"] = {}
json.dump(m, open(sys.argv[2], "w"))
PY
  for bin in "${bins[@]}"; do
    /usr/bin/time -v "$bin" export usd "$out" 2>"$dir/time.txt" >/dev/null
    rss=$(awk -F': ' '/Maximum resident/ {print $2}' "$dir/time.txt")
    wall=$(awk -F': ' '/Elapsed \(wall/ {print $2}' "$dir/time.txt")
    size=$(du -sbc "$out/cache.usd" $( [ -d "$out/usd" ] && echo "$out/usd" ) | tail -1 | cut -f1)
    particles=$(head -c 400 "$out/particles/0001.ply" | awk '/element vertex/ {print $3; exit}')
    printf '| %s | %s | %s | %.0f | %.0f | %s |\n' "$frames" "$particles" "$bin" "$(echo "$size / 1000000" | bc -l)" "$(echo "$rss / 1024" | bc -l)" "$wall"
    rm -rf "$out/usd" "$out/cache.usd"
  done
  rm -rf "$out"
done
done
