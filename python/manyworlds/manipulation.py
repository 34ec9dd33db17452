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

_envs: Dict[str, "_core.Env"] = {}


def _env(task: str) -> "_core.Env":
    if not getattr(_core, "has_mujoco", False):
        raise _core.Error("this build of manyworlds has no MuJoCo suites")
    if task not in _envs:
        _envs[task] = _core.Env(task)
    return _envs[task]


def state_fields() -> List[str]:
    """The keys of a state record."""
    return list(_core.sawyer_state_fields)


def reward(task: str, state: Dict[str, object], action: Sequence[float]) -> Dict[str, float]:
    """Reward, success and the info fields of manipulation task ``task`` for ``state`` and a
    4-value ``action``. Unknown or missing keys raise ConfigError naming them."""
    return _core.sawyer_reward(_env(task), dict(state), np.asarray(action, dtype=np.float32))


def state(task: str, seed: int = 0) -> Dict[str, object]:
    """The state record of ``task`` after a reset on its first variation (task seed ``seed``)."""
    env = _core.Env(task)
    env.seed_task(seed)
    env.reset()
    return _core.sawyer_state(env)
