#!/usr/bin/env bash
# Installs the system packages perifrac needs (Debian, as root or with sudo), once.
# Called by scripts/demo.sh and scripts/test.sh; safe to run again (it only installs
# what is missing).
set -euo pipefail

packages=(
  # Build tools for the C++ OpenVDB shim and -sys crates.
  build-essential pkg-config
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "perifrac setup: installing ${missing[*]}" >&2
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
if ! command -v cargo >/dev/null 2>&1; then
  echo "perifrac setup: cargo is not on PATH; install the Rust toolchain (rustup) first" >&2
  exit 1
fi
