"""Pixel observations (obs="pixels") through Gymnasium, the vector env and Stable-Baselines3.

The C++ tests (tests/envs/pixel_observation_test.cc) check the frames against direct renders
and hand-stepped stacks; these check what a Python user sees: uint8 Boxes that pass Gymnasium's
checker, MTEnv's shapes, zero-copy vector observations, and a CNN learner that runs on them
reproducibly.
"""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import manyworlds

pytestmark = pytest.mark.skipif(not manyworlds._core.has_render, reason="this build cannot render")

SMALL = {"obs": "pixels", "pixel_width": 32, "pixel_height": 32}


@pytest.mark.parametrize("env_id", ["hipbmdp-finger-spin-size", "dmc-cheetah-run", "reach", "box-world-simple"])
def test_gymnasium_checker_passes_on_pixels(env_id):
    env = gym.make(f"manyworlds/{env_id}", **SMALL)
    space = env.observation_space["env_obs"]
    assert space.dtype == np.uint8 and space.shape == (3, 32, 32)
    check_env(env.unwrapped, skip_render_check=True)
    flat = gym.make(f"manyworlds/{env_id}", flat_obs=True, **SMALL)
    assert flat.observation_space == gym.spaces.Box(0, 255, (3, 32, 32), np.uint8)
    check_env(flat.unwrapped, skip_render_check=True)


def test_mtenv_defaults_give_mtenv_shapes():
    # MTEnv's HiP-BMDP envs: 84 x 84 RGB, action repeat 2, 3 stacked frames, channels first
    env = manyworlds.make("hipbmdp-walker-walk-friction", obs="pixels", action_repeat=2, frame_stack=3)
    obs, _ = env.reset(seed=0)
    assert obs["env_obs"].shape == (9, 84, 84) and obs["env_obs"].dtype == np.uint8
    assert obs["state"].shape == (24,) and obs["state"].dtype == np.float32
    assert env.max_episode_steps == 500


def test_stack_holds_the_last_frames_oldest_first():
    single = manyworlds.make("dmc-cheetah-run", **SMALL)
    stacked = manyworlds.make("dmc-cheetah-run", frame_stack=3, **SMALL)
    frames = [single.reset(seed=4)[0]["env_obs"]]
    got = [stacked.reset(seed=4)[0]["env_obs"]]
    rng = np.random.default_rng(0)
    for _ in range(4):
        action = rng.uniform(-1, 1, 6).astype(np.float32)
        frames.append(single.step(action)[0]["env_obs"])
        got.append(stacked.step(action)[0]["env_obs"])
    assert not np.array_equal(frames[1], frames[2])
    for t, stack in enumerate(got):
        expected = np.concatenate([frames[max(0, t - 2 + k)] for k in range(3)])
        np.testing.assert_array_equal(stack, expected)


def test_vector_pixels_are_zero_copy_and_thread_independent():
    one = manyworlds.make_vec("dmc-walker-walk", 4, threads=1, **SMALL)
    two = manyworlds.make_vec("dmc-walker-walk", 4, threads=2, **SMALL)
    a, _ = one.reset(seed=7)
    b, _ = two.reset(seed=7)
    assert a["env_obs"].shape == (4, 3, 32, 32) and a["env_obs"].dtype == np.uint8
    assert one._exec.buffer_addresses()["pixels"] == a["env_obs"].__array_interface__["data"][0]
    rng = np.random.default_rng(1)
    for _ in range(5):
        actions = rng.uniform(-1, 1, (4, 6)).astype(np.float32)
        a = one.step(actions)[0]
        b = two.step(actions)[0]
        np.testing.assert_array_equal(a["env_obs"], b["env_obs"])
        np.testing.assert_array_equal(a["state"], b["state"])


def test_final_observation_of_an_ended_episode_holds_its_frames():
    venv = manyworlds.make_vec("dmc-cheetah-run", 2, max_episode_steps=3, **SMALL)
    venv.reset(seed=0)
    for _ in range(3):
        obs, _, terminated, truncated, infos = venv.step(np.zeros((2, 6), np.float32))
    assert truncated.all()
    final = infos["final_obs"][0]
    assert final["env_obs"].shape == (3, 32, 32) and final["env_obs"].dtype == np.uint8
    assert final["state"].shape == (17,)


def test_envs_without_a_scene_refuse_pixels():
    with pytest.raises(ValueError, match="no MuJoCo scene"):
        manyworlds.make("cartpole", obs="pixels")
    with pytest.raises(ValueError, match="unknown camera"):
        manyworlds.make("reach", obs="pixels", camera="nowhere")
    with pytest.raises(ValueError, match="add obs=pixels"):
        manyworlds.make("reach", camera="top")
    with pytest.raises(ValueError, match="a batch needs one shape"):
        manyworlds.make_vec([("reach", SMALL), ("reach", {"obs": "pixels"})])


sb3 = pytest.importorskip("stable_baselines3", reason="stable-baselines3 is not installed")
torch = pytest.importorskip("torch", reason="torch is not installed")


def train_sac_cnn(seed):
    torch.set_num_threads(1)
    env = gym.make("manyworlds/hipbmdp-finger-spin-size", obs="pixels", flat_obs=True, pixel_width=64,
                   pixel_height=64, max_episode_steps=100)
    model = sb3.SAC("CnnPolicy", env, seed=seed, buffer_size=500, learning_starts=100, batch_size=16,
                    train_freq=4, gradient_steps=1, policy_kwargs={"features_extractor_kwargs": {"features_dim": 32}},
                    device="cpu", verbose=0)
    model.learn(300)
    return model


def test_sb3_sac_with_a_cnn_policy_trains_on_frames_reproducibly():
    from stable_baselines3.common.torch_layers import NatureCNN

    a = train_sac_cnn(seed=3)
    b = train_sac_cnn(seed=3)
    assert isinstance(a.actor.features_extractor, NatureCNN)
    # the replay buffer stores the env's uint8 frames, not floats
    assert a.replay_buffer.observations.dtype == np.uint8
    assert a.replay_buffer.observations[:a.replay_buffer.pos].std() > 0
    for (name, pa), pb in zip(a.policy.state_dict().items(), b.policy.state_dict().values()):
        assert torch.equal(pa, pb), name
    # and the updates did change the actor
    c = train_sac_cnn(seed=4)
    assert any(not torch.equal(pa, pc) for pa, pc in zip(a.policy.state_dict().values(), c.policy.state_dict().values()))
