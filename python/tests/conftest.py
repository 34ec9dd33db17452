"""Shared fixtures of the manyworlds Python tests."""

import fcntl
import json
import os
import pathlib
import subprocess
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


@pytest.fixture(scope="session")
def metaworld_records(tmp_path_factory):
    """The official package's steps of all 50 tasks, rows per reward version ("v2", "v1"), and
    their observation bounds ("spaces"): python/tests/fidelity/metaworld_record.py, run once
    per test session. Under pytest-xdist the workers share one recording (the first to ask
    makes it, under a lock; the others read it): building each task's MT1 benchmark is most of
    the recorder's minutes, and the v2 and v1 fidelity files would build it twice."""
    python = os.environ.get("MANYWORLDS_METAWORLD_PYTHON")
    if not python:
        pytest.skip("MANYWORLDS_METAWORLD_PYTHON is not set (scripts/python_test.sh sets it)")
    import manyworlds.benchmarks as mb

    run = os.environ.get("PYTEST_XDIST_TESTRUNUID")  # the same in every worker of this session
    base = tmp_path_factory.getbasetemp()
    shared = base.parent / f"metaworld-{run}" if run else base / "metaworld"
    shared.mkdir(exist_ok=True)
    out = shared / "records.json"
    with open(shared / "lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not out.exists():
            partial = shared / "records.json.partial"
            recorder = REPO / "python" / "tests" / "fidelity" / "metaworld_record.py"
            done = subprocess.run([python, str(recorder), "--tasks", ",".join(mb.MT50_TASKS),
                                   "--goals", "3", "--steps", "150", "--seed", "7",
                                   "--reward-versions", "v2,v1", "--observation-spaces",
                                   "--out", str(partial)],
                                  timeout=1800, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                  text=True)
            assert done.returncode == 0, f"the recorder failed:\n{done.stderr[-3000:]}"
            partial.rename(out)
        return json.loads(out.read_text())
