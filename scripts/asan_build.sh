#!/usr/bin/env bash
# The one sanitizer build, shared by scripts/fuzz.sh and scripts/sanitize.sh:
# every layer without libtorch (core, sim, classic, manipulation, locomotion,
# boxworld, envs, config, the program without its torch commands), their
# tests and the libFuzzer targets (fuzz/), compiled once by clang with
# AddressSanitizer, UndefinedBehaviorSanitizer (-fno-sanitize-recover) and
# libFuzzer's coverage instrumentation (fuzzer-no-link), -O1 -g, in build-asan/.
# One build instead of a gcc one for the tests and a clang one for the fuzzers
# saves CI a whole compile of those layers.
#
#   scripts/asan_build.sh [TARGET ...]      # configure, then build the targets (default: all)
#   scripts/asan_build.sh --configure-only  # configure only (to ask which targets exist)
#
# Needs clang (Debian: clang), which setup.sh does not install; installed here
# if missing. MANYWORLDS_JOBS sets the parallel jobs (default: every core). The
# build log is build-asan/build.log; a failed build prints its last 40 lines.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${MANYWORLDS_JOBS:-$(nproc)}

if ! command -v clang++ > /dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update && $SUDO apt-get install -y --no-install-recommends clang
fi
bash scripts/setup.sh
launcher=()
if command -v ccache > /dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
sanitizers="-fsanitize=address,undefined -fno-sanitize-recover=undefined"
mkdir -p build-asan
# -O1: sanitizer reports keep their lines, the build is faster than at -O2, and 20 s of fuzzing
# needs no more speed. The coverage instrumentation (fuzzer-no-link) costs the tests little and
# guides the fuzzers through our libraries; only the fuzz targets link libFuzzer itself.
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
  -DCMAKE_CXX_COMPILER=clang++ "${launcher[@]}" \
  -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link $sanitizers -fno-omit-frame-pointer" \
  -DCMAKE_EXE_LINKER_FLAGS="$sanitizers" -DCMAKE_SHARED_LINKER_FLAGS="$sanitizers" \
  -DMANYWORLDS_FUZZ=ON -DMANYWORLDS_WITH_TORCH=OFF -DMANYWORLDS_BUILD_TESTS=ON \
  -DMANYWORLDS_BUILD_BENCHMARKS=OFF -DMANYWORLDS_NATIVE=OFF > build-asan/build.log
[ "${1:-}" = "--configure-only" ] && exit 0
targets=()
if [ $# -gt 0 ]; then targets=(--target "$@"); fi
cmake --build build-asan -j "$jobs" "${targets[@]}" >> build-asan/build.log 2>&1 || {
  tail -n 40 build-asan/build.log >&2
  exit 1
}
