#!/usr/bin/env bash
# Builds every layer without libtorch (core, sim, classic, manipulation,
# locomotion, envs, config, and the program without its torch commands) and
# their tests with AddressSanitizer (leaks included) and UndefinedBehavior-
# Sanitizer in build-asan/, then runs the tests with ctest. Any report fails
# its test: UBSan does not recover, ASan and LSan end the process with an
# error. MuJoCo, OSMesa and the other system libraries are not instrumented;
# leaks whose every frame is inside them are suppressed by scripts/lsan.supp
# (each entry says why). Not covered: the torch layers (nn, rl, agents,
# experiments; see docs/reliability.md, "Sanitizers"), and the install test
# (it builds an outside project against this build's sanitized libraries,
# which is a packaging check, not a memory one).
#
#   scripts/sanitize.sh   # configure, build, run; exits non-zero if a test fails
#
# MANYWORLDS_JOBS sets the build's and ctest's parallel jobs (default: every
# core). The build log is build-asan/build.log.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${MANYWORLDS_JOBS:-$(nproc)}

bash scripts/setup.sh
flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
mkdir -p build-asan
# -O1: sanitizer reports keep their lines, and the build is faster than at -O2
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DMANYWORLDS_WITH_TORCH=OFF -DMANYWORLDS_BUILD_TESTS=ON -DMANYWORLDS_BUILD_BENCHMARKS=OFF \
  -DMANYWORLDS_NATIVE=OFF > build-asan/build.log
cmake --build build-asan -j "$jobs" >> build-asan/build.log 2>&1 || {
  tail -n 40 build-asan/build.log >&2
  exit 1
}
export ASAN_OPTIONS="detect_leaks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export UBSAN_OPTIONS="print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$(pwd)/scripts/lsan.supp:print_suppressions=0"
ctest --test-dir build-asan --output-on-failure -j "$jobs" -E '^install\.'
