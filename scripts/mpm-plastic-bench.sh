#!/bin/sh
# Plastic against elastic MLS-MPM steps, side by side: `OLD` and `NEW` are two builds
# of the `mpm` test binary (cargo test --release -p perifrac-sim --test mpm --no-run);
# each repeat runs the same block (fixed corotated, ≈10⁵ particles, thrown at the
# ground at 2 m/s so that it flows at once) elastic, Johnson–Cook, snow and
# Drucker–Prager, with the old and the new binary alternating. Prints particle-steps/s
# per run. MPM_BENCH_STEPS (default 20) sets the steps a run: at 60 nearly the whole
# block flows. MODELS picks the models (default "elastic jc snow dp").
# Usage: scripts/mpm-plastic-bench.sh OLD NEW [REPEATS]
set -e
OLD=$1
NEW=$2
REPEATS=${3:-3}
MODELS=${MODELS:-elastic jc snow dp}
JC='plasticity = { type = "johnson-cook", yield_stress = 1e3 }'
SNOW='plasticity = { type = "snow", critical_compression = 0.025, critical_stretch = 0.0075 }'
DP='plasticity = { type = "drucker-prager", friction_angle = 30 }'
for r in $(seq "$REPEATS"); do
    for bin in "$OLD" "$NEW"; do
        for model in $MODELS; do
            case $model in
                elastic) mpm="" ;;
                jc) mpm=$JC ;;
                snow) mpm=$SNOW ;;
                dp) mpm=$DP ;;
            esac
            rate=$(MPM_BENCH_MPM="$mpm" MPM_BENCH_VELOCITY=2 "$bin" throughput --ignored \
                --nocapture --test-threads 1 2>/dev/null | grep -o '[0-9.e]*e[0-9]* particle-steps/s' | cut -d' ' -f1)
            echo "$r $(basename "$bin") $model $rate"
        done
    done
done
