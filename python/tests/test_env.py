"""The single env: Gymnasium's checker on every registered env, spaces, seeds, task API."""

import json

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import manyworlds
from manyworlds import _core

ALL_IDS = manyworlds.env_ids()
MUJOCO_IDS = [e["id"] for e in manyworlds.registry() if e["family"] in ("manipulation", "benchmark")]


def test_registry_lists_every_suite():
    assert {"bandit", "cartpole", "point-nav", "reach", "mt10", "ml10"} <= set(ALL_IDS)
    assert len(ALL_IDS) == len(set(ALL_IDS))


@pytest.mark.parametrize("env_id", ALL_IDS)
def test_gymnasium_check_env(env_id):
    env = gym.make(f"manyworlds/{env_id}")
    check_env(env.unwrapped)
    env.close()


@pytest.mark.parametrize("env_id", ["cartpole", "bandit", "point-nav", "reach", "mt10"])
def test_gymnasium_check_env_flat(env_id):
    env = manyworlds.make(env_id, flat_obs=True)
    check_env(env)
    obs, _ = env.reset(seed=0)
    assert obs.dtype == np.float32 and obs.shape == env.observation_space.shape


def test_gymnasium_make_passes_options():
    env = gym.make("manyworlds/bandit", n_arms=3)
    assert env.action_space == gym.spaces.Discrete(3)
    assert env.unwrapped.options == {"n_arms": 3}
    # The C++ episode limit is the registry option max_episode_steps (gymnasium.make's own
    # argument of that name adds Gymnasium's TimeLimit instead; both truncate).
    for env in (manyworlds.make("point-nav", max_episode_steps=7), gym.make("manyworlds/point-nav", max_episode_steps=7)):
        env.reset(seed=0)
        steps = 0
        while True:
            steps += 1
            _, _, terminated, truncated, _ = env.step(env.action_space.sample())
            if terminated or truncated:
                break
        assert steps == 7 and truncated
    assert manyworlds.make("point-nav", max_episode_steps=7).max_episode_steps == 7


def test_recurrent_meta_obs_option_feeds_a_recurrent_policy():
    # Meta-World v3's recurrent meta-RL observation: env obs, previous action (one-hot for
    # Discrete), reward / 10, episode-end flag; zeros for the three after reset.
    env = manyworlds.make("bandit", n_arms=3, horizon=2, recurrent_meta_obs=True)
    assert env.observation_space["env_obs"].shape == (4 + 3 + 2,)
    check_env(env)
    env.set_task_state({"env": "bandit", "params": {"probs": [0.0, 1.0, 0.0]}})
    obs, _ = env.reset(seed=1)
    assert np.all(obs["env_obs"][4:] == 0)
    obs, reward, terminated, truncated, _ = env.step(1)
    np.testing.assert_allclose(obs["env_obs"], [0, 1, 0, 1, 0, 1, 0, 0.1, 0], rtol=1e-6)
    obs, *_ , truncated, _ = env.step(0)
    assert truncated and obs["env_obs"][-1] == 1.0
    scaled = manyworlds.make("point-nav", recurrent_meta_obs=True, recurrent_meta_obs_reward_scale=1.0)
    scaled.reset(seed=0)
    obs, reward, *_ = scaled.step(np.array([0.05, 0.0], dtype=np.float32))
    assert obs["env_obs"][4] == pytest.approx(reward)


def test_spaces_and_step_types():
    env = manyworlds.make("cartpole")
    assert isinstance(env.observation_space, gym.spaces.Dict)
    assert set(env.observation_space.spaces) == {"env_obs", "task_obs"}
    assert env.action_space == gym.spaces.Discrete(2)
    obs, info = env.reset(seed=3)
    assert info == {}
    assert obs in env.observation_space
    obs, reward, terminated, truncated, info = env.step(1)
    assert isinstance(reward, float) and isinstance(terminated, bool) and isinstance(truncated, bool)
    assert set(info) == set(env.info_fields) == {"success"}
    # numpy integers and 0-d arrays are Discrete actions too
    env.step(np.int64(0))
    env.step(np.array(1))

    reach = manyworlds.make("reach")
    assert reach.action_space == gym.spaces.Box(-1.0, 1.0, (4,), np.float32)
    assert reach.observation_space["env_obs"].shape == (39,)
    _, info = reach.reset()
    _, _, _, _, info = reach.step(reach.action_space.sample())
    assert "success" in info and "near_object" in info


