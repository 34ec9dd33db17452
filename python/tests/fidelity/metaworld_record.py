"""Drives Meta-World's own tasks (the official `metaworld` package) and records, at every step,
the quantities its reward reads from its simulator together with its reward and info.

Runs in the Python that has `metaworld` installed (scripts/python_test.sh makes .venv-metaworld/
for it); python/tests/test_metaworld_fidelity.py runs it and evaluates manyworlds' reward on the
records (`manyworlds.sawyer_reward`). Only the official package is imported here.

    python metaworld_record.py --tasks reach,push --out records.json
    python metaworld_record.py --tasks reach,push --reward-versions v2,v1 --observation-spaces \
        --out records.json

Per task: `--goals` of MT1's training goals (seed `--seed`); for each, one episode of uniform
random actions and one of the package's scripted policy with Gaussian action noise (so that the
arm reaches, grasps and moves the object), `--steps` steps each. A record is one step:
{"state": {...}, "action": [...], "reward": r, "info": {...}}; the state keys are manyworlds'
state record (SawyerState), taken from the official env as its reward code reads them. The
output's "rows" holds them per reward version (`--reward-versions`, of v1 and v2: v3's envs
built with that reward_function_version, stepped on the same actions).

With `--observation-spaces`, per task the observation bounds too ("spaces").
Tasks are recorded by `--jobs` processes at once (default: every core); each task's records
depend on its own arguments only, so the output is the same for any count.
"""
import argparse
import concurrent.futures
import functools
import json
import os
import re

import numpy as np


# Articulated tasks: where v3 keeps the fixture quantities its reward reads; the record holds
# neutral zeros for tasks that have none.
JOINT_QPOS = {"door-open": "doorjoint", "door-close": "doorjoint", "lever-pull": "LeverAxis",
              "hammer": "NailSlideJoint"}
HANDLE_INIT = {"window-open": "window_handle_pos_init", "window-close": "window_handle_pos_init",
               "lever-pull": "_lever_pos_init", "dial-turn": "dial_push_position",
               "handle-press": "_handle_init_pos", "handle-press-side": "_handle_init_pos"}
OBJ_TO_TARGET_INIT = {"button-press-topdown": "_obj_to_target_init",
                      "button-press": "_obj_to_target_init",
                      "button-press-wall": "_obj_to_target_init",
                      "button-press-topdown-wall": "_obj_to_target_init",
                      "coffee-button": "max_dist",
                      "bin-picking": "_target_to_obj_init"}


# Reward version v1: the attribute holding each task's normaliser (v3 sets it at reset).
V1_MAX_DIST = {"reach": "maxReachDist", "push": "maxPushDist", "pick-place": "maxPlacingDist",
               "door-open": "maxPullDist", "drawer-open": "maxDist", "drawer-close": "maxDist",
               "button-press-topdown": "maxDist", "peg-insert-side": "maxPlacingDist",
               "window-open": "maxPullDist", "window-close": "maxPullDist",
               "door-close": "maxPullDist", "lever-pull": "maxPullDist",
               "reach-wall": "maxReachDist", "push-wall": "maxPushDist",
               "push-back": "maxPushDist", "soccer": "maxPushDist", "sweep": "maxPushDist",
               "sweep-into": "maxPushDist", "basketball": "maxPlacingDist",
               "shelf-place": "maxPlacingDist", "pick-place-wall": "maxPlacingDist",
               "plate-slide": "maxDist", "plate-slide-side": "maxDist",
               "plate-slide-back": "maxDist", "plate-slide-back-side": "maxDist",
               "faucet-open": "maxPullDist", "faucet-close": "maxPullDist",
               "dial-turn": "maxPullDist", "door-lock": "maxPullDist",
               "door-unlock": "maxPullDist", "button-press-topdown-wall": "maxDist",
               "button-press": "maxDist", "button-press-wall": "maxDist",
               "handle-press": "maxDist", "handle-press-side": "maxDist",
               "handle-pull": "maxDist", "handle-pull-side": "maxDist",
               "coffee-button": "maxDist", "coffee-push": "maxPushDist",
               "coffee-pull": "maxPullDist", "hand-insert": "maxReachDist",
               "pick-out-of-hole": "maxPlacingDist", "peg-unplug-side": "maxPlacingDist",
               "bin-picking": "maxPlacingDist", "box-close": "maxPlacingDist",
               "assembly": "maxPlacingDist", "disassemble": "maxPlacingDist",
               "hammer": "maxHammerDist", "stick-push": "maxPlaceDist",
               "stick-pull": "maxPlaceDist"}
