#!/usr/bin/env bash
# Installs dependencies, builds everything with tests (Release) and runs the
# whole test suite. Idempotent; MANYWORLDS_BUILD_DIR picks another build
# directory (default build/).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${MANYWORLDS_BUILD_DIR:-build}

bash scripts/setup.sh
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DMANYWORLDS_BUILD_TESTS=ON
cmake --build "$build_dir" -j"$(nproc)"
ctest --test-dir "$build_dir" --output-on-failure -j2
