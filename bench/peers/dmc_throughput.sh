#!/usr/bin/env bash
# The DeepMind-Control-style suites' speed table (bench/peers/dmc_throughput.py): makes
# .venv-dmc/ with dm-control from PyPI (pinned as scripts/record_dmc_rewards.py says) and runs
# the measurement against build/manyworlds and, for the Python vector-env row, the Python of
# .venv-py (scripts/python_test.sh makes it). Arguments go to dmc_throughput.py
# (e.g. --rounds 5 --json out.json).
set -euo pipefail
cd "$(dirname "$0")/../.."
venv=${MANYWORLDS_DMC_VENV:-.venv-dmc}
python=${PYTHON:-/usr/bin/python3}
if [ ! -x "$venv/bin/python" ]; then
  "$python" -m venv "$venv"
fi
"$venv/bin/python" -m pip install -q --disable-pip-version-check dm-control==1.0.50 mujoco==3.17.0
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1 MUJOCO_GL=osmesa
bin=$(mktemp -d)
trap 'rm -rf "$bin"' EXIT
cp build/manyworlds "$bin/"
ours_python=()
if [ -x .venv-py/bin/python ]; then ours_python=(--ours-python .venv-py/bin/python); fi
"$venv/bin/python" bench/peers/dmc_throughput.py --cli "$bin/manyworlds" "${ours_python[@]}" "$@"
