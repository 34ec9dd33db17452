#!/usr/bin/env bash
# Downloads into .debs/ (ignored by git) the Debian packages that scripts/gpu_check.sh unpacks on
# a GPU machine that has CUDA, PyTorch and CMake but none of our packages and no network: the
# build's libraries (MuJoCo and what it loads, qhull, yaml-cpp, CLI11, nlohmann-json, zlib,
# GoogleTest, Google Benchmark), 19 files, about 4.5 MB. Not taken: libtorch (PyTorch's is
# used), OpenBLAS (PyTorch's libtorch multiplies with its own MKL) and OSMesa (rendering is left
# out of that build). Run on a Debian 12 machine with its archive (apt-get download).
#
#   scripts/gpu_debs.sh            # then carry .debs to the GPU machine with the checkout
set -euo pipefail
cd "$(dirname "$0")/.."
packages=(
  libmujoco-dev libmujoco2.2.2 libccd2 liblodepng0 libtinyxml2-9
  libqhull-dev libqhull8.0 libqhull-r8.0 libqhullcpp8.0
  libyaml-cpp-dev libyaml-cpp0.7 libcli11-dev nlohmann-json3-dev zlib1g-dev
  libgtest-dev libgmock-dev googletest libbenchmark-dev libbenchmark1debian
)
mkdir -p .debs
cd .debs
rm -f ./*.deb
apt-get download "${packages[@]}" 2>&1 | grep -v "^W: Download is performed unsandboxed" || true
count=$(ls ./*.deb 2>/dev/null | wc -l)
if [ "$count" -ne "${#packages[@]}" ]; then
  echo "gpu_debs.sh: got $count of ${#packages[@]} packages into .debs/; apt-get download failed (no Debian archive?)" >&2
  exit 1
fi
echo "gpu_debs.sh: $count packages, $(du -sh . | cut -f1), in .debs/"
