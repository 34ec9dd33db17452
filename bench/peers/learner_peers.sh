#!/usr/bin/env bash
# The learner peer table (bench/peers/learner_peers.py): manyworlds' SAC update,
# PPO epoch and PPO training run against plain PyTorch in Python and
# Stable-Baselines3, interleaved. Prepares the Pythons it compares:
# - Debian's python3-torch (1.13) through /usr/bin/python3 (apt-get if missing);
# - .venv-py/ (scripts/python_test.sh makes it: SB3 2.4 on Debian's torch and
#   this checkout's package), made by running python_test.sh if it is missing;
# - .venv-torch/ (override with MANYWORLDS_TORCH_VENV): PyPI's torch, the CPU
#   wheel from download.pytorch.org when that index is reachable, else PyPI's
#   default wheel (a CUDA build, ~5 GB installed, run on the CPU here), with
#   the current Stable-Baselines3 and Gymnasium and this checkout's package
#   (built in build-py/torch-venv).
# Needs build/manyworlds (scripts/test.sh). Arguments go to learner_peers.py
# (e.g. --rounds 5 --json out.json).
set -euo pipefail
cd "$(dirname "$0")/../.."
python=${PYTHON:-/usr/bin/python3}
venv=${MANYWORLDS_TORCH_VENV:-.venv-torch}

if ! "$python" -c "import torch" 2>/dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends python3-torch
fi
[ -x .venv-py/bin/python ] || bash scripts/python_test.sh -q -x
if [ ! -x "$venv/bin/python" ]; then
  "$python" -m venv "$venv"
fi
pip=("$venv/bin/python" -m pip --disable-pip-version-check)
if ! "$venv/bin/python" -c "import torch" 2>/dev/null; then
  "${pip[@]}" install -q --retries 1 --timeout 15 torch --index-url https://download.pytorch.org/whl/cpu \
    || { echo "learner_peers.sh: download.pytorch.org not reachable; PyPI's default torch wheel instead" >&2;
         "${pip[@]}" install -q torch; }
fi
"${pip[@]}" install -q stable-baselines3 "gymnasium>=1.0"
CMAKE_BUILD_PARALLEL_LEVEL=${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)} \
  "${pip[@]}" install -q . --config-settings=build-dir=build-py/torch-venv
exec "$python" bench/peers/learner_peers.py --pypi-python "$venv/bin/python" \
  --sb3-pypi-python "$venv/bin/python" "$@"
