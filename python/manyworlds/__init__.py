"""manyworlds: multi-task and meta-RL environments from a C++ core, for Gymnasium.

>>> import manyworlds
>>> env = manyworlds.make("cartpole")            # a gymnasium.Env
>>> obs, info = env.reset(seed=42)               # obs = {"env_obs": ..., "task_obs": ...}
>>> obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
>>> envs = manyworlds.make_vec("cartpole", 16, threads=2)   # a gymnasium.vector.VectorEnv

Every registry id is also registered with Gymnasium as ``manyworlds/<id>``
(``gymnasium.make("manyworlds/mt10")``), and Meta-World v3's benchmark ids as
``manyworlds-Meta-World/<id>`` (``gymnasium.make_vec("manyworlds-Meta-World/MT10")``;
``manyworlds.metaworld_gym``). The extension links manyworlds' env, executor and
suite libraries only (never libtorch), so it imports beside PyTorch or JAX.
"""

from __future__ import annotations

from typing import Any, Dict, List

from manyworlds import _core
from manyworlds._core import (
    ConfigError,
    EpisodeStateError,
    Error,
    InvalidActionError,
    TaskStateError,
    mix_seed,
)
from manyworlds.env import ManyworldsEnv, make
from manyworlds.vector import ManyworldsVectorEnv, make_vec
from manyworlds import benchmarks, manipulation

__version__ = "0.1.0"

__all__ = [
    "ManyworldsEnv",
    "ManyworldsVectorEnv",
    "make",
    "make_vec",
    "env_ids",
    "registry",
    "benchmarks",
    "manipulation",
    "mix_seed",
    "Error",
    "ConfigError",
    "InvalidActionError",
    "TaskStateError",
    "EpisodeStateError",
    "GYMNASIUM_NAMESPACE",
]

GYMNASIUM_NAMESPACE = "manyworlds"


def registry() -> List[Dict[str, Any]]:
    """Every registered env: dicts ``{id, family, description, options}``.

    Each option is ``{name, type, default, doc, choices}``; these are the keyword arguments of
    ``make``.
    """
    return _core.registry_entries()


def env_ids() -> List[str]:
    """The ids of every registered env, in registry order."""
    return [entry["id"] for entry in _core.registry_entries()]


def _register_with_gymnasium() -> None:
    import gymnasium

    for env_id in env_ids():
        gym_id = f"{GYMNASIUM_NAMESPACE}/{env_id}"
        if gym_id in gymnasium.registry:
            continue
        gymnasium.register(
            id=gym_id,
            entry_point="manyworlds.env:ManyworldsEnv",
            vector_entry_point="manyworlds.vector:_gymnasium_vector_entry_point",
            kwargs={"env_id": env_id},
        )


_register_with_gymnasium()

# Meta-World v3's ids (MT1, MT10, ML10-train, ...) under a namespace of our own, so that they never
# replace the official package's "Meta-World/..." when both are imported.
from manyworlds import metaworld_gym  # noqa: E402

metaworld_gym.register_envs()
