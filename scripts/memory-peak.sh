#!/usr/bin/env bash
# The memory estimate against the measured peak resident memory (docs/memory.md):
# three elastic 1 × 1 × 0.1 m walls (Chen Table 1's), λ from coarse to fine, each run
# for one frame (meshing, families, a few steps, one PLY) under /usr/bin/time -v;
# then MPM: an elastic 0.4 m block at four grid spacings and a wall two cells thick,
# three frames with a checkpoint at each; then the walls on 1, 2 and 4 ranks of
# `mpirun` (a binary built with `--features mpi`; each rank's peak, the largest).
# Usage: scripts/memory-peak.sh [PERIFRAC_BINARY] [REPEATS]
set -euo pipefail
bin=${1:-target/release/perifrac}
repeats=${2:-2}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# The peak resident memory (MiB) of REPEATS runs of SCENE against ESTIMATE (MiB):
# prints "LO–HI | ESTIMATE/HI–ESTIMATE/LO". Usage: measure ESTIMATE SCENE [RUN ARGS];
# with RANKS=N set, on N ranks of mpirun (one thread each), the largest rank's peak.
measure() {
  local estimate=$1 scene=$2 peaks=() lo hi launch=()
  shift 2
  if [ "${RANKS:-1}" -gt 1 ]; then
    launch=(mpirun --oversubscribe --allow-run-as-root -np "$RANKS")
    set -- "$@" --threads 1
  fi
  for _ in $(seq "$repeats"); do
    rm -rf "$dir/out"
    peaks+=("$("${launch[@]}" /usr/bin/time -v "$bin" run "$scene" -o "$dir/out" --quiet "$@" \
      2>&1 >/dev/null | sed -n 's/.*Maximum resident set size (kbytes): \([0-9]*\).*/\1/p' \
      | sort -n | tail -1 | awk '{ printf "%.1f", $1 / 1024 }')")
  done
  lo=$(printf '%s\n' "${peaks[@]}" | sort -n | head -1)
  hi=$(printf '%s\n' "${peaks[@]}" | sort -n | tail -1)
  awk -v a="$estimate" -v l="$lo" -v h="$hi" 'BEGIN { printf "%s–%s | %.2f–%.2f", l, h, a / h, a / l }'
}
printf '| λ (m) | particles | directed bonds | estimate before meshing (MiB) | estimate after meshing (MiB) | peak RSS (MiB) | estimate / peak |\n'
printf '|---|---|---|---|---|---|---|\n'
wall() {
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
resolution = $1
shape = { type = "box", center = [0, 0.5, 0], size = [1.0, 1.0, 0.1] }

[output]
checkpoint_every = 0
preview = false
TOML
}
for lambda in 0.021 0.0154 0.0122; do
  wall "$lambda"
  check=$("$bin" check "$dir/wall.toml")
  particles=$(sed -n 's/^  particles: \([0-9]*\).*/\1/p' <<<"$check")
  bonds=$(sed -n 's/^  bonds: *\([0-9]*\) directed.*/\1/p' <<<"$check")
  after=$(sed -n 's/^  memory: *\([0-9.]*\) MiB at the peak.*/\1/p' <<<"$check")
  before=$(sed -n 's/^ *\([0-9.]*\) MiB as estimated before meshing.*/\1/p' <<<"$check")
  printf '| %s | %s | %s | %s | %s | %s |\n' "$lambda" "$particles" "$bonds" "$before" "$after" \
    "$(measure "$before" "$dir/wall.toml" --frames 1)"
done

printf '\n| MPM body | particles | estimate (MiB) | of it the grid (MiB) | peak RSS (MiB) | estimate / peak |\n'
printf '|---|---|---|---|---|---|\n'
for body in "block 0.02 0.4" "block 0.0125 0.4" "block 0.008 0.4" "block 0.006 0.4" "wall 0.005 0.01"; do
  read -r kind dx thick <<<"$body"
  cat > "$dir/mpm.toml" <<TOML
[scene]
name = "mpm"
duration = 0.003
fps = 1000.0
[materials.m]
density = 1000.0
youngs_modulus = 1.0e5
poisson_ratio = 0.3
[[body]]
model = "mpm"
material = "m"
resolution = $dx
velocity = [0.0, -1.0, 0.0]
shape = { type = "box", center = [0.0, 0.5, 0.0], size = [$thick, $( [ "$kind" = wall ] && echo 0.6 || echo 0.4 ), $( [ "$kind" = wall ] && echo 0.6 || echo 0.4 )] }
[output]
preview = false
usd = false
surface = "none"
tets = false
checkpoint_every = 1
TOML
  check=$("$bin" check "$dir/mpm.toml")
  particles=$(sed -n 's/^  particles: \([0-9]*\).*/\1/p' <<<"$check")
  estimate=$(sed -n 's/^  memory: *\([0-9.]*\) MiB at the peak.*/\1/p' <<<"$check")
  grid=$(sed -n "s/.*the grid's \([0-9.]*\) MiB.*/\1/p" <<<"$check")
  printf '| %s, Δx %s m | %s | %s | %s | %s |\n' "$kind" "$dx" "$particles" "$estimate" "$grid" \
    "$(measure "$estimate" "$dir/mpm.toml")"
done

printf '\n| wall λ (m) | ranks | estimate a rank (MiB) | peak RSS of the largest rank (MiB) | estimate / peak |\n'
printf '|---|---|---|---|---|\n'
for lambda in 0.035 0.0154; do
  wall "$lambda"
  check=$("$bin" check "$dir/wall.toml")
  for ranks in 1 2 4; do
    if [ "$ranks" = 1 ]; then
      estimate=$(sed -n 's/^  memory: *\([0-9.]*\) MiB at the peak.*/\1/p' <<<"$check")
    else
      estimate=$(sed -n "s/^  ranks: .* $ranks: \([0-9.]*\)[,:].*/\1/p" <<<"$check")
    fi
    printf '| %s | %s | %s | %s |\n' "$lambda" "$ranks" "$estimate" \
      "$(RANKS=$ranks measure "$estimate" "$dir/wall.toml" --frames 1)"
  done
done
