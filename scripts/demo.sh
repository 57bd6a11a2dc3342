#!/usr/bin/env bash
# The main job: the built-in demo scene through the whole pipeline.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
# A rerun replaces the previous demo cache, unless asked to --resume it.
replace=(--force)
for arg in "$@"; do [[ "$arg" == --resume || "$arg" == --force ]] && replace=(); done
cargo run --release -q -p perifrac -- demo -o out/demo "${replace[@]}" "$@"
