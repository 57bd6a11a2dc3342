#!/usr/bin/env bash
# The memory estimate against the measured peak resident memory (docs/memory.md):
# three elastic 1 × 1 × 0.1 m walls (Chen Table 1's), λ from coarse to fine, each run
# for one frame (meshing, families, a few steps, one PLY) under /usr/bin/time -v.
# Usage: scripts/memory-peak.sh [PERIFRAC_BINARY] [REPEATS]
set -euo pipefail
bin=${1:-target/release/perifrac}
repeats=${2:-2}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
printf '| λ (m) | particles | directed bonds | estimate before meshing (MiB) | estimate after meshing (MiB) | peak RSS (MiB) | estimate / peak |\n'
printf '|---|---|---|---|---|---|---|\n'
for lambda in 0.021 0.0154 0.0122; do
  cat > "$dir/wall.toml" <<TOML
[scene]
name = "wall"
duration = 0.0001
fps = 10000
gravity = [0, 0, 0]

[materials.soft]
density = 1000.0
bulk_modulus = 1.0e7
shear_modulus = 6.0e6

[[body]]
material = "soft"
resolution = $lambda
shape = { type = "box", center = [0, 0.5, 0], size = [1.0, 1.0, 0.1] }

[output]
checkpoint_every = 0
preview = false
TOML
  check=$("$bin" check "$dir/wall.toml")
  particles=$(sed -n 's/^  particles: \([0-9]*\).*/\1/p' <<<"$check")
  bonds=$(sed -n 's/^  bonds: *\([0-9]*\) directed.*/\1/p' <<<"$check")
  after=$(sed -n 's/^  memory: *\([0-9.]*\) MiB at the peak.*/\1/p' <<<"$check")
  before=$(sed -n 's/^ *\([0-9.]*\) MiB as estimated before meshing.*/\1/p' <<<"$check")
  peaks=()
  for _ in $(seq "$repeats"); do
    rm -rf "$dir/out"
    kib=$(/usr/bin/time -v "$bin" run "$dir/wall.toml" -o "$dir/out" --frames 1 --quiet 2>&1 >/dev/null \
      | sed -n 's/.*Maximum resident set size (kbytes): \([0-9]*\).*/\1/p')
    peaks+=("$(awk -v k="$kib" 'BEGIN { printf "%.0f", k / 1024 }')")
  done
  lo=$(printf '%s\n' "${peaks[@]}" | sort -n | head -1)
  hi=$(printf '%s\n' "${peaks[@]}" | sort -n | tail -1)
  ratio=$(awk -v a="$before" -v l="$lo" -v h="$hi" 'BEGIN { printf "%.2f–%.2f", a / h, a / l }')
  printf '| %s | %s | %s | %s | %s | %s–%s | %s |\n' "$lambda" "$particles" "$bonds" "$before" "$after" "$lo" "$hi" "$ratio"
done
