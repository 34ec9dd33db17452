#!/usr/bin/env bash
# The main job: install dependencies, build manyworlds (Release) and run the
# demo. Extra arguments go to the demo, e.g. `scripts/main.sh episodes=3`.
# Idempotent; MANYWORLDS_BUILD_DIR picks another build directory (default build/).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${MANYWORLDS_BUILD_DIR:-build}

bash scripts/setup.sh
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j"$(nproc)" --target manyworlds
"$build_dir/manyworlds" demo configs/demo.yaml "$@"
