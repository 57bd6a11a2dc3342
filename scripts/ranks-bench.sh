#!/bin/sh
# Strong scaling 1 → 2 ranks on this machine against threads of one process
# (docs/ranks.md): SCENE (default assets/scenes/glass-wall.toml: 73,696 particles,
# 111 bonds each, fracturing, 0.4 ms and 313 steps a frame) for FRAMES frames, with
# checkpoints, previews, the stage and surfaces off, run as
#   1t:  one process, one thread
#   2t:  one process, two threads
#   2r:  mpirun -np 2, one thread a rank
# interleaved, REPEATS times. Prints, per run, the wall time of the command and the
# manifest's step-loop seconds (stages + integration and contact) and exchange seconds;
# then each configuration's median and spread. The last 2r run also writes OpenMPI's
# own count of the bytes each rank sent (its monitoring component, not our counter).
# Needs a build with the mpi feature: cargo build --release -p perifrac --features mpi
# Usage: scripts/ranks-bench.sh [REPEATS] [FRAMES] [SCENE]
set -eu
REPEATS=${1:-3}
FRAMES=${2:-1}
SCENE=$(realpath "${3:-$(dirname "$0")/../assets/scenes/glass-wall.toml}")
cd "$(dirname "$0")/.."
BIN=$PWD/target/release/perifrac
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
# The scene with these keys of its [output] table replaced (or added).
python3 - "$SCENE" "$WORK/wall.toml" <<'EOF'
import sys
text = open(sys.argv[1]).read()
off = {"checkpoint_every": "0", "preview": "false", "usd": "false", "surface": '"none"'}
head, sep, table = text.partition("\n[output]\n")
kept = [l for l in table.splitlines() if l.split("=")[0].strip() not in off]
keys = "".join("%s = %s\n" % kv for kv in off.items())
open(sys.argv[2], "w").write(head + "\n[output]\n" + keys + "\n".join(kept) + "\n")
EOF
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
loop_seconds() {
    python3 -c '
import json, sys
t = json.load(open(sys.argv[1]))["timings"]
print("%.2f %.2f" % (sum(t["stages"].values()) + t["integrate_contact"], t["stages"].get("exchange", 0.0)))' "$1/manifest.json"
}
run() {
    config=$1
    out="$WORK/$config"
    start=$(date +%s.%N)
    case $config in
        1t) "$BIN" run "$WORK/wall.toml" -o "$out" --force --quiet --threads 1 --frames "$FRAMES" ;;
        2t) "$BIN" run "$WORK/wall.toml" -o "$out" --force --quiet --threads 2 --frames "$FRAMES" ;;
        2r) mpirun -np 2 $MONITOR "$BIN" run "$WORK/wall.toml" -o "$out" --force --quiet \
                --threads 1 --frames "$FRAMES" ;;
    esac
    end=$(date +%s.%N)
    echo "$config $(echo "$end - $start" | bc) $(loop_seconds "$out")"
}
MONITOR=""
for r in $(seq "$REPEATS"); do
    if [ "$r" = "$REPEATS" ]; then
        MONITOR="--mca pml_monitoring_enable 2 --mca pml_monitoring_enable_output 3 \
--mca pml_monitoring_filename $WORK/traffic"
    fi
    for config in 1t 2t 2r; do
        run "$config"
    done
done | tee "$WORK/runs.txt"
cmp "$WORK/1t/particles/0002.ply" "$WORK/2r/particles/0002.ply" && echo "2r wrote the bytes of 1t"
python3 - "$WORK/runs.txt" <<'EOF'
import statistics, sys
rows = [line.split() for line in open(sys.argv[1])]
by = {}
for config, wall, loop, exchange in rows:
    by.setdefault(config, []).append((float(wall), float(loop), float(exchange)))
base = statistics.median(l for _, l, _ in by["1t"])
for config, runs in by.items():
    walls = [w for w, _, _ in runs]
    loops = [l for _, l, _ in runs]
    print("%s: wall median %.1f s (%.1f–%.1f), step loop median %.1f s (%.1f–%.1f), "
          "speed-up over 1t %.2f (%.2f–%.2f), exchange %.2f s" % (
              config, statistics.median(walls), min(walls), max(walls),
              statistics.median(loops), min(loops), max(loops),
              base / statistics.median(loops), base / max(loops), base / min(loops),
              statistics.median(e for _, _, e in runs)))
EOF
for f in "$WORK"/traffic.*.prof; do
    echo "$(basename "$f"): $(grep '^C' "$f")"
done
