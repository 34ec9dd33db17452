"""Same seeds, identical arrays; and the same numbers as the C++ command line."""

import json
import subprocess

import numpy as np
import pytest

import manyworlds
from manyworlds import _core

from conftest import cli_path

# The command line's policy seed stream (apps/manyworlds/cli_util.h, kPolicySeedStream).
POLICY_SEED_STREAM = 0x706F6C696379


def trajectory(env_id, seed, task_seed, steps=300):
    env = manyworlds.make(env_id)
    obs, _ = env.reset(seed=seed, options={"task_seed": task_seed})
    env.action_space.seed(seed)
    out = [obs["env_obs"], obs["task_obs"]]
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        out += [obs["env_obs"], obs["task_obs"], np.float64(reward), np.array([terminated, truncated])]
        out += [np.array(list(info.values()))]
        if terminated or truncated:
            obs, _ = env.reset()
            out.append(obs["env_obs"])
    return out


@pytest.mark.parametrize("env_id", ["cartpole", "acrobot", "bandit", "point-nav", "pick-place", "ml10"])
def test_same_seeds_identical_arrays(env_id):
    a = trajectory(env_id, 3, 4)
    b = trajectory(env_id, 3, 4)
    assert len(a) == len(b)
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)
    c = trajectory(env_id, 3, 5)  # another task seed, another task
    assert any(not np.array_equal(x, y) for x, y in zip(a, c))


def python_rollout(env_id, seed, task_seed, episodes):
    """`manyworlds rollout --policy random` in Python: per-episode seeds as the CLI derives them."""
    env = manyworlds.make(env_id)
    core = env.unwrapped._core
    results = []
    for i in range(episodes):
        env.reset(seed=_core.mix_seed(seed, i), options={"task_seed": task_seed})
        rng = _core.Rng(_core.mix_seed(_core.mix_seed(seed, POLICY_SEED_STREAM), i))
        total, length, success = 0.0, 0, 0 if "success" in env.info_fields else None
        while True:
            action = core.sample_action(rng)
            if env.action_space.shape == ():
                action = int(action[0])
            _, reward, terminated, truncated, info = env.step(action)
            total += reward
            length += 1
            if success is not None and info["success"] > 0:
                success = 1
            if terminated or truncated:
                break
        results.append({"return": total, "length": length, "success": success})
    return results


@pytest.mark.skipif(cli_path() is None, reason="the manyworlds program is not built (build/manyworlds, or set MANYWORLDS_CLI)")
@pytest.mark.parametrize("env_id", ["cartpole", "bandit", "two-goal-maze", "point-nav", "acrobot", "reach"])
def test_equal_to_the_command_line_rollout(env_id):
    seed, task_seed, episodes = 7, 3, 3
    out = subprocess.run(
        [cli_path(), "rollout", "--env", env_id, "--episodes", str(episodes), "--seed", str(seed),
         "--task-seed", str(task_seed), "--json"],
        capture_output=True, text=True, check=True,
    ).stdout
    expected = json.loads(out)["episodes"]
    assert python_rollout(env_id, seed, task_seed, episodes) == expected
