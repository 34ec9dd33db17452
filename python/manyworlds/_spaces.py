"""Conversion of manyworlds spaces into Gymnasium spaces."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np
from gymnasium import spaces


def action_space(desc: Mapping[str, Any]) -> spaces.Space:
    """The Gymnasium action space of a manyworlds space description.

    A ``Discrete(n)`` action stays ``gymnasium.spaces.Discrete(n)``; a Box becomes a float32
    ``gymnasium.spaces.Box`` with the same per-element bounds and shape.
    """
    if desc["kind"] == "discrete":
        return spaces.Discrete(int(desc["n"]))
    return spaces.Box(low=desc["low"], high=desc["high"], shape=tuple(desc["shape"]), dtype=np.float32)


def observation_box(desc: Mapping[str, Any]) -> spaces.Box:
    """The Gymnasium space of one observation part, always a float32 Box.

    manyworlds carries every value as float32; a ``Discrete(n)`` observation part (the task
    index of an MT benchmark, of ``MultiEnv`` or ``NTasksId``) is one float holding the
    integer, so it becomes ``Box(0, n - 1, (1,), float32)``. This keeps observations of the
    single and the vector env the same arrays the C++ core writes (no conversion, no copy).
    """
    if desc["kind"] == "discrete":
        n = int(desc["n"])
        return spaces.Box(low=0.0, high=float(n - 1), shape=(1,), dtype=np.float32)
    return spaces.Box(low=desc["low"], high=desc["high"], shape=tuple(desc["shape"]), dtype=np.float32)


def observation_space(env_obs: Mapping[str, Any], task_obs: Mapping[str, Any], flat: bool) -> spaces.Space:
    """``Dict(env_obs=Box, task_obs=Box)``, or with ``flat`` one Box of both concatenated."""
    env_box = observation_box(env_obs)
    task_box = observation_box(task_obs)
    if not flat:
        return spaces.Dict({"env_obs": env_box, "task_obs": task_box})
    low = np.concatenate([env_box.low.ravel(), task_box.low.ravel()])
    high = np.concatenate([env_box.high.ravel(), task_box.high.ravel()])
    return spaces.Box(low=low, high=high, shape=low.shape, dtype=np.float32)
