"""C++ errors cross into Python as exceptions (never a crash); Ctrl-C works."""

import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import manyworlds


def test_unknown_id_and_option_are_value_errors_with_suggestions():
    with pytest.raises(ValueError, match="did you mean 'cartpole'"):
        manyworlds.make("cartpol")
    with pytest.raises(manyworlds.ConfigError, match="n_arms"):
        manyworlds.make("bandit", n_armz=3)
    with pytest.raises(ValueError):
        manyworlds.make("bandit", n_arms="many")
    with pytest.raises(ValueError, match="unsupported type"):
        manyworlds.make("bandit", n_arms={1, 2})


def test_invalid_actions_are_value_errors_and_keep_the_episode():
    env = manyworlds.make("cartpole")
    env.reset()
    with pytest.raises(manyworlds.InvalidActionError):
        env.step(2)
    with pytest.raises(ValueError):
        env.step(np.array([0, 1]))
    box = manyworlds.make("point-nav")
    box.reset()
    with pytest.raises(ValueError, match="NaN|nan|finite"):
        box.step(np.array([np.nan, 0.0]))
    with pytest.raises(ValueError):
        box.step(np.zeros(3))
    with pytest.raises(ValueError):
        box.step("left")
    # a batch of actions is not one action (it was flattened: (1, 2) stepped as (2,))
    for batch in (np.zeros((1, 2)), np.zeros((3, 1, 2))):
        with pytest.raises(manyworlds.InvalidActionError, match=r"action of shape \("):
            box.step(batch)
    box.step(np.zeros(2))  # the episode still runs
    env.step(0)


def test_hostile_option_values_and_reset_options_are_one_clear_error():
    # integers past 2^63 were wrapped to negative numbers; nested lists crashed the process
    with pytest.raises(manyworlds.ConfigError, match=r"beyond the integers \[-2\^63, 2\^63\)"):
        manyworlds.make("point-nav", max_episode_steps=2**64 - 1)
    with pytest.raises(manyworlds.ConfigError, match="has value"):
        manyworlds.make("bandit", n_arms="[" * 60000 + "]" * 60000)
    with pytest.raises(manyworlds.ConfigError, match="episodes of 1000000000000000 steps"):
        manyworlds.make("point-nav", horizon=10**15)
    env = manyworlds.make("point-nav")
    with pytest.raises(ValueError, match="reset options must be a mapping"):
        env.reset(options="abc")


def test_protocol_errors_are_runtime_errors():
    env = manyworlds.make("cartpole")
    with pytest.raises(manyworlds.EpisodeStateError):
        env.step(0)
    with pytest.raises(RuntimeError, match="task"):
        env.get_task_state()


@pytest.mark.parametrize(
    "state, field",
    [
        ({"env": "point-nav", "params": {"goal": [0.1]}}, "goal"),
        ({"env": "point-nav", "params": {"goal": [0.1, "x"]}}, "goal"),
        ({"env": "point-nav", "params": {"goal": [0.1, 9.0]}}, "goal"),
        ({"env": "point-nav", "params": {"goal": [0.1, 0.2], "speed": 1}}, "speed"),
        ({"env": "point-nav", "params": {}}, "goal"),
        ({"env": "cartpole", "params": {"mu": [0, 0, 0, 0, 0]}}, "env"),
        ({"env": "point-nav"}, "params"),
        ({"params": {}}, "env"),
        ({"env": 3, "params": {}}, "env"),
        ({"env": "point-nav", "params": [1, 2]}, "params"),
        ({"env": "point-nav", "params": {"goal": [0.1, 0.2]}, "extra": 1}, "extra"),
        ({"env": "point-nav", "params": {"goal": [0.1, {1, 2}]}}, "params.goal[1]"),
        ("point-nav", "dict"),
    ],
)
def test_malformed_task_states_raise_value_error_naming_the_field(state, field):
    env = manyworlds.make("point-nav")
    env.reset()
    before = env.get_task_state()
    with pytest.raises(ValueError, match=field.replace("[", r"\[").replace("]", r"\]")):
        env.set_task_state(state)
    assert env.get_task_state() == before  # the previous task stays


def test_vector_env_errors():
    with pytest.raises(ValueError):
        manyworlds.make_vec(["cartpole", "point-nav"])  # different spaces
    envs = manyworlds.make_vec("cartpole", 2)
    envs.reset()
    with pytest.raises(ValueError):
        envs.step(np.array([0, 5]))
    with pytest.raises(ValueError):
        envs.step(np.zeros(3))
    with pytest.raises(IndexError):
        envs.get_task_state(2)
    with pytest.raises(ValueError, match="goal|env"):
        envs.set_task_state(0, {"env": "point-nav", "params": {"goal": [0, 0]}})
    envs.send(np.array([0, 1]))
    with pytest.raises(RuntimeError):
        envs.step(np.array([0, 1]))  # a step is pending
    envs.recv()
    envs.step(np.array([0, 1]))


def test_vector_env_counts_and_memory_are_bounded_before_envs_are_made():
    # 10^12 envs grew memory until killed; 10^9 threads aborted when the system refused them
    with pytest.raises(ValueError, match=r"num_envs must be in \[1, 65536\]"):
        manyworlds.make_vec("point-nav", num_envs=10**12)
    assert manyworlds._core.MAX_ENVS == 65536 and manyworlds._core.MAX_THREADS == 256
    with pytest.raises(ValueError, match=r"threads must be an int in \[1, 256\]"):
        manyworlds.make_vec("cartpole", 2, threads=10**9)
    # a batch that cannot fit in memory: refused after its first items are made, from their
    # measured resident size (4 MiB per item here, 10^9 items)
    check = manyworlds._core.BatchMemoryCheck(10**9, "a billion envs", "num_envs")
    blocks = []
    with pytest.raises(manyworlds.ConfigError, match="a billion envs needs about .* GiB.*lower num_envs"):
        for index in range(32):
            blocks.append(bytearray(4 << 20))  # 4 MiB resident per "env"
            for k in range(0, len(blocks[-1]), 4096):
                blocks[-1][k] = 1
            check.made(index)


def test_keyboard_interrupt_during_a_long_stepping_loop():
    script = textwrap.dedent(
        """
        import signal, sys, numpy as np, manyworlds
        # A process started in the background by a shell without job control inherits SIGINT
        # ignored, and Python then installs no KeyboardInterrupt handler: restore it, as an
        # interactive session has it.
        signal.signal(signal.SIGINT, signal.default_int_handler)
        envs = manyworlds.make_vec("reach", 8, threads=2)
        envs.reset(seed=0)
        actions = np.zeros((8, 4), np.float32)
        print("ready", flush=True)
        try:
            while True:
                envs.step(actions)
        except KeyboardInterrupt:
            print("interrupted", flush=True)
            sys.exit(0)
        """
    )
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "ready"
        time.sleep(0.5)
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, err
    assert "interrupted" in out
