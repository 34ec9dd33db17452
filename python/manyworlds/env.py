"""manyworlds environments as ``gymnasium.Env``, with the MTEnv task API."""

from __future__ import annotations

import logging
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import gymnasium as gym
import numpy as np

from manyworlds import _core, _spaces

ObsType = Union[Dict[str, np.ndarray], np.ndarray]

_log = logging.getLogger("manyworlds")

# reset(options=...) keys this env understands.
RESET_OPTIONS = ("task_seed", "task_state", "sample_task")
# Keyword arguments of ManyworldsEnv that are not registry options.
_OWN_KWARGS = ("render_mode", "flat_obs", "camera_name", "width", "height")

MUJOCO_FAMILIES = ("manipulation", "benchmark")


def _check_seed(seed: Any, what: str) -> int:
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)):
        raise ValueError(f"{what} must be a non-negative int, got {type(seed).__name__}")
    seed = int(seed)
    if seed < 0 or seed >= 2**64:
        raise ValueError(f"{what} must be in [0, 2**64), got {seed}")
    return seed


def discrete_action_value(action: Any, n: int) -> np.ndarray:
    """One float holding the integer of a Discrete(n) action (validated by the C++ core)."""
    value = np.asarray(action)
    if value.size != 1:
        raise ValueError(f"action: expected one integer in [0, {n}), got an array of {value.size} values")
    return value.astype(np.float32).reshape(1)


