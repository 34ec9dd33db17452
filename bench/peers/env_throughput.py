#!/usr/bin/env python3
"""Env steps per second per core: manyworlds (C++ and through Python) against Python
Meta-World v3 and EnvPool's Meta-World port, on the same task names, with the raw MuJoCo
cost of each side's scene next to the env rate.

Run by bench/peers/env_throughput.sh, which makes the virtual environment (.venv-peers/:
metaworld, envpool, mujoco and this checkout's manyworlds from PyPI/pip) and passes the
C++ programs. Every measurement is one thread on one core; rounds are interleaved (every
method of every task once per round) and the median over rounds is reported, so a noisy
machine affects all methods alike. Every rate is wall-clock (the C++ benchmark's CPU-time rate
is converted), so the rows stay comparable when other work shares the machine.

Methods (env steps/s, random actions in [-1, 1]^4 drawn beforehand, episodes of 500 steps):
  mw_env        metaworld v3: gymnasium.make("Meta-World/MT1", env_name="<task>-v3")
  mw_raw        the Meta-World model driven by hand: mocap and ctrl written, frame_skip
                mj_step calls (nstep, one Python call), hand and object positions read;
                this is the scene cost the env pays at least (MuJoCo from PyPI)
  envpool_1     envpool "MetaWorld/<Task>-v3", 1 env, 1 thread
  envpool_16    envpool, 16 envs stepped as one batch on 1 thread
  mw_py_env     manyworlds through Python: manyworlds.make("<task>"), one step per call
  mw_py_vec16   manyworlds through Python: make_vec("<task>", 16, threads=1)
  ours_raw_py   our model (manyworlds export-xml) in PyPI's MuJoCo, driven like mw_raw
  cpp_env       manyworlds C++ env step (bench_manipulation BM_EnvStep, Debian's MuJoCo 2.2.2)
  cpp_raw       our model driven by hand in C++ (BM_RawPhysics, MuJoCo 2.2.2)
  cpp_vec16     manyworlds C++ executor, 16 envs, 1 thread (`manyworlds bench env`)
(mw_* here is Meta-World; manyworlds' own rows are mw_py_*, ours_*, cpp_*.)
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

TASKS = ["reach", "push", "pick-place", "door-open", "drawer-open", "window-open"]
EPISODE = 500


def camel(task: str) -> str:
    return "".join(p.capitalize() for p in task.split("-"))


def actions(n: int, seed: int = 1) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-1, 1, size=(n, 4)).astype(np.float32)


class Timer:
    """Runs fn(steps) and returns env steps per second."""

    @staticmethod
    def rate(fn, steps: int) -> float:
        start = time.perf_counter()
        done = fn(steps)
        return done / (time.perf_counter() - start)


# -- Meta-World ------------------------------------------------------------------------------


def make_mw(task: str):
    import gymnasium as gym
    import metaworld  # noqa: F401  (registers Meta-World/*)

    env = gym.make("Meta-World/MT1", env_name=f"{task}-v3", seed=0)
    env.reset(seed=0)
    return env


def mw_env_runner(task: str):
    env = make_mw(task)
    acts = actions(4096)

    def run(steps: int) -> int:
        env.reset()
        t = 0
        for i in range(steps):
            _, _, term, trunc, _ = env.step(acts[i % 4096])
            t += 1
            if term or trunc or t == EPISODE:
                env.reset()
                t = 0
        return steps

    return run


def raw_runner(model, data, frame_skip: int, mocap_id: int, low, high, scale: float, sites):
    import mujoco

    acts = actions(4096)
    start = (data.qpos.copy(), data.qvel.copy(), data.mocap_pos.copy(), data.mocap_quat.copy(),
             data.act.copy() if model.na else None, data.time)

    def restore():
        data.qpos[:], data.qvel[:], data.mocap_pos[:], data.mocap_quat[:] = start[0], start[1], start[2], start[3]
        if start[4] is not None:
            data.act[:] = start[4]
        data.time = start[5]
        mujoco.mj_forward(model, data)

    def run(steps: int) -> int:
        restore()
        t = 0
        for i in range(steps):
            a = acts[i % 4096]
            data.mocap_pos[mocap_id] = np.clip(data.mocap_pos[mocap_id] + scale * a[:3], low, high)
            data.ctrl[:] = (a[3], -a[3]) if model.nu == 2 else a[3]
            mujoco.mj_step(model, data, nstep=frame_skip)
            _ = [data.site_xpos[s].sum() for s in sites]
            t += 1
            if t == EPISODE:
                restore()
                t = 0
        return steps

    return run


def mw_raw_runner(task: str):
    import mujoco

    env = make_mw(task).unwrapped
    m, d = env.model, env.data
    mocap = m.body_mocapid[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "mocap")]
    sites = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, n) for n in ("rightEndEffector", "leftEndEffector")]
    sites = [s for s in sites if s >= 0]
    return raw_runner(m, d, env.frame_skip, mocap, env.mocap_low, env.mocap_high, env.action_scale, sites)


# -- EnvPool ---------------------------------------------------------------------------------


def envpool_runner(task: str, num_envs: int):
    import envpool

    env = envpool.make(f"MetaWorld/{camel(task)}-v3", env_type="gymnasium", num_envs=num_envs,
                       batch_size=num_envs, num_threads=1, seed=0)
    env.reset()
    acts = actions(4096)

    def run(steps: int) -> int:
        rounds = max(1, steps // num_envs)
        for i in range(rounds):
            a = np.repeat(acts[i % 4096][None], num_envs, axis=0)
            env.step(a)
        return rounds * num_envs

    return run


# -- manyworlds through Python ---------------------------------------------------------------


def ours_env_runner(task: str):
    import manyworlds

    env = manyworlds.make(task)
    env.reset(seed=0)
    acts = actions(4096)

    def run(steps: int) -> int:
        env.reset()
        for i in range(steps):
            _, _, term, trunc, _ = env.step(acts[i % 4096])
            if term or trunc:
                env.reset()
        return steps

    return run


def ours_vec_runner(task: str, num_envs: int = 16):
    import manyworlds

    envs = manyworlds.make_vec(task, num_envs, threads=1)
    envs.reset(seed=0)
    acts = actions(4096)

    def run(steps: int) -> int:
        rounds = max(1, steps // num_envs)
        for i in range(rounds):
            envs.step(np.repeat(acts[i % 4096][None], num_envs, axis=0))
        return rounds * num_envs

    return run


def ours_raw_py_runner(task: str, cli: str):
    import mujoco

    path = os.path.join(tempfile.mkdtemp(), f"{task}.xml")
    subprocess.run([cli, "export-xml", "--env", task, "--out", path], check=True, capture_output=True)
    m = mujoco.MjModel.from_xml_path(path)
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    mujoco.mj_forward(m, d)
    mocap = m.body_mocapid[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "hand_mocap")]
    sites = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, n) for n in ("hand_site", "left_pad_site", "right_pad_site")]
    low = d.mocap_pos[mocap] - 0.5
    high = d.mocap_pos[mocap] + 0.5
    return raw_runner(m, d, 5, mocap, low, high, 0.01, [s for s in sites if s >= 0])


# -- C++ -------------------------------------------------------------------------------------


def cpp_bench_manipulation(binary: str, task: str, which: str) -> float:
    out = subprocess.run(
        [binary, f"--benchmark_filter=^BM_{which}/{task}$", "--benchmark_min_time=1", "--benchmark_format=json"],
        check=True, capture_output=True, text=True,
    ).stdout
    bench = json.loads(out)["benchmarks"][0]
    # Google Benchmark's items_per_second counts CPU time; every other row here is wall-clock
    # (and a loaded machine slows the wall clock alone), so convert.
    return float(bench["items_per_second"]) * float(bench["cpu_time"]) / float(bench["real_time"])


def cpp_vec(cli: str, task: str, num_envs: int = 16) -> float:
    out = subprocess.run(
        [cli, "bench", "env", "--env", task, "--num-envs", str(num_envs), "--threads", "1",
         "--steps", "40000", "--repeats", "1", "--json"],
        check=True, capture_output=True, text=True,
    ).stdout
    return float(json.loads(out)["steps_per_s"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tasks", nargs="+", default=TASKS)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=1.0, help="target time per measurement")
    parser.add_argument("--cli", default="build/manyworlds")
    parser.add_argument("--bench-manipulation", default="build/bench/bench_manipulation")
    parser.add_argument("--json", help="write the results here as well")
    args = parser.parse_args()

    have_cli = os.access(args.cli, os.X_OK)
    have_bm = os.access(args.bench_manipulation, os.X_OK)
    methods = {}
    for task in args.tasks:
        methods[(task, "mw_env")] = mw_env_runner(task)
        methods[(task, "mw_raw")] = mw_raw_runner(task)
        try:
            methods[(task, "envpool_1")] = envpool_runner(task, 1)
            methods[(task, "envpool_16")] = envpool_runner(task, 16)
        except Exception as error:  # an EnvPool build without this task
            print(f"envpool: {task}: {error}", file=sys.stderr)
        methods[(task, "mw_py_env")] = ours_env_runner(task)
        methods[(task, "mw_py_vec16")] = ours_vec_runner(task)
        if have_cli:
            methods[(task, "ours_raw_py")] = ours_raw_py_runner(task, args.cli)

    # Calibrate: steps that take about --seconds each.
    steps = {}
    for key, fn in methods.items():
        rate = Timer.rate(fn, 200)
        steps[key] = max(200, int(rate * args.seconds))

    samples = {key: [] for key in methods}
    for task in args.tasks:
        if have_bm:
            samples[(task, "cpp_env")] = []
            samples[(task, "cpp_raw")] = []
        if have_cli:
            samples[(task, "cpp_vec16")] = []
    for r in range(args.rounds):
        for task in args.tasks:
            for key, fn in methods.items():
                if key[0] == task:
                    samples[key].append(Timer.rate(fn, steps[key]))
            if have_bm:
                samples[(task, "cpp_env")].append(cpp_bench_manipulation(args.bench_manipulation, task, "EnvStep"))
                samples[(task, "cpp_raw")].append(cpp_bench_manipulation(args.bench_manipulation, task, "RawPhysics"))
            if have_cli:
                samples[(task, "cpp_vec16")].append(cpp_vec(args.cli, task))
        print(f"round {r + 1}/{args.rounds} done", file=sys.stderr)

    order = ["cpp_env", "cpp_vec16", "mw_py_env", "mw_py_vec16", "cpp_raw", "ours_raw_py",
             "mw_env", "envpool_1", "envpool_16", "mw_raw"]
    medians = {f"{t}/{m}": statistics.median(v) for (t, m), v in samples.items() if v}
    header = ["task"] + order
    print(" ".join(f"{h:>12}" for h in header))
    for task in args.tasks:
        row = [f"{task:>12}"]
        for m in order:
            v = medians.get(f"{task}/{m}")
            row.append(f"{v:12.0f}" if v is not None else f"{'-':>12}")
        print(" ".join(row))
    info = {
        "machine": platform.processor() or platform.machine(),
        "cpu": next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?"),
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "loadavg": os.getloadavg(),
        "rounds": args.rounds,
        "medians": medians,
        "samples": {f"{t}/{m}": v for (t, m), v in samples.items()},
    }
    print(json.dumps({k: info[k] for k in ("cpu", "date", "loadavg", "rounds")}))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(info, f, indent=1)


if __name__ == "__main__":
    main()
