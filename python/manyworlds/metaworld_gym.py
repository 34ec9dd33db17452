"""Meta-World v3's Gymnasium entry points over ``manyworlds.benchmarks``, in a namespace of our own.

The official package registers ``Meta-World/MT1``, ``Meta-World/MT10``, ``Meta-World/ML10-train``,
... when it is imported. Ours are the same ids under ``manyworlds-Meta-World/``, so both packages
can be imported in one process without one replacing the other's envs (Gymnasium would warn
and keep whichever registered last)::

    import gymnasium as gym
    import manyworlds

    env = gym.make("manyworlds-Meta-World/MT1", env_name="reach-v3", seed=0)     # one env
    envs = gym.make_vec("manyworlds-Meta-World/MT10", seed=0)                    # 10 envs
    envs = gym.make_vec("manyworlds-Meta-World/ML10-test", meta_batch_size=20,
                        total_tasks_per_cls=40)                                  # 4 per task

They take v3's arguments (``seed``, ``use_one_hot``, ``vector_strategy``, ``autoreset_mode``,
``meta_batch_size``, ``total_tasks_per_cls``, ``max_episode_steps``, ``terminate_on_success``,
``task_select``, ``recurrent_info_in_obs``, ``normalize_reward_in_recurrent_info``,
``reward_function_version``, ``reward_normalization_method="gymnasium"``,
``normalize_observations``, ``render_mode``, ``camera_name``, ``width``, ``height``) and build
what v3 builds: a ``SyncVectorEnv`` (or ``AsyncVectorEnv``) of single-task envs, each wrapped as
v3 wraps it, with v3's methods for ``envs.call``: ``sample_tasks``,
``toggle_sample_tasks_on_reset`` and ``toggle_terminate_on_success``. ``make_mt_envs`` and
``make_ml_envs`` are v3's functions of the same names. Not offered: v3's ``goal_hidden``,
``goal_observable``, ``custom-mt-envs`` and ``custom-ml-envs`` ids, the ``exponential`` reward
normalisation, ``camera_id`` and the checkpoint wrapper's ``get_checkpoint``/``load_checkpoint``.
``autoreset_mode`` needs Gymnasium 1.1 or later (1.0 resets next-step only; there the argument
is accepted and ignored, with a warning when it asks for another mode).
"""

from __future__ import annotations

import warnings
from functools import partial
from typing import Any, List, Optional, Sequence

import gymnasium as gym
import numpy as np

GYMNASIUM_NAMESPACE = "manyworlds-Meta-World"

_MT_BENCHMARKS = ("MT10", "MT25", "MT50")
_ML_BENCHMARKS = ("ML10", "ML25", "ML45")

__all__ = [
    "GYMNASIUM_NAMESPACE", "make_mt_envs", "make_ml_envs", "AutoTerminateOnSuccessWrapper",
    "OneHotWrapper", "RNNBasedMetaRLWrapper", "RandomTaskSelectWrapper",
    "PseudoRandomTaskSelectWrapper",
]


# -- v3's wrappers (metaworld/wrappers.py), same names, arguments and behaviour ------------------

class OneHotWrapper(gym.ObservationWrapper):
    """Appends the one-hot of the env's task index to the observation."""

    def __init__(self, env: gym.Env, task_idx: int, num_tasks: int):
        super().__init__(env)
        assert isinstance(env.observation_space, gym.spaces.Box)
        dtype = env.observation_space.dtype
        self.one_hot = np.zeros(num_tasks, dtype=dtype)
        self.one_hot[task_idx] = 1.0
        self.observation_space = gym.spaces.Box(
            np.concatenate([env.observation_space.low, np.zeros(num_tasks, dtype=dtype)]),
            np.concatenate([env.observation_space.high, np.ones(num_tasks, dtype=dtype)]), dtype=dtype)

    def observation(self, obs):
        return np.concatenate([obs, self.one_hot])


class RNNBasedMetaRLWrapper(gym.Wrapper):
    """Appends the previous action, the reward (/10 when normalised) and the done flag."""

    def __init__(self, env: gym.Env, normalize_reward: bool = True):
        super().__init__(env)
        obs_dim = int(np.prod(env.observation_space.shape))
        action_dim = int(np.prod(env.action_space.shape))
        self.observation_space = gym.spaces.Box(low=-np.inf, high=np.inf, shape=(obs_dim + action_dim + 2,))
        self._normalize_reward = normalize_reward

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        obs_reward = float(reward) / 10.0 if self._normalize_reward else float(reward)
        done = float(np.logical_or(terminated, truncated))
        return np.concatenate([obs, action, [obs_reward], [done]]), reward, terminated, truncated, info

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        obs, info = self.env.reset(seed=seed, options=options)
        return np.concatenate([obs, np.zeros(self.env.action_space.shape), [0.0], [0.0]]), info


