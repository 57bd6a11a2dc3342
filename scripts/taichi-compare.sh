#!/bin/sh
# perifrac's MLS-MPM against Taichi's, side by side (a benchmark, not a test).
#
# Both run the same problem: a 0.4 × 0.2 × 0.16 m block on a slip ground under gravity,
# 8 particles a cell, quadratic B-splines, APIC, fixed corotated elasticity, the same
# stable step; Taichi on its CPU backend in f32 with one dense grid
# (scripts/taichi_mpm3d.py), perifrac in f64 on its sparse grid (the ignored test
# `throughput` in sim/tests/mpm.rs, built with the release profile like the binary). The runs are interleaved (perifrac, Taichi,
# perifrac, …) so that the load of a shared machine falls on both alike; the script
# prints every run and the ratio perifrac/Taichi as median and range.
#
# Usage: scripts/taichi-compare.sh [DX] [REPEATS] [STEPS]
#   DX 0.01 is ≈ 1.0e5 particles, 0.0046 ≈ 1.0e6. Default 0.01, 5 repeats, 20 steps.
# Taichi is installed on demand into target/taichi-venv (PyPI `taichi`).
set -e
cd "$(dirname "$0")/.."
DX=${1:-0.01}
REPEATS=${2:-5}
STEPS=${3:-20}
THREADS=${THREADS:-2}
VENV=${CARGO_TARGET_DIR:-target}/taichi-venv
if [ ! -x "$VENV/bin/python" ] || ! "$VENV/bin/python" -c "import taichi" 2>/dev/null; then
    python3 -m venv "$VENV"
    "$VENV/bin/pip" install --quiet taichi
fi
export MPM_BENCH_RESOLUTION="$DX" MPM_BENCH_STEPS="$STEPS" RAYON_NUM_THREADS="$THREADS"
cargo test -q --release -p perifrac-sim --test mpm --no-run 2>/dev/null
OUT=$(mktemp)
i=0
while [ "$i" -lt "$REPEATS" ]; do
    cargo test -q --release -p perifrac-sim --test mpm throughput -- --ignored --nocapture --test-threads 1 \
        | grep "particle-steps/s" | sed 's/^/perifrac /' | tee -a "$OUT"
    "$VENV/bin/python" scripts/taichi_mpm3d.py "$DX" "$STEPS" "$THREADS" 2>/dev/null \
        | grep "particle-steps/s" | tee -a "$OUT"
    i=$((i + 1))
done
python3 - "$OUT" <<'PY'
import re, statistics, sys
rates = {"perifrac": [], "taichi": []}
for line in open(sys.argv[1]):
    who = line.split()[0]
    rates[who].append(float(re.search(r"([0-9.e+]+) particle-steps/s", line).group(1)))
p, t = rates["perifrac"], rates["taichi"]
ratios = [a / b for a, b in zip(p, t)]
print(f"perifrac: median {statistics.median(p):.3e} particle-steps/s (range {min(p):.3e}–{max(p):.3e})")
print(f"taichi:   median {statistics.median(t):.3e} particle-steps/s (range {min(t):.3e}–{max(t):.3e})")
print(f"perifrac/taichi, interleaved pairs: median {statistics.median(ratios):.2f} (range {min(ratios):.2f}–{max(ratios):.2f}, {len(ratios)} pairs)")
PY
rm -f "$OUT"
