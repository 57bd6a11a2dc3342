#!/usr/bin/env bash
# The whole test suite (what CI runs), plus formatting, lints and licences.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo fmt --all -- --check
cargo clippy --workspace --all-targets -q -- -D warnings
# With --workspace the dependencies keep the features of the step above (`-p perifrac`
# alone resolves them differently and rebuilds the simulator crates).
cargo clippy --workspace --all-targets --features perifrac/mpi -q -- -D warnings
cargo run -q -p licence-check
# The build without OpenVDB and without GL that the README promises, and the API docs
# with every warning (broken or private intra-doc links, missing docs) an error.
cargo check --workspace --all-targets --no-default-features -q
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps -q
# cli/tests/usd.rs runs scripts/dcc-check.sh: cache.usd through Pixar's usd-core
# validator and Blender's importers (PyPI usd-core, meshio, bpy in target/dcc-venv).
cargo test --workspace
# `mpirun -np N perifrac run` (cli/tests/ranks.rs) on a build with the `mpi` feature.
# --workspace for the same reason as the clippy step: only the CLI is built again.
cargo test --workspace --features perifrac/mpi --test ranks
