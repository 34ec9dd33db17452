"""Stable-Baselines3 adapter: a manyworlds vector env as an SB3 ``VecEnv``.

SB3 (2.x) has its own vector-env interface rather than Gymnasium's; its autoreset is the same
as manyworlds' (same step: the observation after an episode's end is the next episode's first,
the last one is ``infos[i]["terminal_observation"]``), so the executor maps onto it directly::

    from stable_baselines3 import PPO
    from manyworlds.sb3 import SB3VecEnv

    venv = SB3VecEnv("point-nav", num_envs=8, threads=2)
    model = PPO("MlpPolicy", venv, seed=0).learn(20_000)

Observations are flat (``flat_obs=True``) float32 arrays, or with ``obs="pixels"`` the uint8
frames (``CnnPolicy``). Unlike ``ManyworldsVectorEnv``, this
adapter **copies** observations and rewards every step, because SB3's learners keep a reference
to the previous observation while stepping. Importing this module needs stable-baselines3.
"""

from __future__ import annotations

from typing import Any, List, Optional, Sequence

import numpy as np
from stable_baselines3.common.vec_env.base_vec_env import VecEnv

from manyworlds.vector import ManyworldsVectorEnv


class SB3VecEnv(VecEnv):
    """N manyworlds envs on the batched executor, as a Stable-Baselines3 ``VecEnv``.

    Arguments are those of :func:`manyworlds.make_vec` (``env_ids``, ``num_envs``, ``threads``,
    ``task_states``, registry options); observations are always flat.
    """

    def __init__(self, env_ids: Any, num_envs: Optional[int] = None, **kwargs: Any) -> None:
        kwargs["flat_obs"] = True
        self.venv = ManyworldsVectorEnv(env_ids, num_envs, **kwargs)
        super().__init__(self.venv.num_envs, self.venv.single_observation_space, self.venv.single_action_space)
        # float32 states, or uint8 frames with obs="pixels" (SB3's CnnPolicy scales them)
        self._obs_dtype = self.venv.single_observation_space.dtype
        self._actions: Optional[np.ndarray] = None

    def reset(self) -> np.ndarray:
        seeds = getattr(self, "_seeds", None)
        seed: Any = None
        if seeds and any(s is not None for s in seeds):
            seed = [None if s is None else int(s) % 2**64 for s in seeds]
        obs, _ = self.venv.reset(seed=seed)
        self._seeds = [None] * self.num_envs
        return np.array(obs, dtype=self._obs_dtype, copy=True)

    def step_async(self, actions: np.ndarray) -> None:
        self.venv.step_async(actions)

    def step_wait(self):
        obs, rewards, terminated, truncated, infos = self.venv.step_wait()
        dones = terminated | truncated
        fields = self.venv.info_fields
        out_infos: List[dict] = []
        for i in range(self.num_envs):
            info = {name: float(infos[name][i]) for name in fields}
            if dones[i]:
                info["terminal_observation"] = np.asarray(infos["final_obs"][i], dtype=self._obs_dtype)
                info["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
            out_infos.append(info)
        return (
            np.array(obs, dtype=self._obs_dtype, copy=True),
            rewards.astype(np.float32, copy=True),
            dones.copy(),
            out_infos,
        )

    def close(self) -> None:
        self.venv.close()

    def get_attr(self, attr_name: str, indices: Any = None) -> List[Any]:
        value = getattr(self.venv, attr_name, None)
        return [value for _ in self._get_indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        raise AttributeError(f"SB3VecEnv: attributes of the envs cannot be set ({attr_name})")

    def env_method(self, method_name: str, *method_args: Any, indices: Any = None, **method_kwargs: Any) -> List[Any]:
        if method_name in ("get_task_state", "sample_task_state", "reset_task_state"):
            return [getattr(self.venv, method_name)(i) for i in self._get_indices(indices)]
        raise AttributeError(f"SB3VecEnv: env method '{method_name}' is not available")

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> List[bool]:
        return [False for _ in self._get_indices(indices)]

    def _get_indices(self, indices: Any) -> Sequence[int]:
        if indices is None:
            return range(self.num_envs)
        if isinstance(indices, int):
            return [indices]
        return list(indices)
