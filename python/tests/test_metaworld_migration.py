"""The README's Meta-World migration example, run with the official package and with ours.

README.md promises that a Meta-World v3 script runs with only its import changed (and, for
gymnasium.make, the namespace). The example block there (the ```python block with "# was: import
metaworld") is run as it stands with this package, and with its two marked lines put back
(`import metaworld`, "Meta-World/...") with the official package in its own virtual environment
($MANYWORLDS_METAWORLD_PYTHON, see test_metaworld_fidelity.py); both must succeed and print the
same, which the README quotes. Also: every name v3 gives a benchmark's classes looks a class up in
ours, and our Gymnasium ids never take the official "Meta-World" namespace.
"""

import json
import os
import pathlib
import re
import subprocess
import sys

import gymnasium as gym
import numpy as np
import pytest

import manyworlds
import manyworlds.benchmarks as benchmarks
from manyworlds import metaworld_gym

README = pathlib.Path(__file__).resolve().parents[2] / "README.md"
IMPORT_OURS = "import manyworlds.benchmarks as metaworld"
NAMESPACE_OURS = f'"{metaworld_gym.GYMNASIUM_NAMESPACE}/'


def metaworld_python():
    python = os.environ.get("MANYWORLDS_METAWORLD_PYTHON")
    if not python:
        pytest.skip("MANYWORLDS_METAWORLD_PYTHON is not set (scripts/python_test.sh sets it)")
    return python


def readme_example():
    text = README.read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    examples = [b for b in blocks if "# was: import metaworld" in b]
    assert len(examples) == 1, "README.md has one migration example (# was: import metaworld)"
    return text, examples[0]


def as_official(code):
    """The example with its marked lines as a Meta-World v3 script has them."""
    lines = []
    for line in code.splitlines():
        if "# was:" in line:
            line = line.replace(IMPORT_OURS, "import metaworld").replace(NAMESPACE_OURS, '"Meta-World/')
            line = line.split("# was:")[0].rstrip()
        lines.append(line)
    official = "\n".join(lines) + "\n"
    assert "manyworlds" not in official, official
    return official


