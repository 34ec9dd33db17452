"""Conversion of manyworlds spaces into Gymnasium spaces."""

from __future__ import annotations

from typing import Any, Mapping, Optional

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


def has_pixels(pixel_desc: Optional[Mapping[str, Any]]) -> bool:
    """True for the pixel space of an env made with ``obs="pixels"`` (else its shape is (0,))."""
    return pixel_desc is not None and int(np.prod(pixel_desc["shape"])) > 0


def pixel_box(pixel_desc: Mapping[str, Any]) -> spaces.Box:
    """The uint8 Box of pixel observations: ``(3 x frames, height, width)``, values 0..255."""
    return spaces.Box(low=0, high=255, shape=tuple(pixel_desc["shape"]), dtype=np.uint8)


def observation_space(env_obs: Mapping[str, Any], task_obs: Mapping[str, Any], flat: bool,
                      pixels: Optional[Mapping[str, Any]] = None) -> spaces.Space:
    """``Dict(env_obs=Box, task_obs=Box)``, or with ``flat`` one Box of both concatenated.

    With pixels: ``Dict(env_obs=uint8 frames, task_obs=Box, state=Box)`` (the state is the
    float env observation, for asymmetric critics), or with ``flat`` the frames alone.
    """
    env_box = observation_box(env_obs)
    task_box = observation_box(task_obs)
    if has_pixels(pixels):
        frames = pixel_box(pixels)
        if flat:
            return frames
        return spaces.Dict({"env_obs": frames, "task_obs": task_box, "state": env_box})
    if not flat:
        return spaces.Dict({"env_obs": env_box, "task_obs": task_box})
    low = np.concatenate([env_box.low.ravel(), task_box.low.ravel()])
    high = np.concatenate([env_box.high.ravel(), task_box.high.ravel()])
    return spaces.Box(low=low, high=high, shape=low.shape, dtype=np.float32)
