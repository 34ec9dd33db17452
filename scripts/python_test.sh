#!/usr/bin/env bash
# Builds and tests the Python package: installs the Debian packages it needs,
# creates a virtual environment (default .venv-py/, override with
# MANYWORLDS_VENV), pip-installs the package from this checkout (`pip install .`,
# which builds manyworlds._core with CMake into build-py/) and the test
# dependencies, and runs the pytest suite in python/tests.
#
# Test dependencies: the package's sweep extra (Ray, rliable, tensorboardX), gymnasium 1.0,
# pytest, hypothesis (test_properties.py) and Stable-Baselines3 2.4 on Debian's python3-torch
# (1.13; the venv sees it through --system-site-packages), so no CUDA wheels are downloaded.
# Where build/manyworlds exists (scripts/test.sh builds it) the determinism test also compares
# with `manyworlds rollout --json`.
# The Meta-World fidelity tests use the official package from PyPI in a second
# venv (default .venv-metaworld/, override with MANYWORLDS_METAWORLD_VENV).
# MANYWORLDS_NATIVE=ON builds the extension for this CPU (-march=native; see below).
# Idempotent; extra arguments go to pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
venv=${MANYWORLDS_VENV:-.venv-py}
python=${PYTHON:-/usr/bin/python3}

bash scripts/setup.sh
packages=(python3-dev python3-venv python3-pip python3-torch)
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

if [ ! -x "$venv/bin/python" ]; then
  "$python" -m venv --system-site-packages "$venv"
fi
pip=("$venv/bin/python" -m pip --disable-pip-version-check)
"${pip[@]}" install -q --upgrade pip
# numpy<2: Debian's torch 1.13 is built against numpy 1.x. SB3 2.4 is the last
# release that accepts torch 1.13; it needs gymnasium < 1.1. --no-deps keeps
# pip from replacing Debian's torch (which reports itself as 1.13.0a0) with
# PyPI's CUDA build.
"${pip[@]}" install -q "gymnasium>=1.0,<1.1" "numpy>=1.21,<2" "pytest>=7" "pytest-xdist>=3" \
  "hypothesis>=6" cloudpickle pandas matplotlib
"${pip[@]}" install -q --no-deps "stable-baselines3>=2.4,<2.5"

export CMAKE_BUILD_PARALLEL_LEVEL=${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}
# ccache, where installed, and MANYWORLDS_NATIVE=ON (scripts/test.sh sets it, as its main build
# has it) let this build take the main build's compiled objects instead of compiling the env
# layers again; a wheel built so is for this CPU only (the default, OFF, is portable).
build_settings=(-C "cmake.define.MANYWORLDS_NATIVE=${MANYWORLDS_NATIVE:-OFF}")
if command -v ccache > /dev/null; then
  build_settings+=(-C cmake.define.CMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
# .[sweep]: Ray (tasks and Tune), rliable and tensorboardX for manyworlds-sweep; pyarrow<21 (Ray
# Tune's) is the last that runs on numpy 1.x, which Debian's torch needs here.
"${pip[@]}" install -q ".[sweep]" "numpy>=1.21,<2" "pyarrow<21" "${build_settings[@]}"

# The official Meta-World package for the fidelity tests, in a venv of its own: metaworld 3.1
# needs gymnasium >= 1.1, Stable-Baselines3 2.4 < 1.1. Nothing of ours is installed there; the
# tests run its recorder (python/tests/fidelity/metaworld_record.py) as a subprocess, and the
# protocol test (test_metaworld_protocols.py) runs v3's evaluation functions there with our
# installed package put on its path.
metaworld_venv=${MANYWORLDS_METAWORLD_VENV:-.venv-metaworld}
if [ ! -x "$metaworld_venv/bin/python" ]; then
  "$python" -m venv "$metaworld_venv"
fi
"$metaworld_venv/bin/python" -m pip --disable-pip-version-check install -q "metaworld==3.1.1" packaging
case "$metaworld_venv" in /*) ;; *) metaworld_venv=$(pwd)/$metaworld_venv ;; esac
export MANYWORLDS_METAWORLD_PYTHON="$metaworld_venv/bin/python"

# python/manyworlds is not on sys.path here: the tests import the installed package.
# One pytest worker per core (pytest-xdist), a test file's tests on one worker (--dist
# loadfile: a module's fixtures are made once).
workers=(-n "$(nproc)" --dist loadfile)
[ "$(nproc)" -le 1 ] && workers=()
# --durations: the slowest tests named in the log, to keep the suite within CI's budget
set +e
"$venv/bin/python" -m pytest -p no:cacheprovider -q --durations=15 "${workers[@]}" python/tests "$@"
status=$?
set -e
if [ "$status" -eq 5 ]; then
  echo "python_test.sh: pytest collected no tests (exit code 5); the suite must not be empty" >&2
  exit 1
fi
exit "$status"
