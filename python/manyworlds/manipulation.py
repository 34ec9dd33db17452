"""The manipulation tasks' reward as a pure function of a state record.

Every manipulation task computes its reward, success and info from a record of world-frame
quantities (C++ ``SawyerState``: hand, tcp, finger pads, object, goal, initial positions,
gripper opening, contact) and the action. ``reward`` evaluates a task on a record given from
Python, e.g. quantities read from Meta-World's own simulator, which is how
``python/tests/test_metaworld_fidelity.py`` checks our definitions against the official package.

>>> import manyworlds.manipulation as mp
>>> record = mp.state("reach")           # the record after a reset
>>> mp.reward("reach", record, [0, 0, 0, -1])["reward"]
"""

from __future__ import annotations

from typing import Dict, List, Sequence

import numpy as np

from manyworlds import _core

_envs: Dict[tuple, "_core.Env"] = {}


def _env(task: str, reward_version: str = "v2") -> "_core.Env":
    if not getattr(_core, "has_mujoco", False):
        raise _core.Error("this build of manyworlds has no MuJoCo suites")
    key = (task, reward_version)
    if key not in _envs:
        _envs[key] = _core.Env(task, {"reward_version": reward_version})
    return _envs[key]


def state_fields() -> List[str]:
    """The keys of a state record."""
    return list(_core.sawyer_state_fields)


def reward(task: str, state: Dict[str, object], action: Sequence[float],
           reward_version: str = "v2") -> Dict[str, float]:
    """Reward, success and the info fields of manipulation task ``task`` for ``state`` and a
    4-value ``action``, under Meta-World's ``reward_version`` ("v2", v3's default, or "v1" where
    the task has it). Unknown or missing keys raise ConfigError naming them."""
    return _core.sawyer_reward(_env(task, reward_version), dict(state),
                               np.asarray(action, dtype=np.float32))


def state(task: str, seed: int = 0) -> Dict[str, object]:
    """The state record of ``task`` after a reset on its first variation (task seed ``seed``)."""
    env = _core.Env(task)
    env.seed_task(seed)
    env.reset()
    return _core.sawyer_state(env)