def run(python, code):
    result = subprocess.run([python, "-c", code], capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, f"{python}: exit {result.returncode}\n{result.stderr[-3000:]}"
    return result.stdout


def test_readme_example_runs_with_ours_and_with_metaworld_alike():
    text, code = readme_example()
    ours = run(sys.executable, code)
    assert ours.strip(), "the example prints"
    for line in ours.strip().splitlines():
        assert f"`{line}`" in text, f"README.md does not quote the example's output line {line!r}"
    official = run(metaworld_python(), as_official(code))
    assert official == ours


def test_v3_names_look_up_our_classes():
    official = json.loads(run(metaworld_python(), """
import json
from metaworld import env_dict as d
print(json.dumps({
    "MT10": [list(d.MT10_V3), []], "MT25": [list(d.MT25_V3), []], "MT50": [list(d.MT50_V3), []],
    "ML10": [list(d.ML10_V3["train"]), list(d.ML10_V3["test"])],
    "ML25": [list(d.ML25_V3["train"]), list(d.ML25_V3["test"])],
    "ML45": [list(d.ML45_V3["train"]), list(d.ML45_V3["test"])],
    "all": list(d.ALL_V3_ENVIRONMENTS)}))
""").strip().splitlines()[-1])
    for bench, (train, test) in ((k, v) for k, v in official.items() if k != "all"):
        ours = getattr(benchmarks, bench)()
        for names, classes in ((train, ours.train_classes), (test, ours.test_classes)):
            assert len(classes) == len(names)
            for name in names:
                assert name in classes, f"{bench}: {name}"
                assert classes[name] is classes[name[: -len("-v3")]]
                assert classes.get(name) is classes[name]
    for name in official["all"]:
        assert list(benchmarks.MT1(name).train_classes) == [name]


def test_v3_and_our_names_are_one_task():
    mt10 = benchmarks.MT10()
    assert list(mt10.train_classes)[0] == "reach"
    env = mt10.train_classes["reach-v3"]()
    env.set_task(mt10.train_tasks[0]._replace(env_name="reach-v3"))
    with pytest.raises(ValueError, match="push"):
        env.set_task(next(t for t in mt10.train_tasks if t.env_name == "push")._replace(env_name="push-v3"))
    with pytest.raises(KeyError, match="not a task of this benchmark"):
        mt10.train_classes["reach-v2"]
    assert "push-v3" not in benchmarks.ML10().test_classes
    ml1 = benchmarks.ML1("pick-place-v3")
    assert ml1.test_classes["pick-place"] is ml1.test_classes["pick-place-v3"]


def test_gymnasium_ids_have_a_namespace_of_their_own():
    ours = [k for k in gym.registry if k.startswith(metaworld_gym.GYMNASIUM_NAMESPACE + "/")]
    assert sorted(k.split("/")[1] for k in ours) == sorted(
        ["MT1", "MT10", "MT25", "MT50"] + [f"{b}-{s}" for b in ("ML1", "ML10", "ML25", "ML45")
                                            for s in ("train", "test")])
    # the official package's namespace stays free for it (it registers "Meta-World/MT10", ...)
    assert not [k for k in gym.registry if k.split("/")[0] == "Meta-World"]
    manyworlds.metaworld_gym.register_envs()  # idempotent: no re-registration warning
    assert len([k for k in gym.registry if k.startswith(metaworld_gym.GYMNASIUM_NAMESPACE)]) == len(ours)


def test_gymnasium_entry_points_build_what_v3_builds():
    env = gym.make(f"{metaworld_gym.GYMNASIUM_NAMESPACE}/MT1", env_name="reach-v3", seed=0)
    obs, _ = env.reset()
    assert obs.shape == (39,)

    envs = gym.make_vec(f"{metaworld_gym.GYMNASIUM_NAMESPACE}/MT10", seed=1, use_one_hot=True)
    obs, _ = envs.reset()
    assert obs.shape == (10, 49)
    np.testing.assert_array_equal(obs[:, 39:], np.eye(10))
    envs.call("toggle_terminate_on_success", True)
    assert all(envs.get_attr("terminate_on_success"))
    envs.close()

    # ML10's test split as v3's evaluation makes it: meta-batch 20 = 4 envs per test task, 40
    # variations per task, every 4th to each env, ending at success (v3's make_ml_envs_test)
    ml10_test = f"{metaworld_gym.GYMNASIUM_NAMESPACE}/ML10-test"
    envs = gym.make_vec(ml10_test, meta_batch_size=20, total_tasks_per_cls=40, seed=2)
    assert envs.num_envs == 20
    assert all(envs.get_attr("terminate_on_success"))
    assert not any(envs.get_attr("sample_tasks_on_reset"))
    tasks = envs.get_attr("tasks")
    assert [len(t) for t in tasks] == [10] * 20
    assert [t[0].env_name for t in tasks][::4] == benchmarks.ML10_TEST_TASKS
    ml10 = benchmarks.ML10(seed=2)  # the seed picks the benchmark's variations, as in v3
    lever = [t.data for t in ml10.test_tasks if t.env_name == "lever-pull"][:40]
    assert sorted(t.data for t in tasks[16]) == sorted(lever[0::4])
    obs, _ = envs.call("sample_tasks")[0]
    assert obs.shape == (39,) and not obs[36:].any()  # goal hidden
    envs.close()

    # as in v3: 50 variations do not split over 4 envs, nor 10 train tasks over 15
    with pytest.raises(ValueError, match="total_tasks_per_cls"):
        gym.make_vec(ml10_test, meta_batch_size=20)
    with pytest.raises(ValueError, match="multiple"):
        gym.make_vec(f"{metaworld_gym.GYMNASIUM_NAMESPACE}/ML10-train", meta_batch_size=15)
    assert benchmarks.make_mt_envs("reach-v3").reset()[0].shape == (39,)