# ... the second normaliser of the stick tasks, and the attribute holding the lift reference
V1_MAX_DIST2 = {"stick-push": "maxPushDist", "stick-pull": "maxPullDist"}
V1_OBJ_HEIGHT = {"assembly": "obj_height", "hammer": "hammerHeight", "stick-push": "stickHeight",
                 "stick-pull": "stickHeight"}


def v1_fields(env, task):
    """The v1 reward's reset-time quantities (zeros where the task's v1 reads none)."""
    value = lambda name: float(np.asarray(getattr(env, name, 0.0), dtype=np.float64))
    return {"v1_max_dist": value(V1_MAX_DIST[task]) if task in V1_MAX_DIST else 0.0,
            "v1_obj_height": value(V1_OBJ_HEIGHT.get(task, "objHeight")),
            "v1_height_target": value("heightTarget"),
            "left_finger": [float(x) for x in env._get_site_pos("leftEndEffector")],
            "v1_max_dist2": value(V1_MAX_DIST2[task]) if task in V1_MAX_DIST2 else 0.0,
            "obj2_head": ([float(x) for x in env._get_site_pos("nailHead")] if task == "hammer"
                          else [0.0] * 3)}


def state_record(env, obs, task=None):
    """manyworlds' SawyerState fields, read the way Meta-World v3's reward code reads them."""
    vec = lambda v: [float(x) for x in np.asarray(v, dtype=np.float64)]
    return {
        "hand": vec(obs[0:3]),
        "tcp": vec(env.tcp_center),
        "left_pad": vec(env.get_body_com("leftpad")),
        "right_pad": vec(env.get_body_com("rightpad")),
        "obj": vec(obs[4:7]),
        "goal": vec(env._target_pos),
        # the stick tasks keep the stick's start apart (obj_init_pos is the thermos's base there)
        "obj_init": vec(env.stick_init_pos if task in ("stick-push", "stick-pull") else env.obj_init_pos),
        "tcp_init": vec(env.init_tcp),
        "hand_init": vec(env.hand_init_pos),
        "gripper_opening": float(obs[3]),
        "touching_obj": touching(env),
        # peg-insert-side (pegHead), stick-pull (stick_end), assembly and disassemble (RoundNut),
        # hammer (HammerHead)
        "obj_head": (vec(env._get_site_pos("pegHead")) if hasattr(env, "peg_head_pos_init") else
                     vec(env._get_site_pos("stick_end")) if task == "stick-pull" else
                     vec(env._get_site_pos("RoundNut")) if task in ("assembly", "disassemble") else
                     vec(env.data.geom("HammerHead").xpos) if task == "hammer" else
                     [0.0] * 3),
        "obj_head_init": vec(getattr(env, "peg_head_pos_init", np.zeros(3))),
        # articulated tasks
        "joint_qpos": (float(env.data.joint(JOINT_QPOS[task]).qpos.item())
                       if task in JOINT_QPOS else 0.0),
        "handle_init": vec(getattr(env, HANDLE_INIT[task]) if task in HANDLE_INIT else np.zeros(3)),
        # (v1 leaves bin-picking's _target_to_obj_init at None: its reward never reads it)
        "obj_to_target_init": float(getattr(env, OBJ_TO_TARGET_INIT.get(task, ""), None) or 0.0),
        "obj_quat": vec(obs[7:11]),
        # tool-use tasks: the second object (obs[11:14]) and the thermos's base at reset
        "obj2": vec(obs[11:14]),
        "obj2_init": vec(env.obj_init_pos) if task in ("stick-push", "stick-pull") else [0.0] * 3,
        **v1_fields(env, task),
    }


def touching(env):
    """Both pads pressing on the task's main object. Tasks without one ("objGeom") never touch;
    basketball's lookup calls a MuJoCo function that no longer exists (AttributeError), and its
    reward never reads it."""
    try:
        return bool(env.touching_main_object)
    except (KeyError, AttributeError):
        return False


# Scripted policies whose class name does not follow the task's name.
POLICY_NAMES = {"peg-insert-side": "SawyerPegInsertionSideV3Policy"}


def policy_for(task):
    import metaworld.policies as policies

    name = POLICY_NAMES.get(task) or (
        "Sawyer" + "".join(part.capitalize() for part in re.split(r"[-_]", task)) + "V3Policy")
    return getattr(policies, name)()


