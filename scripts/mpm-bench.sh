#!/bin/sh
# MLS-MPM throughput (fixed corotated, APIC, f64, ≈10⁵ particles): particle-steps per
# second and the time in sort, P2G, grid update and G2P. Built with the release
# profile, as the `perifrac` binary is.
set -e
cd "$(dirname "$0")/.."
# MPM_BENCH_RESOLUTION=0.0046 gives ≈10⁶ particles.
cargo test --release -p perifrac-sim --test mpm throughput -- --ignored --nocapture --test-threads 1
