"""manyworlds' batched executor as a ``gymnasium.vector.VectorEnv``."""

from __future__ import annotations

from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import gymnasium as gym
import numpy as np
from gymnasium.vector.utils import batch_space

from manyworlds import _core, _spaces
from manyworlds.env import RESET_OPTIONS, _check_seed

try:  # Gymnasium >= 1.1 names the modes
    from gymnasium.vector import AutoresetMode

    _SAME_STEP: Any = AutoresetMode.SAME_STEP
except ImportError:  # Gymnasium 1.0
    _SAME_STEP = "SameStep"

EnvEntry = Union[str, Tuple[str, Mapping[str, Any]]]


class ManyworldsVectorEnv(gym.vector.VectorEnv):
    """N manyworlds envs stepped together by the C++ batched executor.

    Observations, rewards, terminations, truncations and the info fields are **numpy views of
    the executor's buffers**: no copy is made, and the same array objects are returned by every
    ``reset``/``step``/``recv`` and overwritten by the next one. Copy what you keep
    (``obs["env_obs"].copy()``). The views are read-only.

    Autoreset mode: **same-step** (Gymnasium's ``AutoresetMode.SAME_STEP``, also in
    ``metadata["autoreset_mode"]``). When an env's episode ends in a step, its reward,
    termination, truncation and info describe that last step, while its observation row already
    holds the first observation of the next episode; the last observation of the ended episode
    is in ``infos["final_obs"][i]`` (masked by ``infos["_final_obs"]``) and its info in
    ``infos["final_info"]``. There is no extra reset step, and the next action applies to the
    new episode.

    The envs may mix tasks and even env ids, as long as their action, env-observation and
    task-observation sizes and their info fields agree (e.g. the ten MT10 tasks, or one
    benchmark id with a different task state per env).

    Seeding: ``reset(seed=s)`` gives env i the env seed ``mix_seed(s, i)`` and the task seed
    ``mix_seed(t, i)``, where ``t`` is the reset option ``task_seed`` (default: the last one,
    initially 0); ``seed`` may also be a list with one seed (or ``None``) per env. Before any
    seed, env i has the seeds ``mix_seed(0, i)``, so the envs differ from the start. Results
    never depend on ``threads``.

    Args:
        env_ids: One id (repeated ``num_envs`` times), or a list of ids or ``(id, options)``
            pairs, one per env.
        num_envs: Number of envs when ``env_ids`` is one id (default 1).
        threads: Worker threads stepping the envs (1 steps on the calling thread).
        flat_obs: One float32 Box per env instead of the ``env_obs``/``task_obs`` dict (a copy
            unless the task observation is empty).
        task_states: Optional list of task states, one per env (``None`` entries sample).
        **options: Registry options applied to every env (merged under per-env options).
    """

    def __init__(
        self,
        env_ids: Union[str, Sequence[EnvEntry]],
        num_envs: Optional[int] = None,
        *,
        threads: int = 1,
        flat_obs: bool = False,
        task_states: Optional[Sequence[Optional[Mapping[str, Any]]]] = None,
        **options: Any,
    ) -> None:
        if isinstance(env_ids, str):
            count = 1 if num_envs is None else int(num_envs)
            if not 1 <= count <= _core.MAX_ENVS:
                raise ValueError(f"num_envs must be in [1, {_core.MAX_ENVS}], got {count}")
            entries: List[Tuple[str, Dict[str, Any]]] = [(env_ids, {}) for _ in range(count)]
        else:
            entries = []
            for item in env_ids:
                if isinstance(item, str):
                    entries.append((item, {}))
                else:
                    env_id, env_options = item
                    entries.append((env_id, dict(env_options)))
            if not entries:
                raise ValueError("env_ids: at least one env is needed")
            if num_envs is not None and int(num_envs) != len(entries):
                raise ValueError(f"num_envs={num_envs} but {len(entries)} env ids were given")
        if isinstance(threads, bool) or not 1 <= int(threads) <= _core.MAX_THREADS:
            raise ValueError(f"threads must be an int in [1, {_core.MAX_THREADS}], got {threads!r}")
        if len(entries) > _core.MAX_ENVS:
            raise ValueError(f"at most {_core.MAX_ENVS} envs, got {len(entries)}")

        # envs too many for this machine's memory are refused after the first few are made
        memory = _core.BatchMemoryCheck(len(entries), f"{len(entries)} envs", "num_envs")
        core_envs = []
        for index, (env_id, env_options) in enumerate(entries):
            core_envs.append(_core.Env(env_id, {**options, **env_options}))
            memory.made(index)
        if task_states is not None:
            if len(task_states) != len(core_envs):
                raise ValueError(f"task_states: expected {len(core_envs)} entries, got {len(task_states)}")
            for env, state in zip(core_envs, task_states):
                if state is not None:
                    env.set_task_state(state)
        first = core_envs[0]
        action_desc = first.action_space
        env_obs_desc = first.env_obs_space
        task_obs_desc = first.task_obs_space
        pixel_desc = first.pixel_space
        for (env_id, _), env in zip(entries, core_envs):
            if tuple(env.pixel_space["shape"]) != tuple(pixel_desc["shape"]):
                raise ValueError(f"env '{env_id}' has pixel observations of shape {tuple(env.pixel_space['shape'])}, "
                                 f"env '{entries[0][0]}' of shape {tuple(pixel_desc['shape'])}; a batch needs one shape")
        for (env_id, _), env in zip(entries, core_envs):
            if env.action_space["kind"] != action_desc["kind"]:
                raise ValueError(
                    f"env '{env_id}' has a {env.action_space['kind']} action space, "
                    f"env '{entries[0][0]}' a {action_desc['kind']} one"
                )

        self._exec = _core.Executor(core_envs, num_threads=int(threads))
        # Distinct, deterministic envs even without a seed: env i gets the env and task
        # seeds mix_seed(0, i) (a task state given above stays).
        self._exec.seed(0, 0)
        self.env_ids = [env_id for env_id, _ in entries]
        self.num_envs = len(entries)
        self.flat_obs = bool(flat_obs)
        self.threads = int(threads)
        self.metadata = {"autoreset_mode": _SAME_STEP, "render_modes": []}
        self.render_mode = None
        self._task_seed = 0
        self._discrete = action_desc["kind"] == "discrete"

        self.single_action_space = _spaces.action_space(action_desc)
        self.pixels = _spaces.has_pixels(pixel_desc)
        self.single_observation_space = _spaces.observation_space(env_obs_desc, task_obs_desc, self.flat_obs,
                                                                  pixel_desc)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)

        # The views, made once: the same objects every step, over the same memory.
        n = self.num_envs
        env_shape = _spaces.observation_box(env_obs_desc).shape
        task_shape = _spaces.observation_box(task_obs_desc).shape
        self._env_obs = self._exec.env_obs.reshape((n,) + tuple(env_shape))
        self._task_obs = self._exec.task_obs.reshape((n,) + tuple(task_shape))
        self._final_env_obs = self._exec.final_env_obs.reshape((n,) + tuple(env_shape))
        self._final_task_obs = self._exec.final_task_obs.reshape((n,) + tuple(task_shape))
        self._rewards = self._exec.rewards
        self._terminated = self._exec.terminated
        self._truncated = self._exec.truncated
        self._info = self._exec.info
        self.info_fields: List[str] = list(self._exec.info_fields)
        self._info_columns = {name: self._info[:, j] for j, name in enumerate(self.info_fields)}
        self._all = np.ones(n, dtype=bool)
        self._all.setflags(write=False)
        self._obs_dict = {"env_obs": self._env_obs, "task_obs": self._task_obs}
        if self.pixels:
            # zero copy: uint8 views of the executor's pixel buffers
            self._pixels = self._exec.pixels
            self._final_pixels = self._exec.final_pixels
            self._obs_dict = {"env_obs": self._pixels, "task_obs": self._task_obs, "state": self._env_obs}
        if self.flat_obs and self._exec.task_obs_size == 0:
            self._flat = self._env_obs.reshape(n, -1)
        else:
            self._flat = None

    # -- Gymnasium VectorEnv API -----------------------------------------------------------

    def reset(
        self,
        *,
        seed: Optional[Union[int, Sequence[Optional[int]]]] = None,
        options: Optional[Mapping[str, Any]] = None,
    ) -> Tuple[Any, Dict[str, Any]]:
        """Resets every env; returns ``(obs, infos)``.

        Options: ``task_seed`` (re-seed every env's task sampler with ``mix_seed(t, i)`` and
        switch each env to a task sampled from it), ``task_states`` (a list with one task state
        or ``None`` per env), ``sample_task`` (every env switches to a freshly sampled task).
        """
        self._check_open()
        opts = dict(options or {})
        unknown = [k for k in opts if k not in ("task_seed", "task_states", "sample_task")]
        if unknown:
            raise ValueError(
                f"vector env: unknown reset option(s) {unknown}; allowed: ['task_seed', 'task_states', 'sample_task']"
            )
        if isinstance(seed, (list, tuple, np.ndarray)):
            if len(seed) != self.num_envs:
                raise ValueError(f"seed: expected {self.num_envs} seeds, got {len(seed)}")
            super().reset(seed=None)
            for i, s in enumerate(seed):
                if s is not None:
                    self._exec.seed_env(i, _check_seed(s, f"seed[{i}]"))
        else:
            super().reset(seed=seed)
        new_task_seed = opts.get("task_seed")
        if new_task_seed is not None:
            self._task_seed = _check_seed(new_task_seed, "reset option 'task_seed'")
        if seed is not None and not isinstance(seed, (list, tuple, np.ndarray)):
            self._exec.seed(_check_seed(seed, "seed"), self._task_seed)
        elif new_task_seed is not None:
            for i in range(self.num_envs):
                self._exec.seed_task_env(i, _core.mix_seed(self._task_seed, i))
        if new_task_seed is not None or opts.get("sample_task"):
            for i in range(self.num_envs):
                self._exec.switch_task(i)
        states = opts.get("task_states")
        if states is not None:
            if len(states) != self.num_envs:
                raise ValueError(f"reset option 'task_states': expected {self.num_envs} entries, got {len(states)}")
            for i, state in enumerate(states):
                if state is not None:
                    self._exec.set_task_state(i, state, reset=False)
        self._exec.reset()
        return self._observations(), {}

    def step(self, actions: Any) -> Tuple[Any, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        """Steps every env: ``(obs, rewards, terminations, truncations, infos)`` (views)."""
        self._check_open()
        self._exec.step(self._flat_actions(actions))
        return self._results()

    def step_async(self, actions: Any) -> None:
        """Starts a step on the worker threads and returns at once (``send``)."""
        self._check_open()
        self._exec.send(self._flat_actions(actions))

    def step_wait(self) -> Tuple[Any, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        """Waits for the step started by ``step_async``; the same 5-tuple as ``step``."""
        self._check_open()
        self._exec.recv()
        return self._results()

    send = step_async
    recv = step_wait

    def close_extras(self, **kwargs: Any) -> None:
        """Finishes a pending step; the C++ buffers are freed with the last view."""
        core = getattr(self, "_exec", None)  # absent if __init__ failed
        if core is not None:
            core.close()

    # -- MTEnv task API per env ------------------------------------------------------------

    def sample_task_state(self, index: int) -> Dict[str, Any]:
        """Draws a task state from env ``index``'s task sampler (no switch)."""
        return self._exec.sample_task_state(self._index(index))

    def get_task_state(self, index: int) -> Dict[str, Any]:
        """The current task state of env ``index``."""
        return self._exec.get_task_state(self._index(index))

    def set_task_state(self, index: int, state: Mapping[str, Any]) -> None:
        """Switches env ``index`` to a task and resets it at once (its observation rows change)."""
        self._exec.set_task_state(self._index(index), state)

    def reset_task_state(self, index: int) -> None:
        """Switches env ``index`` to a freshly sampled task and resets it at once."""
        self._exec.reset_task_state(self._index(index))

    def get_task_states(self) -> List[Dict[str, Any]]:
        """The current task state of every env."""
        return [self._exec.get_task_state(i) for i in range(self.num_envs)]

    @property
    def episode_steps(self) -> np.ndarray:
        """(num_envs,) int64 view: steps into each env's current episode."""
        return self._exec.episode_steps

    # -- internals -------------------------------------------------------------------------

    def _check_open(self) -> None:
        if self.closed:
            raise RuntimeError("vector env is closed")

    def _index(self, index: int) -> int:
        index = int(index)
        if not 0 <= index < self.num_envs:
            raise IndexError(f"env index {index} out of range [0, {self.num_envs})")
        return index

    def _flat_actions(self, actions: Any) -> np.ndarray:
        a = np.asarray(actions)
        if self._discrete:
            a = a.reshape(self.num_envs, 1)
        return np.ascontiguousarray(a, dtype=np.float32)

    def _observations(self) -> Any:
        if self.pixels and self.flat_obs:
            return self._pixels
        if not self.flat_obs or self.pixels:
            return self._obs_dict
        if self._flat is not None:
            return self._flat
        n = self.num_envs
        return np.concatenate([self._env_obs.reshape(n, -1), self._task_obs.reshape(n, -1)], axis=1)

    def _results(self) -> Tuple[Any, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        infos: Dict[str, Any] = {}
        for name, column in self._info_columns.items():
            infos[name] = column
            infos["_" + name] = self._all
        ended = self._terminated | self._truncated
        if ended.any():
            final_obs = np.empty(self.num_envs, dtype=object)
            final_info: Dict[str, Any] = {}
            for i in np.flatnonzero(ended):
                if self.pixels:
                    frames = self._final_pixels[i].copy()
                    final_obs[i] = frames if self.flat_obs else {
                        "env_obs": frames,
                        "task_obs": self._final_task_obs[i].copy(),
                        "state": self._final_env_obs[i].copy(),
                    }
                elif self.flat_obs:
                    final_obs[i] = np.concatenate([self._final_env_obs[i].ravel(), self._final_task_obs[i].ravel()])
                else:
                    final_obs[i] = {
                        "env_obs": self._final_env_obs[i].copy(),
                        "task_obs": self._final_task_obs[i].copy(),
                    }
            for name, column in self._info_columns.items():
                final_info[name] = np.where(ended, column, 0.0).astype(np.float32)
                final_info["_" + name] = ended.copy()
            infos["final_obs"] = final_obs
            infos["_final_obs"] = ended
            infos["final_info"] = final_info
            infos["_final_info"] = ended
        return self._observations(), self._rewards, self._terminated, self._truncated, infos

    def __repr__(self) -> str:
        return f"<ManyworldsVectorEnv {self.num_envs} envs, {self.threads} thread(s)>"


def make_vec(
    env_ids: Union[str, Sequence[EnvEntry]],
    num_envs: Optional[int] = None,
    *,
    threads: int = 1,
    flat_obs: bool = False,
    task_states: Optional[Sequence[Optional[Mapping[str, Any]]]] = None,
    **options: Any,
) -> ManyworldsVectorEnv:
    """Makes a vector env over the batched executor (see ``ManyworldsVectorEnv``).

    ``make_vec("cartpole", 16, threads=2)``; ``make_vec(manyworlds.benchmarks.MT10_TASKS)``;
    also ``gymnasium.make_vec("manyworlds/cartpole", num_envs=16, vectorization_mode="vector_entry_point")``.
    """
    return ManyworldsVectorEnv(
        env_ids, num_envs, threads=threads, flat_obs=flat_obs, task_states=task_states, **options
    )


def _gymnasium_vector_entry_point(
    env_id: str, num_envs: int = 1, render_mode: Optional[str] = None, **kwargs: Any
) -> ManyworldsVectorEnv:
    """``gymnasium.make_vec("manyworlds/<id>", num_envs=n, threads=..., **options)``."""
    if render_mode is not None:
        raise ValueError(f"vector env '{env_id}': render_mode is not supported (got {render_mode!r})")
    return ManyworldsVectorEnv(env_id, num_envs, **kwargs)