def test_discrete_task_observation_is_a_float_box():
    env = manyworlds.make("mt10")
    space = env.observation_space["task_obs"]
    assert space == gym.spaces.Box(0.0, 9.0, (1,), np.float32)
    obs, _ = env.reset()
    assert obs["task_obs"].dtype == np.float32
    name = env.get_task_state()["params"]["task"]
    assert obs["task_obs"][0] == manyworlds.benchmarks.MT10_TASKS.index(name)


def test_reset_seed_is_the_env_seed():
    a, b = manyworlds.make("cartpole"), manyworlds.make("cartpole")
    obs_a, _ = a.reset(seed=5)
    obs_b, _ = b.reset(seed=5)
    np.testing.assert_array_equal(obs_a["env_obs"], obs_b["env_obs"])
    obs_c, _ = b.reset(seed=6)
    assert not np.array_equal(obs_a["env_obs"], obs_c["env_obs"])
    # Same task: the env seed does not change the task.
    np.testing.assert_array_equal(obs_a["task_obs"], obs_c["task_obs"])


def test_task_seed_reset_option():
    env = manyworlds.make("cartpole")
    obs1, _ = env.reset(seed=0, options={"task_seed": 1})
    task1 = env.get_task_state()
    obs2, _ = env.reset(seed=0, options={"task_seed": 2})
    assert env.get_task_state() != task1
    obs3, _ = env.reset(seed=0, options={"task_seed": 1})
    assert env.get_task_state() == task1
    np.testing.assert_array_equal(obs1["task_obs"], obs3["task_obs"])
    # The task persists across plain resets.
    env.reset()
    assert env.get_task_state() == task1
    env.reset(options={"sample_task": True})
    assert env.get_task_state() != task1
    with pytest.raises(ValueError, match="unknown reset option"):
        env.reset(options={"task_sed": 1})


def test_task_api_round_trips_through_json():
    for env_id in ["cartpole", "bandit", "tabular-mdp", "point-nav", "push", "mt10", "ml10"]:
        env = manyworlds.make(env_id)
        env.seed_task(7)
        state = env.sample_task_state()
        text = json.dumps(state)
        restored = json.loads(text)
        assert restored == state
        env.set_task_state(restored)
        assert env.get_task_state() == state
        obs, _ = env.reset(seed=1)
        other = manyworlds.make(env_id)
        other.set_task_state(json.loads(json.dumps(env.get_task_state())))
        obs_other, _ = other.reset(seed=1)
        np.testing.assert_array_equal(obs["env_obs"], obs_other["env_obs"])
        np.testing.assert_array_equal(obs["task_obs"], obs_other["task_obs"])


def test_reset_task_state_and_seed_task():
    a, b = manyworlds.make("point-nav"), manyworlds.make("point-nav")
    a.seed_task(3)
    b.seed_task(3)
    a.reset_task_state()
    b.reset_task_state()
    assert a.get_task_state() == b.get_task_state()
    a.reset_task_state()
    assert a.get_task_state() != b.get_task_state()
    b.reset(options={"task_state": a.get_task_state()})
    assert a.get_task_state() == b.get_task_state()


def test_set_task_state_requires_reset():
    env = manyworlds.make("cartpole")
    env.reset()
    env.set_task_state(env.sample_task_state())
    with pytest.raises(RuntimeError, match="before Reset"):
        env.step(0)


@pytest.mark.skipif(not _core.has_render, reason="this build has no renderer (OSMesa missing)")
def test_render_rgb_array():
    env = manyworlds.make("reach", render_mode="rgb_array", width=96, height=64)
    assert env.metadata["render_modes"] == ["rgb_array"]
    env.reset()
    frame = env.render()
    assert frame.shape == (64, 96, 3) and frame.dtype == np.uint8
    assert frame.std() > 5  # a picture, not a blank frame
    bench = manyworlds.make("mt10", render_mode="rgb_array", width=32, height=32, camera_name="top")
    bench.reset()
    assert bench.render().shape == (32, 32, 3)


def test_render_mode_refused_where_there_is_no_renderer():
    assert manyworlds.make("cartpole").metadata["render_modes"] == []
    with pytest.raises(ValueError, match="render_mode"):
        manyworlds.make("cartpole", render_mode="rgb_array")
    with pytest.raises(ValueError, match="render_mode"):
        manyworlds.make("reach", render_mode="human")


def test_close_is_idempotent_and_final():
    env = manyworlds.make("cartpole")
    env.reset()
    env.close()
    env.close()
    with pytest.raises(RuntimeError, match="closed"):
        env.reset()


def test_no_libtorch_in_the_extension():
    import subprocess

    out = subprocess.run(["ldd", _core.__file__], capture_output=True, text=True).stdout
    assert "libtorch" not in out and "libc10" not in out, out
