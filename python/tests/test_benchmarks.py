"""Meta-World-shaped benchmarks, and the README's Meta-World script with only its import changed."""

import json
import random

import numpy as np
import pytest

import manyworlds
import manyworlds.benchmarks as benchmarks


def test_mt10_shape():
    mt10 = benchmarks.MT10()
    assert list(mt10.train_classes) == benchmarks.MT10_TASKS
    assert len(mt10.train_tasks) == 500
    assert mt10.test_classes == {} and mt10.test_tasks == []
    assert {t.env_name for t in mt10.train_tasks} == set(benchmarks.MT10_TASKS)
    # The variations are the benchmark env's own.
    bench = manyworlds.make("mt10")
    push = dict(bench.evaluation_tasks())["push"]
    ours = [t.state for t in mt10.train_tasks if t.env_name == "push"]
    assert ours == [s["params"]["state"] for s in push]


def test_ml10_and_ml1_and_mt1_shapes():
    ml10 = benchmarks.ML10()
    assert list(ml10.train_classes) == benchmarks.ML10_TRAIN_TASKS
    assert list(ml10.test_classes) == benchmarks.ML10_TEST_TASKS
    assert len(ml10.train_tasks) == 500 and len(ml10.test_tasks) == 250
    ml1 = benchmarks.ML1("pick-place-v3")
    assert list(ml1.train_classes) == ["pick-place-v3"] == list(ml1.test_classes)
    assert len(ml1.train_tasks) == len(ml1.test_tasks) == 50
    assert {t.data for t in ml1.train_tasks}.isdisjoint({t.data for t in ml1.test_tasks})
    env = ml1.train_classes["pick-place-v3"]()
    env.set_task(ml1.test_tasks[0])
    obs, _ = env.reset()
    assert obs.shape == (39,) and np.all(obs[36:39] == 0)  # goal hidden in ML
    mt1 = benchmarks.MT1("reach", seed=1)
    assert len(mt1.train_tasks) == 50 and mt1.test_tasks == []
    assert mt1.train_tasks[0] != benchmarks.MT1("reach").train_tasks[0]


def test_set_task_checks_the_class():
    mt10 = benchmarks.MT10()
    env = mt10.train_classes["reach"]()
    with pytest.raises(ValueError, match="push"):
        env.set_task(next(t for t in mt10.train_tasks if t.env_name == "push"))
    task = next(t for t in mt10.train_tasks if t.env_name == "reach")
    env.set_task(task)
    assert env.get_task_state() == json.loads(task.data)
    assert env.max_path_length == 500


def test_readme_metaworld_script_with_only_the_import_changed():
    import manyworlds.benchmarks as metaworld  # instead of: import metaworld

    random.seed(0)
    mt10 = metaworld.MT10()
    training_envs = []
    for name, env_cls in mt10.train_classes.items():
        env = env_cls()
        task = random.choice([task for task in mt10.train_tasks if task.env_name == name])
        env.set_task(task)
        training_envs.append(env)

    for env in training_envs:
        obs, info = env.reset()
        a = env.action_space.sample()
        obs, reward, terminated, truncated, info = env.step(a)
        assert obs.shape == (39,) and 0.0 <= reward <= 10.0 and "success" in info
