"""Shared fixtures of the manyworlds Python tests."""

import os
import pathlib
import warnings

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]

# pytest-xdist runs a worker per core: that is the suite's one layer of parallelism. The products
# of every `manyworlds` program a test starts, and of torch, take one thread each (as ctest gives
# each C++ test): two product threads per process beside the other worker spin at every barrier
# and ran the training tests several times slower (docs/benchmarks.md, "BLAS threads on a shared
# machine"). setdefault: a caller's own setting stands.
for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")


def cli_path():
    """The `manyworlds` program: $MANYWORLDS_CLI, else build/manyworlds, else None."""
    candidate = os.environ.get("MANYWORLDS_CLI") or str(REPO / "build" / "manyworlds")
    return candidate if os.path.isfile(candidate) and os.access(candidate, os.X_OK) else None


@pytest.fixture(autouse=True)
def _quiet_gymnasium_bounds_warnings():
    # Gymnasium's checker warns about infinite Box bounds, which several envs have on
    # purpose (positions, velocities); everything else still shows.
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*infinity.*")
        warnings.filterwarnings("ignore", message=".*maximum and minimum values are equal.*")
        warnings.filterwarnings("ignore", message=".*Not able to test alternative render modes.*")
        yield
