"""Records dm_control's finger-spin, cheetah-run and walker-walk rewards together with the
physical quantities each reward reads, for tests/dmc/reward_agreement_test.cc to recompute with
our reward functions (src/manyworlds/dmc/rewards.h) and compare step by step.

    python3 -m venv .venv-dmc && .venv-dmc/bin/pip install dm-control==1.0.50 mujoco==3.17.0
    .venv-dmc/bin/python scripts/record_dmc_rewards.py > tests/dmc/data/dmc_rewards.json

(dm-control 1.0.50 with mujoco 4.0.0, what pip picks by default, fails on loading any model.)

Per task, one seed, three whole episodes (1000 control steps): uniform random actions, a
fixed sinusoid per actuator (SINUSOID_PERIOD control steps, actuator i at phase 2 pi i / n)
and zero actions. Each episode keeps its initial state (qpos, qvel after dm_control's reset),
every reward (for the return, and for tests/dmc/physics_replay_test.cc, which replays the
sinusoid and zero episodes in our env from the same initial state) and, for its first
RECORDED steps, the quantities the reward reads with dm_control's reward; the sinusoid and zero
episodes also keep their first OBSERVED flat state observations (8 significant digits), which
the replay compares with ours (order, sizes, and the finger's touch sensors).

Neither policy reaches every branch of the rewards (finger-spin pays only at <= -15 rad/s, the
walker soon lies on the floor), so each task's record also holds PROBES states set directly
(spinner velocity around the threshold; cheetah forward velocity up to past 10 m/s; walker
height, pitch and forward velocity), each rewarded by dm_control's task itself.

With --random-returns N it records nothing and prints instead, per task, the mean and standard
deviation of the return of N uniform-random-action episodes (seeds 0 .. N-1), dm_control's side
of the comparison with `manyworlds rollout --env dmc-<task> --episodes N` in docs/fidelity.md.
"""

import argparse
import json
import math
import statistics
from importlib.metadata import version

import numpy as np
from dm_control import suite

STEPS = 1000
RECORDED = 300
PROBES = 60
OBSERVED = 50
SINUSOID_PERIOD = {"finger": 80, "cheetah": 40, "walker": 40}
SEED = 7


NAMES = {"finger": ["hinge_velocity"], "cheetah": ["com_velocity_x"],
         "walker": ["torso_height", "torso_upright", "com_velocity_x"]}


def quantities(domain, physics):
    """What the task's reward reads, in the order of NAMES (rewards.h's arguments)."""
    data = physics.named.data
    if domain == "finger":
        return [float(data.sensordata["hinge_velocity"][0])]
    if domain == "cheetah":
        return [float(data.sensordata["torso_subtreelinvel"][0])]
    return [float(data.xpos["torso", "z"]), float(data.xmat["torso", "zz"]),
            float(data.sensordata["torso_subtreelinvel"][0])]


def sinusoid(t, size, period):
    """A fixed gait: actuator i at phase 2 pi i / size, amplitude 1."""
    return np.array([math.sin(2 * math.pi * t / period + 2 * math.pi * i / size)
                     for i in range(size)])


def episode(domain, task, policy, seed):
    env = suite.load(domain, task, task_kwargs={"random": seed})
    spec = env.action_spec()
    rng = np.random.RandomState(seed)
    env.reset()
    physics = env.physics
    run = {"policy": policy, "seed": seed,
           "qpos0": [float(x) for x in physics.data.qpos],
           "qvel0": [float(x) for x in physics.data.qvel],
           "quantities": [], "rewards": []}
    for t in range(STEPS):
        if policy == "random":
            action = rng.uniform(spec.minimum, spec.maximum)
        elif policy == "sinusoid":
            action = sinusoid(t, spec.shape[0], SINUSOID_PERIOD[domain])
        else:
            action = np.zeros(spec.shape)
        timestep = env.step(action)
        run["rewards"].append(float(timestep.reward))
        if t < RECORDED:
            run["quantities"].append(quantities(domain, physics))
        if t < OBSERVED and policy != "random":
            flat = np.concatenate([np.ravel(v) for v in timestep.observation.values()])
            run.setdefault("observations", []).append([float(f"{x:.8g}") for x in flat])
    run["episode_return"] = sum(run["rewards"])
    return run


def probes(domain, task, seed):
    """States set directly to reach every branch of the reward, rewarded by dm_control."""
    env = suite.load(domain, task, task_kwargs={"random": seed})
    env.reset()
    physics = env.physics
    qpos, qvel = physics.named.data.qpos, physics.named.data.qvel
    rng = np.random.RandomState(seed)
    steps, rewards = [], []
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
        steps.append(quantities(domain, physics))
        rewards.append(float(env.task.get_reward(physics)))
    return {"policy": "set_state", "seed": seed, "quantities": steps, "rewards": rewards}


def random_returns(episodes):
    for domain, task in (("finger", "spin"), ("cheetah", "run"), ("walker", "walk")):
        returns = []
        for seed in range(episodes):
            env = suite.load(domain, task, task_kwargs={"random": seed})
            spec = env.action_spec()
            rng = np.random.RandomState(1000 + seed)
            timestep, total = env.reset(), 0.0
            while not timestep.last():
                timestep = env.step(rng.uniform(spec.minimum, spec.maximum))
                total += timestep.reward
            returns.append(total)
        sd = statistics.stdev(returns)
        mean = statistics.mean(returns)
        print(f"{domain}-{task}: {episodes} random episodes, return mean {mean:.2f} sd {sd:.2f}"
              f" (standard error {sd / math.sqrt(episodes):.2f})")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--random-returns", type=int, metavar="N",
                        help="print random-policy return statistics over N episodes instead")
    args = parser.parse_args()
    if args.random_returns:
        random_returns(args.random_returns)
        return
    tasks = {}
    for domain, task in (("finger", "spin"), ("cheetah", "run"), ("walker", "walk")):
        runs = [episode(domain, task, policy, SEED) for policy in ("random", "sinusoid", "zero")]
        runs.append(probes(domain, task, SEED))
        tasks[f"{domain}-{task}"] = {"names": NAMES[domain],
                                     "sinusoid_period": SINUSOID_PERIOD[domain], "runs": runs}
    print(json.dumps({"dm_control": version("dm-control"), "mujoco": version("mujoco"),
                      "tasks": tasks}))


if __name__ == "__main__":
    main()
