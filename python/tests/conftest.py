"""Shared fixtures of the manyworlds Python tests."""

import os
import pathlib
import warnings

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


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
