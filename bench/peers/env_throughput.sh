#!/usr/bin/env bash
# The env-throughput peer table (bench/peers/env_throughput.py): makes
# .venv-peers/ with Meta-World v3, EnvPool (both from PyPI, with PyPI's MuJoCo)
# and this checkout's manyworlds package, then runs the measurement against the
# C++ programs of build/ (build/manyworlds and build/bench/bench_manipulation,
# from scripts/test.sh; rows that need them are left out otherwise).
# Arguments go to env_throughput.py (e.g. --rounds 5 --json out.json).
set -euo pipefail
cd "$(dirname "$0")/../.."
venv=${MANYWORLDS_PEERS_VENV:-.venv-peers}
python=${PYTHON:-/usr/bin/python3}
if [ ! -x "$venv/bin/python" ]; then
  "$python" -m venv "$venv"
fi
"$venv/bin/python" -m pip install -q --disable-pip-version-check metaworld envpool
CMAKE_BUILD_PARALLEL_LEVEL=${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)} \
  "$venv/bin/python" -m pip install -q --disable-pip-version-check . --config-settings=build-dir=build-py/peers
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1
# Private copies of the C++ programs, so that a rebuild of build/ during the
# run cannot change them halfway.
bin=$(mktemp -d)
trap 'rm -rf "$bin"' EXIT
cp build/manyworlds "$bin/" 2>/dev/null || true
cp build/bench/bench_manipulation "$bin/" 2>/dev/null || true
"$venv/bin/python" bench/peers/env_throughput.py --cli "$bin/manyworlds" \
  --bench-manipulation "$bin/bench_manipulation" "$@"
