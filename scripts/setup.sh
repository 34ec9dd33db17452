#!/usr/bin/env bash
# Installs every Debian package manyworlds needs. Idempotent; nothing is downloaded from outside Debian.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libmujoco-dev libqhull-dev  # MuJoCo 2.2.2 physics (its CMake package names qhull's include dir)
  libtorch-dev             # libtorch 1.13.1 (agents)
  libopenblas0-pthread     # libtorch only *recommends* it; without it GEMM falls back to reference BLAS
  libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libspdlog-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libosmesa6-dev           # offscreen rendering
  libegl-dev libegl-mesa0  # EGL rendering (MANYWORLDS_GL=egl): headers at build time, Mesa's EGL to test it
  ffmpeg                   # video encoding for `manyworlds render`
  zlib1g-dev               # CRC-32 of checkpoint files
  ccache                   # the Python package's build reuses the main build's objects (scripts/test.sh)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update
  $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi
