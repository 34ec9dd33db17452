"""Records dm_control's finger-spin, cheetah-run and walker-walk rewards together with the
physical quantities each reward reads, for tests/dmc/reward_agreement_test.cc to recompute with
our reward functions (src/manyworlds/dmc/rewards.h) and compare step by step.

    python3 -m venv .venv-dmc && .venv-dmc/bin/pip install dm-control
    .venv-dmc/bin/python scripts/record_dmc_rewards.py > tests/dmc/data/dmc_rewards.json

Per task, fixed seeds: one episode of uniform random actions and one of a scripted policy (a
fixed sinusoid per actuator), STEPS control steps each. Neither policy reaches every branch
of the rewards (finger-spin pays only at <= -15 rad/s, the walker soon lies on the floor), so
each task's record also holds PROBES states set directly (spinner velocity around the
threshold; cheetah forward velocity up to past 10 m/s; walker height, pitch and forward
velocity), each rewarded by dm_control's task itself.
"""

import json
import math
from importlib.metadata import version

import numpy as np
from dm_control import suite

STEPS = 300
PROBES = 60
SEED = 7


def quantities(domain, physics):
    """What the task's reward reads, by the names rewards.h uses."""
    data = physics.named.data
    if domain == "finger":
        return {"hinge_velocity": float(data.sensordata["hinge_velocity"][0])}
    if domain == "cheetah":
        return {"com_velocity_x": float(data.sensordata["torso_subtreelinvel"][0])}
    return {"torso_height": float(data.xpos["torso", "z"]),
            "torso_upright": float(data.xmat["torso", "zz"]),
            "com_velocity_x": float(data.sensordata["torso_subtreelinvel"][0])}


def sinusoid(t, size, period):
    """A fixed gait: actuator i at phase 2 pi i / size, amplitude 1."""
    return np.array([math.sin(2 * math.pi * t / period + 2 * math.pi * i / size)
                     for i in range(size)])


def episode(domain, task, policy, seed):
    env = suite.load(domain, task, task_kwargs={"random": seed})
    spec = env.action_spec()
    rng = np.random.RandomState(seed)
    env.reset()
    steps = []
    for t in range(STEPS):
        if policy == "random":
            action = rng.uniform(spec.minimum, spec.maximum)
        else:
            action = sinusoid(t, spec.shape[0], 20 if domain == "finger" else 40)
        timestep = env.step(action)
        record = quantities(domain, env.physics)
        record["reward"] = float(timestep.reward)
        steps.append(record)
    return {"policy": policy, "seed": seed, "steps": steps}


def probes(domain, task, seed):
    """States set directly to reach every branch of the reward, rewarded by dm_control."""
    env = suite.load(domain, task, task_kwargs={"random": seed})
    env.reset()
    physics = env.physics
    qpos, qvel = physics.named.data.qpos, physics.named.data.qvel
    rng = np.random.RandomState(seed)
    steps = []
    for i in range(PROBES):
        if domain == "finger":
            fixed = [-15.0, -15.0 + 1e-9, -15.0 - 1e-9, 0.0, 15.0, -100.0]
            qvel["hinge"] = fixed[i] if i < len(fixed) else rng.uniform(-30.0, 10.0)
        elif domain == "cheetah":
            qvel["rootx"] = rng.uniform(-5.0, 15.0)
        else:
            qpos["rootz"] = rng.uniform(-1.0, 0.3)  # the torso origin at 0.3 ... 1.6 m
            qpos["rooty"] = rng.uniform(-math.pi, math.pi)
            qvel["rootx"] = rng.uniform(-1.0, 3.0)
        physics.forward()
        record = quantities(domain, physics)
        record["reward"] = float(env.task.get_reward(physics))
        steps.append(record)
    return {"policy": "set_state", "seed": seed, "steps": steps}


def main():
    tasks = {}
    for domain, task in (("finger", "spin"), ("cheetah", "run"), ("walker", "walk")):
        runs = [episode(domain, task, "random", SEED), episode(domain, task, "sinusoid", SEED),
                probes(domain, task, SEED)]
        tasks[f"{domain}-{task}"] = runs
    print(json.dumps({"dm_control": version("dm-control"), "mujoco": version("mujoco"),
                      "tasks": tasks}))


if __name__ == "__main__":
    main()
