"""The batched executor as a gymnasium.vector.VectorEnv: zero copy, autoreset, async, tasks."""

import gymnasium as gym
import numpy as np
import pytest

import manyworlds
from manyworlds.benchmarks import MT10_TASKS


def address(array):
    return array.__array_interface__["data"][0]


def random_actions(envs, seed, steps):
    space = envs.action_space
    space.seed(seed)
    return [space.sample() for _ in range(steps)]


def test_observations_rewards_and_flags_are_views_of_the_executor_buffers():
    envs = manyworlds.make_vec("cartpole", 4)
    buffers = envs._exec.buffer_addresses()
    obs, _ = envs.reset(seed=0)
    assert address(obs["env_obs"]) == buffers["env_obs"]
    assert address(obs["task_obs"]) == buffers["task_obs"]
    for action in random_actions(envs, 0, 50):
        obs2, rewards, terminated, truncated, infos = envs.step(action)
        assert obs2["env_obs"] is obs["env_obs"]  # the same array object every step
        assert address(obs2["env_obs"]) == buffers["env_obs"]
        assert address(obs2["task_obs"]) == buffers["task_obs"]
        assert address(rewards) == buffers["rewards"]
        assert address(terminated) == buffers["terminated"]
        assert address(truncated) == buffers["truncated"]
        assert address(infos["success"]) == buffers["info"]  # column 0 of (N, fields)
    assert not obs["env_obs"].flags.owndata and not obs["env_obs"].flags.writeable
    assert rewards.dtype == np.float32 and terminated.dtype == np.bool_


def test_spaces_are_batched_and_contain_the_observations():
    envs = manyworlds.make_vec("point-nav", 3)
    assert envs.num_envs == 3
    assert envs.single_action_space == gym.spaces.Box(-0.1, 0.1, (2,), np.float32)
    assert envs.action_space.shape == (3, 2)
    obs, infos = envs.reset(seed=1)
    assert obs in envs.observation_space
    assert infos == {}
    obs, *_ = envs.step(envs.action_space.sample())
    assert obs in envs.observation_space
    flat = manyworlds.make_vec("point-nav", 3, flat_obs=True)
    obs, _ = flat.reset(seed=1)
    assert obs.shape == (3, 4) and obs in flat.observation_space


def test_same_step_autoreset_matches_single_envs():
    n, steps = 3, 120
    envs = manyworlds.make_vec("cartpole", n, threads=2)
    assert envs.metadata["autoreset_mode"] in ("SameStep",) or envs.metadata["autoreset_mode"].name == "SAME_STEP"
    obs, _ = envs.reset(seed=11, options={"task_seed": 4})
    singles = [manyworlds.make("cartpole") for _ in range(n)]
    single_obs = []
    for i, env in enumerate(singles):
        o, _ = env.reset(seed=manyworlds.mix_seed(11, i), options={"task_seed": manyworlds.mix_seed(4, i)})
        single_obs.append(o)
        np.testing.assert_array_equal(obs["env_obs"][i], o["env_obs"])
        np.testing.assert_array_equal(obs["task_obs"][i], o["task_obs"])
    ended_somewhere = False
    for action in random_actions(envs, 5, steps):
        obs, rewards, terminated, truncated, infos = envs.step(action)
        for i, env in enumerate(singles):
            o, r, te, tr, info = env.step(int(action[i]))
            assert r == rewards[i] and te == terminated[i] and tr == truncated[i]
            assert info["success"] == infos["success"][i]
            if te or tr:
                ended_somewhere = True
                assert infos["_final_obs"][i]
                np.testing.assert_array_equal(infos["final_obs"][i]["env_obs"], o["env_obs"])
                assert infos["final_info"]["_success"][i]
                o, _ = env.reset()
            np.testing.assert_array_equal(obs["env_obs"][i], o["env_obs"])
    assert ended_somewhere


def test_results_do_not_depend_on_threads_and_async_equals_sync():
    actions = None
    runs = []
    for threads, mode in [(1, "sync"), (2, "sync"), (2, "async"), (1, "async")]:
        envs = manyworlds.make_vec("reach", 4, threads=threads)
        if actions is None:
            actions = random_actions(envs, 3, 40)
        obs, _ = envs.reset(seed=2, options={"task_seed": 9})
        trace = [obs["env_obs"].copy()]
        for a in actions:
            if mode == "sync":
                obs, rewards, *_ = envs.step(a)
            else:
                envs.send(a)
                obs, rewards, *_ = envs.recv()
            trace.append(obs["env_obs"].copy())
            trace.append(rewards.copy())
        runs.append(trace)
        envs.close()
    for other in runs[1:]:
        for x, y in zip(runs[0], other):
            np.testing.assert_array_equal(x, y)