class ManyworldsEnv(gym.Env):
    """A manyworlds environment behind Gymnasium's API.

    ``reset(seed=s)`` seeds the env's dynamics and initial states (the C++ ``Env::Seed``); the
    task is chosen by the task seed, set with ``seed_task(t)`` or the reset option
    ``task_seed``. Without any seed an env is still deterministic (both seeds default to 0).
    The task persists across resets (MTEnv semantics) until it is changed with
    ``set_task_state``, ``reset_task_state`` or a reset option.

    Reset options (``env.reset(options={...})``):

    - ``"task_seed": t`` -- seed the task sampler with ``t`` and switch to a task sampled from it;
    - ``"task_state": {...}`` -- switch to this task state first;
    - ``"sample_task": True`` -- switch to a freshly sampled task (next draw of the task sampler).

    Observations are ``{"env_obs": float32 array, "task_obs": float32 array}`` (the
    ``observation_space`` is a ``gymnasium.spaces.Dict``), or with ``flat_obs=True`` one float32
    array with both concatenated. With ``obs="pixels"`` (MuJoCo envs) ``env_obs`` is the rendered
    frames, uint8 ``(3 x frame_stack, pixel_height, pixel_width)``, and ``"state"`` holds the
    float32 state beside them; ``flat_obs=True`` then gives the frames alone (a uint8 Box, what
    CNN policies such as SB3's ``CnnPolicy`` take). ``info`` holds the env's named float fields every step, e.g.
    ``info["success"]``.

    Args:
        env_id: A registry id (``manyworlds.env_ids()``).
        render_mode: ``None`` or ``"rgb_array"`` (MuJoCo suites only).
        flat_obs: Concatenate env and task observation into one Box.
        camera_name: Camera used by ``render()``: ``front``, ``top``, ``side``, ``gripper`` or a
            camera of the model.
        width, height: Size of rendered images.
        **options: Registry options of ``env_id`` (e.g. ``n_arms=3``, ``max_episode_steps=200``).
    """

    metadata: Dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 80}

    def __init__(
        self,
        env_id: str,
        render_mode: Optional[str] = None,
        flat_obs: bool = False,
        camera_name: str = "front",
        width: int = 480,
        height: int = 480,
        **options: Any,
    ) -> None:
        self._core: Optional[_core.Env] = _core.Env(env_id, dict(options))
        self.env_id = env_id
        self.options = dict(options)
        self.family = self._core.family
        mujoco = self.family in MUJOCO_FAMILIES
        self.metadata = {
            "render_modes": ["rgb_array"] if mujoco and _core.has_render else [],
            "render_fps": 80 if mujoco else 0,
        }
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            allowed = self.metadata["render_modes"] or "none (this env does not render)"
            raise ValueError(f"env '{env_id}': render_mode {render_mode!r} is not supported; allowed: {allowed}")
        self.render_mode = render_mode
        self.camera_name = camera_name
        self.width = int(width)
        self.height = int(height)
        self.flat_obs = bool(flat_obs)

        self._action_desc = self._core.action_space
        self.action_space = _spaces.action_space(self._action_desc)
        pixel_desc = self._core.pixel_space
        self.pixels = _spaces.has_pixels(pixel_desc)
        if self.pixels:
            _log.info("env '%s': pixel observations %s rendered with %s", env_id, tuple(pixel_desc["shape"]),
                      _core.render_backend)
        self.observation_space = _spaces.observation_space(
            self._core.env_obs_space, self._core.task_obs_space, self.flat_obs, pixel_desc
        )
        if self.pixels:
            self._env_shape = tuple(_spaces.observation_box(self._core.env_obs_space).shape)
        else:
            self._env_shape = tuple(self.observation_space["env_obs"].shape) if not self.flat_obs else None
        self._info_fields: List[str] = list(self._core.info_fields)
        self._discrete_n = int(self._action_desc["n"]) if self._action_desc["kind"] == "discrete" else 0

    # -- Gymnasium API ---------------------------------------------------------------------

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Mapping[str, Any]] = None
    ) -> Tuple[ObsType, Dict[str, Any]]:
        """Starts an episode; returns ``(obs, info)``.

        ``seed`` seeds the env (dynamics and initial states); ``options`` may hold ``task_seed``,
        ``task_state`` or ``sample_task`` (see the class docstring). Raises ``ValueError`` for an
        unknown option or a malformed task state.
        """
        super().reset(seed=seed)
        env = self._live()
        if options is not None and not isinstance(options, Mapping):
            raise ValueError(f"env '{self.env_id}': reset options must be a mapping such as "
                             f"{{'task_seed': 3}}, got {type(options).__name__}")
        if options:
            unknown = [k for k in options if k not in RESET_OPTIONS]
            if unknown:
                raise ValueError(
                    f"env '{self.env_id}': unknown reset option(s) {unknown}; allowed: {list(RESET_OPTIONS)}"
                )
            if "task_seed" in options and options["task_seed"] is not None:
                env.seed_task(_check_seed(options["task_seed"], "reset option 'task_seed'"))
                env.reset_task_state()
            if options.get("task_state") is not None:
                env.set_task_state(options["task_state"])
            if options.get("sample_task"):
                env.reset_task_state()
        if seed is not None:
            env.seed(_check_seed(seed, "seed"))
        env_obs, task_obs = env.reset()
        return self._obs(env_obs, task_obs), {}

    def step(self, action: Any) -> Tuple[ObsType, float, bool, bool, Dict[str, Any]]:
        """One step: ``(obs, reward, terminated, truncated, info)``.

        Box actions are clipped to the bounds; an action of the wrong size, with NaN/inf, or
        outside a Discrete space raises ``ValueError`` (``manyworlds.InvalidActionError``) and
        leaves the episode running. Stepping before ``reset`` or after the end of an episode
        raises ``RuntimeError`` (``manyworlds.EpisodeStateError``).
        """
        env = self._live()
        if self._discrete_n:
            flat = discrete_action_value(action, self._discrete_n)
        else:
            array = np.asarray(action, dtype=np.float32)
            # the action space's own shape, or a flat vector of its size; (1, n) or (3, 1, n)
            # would be a batch (a vector env's), not one action
            if array.shape != self.action_space.shape and array.ndim != 1:
                raise _core.InvalidActionError(
                    f"env '{self.env_id}': action of shape {array.shape}; expected "
                    f"{self.action_space.shape} (one action: vector envs take batches)")
            flat = array.reshape(-1)
        env_obs, task_obs, reward, terminated, truncated, info_values = env.step(flat)
        info = {name: float(v) for name, v in zip(self._info_fields, info_values)}
        return self._obs(env_obs, task_obs), float(reward), bool(terminated), bool(truncated), info

    def render(self) -> Optional[np.ndarray]:
        """With ``render_mode="rgb_array"``: the current frame, uint8 ``(height, width, 3)``."""
        if self.render_mode is None:
            gym.logger.warn(
                f"env '{self.env_id}': render() called without a render_mode; "
                "make it with render_mode='rgb_array'"
            )
            return None
        return self._live().render(self.camera_name, self.width, self.height)

    def close(self) -> None:
        """Frees the C++ env and its renderer. Further calls raise ``RuntimeError``."""
        self._core = None

    # -- MTEnv task API ----------------------------------------------------------------------

    def seed_task(self, seed: int) -> None:
        """Seeds the task sampler (takes effect at the next ``sample_task_state``)."""
        self._live().seed_task(_check_seed(seed, "task seed"))

    def sample_task_state(self) -> Dict[str, Any]:
        """Draws a task state from the task sampler without switching to it."""
        return self._live().sample_task_state()

    def get_task_state(self) -> Dict[str, Any]:
        """The current task state, a plain dict ``{"env": ..., "params": {...}}``.

        It round-trips exactly through ``json.dumps``/``json.loads``. Raises ``RuntimeError``
        before a task was set or sampled (the first ``reset`` samples one).
        """
        return self._live().get_task_state()

    def set_task_state(self, state: Mapping[str, Any]) -> None:
        """Switches to a task state (e.g. from ``get_task_state``, possibly via JSON).

        A malformed state raises ``ValueError`` naming the field; the previous task stays. The
        running episode ends: call ``reset`` next.
        """
        self._live().set_task_state(state)

    def reset_task_state(self) -> None:
        """Switches to a freshly sampled task (``set_task_state(sample_task_state())``)."""
        self._live().reset_task_state()

    # -- manyworlds extras -----------------------------------------------------------------

    @property
    def info_fields(self) -> List[str]:
        """Names of the float fields every ``info`` holds."""
        return list(self._info_fields)

    @property
    def max_episode_steps(self) -> int:
        """Episode limit of the C++ env (truncation); 0 means none."""
        return int(self._live().max_episode_steps)

    @property
    def uses_env_seed(self) -> bool:
        """False where only the task is random (point navigation, manipulation)."""
        return bool(self._live().uses_env_seed)

    @property
    def elapsed_steps(self) -> int:
        """Steps into the current episode."""
        return int(self._live().elapsed_steps)

    def evaluation_tasks(self) -> List[Tuple[str, List[Dict[str, Any]]]]:
        """The fixed evaluation task states in named groups (a benchmark: one per task)."""
        return self._live().evaluation_tasks()

    def _live(self) -> _core.Env:
        if self._core is None:
            raise RuntimeError(f"env '{self.env_id}' is closed")
        return self._core

    def _obs(self, env_obs: np.ndarray, task_obs: np.ndarray) -> ObsType:
        if self.pixels:
            frames = self._live().pixels
            if self.flat_obs:
                return frames
            return {"env_obs": frames, "task_obs": task_obs, "state": env_obs.reshape(self._env_shape)}
        if self.flat_obs:
            return np.concatenate([env_obs, task_obs])
        return {"env_obs": env_obs.reshape(self._env_shape), "task_obs": task_obs}

    def __repr__(self) -> str:
        return f"<ManyworldsEnv {self.env_id}>"


def make(env_id: str, **kwargs: Any) -> ManyworldsEnv:
    """Makes a manyworlds env as a ``gymnasium.Env``.

    ``kwargs`` are the env's registry options (``manyworlds.registry()`` lists them) and
    ``render_mode``, ``flat_obs``, ``camera_name``, ``width``, ``height``. An unknown id or
    option raises ``ValueError`` suggesting the nearest names. The same env through Gymnasium's
    registry, with its standard wrappers: ``gymnasium.make("manyworlds/<id>", **kwargs)``.
    """
    return ManyworldsEnv(env_id, **kwargs)
