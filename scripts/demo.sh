#!/usr/bin/env bash
# The main job: the built-in demo scene through the whole pipeline.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo run --release -q -p perifrac -- demo -o out/demo "$@"
