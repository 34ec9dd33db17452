"""The published benchmarks' memberships and order against the official Meta-World package.

Meta-World v3's env_dict.py fixes which tasks MT10/MT25/MT50 and ML10/ML25/ML45 hold and in
which order (a task's one-hot index is its position). The official package (its own virtual
environment, $MANYWORLDS_METAWORLD_PYTHON, see test_metaworld_fidelity.py) prints its lists;
ours must be the same lists with the "-v3" suffix dropped.
"""

import json
import os
import subprocess

import pytest

import manyworlds
import manyworlds.benchmarks as benchmarks

OFFICIAL = """
import json
from metaworld import env_dict as d
strip = lambda names: [n[: -len("-v3")] for n in names]
print(json.dumps({
    "mt10": {"train": strip(d.MT10_V3), "test": []},
    "mt25": {"train": strip(d.MT25_V3), "test": []},
    "mt50": {"train": strip(d.MT50_V3), "test": []},
    "ml10": {"train": strip(d.ML10_V3["train"]), "test": strip(d.ML10_V3["test"])},
    "ml25": {"train": strip(d.ML25_V3["train"]), "test": strip(d.ML25_V3["test"])},
    "ml45": {"train": strip(d.ML45_V3["train"]), "test": strip(d.ML45_V3["test"])},
}))
"""


def test_memberships_and_order_are_the_official_packages():
    python = os.environ.get("MANYWORLDS_METAWORLD_PYTHON")
    if not python:
        pytest.skip("MANYWORLDS_METAWORLD_PYTHON is not set (scripts/python_test.sh sets it)")
    run = subprocess.run([python, "-c", OFFICIAL], timeout=300, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    assert run.returncode == 0, run.stderr[-3000:]
    official = json.loads(run.stdout.strip().splitlines()[-1])
    ours = manyworlds._core.benchmark_splits()
    assert ours == official


def test_python_lists_and_classes_follow_the_cpp_splits():
    splits = manyworlds._core.benchmark_splits()
    assert benchmarks.MT25_TASKS == splits["mt25"]["train"] and len(benchmarks.MT25_TASKS) == 25
    assert benchmarks.MT50_TASKS == splits["mt50"]["train"] and len(set(benchmarks.MT50_TASKS)) == 50
    assert benchmarks.ML45_TEST_TASKS == splits["ml45"]["test"]
    assert benchmarks.MT10_TASKS == benchmarks.MT25_TASKS[:10]
    # every listed task is a registered env
    ids = {e["id"] for e in manyworlds._core.registry_entries()}
    assert set(benchmarks.MT50_TASKS) <= ids
    assert {"mt25", "mt50", "ml25", "ml45"} <= ids


def test_ml45_has_45_train_and_5_test_classes():
    ml45 = benchmarks.ML45()
    assert list(ml45.train_classes) == benchmarks.ML45_TRAIN_TASKS
    assert list(ml45.test_classes) == benchmarks.ML45_TEST_TASKS
    assert len(ml45.train_tasks) == 45 * 50 and len(ml45.test_tasks) == 5 * 50
    env = ml45.test_classes["door-unlock"]()
    env.set_task(ml45.test_tasks[-1])
    obs, _ = env.reset()
    assert obs.shape == (39,) and not obs[36:39].any()  # goal hidden
