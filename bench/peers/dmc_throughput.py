#!/usr/bin/env python3
"""State and pixel steps per second of the DeepMind-Control-style suites: manyworlds (C++
executor and the Python vector env) against dm_control with an MTEnv-style pixel wrapper, on
finger-spin, cheetah-run and walker-walk.

Run by bench/peers/dmc_throughput.sh (which makes the virtual environment with dm-control from
PyPI). Rounds are interleaved (every method of every task once per round) and the median over
rounds is reported, so a noisy machine affects every method alike. Rates are wall-clock.

The pixel rows use MTEnv's settings for its HiP-BMDP envs: 84 x 84 RGB from camera 0, action
repeat 2, 3 stacked frames, channels first; their rate counts agent steps (each two control
steps and one rendered frame). The state rows count control steps.

Methods:
  dmc_state        dm_control suite env.step, one call per control step (one core)
  ours_state_1     manyworlds C++ executor, 1 env, 1 thread (`manyworlds bench env`)
  ours_state_16    manyworlds C++ executor, 16 envs, 1 thread
  dmc_px           dm_control + an MTEnv-style wrapper (step `repeat` times, then
                   physics.render(84, 84, camera_id=0), HWC -> CHW, a deque of 3 frames
                   concatenated), LP_NUM_THREADS=0: llvmpipe renders on the calling thread
                   (one core); dm_control renders with the model's shadows and multisampling
  dmc_px_2proc     dmc_px in two processes at once, rates summed (both cores)
  ours_px_full_16  manyworlds C++, obs=pixels pixel_quality=full (shadows, multisampling as
                   dm_control), 16 envs, 1 thread
  ours_px_16       manyworlds C++, obs=pixels (pixel_quality=fast: no shadows or multisampling),
                   16 envs, 1 thread
  ours_px_16_2thr  as ours_px_16 on 2 threads (both cores)
  ours_px_py_16    manyworlds through Python: make_vec(..., 16, threads=1, obs="pixels"),
                   random actions drawn beforehand (the Python interpreter in --ours-python)
"""

from __future__ import annotations

import argparse
import collections
import json
import multiprocessing
import os
import platform
import statistics
import subprocess
import sys
import time

import numpy as np

TASKS = {"finger-spin": ("finger", "spin"), "cheetah-run": ("cheetah", "run"), "walker-walk": ("walker", "walk")}
SIZE, REPEAT, FRAMES = 84, 2, 3


def actions(n: int, dim: int, seed: int = 1) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-1, 1, size=(n, dim)).astype(np.float32)


class MtenvStylePixels:
    """What MTEnv's DMC wrapper and frame stack do per agent step (written from its behaviour)."""

    def __init__(self, env):
        self.env = env
        self.frames = collections.deque(maxlen=FRAMES)

    def _frame(self):
        image = self.env.physics.render(SIZE, SIZE, camera_id=0)
        return image.transpose(2, 0, 1).copy()

    def reset(self):
        self.env.reset()
        frame = self._frame()
        for _ in range(FRAMES):
            self.frames.append(frame)
        return np.concatenate(list(self.frames), axis=0)

    def step(self, action):
        reward, last = 0.0, None
        for _ in range(REPEAT):
            last = self.env.step(action)
            reward += last.reward or 0.0
            if last.last():
                break
        self.frames.append(self._frame())
        return np.concatenate(list(self.frames), axis=0), reward, last.last()


def dmc_state_rate(task: str, steps: int) -> float:
    from dm_control import suite

    domain, name = TASKS[task]
    env = suite.load(domain, name, task_kwargs={"random": 0})
    acts = actions(4096, env.action_spec().shape[0])
    env.reset()
    start = time.perf_counter()
    for i in range(steps):
        if env.step(acts[i % 4096]).last():
            env.reset()
    return steps / (time.perf_counter() - start)


def dmc_pixel_rate(task: str, steps: int) -> float:
    from dm_control import suite

    domain, name = TASKS[task]
    env = MtenvStylePixels(suite.load(domain, name, task_kwargs={"random": 0}))
    acts = actions(4096, env.env.action_spec().shape[0])
    env.reset()
    env.step(acts[0])  # the first frame sets up the GL resources
    start = time.perf_counter()
    for i in range(steps):
        if env.step(acts[i % 4096])[2]:
            env.reset()
    return steps / (time.perf_counter() - start)


def _pixel_worker(args):
    task, steps = args
    return dmc_pixel_rate(task, steps)


def dmc_pixel_rate_2proc(task: str, steps: int) -> float:
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(2) as pool:
        return float(sum(pool.map(_pixel_worker, [(task, steps), (task, steps)])))


