#!/usr/bin/env bash
# Runs the C++ tests of every layer without libtorch (core, sim, classic,
# manipulation, locomotion, boxworld, envs, config, and the program without its
# torch commands) built with AddressSanitizer (leaks included) and
# UndefinedBehaviorSanitizer by clang in build-asan/ (scripts/asan_build.sh, the
# build the fuzzers share). Any report fails its test: UBSan does not recover,
# ASan and LSan end the process with an error. MuJoCo, OSMesa and the other
# system libraries are not instrumented; leaks whose every frame is inside them
# are suppressed by scripts/lsan.supp (each entry says why). Not covered: the
# torch layers (nn, rl, agents, experiments; see docs/reliability.md,
# "Sanitizers"), and the install test (it builds an outside project against
# this build's sanitized libraries, which is a packaging check, not a memory one).
#
#   scripts/sanitize.sh   # build (or bring up to date), run; exits non-zero if a test fails
#
# MANYWORLDS_JOBS sets the build's and ctest's parallel jobs (default: every
# core). The build log is build-asan/build.log.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${MANYWORLDS_JOBS:-$(nproc)}

bash scripts/asan_build.sh
export ASAN_OPTIONS="detect_leaks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export UBSAN_OPTIONS="print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$(pwd)/scripts/lsan.supp:print_suppressions=0"
ctest --test-dir build-asan --output-on-failure -j "$jobs" -E '^install\.'
