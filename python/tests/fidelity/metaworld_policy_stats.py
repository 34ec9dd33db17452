"""Scripted- and random-policy statistics of Meta-World's own tasks (the official `metaworld`
package), to set beside manyworlds' on the same task names (scripts/fidelity_effect.py).

Runs in the Python that has `metaworld` installed (.venv-metaworld/). Only the official package
is imported here.

    python metaworld_policy_stats.py --tasks reach,push --scripted 50 --random 20 --out stats.json

Per task, on MT1's training goals (seed `--seed`): the package's scripted policy, without noise,
on the first `--scripted` goals, and uniform random actions in [-1, 1]^4 on the first `--random`
goals; every episode runs the full 500 steps (v3's max_path_length). An episode succeeds when
`info["success"]` is set at any step; its return is the sum of the 500 rewards (v2).
"""
import argparse
import json
import time

import numpy as np

from metaworld_record import policy_for


def episode(env, act, steps):
    obs, _ = env.reset()
    total, success = 0.0, False
    for _ in range(steps):
        obs, reward, _, truncated, info = env.step(act(obs))
        total += float(reward)
        success = success or bool(info["success"])
        if truncated:
            break
    return total, success


def task_stats(task, scripted, random, seed):
    import metaworld

    benchmark = metaworld.MT1(f"{task}-v3", seed=seed)
    env = benchmark.train_classes[f"{task}-v3"]()
    steps = env.max_path_length
    policy = policy_for(task)
    rng = np.random.default_rng(seed)
    out = {"scripted": [], "random": []}
    for i in range(max(scripted, random)):
        env.set_task(benchmark.train_tasks[i])
        if i < scripted:
            ret, ok = episode(env, lambda o: np.clip(policy.get_action(o), -1, 1), steps)
            out["scripted"].append({"return": ret, "success": ok})
        if i < random:
            ret, ok = episode(env, lambda o: rng.uniform(-1, 1, 4).astype(np.float32), steps)
            out["random"].append({"return": ret, "success": ok})
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tasks", required=True, help="comma-separated task names (v3 names less -v3)")
    parser.add_argument("--scripted", type=int, default=50)
    parser.add_argument("--random", type=int, default=20)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    from importlib.metadata import version

    result = {"package": f"metaworld {version('metaworld')}, mujoco {version('mujoco')}",
              "seed": args.seed, "date": time.strftime("%Y-%m-%d"), "tasks": {}}
    for task in args.tasks.split(","):
        result["tasks"][task] = task_stats(task, args.scripted, args.random, args.seed)
    with open(args.out, "w") as f:
        json.dump(result, f)


if __name__ == "__main__":
    main()