def ours_cpp(cli: str, task: str, steps: int, num_envs: int, threads: int, options: list[str]) -> float:
    command = [cli, "bench", "env", "--env", f"dmc-{task}", "--num-envs", str(num_envs), "--threads", str(threads),
               "--steps", str(steps), "--repeats", "1", "--json"]
    for option in options:
        command += ["--option", option]
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    return float(json.loads(out)["steps_per_s"])


OURS_PY = r"""
import sys, time, numpy as np, manyworlds
task, steps = sys.argv[1], int(sys.argv[2])
venv = manyworlds.make_vec(f"dmc-{task}", 16, threads=1, obs="pixels", action_repeat=2, frame_stack=3)
dim = venv.single_action_space.shape[0]
acts = np.random.default_rng(1).uniform(-1, 1, size=(256, 16, dim)).astype(np.float32)
venv.reset(seed=0)
venv.step(acts[0])
rounds = max(1, steps // 16)
start = time.perf_counter()
for i in range(rounds):
    venv.step(acts[i % 256])
print(rounds * 16 / (time.perf_counter() - start))
"""


def ours_python(python: str, task: str, steps: int) -> float:
    out = subprocess.run([python, "-c", OURS_PY, task, str(steps)], check=True, capture_output=True, text=True)
    return float(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cli", required=True, help="the manyworlds program (build/manyworlds)")
    parser.add_argument("--ours-python", default="", help="a Python with the manyworlds package (ours_px_py_16)")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--state-steps", type=int, default=20000)
    parser.add_argument("--pixel-steps", type=int, default=300, help="agent steps per pixel measurement")
    parser.add_argument("--tasks", default=",".join(TASKS))
    parser.add_argument("--json", default="", help="also write the results here")
    args = parser.parse_args()
    os.environ["LP_NUM_THREADS"] = "0"  # one core per renderer, on both sides
    os.environ.setdefault("MUJOCO_GL", "osmesa")
    tasks = args.tasks.split(",")
    px = ["obs=pixels", f"action_repeat={REPEAT}", f"frame_stack={FRAMES}"]
    methods = {
        "dmc_state": lambda t: dmc_state_rate(t, args.state_steps),
        "ours_state_1": lambda t: ours_cpp(args.cli, t, args.state_steps, 1, 1, []),
        "ours_state_16": lambda t: ours_cpp(args.cli, t, args.state_steps, 16, 1, []),
        "dmc_px": lambda t: dmc_pixel_rate(t, args.pixel_steps),
        "dmc_px_2proc": lambda t: dmc_pixel_rate_2proc(t, args.pixel_steps),
        "ours_px_full_16": lambda t: ours_cpp(args.cli, t, args.pixel_steps, 16, 1, px + ["pixel_quality=full"]),
        "ours_px_16": lambda t: ours_cpp(args.cli, t, 4 * args.pixel_steps, 16, 1, px),
        "ours_px_16_2thr": lambda t: ours_cpp(args.cli, t, 4 * args.pixel_steps, 16, 2, px),
    }
    if args.ours_python:
        methods["ours_px_py_16"] = lambda t: ours_python(args.ours_python, t, 4 * args.pixel_steps)
    samples = {(t, m): [] for t in tasks for m in methods}
    for r in range(args.rounds):
        for t in tasks:
            for m, fn in methods.items():
                samples[(t, m)].append(fn(t))
                print(f"round {r + 1}/{args.rounds} {t} {m}: {samples[(t, m)][-1]:.0f}/s", file=sys.stderr, flush=True)
    medians = {f"{t}/{m}": statistics.median(v) for (t, m), v in samples.items()}
    print(f"{'task':<12} " + " ".join(f"{m:>16}" for m in methods))
    for t in tasks:
        print(f"{t:<12} " + " ".join(f"{medians[f'{t}/{m}']:>16.0f}" for m in methods))
    print("ratios: ours_px_16 / dmc_px, ours_px_full_16 / dmc_px, ours_px_16_2thr / dmc_px_2proc, "
          "ours_state_1 / dmc_state")
    for t in tasks:
        g = lambda m: medians[f"{t}/{m}"]  # noqa: E731
        print(f"{t:<12} {g('ours_px_16') / g('dmc_px'):.1f}x {g('ours_px_full_16') / g('dmc_px'):.1f}x "
              f"{g('ours_px_16_2thr') / g('dmc_px_2proc'):.1f}x {g('ours_state_1') / g('dmc_state'):.1f}x")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"machine": platform.processor() or platform.machine(), "rounds": args.rounds,
                       "medians": medians, "samples": {f"{t}/{m}": v for (t, m), v in samples.items()}}, f, indent=1)


if __name__ == "__main__":
    main()