def test_any_mix_of_tasks():
    envs = manyworlds.make_vec(MT10_TASKS, threads=2)
    assert envs.env_ids == MT10_TASKS
    obs, _ = envs.reset(seed=0)
    assert obs["env_obs"].shape == (10, 39)
    assert [s["env"] for s in envs.get_task_states()] == MT10_TASKS
    for action in random_actions(envs, 1, 5):
        envs.step(action)

    # One benchmark id with a chosen task per env.
    bench = manyworlds.make("mt10")
    groups = bench.evaluation_tasks()
    states = [states[0] for _, states in groups[:4]]
    envs = manyworlds.make_vec("mt10", 4, task_states=states)
    obs, _ = envs.reset(seed=0)
    assert envs.get_task_states() == states
    np.testing.assert_array_equal(obs["task_obs"][:, 0], [0, 1, 2, 3])
    # Switching one env's task resets that env at once.
    envs.set_task_state(0, groups[5][1][0])
    assert envs.get_task_state(0) == groups[5][1][0]
    assert obs["task_obs"][0, 0] == 5  # the view shows the new row
    # Per-env options.
    mixed = manyworlds.make_vec([("point-nav", {"goal_range": 0.2}), ("point-nav", {"goal_range": 2.0})])
    assert mixed.single_observation_space["task_obs"].high[0] == pytest.approx(0.2)


def test_reset_options_and_seed_lists():
    envs = manyworlds.make_vec("cartpole", 3)
    obs, _ = envs.reset(seed=[1, 2, 3])
    singles = [manyworlds.make("cartpole") for _ in range(3)]
    for i, env in enumerate(singles):
        o, _ = env.reset(seed=i + 1)
        np.testing.assert_array_equal(obs["env_obs"][i], o["env_obs"])
    before = envs.get_task_states()
    envs.reset(options={"task_seed": 5})
    after = envs.get_task_states()
    assert after != before
    envs.reset(options={"task_seed": 5})
    assert envs.get_task_states() == after
    envs.reset(options={"task_states": [before[0], None, None]})
    assert envs.get_task_states()[0] == before[0]
    with pytest.raises(ValueError, match="unknown reset option"):
        envs.reset(options={"bogus": 1})


def test_gymnasium_make_vec_uses_the_executor():
    envs = gym.make_vec("manyworlds/cartpole", num_envs=5, threads=2)
    assert isinstance(envs, manyworlds.ManyworldsVectorEnv)
    assert envs.num_envs == 5 and envs.threads == 2
    obs, _ = envs.reset(seed=0)
    envs.step(envs.action_space.sample())
    envs.close()
    assert envs.closed


def test_views_keep_the_buffers_alive_after_close():
    envs = manyworlds.make_vec("point-nav", 2)
    obs, _ = envs.reset(seed=0)
    view = obs["env_obs"]
    envs.close()
    del envs
    assert view.shape == (2, 2) and np.all(np.isfinite(view))


def test_gymnasium_sync_vector_env_over_single_envs():
    # Gymnasium's own SyncVectorEnv over ManyworldsEnv instances works as well.
    envs = gym.make_vec("manyworlds/point-nav", num_envs=2, vectorization_mode="sync")
    assert isinstance(envs, gym.vector.SyncVectorEnv)
    obs, _ = envs.reset(seed=0)
    assert obs["env_obs"].shape == (2, 2)
    envs.step(envs.action_space.sample())
    envs.close()


def test_envs_differ_without_a_seed_and_are_deterministic():
    a = manyworlds.make_vec("cartpole", 4)
    obs, _ = a.reset()
    rows = obs["env_obs"].copy()
    assert len({tuple(r) for r in rows}) == 4
    assert len({tuple(r) for r in obs["task_obs"]}) == 4
    b = manyworlds.make_vec("cartpole", 4)
    obs_b, _ = b.reset()
    np.testing.assert_array_equal(rows, obs_b["env_obs"])
