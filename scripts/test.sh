#!/usr/bin/env bash
# The whole test suite (what CI runs), plus formatting, lints and licences.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo fmt --all -- --check
cargo clippy --workspace --all-targets -q -- -D warnings
# And with the CLI's `mpi` feature (cli/src/ranks.rs); --workspace keeps the other
# crates' features as above, so only the CLI is checked again.
cargo clippy --workspace --all-targets --features perifrac/mpi -q -- -D warnings
cargo run -q -p licence-check
# The build without OpenVDB and without GL that the README promises, and the API docs
# with every warning (broken or private intra-doc links, missing docs) an error.
cargo check --workspace --all-targets --no-default-features -q
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps -q
# cli/tests/usd.rs runs scripts/dcc-check.sh: cache.usd through Pixar's usd-core
# validator and Blender's importers (PyPI usd-core, meshio, bpy in target/dcc-venv).
# With the CLI's `mpi` feature, so that `mpirun -np N perifrac run` (cli/tests/ranks.rs)
# is tested in the same build: a second build for it alone compiled the simulator
# crates again (2 minutes). A single process never starts MPI, so every other test
# runs as without it; the refusal of a build without MPI is tested by its unit test
# here and end to end by input_errors.rs in a plain `cargo test`.
cargo test --workspace --features perifrac/mpi