class _TaskSelectWrapper(gym.Wrapper):
    """Sets the task ``_next_task()`` picks on ``sample_tasks`` and, while
    ``sample_tasks_on_reset`` is on, at every reset (v3's task-select wrappers)."""

    def __init__(self, env: gym.Env, tasks: List[Any], sample_tasks_on_reset: bool):
        super().__init__(env)
        self.tasks = list(tasks)
        self.sample_tasks_on_reset = sample_tasks_on_reset

    def _next_task(self) -> Any:
        raise NotImplementedError

    def toggle_sample_tasks_on_reset(self, on: bool) -> None:
        self.sample_tasks_on_reset = on

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        if self.sample_tasks_on_reset:
            self.unwrapped.set_task(self._next_task())
        return self.env.reset(seed=seed, options=options)

    def sample_tasks(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        self.unwrapped.set_task(self._next_task())
        return self.env.reset(seed=seed, options=options)


class RandomTaskSelectWrapper(_TaskSelectWrapper):
    """Sets a task drawn at random from ``tasks`` at every reset (``sample_tasks_on_reset``)."""

    def __init__(self, env: gym.Env, tasks: List[Any], sample_tasks_on_reset: bool = True):
        super().__init__(env, tasks, sample_tasks_on_reset)

    def _next_task(self) -> Any:
        return self.tasks[self.np_random.choice(len(self.tasks))]


class PseudoRandomTaskSelectWrapper(_TaskSelectWrapper):
    """Cycles through ``tasks``, reshuffled at every wrap-around; by default only on ``sample_tasks``."""

    def __init__(self, env: gym.Env, tasks: List[Any], sample_tasks_on_reset: bool = False):
        super().__init__(env, tasks, sample_tasks_on_reset)
        self.current_task_idx = -1

    def _next_task(self) -> Any:
        self.current_task_idx = (self.current_task_idx + 1) % len(self.tasks)
        if self.current_task_idx == 0:
            self.np_random.shuffle(self.tasks)
        return self.tasks[self.current_task_idx]


class AutoTerminateOnSuccessWrapper(gym.Wrapper):
    """``terminated`` becomes ``info["success"] == 1`` while on (v3's evaluation turns it on)."""

    def __init__(self, env: gym.Env):
        super().__init__(env)
        self.terminate_on_success = True

    def toggle_terminate_on_success(self, on: bool) -> None:
        self.terminate_on_success = on

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        if self.terminate_on_success:
            terminated = info["success"] == 1.0
        return obs, reward, terminated, truncated, info


# -- v3's make functions ----------------------------------------------------------------------

def _init_each_env(
    env_cls: type,
    tasks: List[Any],
    seed: Optional[int] = None,
    max_episode_steps: Optional[int] = None,
    terminate_on_success: bool = False,
    use_one_hot: bool = False,
    env_id: Optional[int] = None,
    num_tasks: Optional[int] = None,
    recurrent_info_in_obs: bool = False,
    normalize_reward_in_recurrent_info: bool = True,
    task_select: str = "random",
    reward_function_version: str = "v2",
    reward_normalization_method: Optional[str] = None,
    normalize_observations: bool = False,
    reward_alpha: float = 0.001,
    render_mode: Optional[str] = None,
    camera_name: Optional[str] = None,
    camera_id: Optional[int] = None,
    width: int = 480,
    height: int = 480,
) -> gym.Env:
    """One env as v3's ``_init_each_env`` builds it (v3's wrappers, in v3's order)."""
    if camera_id is not None:
        raise ValueError("camera_id is not offered; name the camera with camera_name")
    if reward_normalization_method not in (None, "gymnasium"):
        raise ValueError(f"reward_normalization_method {reward_normalization_method!r} is not offered "
                         "(None or 'gymnasium')")
    if task_select not in ("random", "pseudorandom"):
        raise ValueError(f"task_select must be 'random' or 'pseudorandom', got {task_select!r}")
    options = {"reward_version": reward_function_version}
    if max_episode_steps:  # v3's TimeLimit; ours truncates at the option itself
        options["max_episode_steps"] = int(max_episode_steps)
    env: gym.Env = env_cls(render_mode=render_mode, camera_name=camera_name or "front",
                           width=width, height=height, **options)
    if seed is not None:  # v3's env.seed(seed): the env's and its generator's seed
        env.reset(seed=seed)
    env = AutoTerminateOnSuccessWrapper(env)
    env.toggle_terminate_on_success(terminate_on_success)
    if use_one_hot:
        assert env_id is not None and num_tasks is not None, "use_one_hot needs env_id and num_tasks"
        env = OneHotWrapper(env, env_id, num_tasks)
    if recurrent_info_in_obs:
        env = RNNBasedMetaRLWrapper(env, normalize_reward=normalize_reward_in_recurrent_info)
    if reward_normalization_method == "gymnasium":
        env = gym.wrappers.NormalizeReward(env)
    if normalize_observations:
        env = gym.wrappers.NormalizeObservation(env)
    env = gym.wrappers.RecordEpisodeStatistics(env)
    if task_select == "random":
        env = RandomTaskSelectWrapper(env, tasks)
    else:
        env = PseudoRandomTaskSelectWrapper(env, tasks)
    if seed is not None:
        env.action_space.seed(seed)
    return env


def _vector_env(env_fns: Sequence[Any], vector_strategy: str, autoreset_mode: Any) -> gym.vector.VectorEnv:
    if vector_strategy not in ("sync", "async"):
        raise ValueError(f"vector_strategy must be 'sync' or 'async', got {vector_strategy!r}")
    vectorizer = gym.vector.SyncVectorEnv if vector_strategy == "sync" else gym.vector.AsyncVectorEnv
    # Each task has its own goal bounds in its observation space (v3 gives every env the same
    # space, zeros for the goal's bounds): the vector env's space stacks the envs' spaces.
    kwargs: dict = {"observation_mode": "different"}
    if hasattr(gym.vector, "AutoresetMode"):  # Gymnasium >= 1.1
        kwargs["autoreset_mode"] = autoreset_mode or gym.vector.AutoresetMode.SAME_STEP
    elif autoreset_mode is not None and str(getattr(autoreset_mode, "value", autoreset_mode)) != "NextStep":
        warnings.warn(f"Gymnasium {gym.__version__} resets vector envs next-step only; "
                      f"autoreset_mode={autoreset_mode!r} needs Gymnasium 1.1", stacklevel=3)
    return vectorizer(list(env_fns), **kwargs)


def _find_benchmark(name: str, kinds: Sequence[str]):
    from manyworlds import benchmarks
    if name in kinds:
        return getattr(benchmarks, name)
    return None


def make_mt_envs(
    name: str,
    seed: Optional[int] = None,
    num_tasks: Optional[int] = None,
    vector_strategy: str = "sync",
    autoreset_mode: Any = None,
    **kwargs: Any,
):
    """v3's ``make_mt_envs``: a task name gives one env (MT1), MT10/MT25/MT50 a vector env."""
    from manyworlds import benchmarks
    benchmark_cls = _find_benchmark(name, _MT_BENCHMARKS)
    if benchmark_cls is None:
        try:
            benchmark = benchmarks.MT1(name, seed=seed)
        except Exception as e:
            raise ValueError(f"invalid MT env name {name!r}: a task name (e.g. 'reach-v3'), "
                             f"'MT10', 'MT25' or 'MT50' ({e})") from None
        return _init_each_env(env_cls=benchmark.train_classes[name], tasks=list(benchmark.train_tasks),
                              seed=seed, num_tasks=num_tasks or 1, **kwargs)
    benchmark = benchmark_cls(seed=seed)
    classes = list(benchmark.train_classes.items())
    return _vector_env(
        [partial(_init_each_env, env_cls=env_cls,
                 tasks=[t for t in benchmark.train_tasks if t.env_name == task_name],
                 seed=seed, env_id=env_id, num_tasks=num_tasks or len(classes), **kwargs)
         for env_id, (task_name, env_cls) in enumerate(classes)],
        vector_strategy, autoreset_mode)


def make_ml_envs(
    name: str,
    seed: Optional[int] = None,
    meta_batch_size: int = 20,
    total_tasks_per_cls: Optional[int] = None,
    split: str = "train",
    vector_strategy: str = "sync",
    autoreset_mode: Any = None,
    **kwargs: Any,
) -> gym.vector.VectorEnv:
    """v3's ``make_ml_envs``: ``meta_batch_size`` envs over one split, as many per task, each with
    every ``envs_per_task``-th variation of its task."""
    from manyworlds import benchmarks
    if split not in ("train", "test"):
        raise ValueError(f"split must be 'train' or 'test', got {split!r}")
    benchmark_cls = _find_benchmark(name, _ML_BENCHMARKS)
    try:
        benchmark = benchmark_cls(seed=seed) if benchmark_cls else benchmarks.ML1(name, seed=seed)
    except Exception as e:
        raise ValueError(f"invalid ML env name {name!r}: a task name (e.g. 'reach-v3'), "
                         f"'ML10', 'ML25' or 'ML45' ({e})") from None
    classes = benchmark.train_classes if split == "train" else benchmark.test_classes
    all_tasks = benchmark.train_tasks if split == "train" else benchmark.test_tasks
    if meta_batch_size % len(classes) != 0:
        raise ValueError(f"meta_batch_size {meta_batch_size} is not a multiple of the "
                         f"{len(classes)} {split} tasks")
    envs_per_task = meta_batch_size // len(classes)
    env_fns = []
    for task_name, env_cls in classes.items():
        tasks = [t for t in all_tasks if t.env_name == task_name]
        if total_tasks_per_cls is not None:
            tasks = tasks[:total_tasks_per_cls]
        if len(tasks) % envs_per_task != 0:  # v3 asserts this too
            raise ValueError(f"{task_name}: {len(tasks)} variations do not split evenly over "
                             f"{envs_per_task} envs per task; set total_tasks_per_cls to a multiple")
        for i in range(envs_per_task):
            env_fns.append(partial(_init_each_env, env_cls=env_cls, tasks=tasks[i::envs_per_task],
                                   seed=seed, **kwargs))
    return _vector_env(env_fns, vector_strategy, autoreset_mode)


# -- entry points (gymnasium.make / make_vec keyword arguments) --------------------------------

def _mt1_entry_point(env_name: str, use_one_hot: bool = False, vector_strategy: str = "sync",
                     autoreset_mode: Any = None, seed: Optional[int] = None, num_envs: Any = None,
                     **kwargs: Any) -> gym.Env:
    return make_mt_envs(env_name, seed=seed, use_one_hot=use_one_hot, vector_strategy=vector_strategy,
                        autoreset_mode=autoreset_mode, **kwargs)


def _mt_vector_entry_point(benchmark: str, vector_strategy: str = "sync", autoreset_mode: Any = None,
                           seed: Optional[int] = None, use_one_hot: bool = False,
                           num_envs: Any = None, **kwargs: Any) -> gym.vector.VectorEnv:
    # num_envs is ignored, as v3 ignores it: a benchmark has one env per task
    return make_mt_envs(benchmark, seed=seed, use_one_hot=use_one_hot, vector_strategy=vector_strategy,
                        autoreset_mode=autoreset_mode, **kwargs)


def _ml_vector_entry_point(benchmark: str, split: str, env_name: Optional[str] = None,
                           vector_strategy: str = "sync", autoreset_mode: Any = None,
                           total_tasks_per_cls: Optional[int] = None, seed: Optional[int] = None,
                           meta_batch_size: int = 20, num_envs: Any = None,
                           **kwargs: Any) -> gym.vector.VectorEnv:
    # v3's make_ml_envs_train / make_ml_envs_test defaults
    kwargs.setdefault("terminate_on_success", split == "test")
    kwargs.setdefault("task_select", "pseudorandom")
    name = env_name if benchmark == "ML1" else benchmark
    if name is None:
        raise ValueError("ML1 needs env_name, e.g. env_name='reach-v3'")
    return make_ml_envs(name, seed=seed, meta_batch_size=meta_batch_size,
                        total_tasks_per_cls=total_tasks_per_cls, split=split,
                        vector_strategy=vector_strategy, autoreset_mode=autoreset_mode, **kwargs)


def register_envs() -> None:
    """Registers the ids with Gymnasium (done when ``manyworlds`` is imported; idempotent)."""
    module = __name__

    def register(name: str, **spec: Any) -> None:
        gym_id = f"{GYMNASIUM_NAMESPACE}/{name}"
        if gym_id not in gym.registry:
            gym.register(id=gym_id, **spec)

    register("MT1", entry_point=f"{module}:_mt1_entry_point", kwargs={})
    for bench in _MT_BENCHMARKS:
        register(bench, vector_entry_point=f"{module}:_mt_vector_entry_point", kwargs={"benchmark": bench})
    for bench in ("ML1",) + _ML_BENCHMARKS:
        for split in ("train", "test"):
            register(f"{bench}-{split}", vector_entry_point=f"{module}:_ml_vector_entry_point",
                     kwargs={"benchmark": bench, "split": split})