def record_task(task, goals, steps, seed, reward_versions, spaces=False):
    """The task's rows per reward version ({version: rows}) and, with `spaces`, its observation
    bounds. One MT1 benchmark serves them all (building it is most of a task's time); an env per
    reward version steps in lockstep with the others, on the same actions."""
    import metaworld

    benchmark = metaworld.MT1(f"{task}-v3", seed=seed)
    env_class = benchmark.train_classes[f"{task}-v3"]
    recorded = {"rows": {}}
    if spaces:
        recorded["spaces"] = observation_spaces(env_class(), benchmark.train_tasks[0])
    envs = {version: env_class(reward_function_version=version) for version in reward_versions}
    rows = recorded["rows"]
    for version in reward_versions:
        rows[version] = []
    policy = policy_for(task)
    rng = np.random.default_rng(seed)
    for goal in benchmark.train_tasks[:goals]:
        for mode in ("random", "scripted"):
            obs = {}
            for version, env in envs.items():
                env.set_task(goal)
                obs[version], _ = env.reset(seed=seed)
            lead = reward_versions[0]  # the reward does not steer the dynamics: obs agree
            for _ in range(steps):
                if mode == "random":
                    action = rng.uniform(-1.0, 1.0, size=4)
                else:
                    action = np.clip(policy.get_action(obs[lead]) + rng.normal(0.0, 0.1, size=4),
                                     -1, 1)
                action = action.astype(np.float32)
                truncated = False
                for version, env in envs.items():
                    obs[version], reward, _, truncated, info = env.step(action)
                    rows[version].append({
                        "task": task,
                        "mode": mode,
                        "state": state_record(env, obs[version], task),
                        "action": [float(a) for a in action],
                        "reward": float(reward),
                        "info": {k: float(v) for k, v in info.items()},
                    })
                if truncated:
                    break
    return recorded


def observation_spaces(env, task):
    """The bounds v3 gives its observation: `sawyer_observation_space`, the Box v3 clips every
    observation to, with the goal hidden ("ml1": as an env is built, and as ML1's tasks keep
    it) and visible ("mt1": after `set_task` with one of MT1's tasks). (The env's
    `observation_space` attribute is the one computed at construction, so its goal bounds stay
    zeros after `set_task` makes the goal visible.) `env`: freshly built; `task`: an MT1 task."""
    box = lambda space: {"low": [float(x) for x in space.low],
                         "high": [float(x) for x in space.high]}
    assert env._partially_observable
    hidden = box(env.sawyer_observation_space)
    env.set_task(task)
    assert not env._partially_observable
    return {"ml1": hidden, "mt1": box(env.sawyer_observation_space)}


def map_tasks(function, tasks, jobs):
    """[function(task) for task in tasks], `jobs` processes at once (one: in this process)."""
    if jobs <= 1 or len(tasks) <= 1:
        return [function(task) for task in tasks]
    with concurrent.futures.ProcessPoolExecutor(max_workers=min(jobs, len(tasks))) as pool:
        return list(pool.map(function, tasks))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tasks", required=True, help="comma-separated task names, e.g. reach,push")
    parser.add_argument("--goals", type=int, default=3, help="MT1 training goals per task")
    parser.add_argument("--steps", type=int, default=150, help="steps per episode")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--reward-versions", default="v2",
                        help="comma-separated, of v1 and v2: the rows of each (default v2)")
    parser.add_argument("--observation-spaces", action="store_true",
                        help="record each task's observation bounds (MT1 and ML1) too")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                        help="tasks recorded at once, each in its own process (default: every core)")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    if args.jobs < 1:
        parser.error(f"--jobs must be at least 1, got {args.jobs}")
    versions = args.reward_versions.split(",")
    if not versions or any(v not in ("v1", "v2") for v in versions) or len(set(versions)) < len(versions):
        parser.error(f"--reward-versions takes distinct v1 and v2, got '{args.reward_versions}'")
    import metaworld

    tasks = args.tasks.split(",")
    record = functools.partial(record_task, goals=args.goals, steps=args.steps, seed=args.seed,
                               reward_versions=versions, spaces=args.observation_spaces)
    per_task = map_tasks(record, tasks, args.jobs)
    out = {"metaworld_version": getattr(metaworld, "__version__", "unknown"),
           "rows": {v: [row for task in per_task for row in task["rows"][v]] for v in versions}}
    if args.observation_spaces:
        out["spaces"] = {task: recorded["spaces"] for task, recorded in zip(tasks, per_task)}
    with open(args.out, "w") as f:
        json.dump(out, f)


if __name__ == "__main__":
    main()
