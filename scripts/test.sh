#!/usr/bin/env bash
# The whole test suite (what CI runs), plus formatting, lints and licences.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo fmt --all -- --check
cargo clippy --workspace --all-targets -q -- -D warnings
cargo run -q -p licence-check
cargo test --workspace
