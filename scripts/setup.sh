#!/usr/bin/env bash
# Installs the system packages perifrac needs (Debian, as root or with sudo), once.
# Called by scripts/demo.sh and scripts/test.sh; safe to run again (it only installs
# what is missing).
set -euo pipefail

packages=(
  # Build tools for the C++ OpenVDB shim and -sys crates.
  build-essential pkg-config
  # OpenVDB 10 for the surface stage's `openvdb` feature (surface/openvdb-sys). Its
  # headers include Boost, which the package does not pull in; Debian ships no
  # pkg-config file, so the shim names its libraries (openvdb, Imath-3_1, tbb) itself.
  libopenvdb-dev libboost-dev
  # vdb_print: an independent reader of the .vdb files, used by the surface tests.
  libopenvdb-tools
  # Mesa's software OpenGL (llvmpipe) for the render stage's `gl` feature: EGL with the
  # surfaceless platform (no display), and OSMesa as the fallback. Both are loaded at
  # run time, so a missing library is reported by name instead of failing to start.
  libegl1 libegl-mesa0 libgl1-mesa-dri libegl-dev libosmesa6-dev
  # ffmpeg: `perifrac render --movie` encodes the H.264 MP4 with it when it is on the
  # PATH (a separate program, not linked), and the tests read the MP4 back with its
  # ffprobe.
  ffmpeg
  # node runs the Khronos glTF validator (npm package gltf-validator) in the tests.
  nodejs
  # OpenMPI for the CLI's optional `mpi` feature (`mpirun -np N perifrac run`), which
  # the tests build: its headers and mpicc for rsmpi's build, mpirun, and libclang
  # for the bindgen that reads the headers.
  libopenmpi-dev openmpi-bin libclang-dev
)
# Node.js builds from other sources bundle npm (and conflict with Debian's package).
command -v npm >/dev/null 2>&1 || packages+=(npm)

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
# The Khronos glTF validator (npm package gltf-validator, Apache-2.0) that the tests
# run over the .glb files we write, into tools/gltf-validator/node_modules.
validator="$(cd "$(dirname "$0")/.." && pwd)/tools/gltf-validator"
if [ ! -f "$validator/node_modules/gltf-validator/package.json" ]; then
  echo "perifrac setup: installing the glTF validator (npm)" >&2
  npm ci --prefix "$validator" --no-audit --no-fund --loglevel=error
fi
if ! command -v cargo >/dev/null 2>&1; then
  echo "perifrac setup: cargo is not on PATH; install the Rust toolchain (rustup) first" >&2
  exit 1
fi
