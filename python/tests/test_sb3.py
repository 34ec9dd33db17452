"""A real client: Stable-Baselines3's PPO and SAC learn point-nav through the package.

Single-task point navigation (the goal of task seed 0 is 0.27 from the start): standing still
returns about -13.4 over 50 steps, a random policy about -20, the best policy about -0.4. The
thresholds below need the learned policy to walk to the goal and stay near it. Measured with
these seeds: SAC -1.57 (success 1.0), PPO -3.61 (success 1.0), PPO on 8 envs with 8 different
goals through SB3VecEnv -3.88 on the evaluation goal (within about 0.07 of it: success 0.0).
"""

import numpy as np
import pytest

sb3 = pytest.importorskip("stable_baselines3", reason="stable-baselines3 is not installed")
torch = pytest.importorskip("torch", reason="torch is not installed")

import gymnasium as gym  # noqa: E402

import manyworlds  # noqa: E402

HORIZON = 50


@pytest.fixture(autouse=True)
def _one_torch_thread():
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(threads)


def evaluate(model, episodes=5):
    env = gym.make("manyworlds/point-nav", flat_obs=True, max_episode_steps=HORIZON)
    returns, successes = [], []
    for episode in range(episodes):
        obs, _ = env.reset(seed=episode)
        total, success = 0.0, False
        while True:
            action, _ = model.predict(obs, deterministic=True)
            obs, reward, terminated, truncated, info = env.step(action)
            total += reward
            success |= info["success"] > 0
            if terminated or truncated:
                break
        returns.append(total)
        successes.append(success)
    return float(np.mean(returns)), float(np.mean(successes))


def test_ppo_learns_point_nav():
    env = gym.make("manyworlds/point-nav", flat_obs=True, max_episode_steps=HORIZON)
    model = sb3.PPO("MlpPolicy", env, seed=0, n_steps=1024, batch_size=64, device="cpu", verbose=0)
    model.learn(10_000)
    mean_return, success = evaluate(model)
    assert mean_return > -6.0, mean_return


def test_sac_learns_point_nav():
    env = gym.make("manyworlds/point-nav", flat_obs=True, max_episode_steps=HORIZON)
    model = sb3.SAC(
        "MlpPolicy", env, seed=0, learning_starts=500, device="cpu", verbose=0,
        policy_kwargs={"net_arch": [64, 64]},
    )
    model.learn(3_000)
    mean_return, success = evaluate(model)
    assert mean_return > -3.0 and success == 1.0, (mean_return, success)


def test_ppo_learns_point_nav_through_the_vector_env():
    from stable_baselines3.common.vec_env import VecMonitor

    from manyworlds.sb3 import SB3VecEnv

    venv = VecMonitor(SB3VecEnv("point-nav", num_envs=8, threads=2, max_episode_steps=HORIZON))
    model = sb3.PPO("MlpPolicy", venv, seed=0, n_steps=128, batch_size=64, device="cpu", verbose=0)
    model.learn(10_000)
    mean_return, success = evaluate(model)
    assert mean_return > -6.0, mean_return
