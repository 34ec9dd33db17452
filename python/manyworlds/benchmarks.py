"""Meta-World-shaped benchmark objects over manyworlds' manipulation suite.

For people moving a Meta-World script over: ``MT1``, ``MT10``, ``MT25``, ``MT50``, ``ML1``,
``ML10``, ``ML25`` and ``ML45`` have
``train_classes`` and ``test_classes`` (dicts from task name to an env class that takes no
required arguments) and ``train_tasks`` and ``test_tasks`` (lists of :class:`Task` with
``env_name`` and ``data``), and the envs have ``set_task(task)``, so::

    import manyworlds.benchmarks as metaworld   # instead of: import metaworld
    import random

    mt10 = metaworld.MT10()
    training_envs = []
    for name, env_cls in mt10.train_classes.items():
        env = env_cls()
        task = random.choice([t for t in mt10.train_tasks if t.env_name == name])
        env.set_task(task)
        training_envs.append(env)

    for env in training_envs:
        obs, info = env.reset()
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

The envs are single manyworlds tasks whose observation is Meta-World's flat 39-value vector
(goal zeroed in the ML benchmarks); the variations are the ones of manyworlds' own benchmark
envs (``mt10``, ``ml10``, ``mt1``, ``ml1``, ...) with ``benchmark_seed = seed``, 50 per task. Task
names are manyworlds ids (``"pick-place"``); MT1/ML1 also accept Meta-World's versioned names
(``"pick-place-v3"``) and then key their dicts by the name given. Wherever v3 takes a name, both
forms work: ``MT10().train_classes["reach-v3"]`` and ``["reach"]`` are the same class, and
``set_task`` takes a task of either name.

``gymnasium.make("manyworlds-Meta-World/MT1", env_name="reach-v3")`` and
``gymnasium.make_vec("manyworlds-Meta-World/MT10")`` (``ML10-train``, ``ML10-test``, ...) are v3's
``Meta-World/...`` entry points under a namespace of our own (``manyworlds.metaworld_gym``).
"""

from __future__ import annotations

import json
import re
from typing import Any, Dict, List, NamedTuple, Optional, Type

from manyworlds import _core
from manyworlds.env import ManyworldsEnv

__all__ = [
    "Task", "Benchmark", "EnvClasses", "SawyerEnv", "MT1", "MT10", "MT25", "MT50", "ML1", "ML10", "ML25", "ML45",
    "MT10_TASKS", "MT25_TASKS", "MT50_TASKS", "ML10_TRAIN_TASKS", "ML10_TEST_TASKS",
    "ML25_TRAIN_TASKS", "ML25_TEST_TASKS", "ML45_TRAIN_TASKS", "ML45_TEST_TASKS",
]


class Task(NamedTuple):
    """One task variation: the task name and its task state as JSON text."""

    env_name: str
    data: str

    @property
    def state(self) -> Dict[str, Any]:
        """The task state as a dict (``json.loads(data)``)."""
        return json.loads(self.data)


_V3_SUFFIX = "-v3"


def _base_name(name: str) -> str:
    """A task name without v3's suffix: "reach-v3" and "reach" name the same task."""
    return name[: -len(_V3_SUFFIX)] if isinstance(name, str) and name.endswith(_V3_SUFFIX) else name


class EnvClasses(dict):
    """``train_classes``/``test_classes``: task name to env class, in the benchmark's order.

    Iteration gives the names the benchmark was made with; a lookup also takes the other form of
    a name (``"reach-v3"`` for ``"reach"`` and back), as v3 scripts index by v3's names.
    """

    def _find(self, key: Any) -> Optional[str]:
        if dict.__contains__(self, key):
            return key
        if isinstance(key, str):
            base = _base_name(key)
            for name in self:
                if _base_name(name) == base:
                    return name
        return None

    def __missing__(self, key: Any) -> Type["SawyerEnv"]:
        name = self._find(key)
        if name is None:
            raise KeyError(f"{key!r} is not a task of this benchmark; its tasks: {', '.join(self)}")
        return dict.__getitem__(self, name)

    def __contains__(self, key: Any) -> bool:
        return self._find(key) is not None

    def get(self, key: Any, default: Any = None) -> Any:
        name = self._find(key)
        return default if name is None else dict.__getitem__(self, name)


# Meta-World v3's env class of each task (metaworld.env_dict.ALL_V3_ENVIRONMENTS), which v3's
# evaluation functions read from an env's ``task_name`` to group episodes by task. Checked
# against the official package by python/tests/test_metaworld_protocols.py.
_V3_CLASS_NAMES = {
    "assembly": "SawyerNutAssemblyEnvV3",
    "basketball": "SawyerBasketballEnvV3",
    "bin-picking": "SawyerBinPickingEnvV3",
    "box-close": "SawyerBoxCloseEnvV3",
    "button-press": "SawyerButtonPressEnvV3",
    "button-press-topdown": "SawyerButtonPressTopdownEnvV3",
    "button-press-topdown-wall": "SawyerButtonPressTopdownWallEnvV3",
    "button-press-wall": "SawyerButtonPressWallEnvV3",
    "coffee-button": "SawyerCoffeeButtonEnvV3",
    "coffee-pull": "SawyerCoffeePullEnvV3",
    "coffee-push": "SawyerCoffeePushEnvV3",
    "dial-turn": "SawyerDialTurnEnvV3",
    "disassemble": "SawyerNutDisassembleEnvV3",
    "door-close": "SawyerDoorCloseEnvV3",
    "door-lock": "SawyerDoorLockEnvV3",
    "door-open": "SawyerDoorEnvV3",
    "door-unlock": "SawyerDoorUnlockEnvV3",
    "drawer-close": "SawyerDrawerCloseEnvV3",
    "drawer-open": "SawyerDrawerOpenEnvV3",
    "faucet-close": "SawyerFaucetCloseEnvV3",
    "faucet-open": "SawyerFaucetOpenEnvV3",
    "hammer": "SawyerHammerEnvV3",
    "hand-insert": "SawyerHandInsertEnvV3",
    "handle-press": "SawyerHandlePressEnvV3",
    "handle-press-side": "SawyerHandlePressSideEnvV3",
    "handle-pull": "SawyerHandlePullEnvV3",
    "handle-pull-side": "SawyerHandlePullSideEnvV3",
    "lever-pull": "SawyerLeverPullEnvV3",
    "peg-insert-side": "SawyerPegInsertionSideEnvV3",
    "peg-unplug-side": "SawyerPegUnplugSideEnvV3",
    "pick-out-of-hole": "SawyerPickOutOfHoleEnvV3",
    "pick-place": "SawyerPickPlaceEnvV3",
    "pick-place-wall": "SawyerPickPlaceWallEnvV3",
    "plate-slide": "SawyerPlateSlideEnvV3",
    "plate-slide-back": "SawyerPlateSlideBackEnvV3",
    "plate-slide-back-side": "SawyerPlateSlideBackSideEnvV3",
    "plate-slide-side": "SawyerPlateSlideSideEnvV3",
    "push": "SawyerPushEnvV3",
    "push-back": "SawyerPushBackEnvV3",
    "push-wall": "SawyerPushWallEnvV3",
    "reach": "SawyerReachEnvV3",
    "reach-wall": "SawyerReachWallEnvV3",
    "shelf-place": "SawyerShelfPlaceEnvV3",
    "soccer": "SawyerSoccerEnvV3",
    "stick-pull": "SawyerStickPullEnvV3",
    "stick-push": "SawyerStickPushEnvV3",
    "sweep": "SawyerSweepEnvV3",
    "sweep-into": "SawyerSweepIntoGoalEnvV3",
    "window-close": "SawyerWindowCloseEnvV3",
    "window-open": "SawyerWindowOpenEnvV3",
}


class SawyerEnv(ManyworldsEnv):
    """One manipulation task with Meta-World's single-task interface.

    Flat 39-value observations (the env observation alone), ``set_task(task)``,
    ``max_path_length`` (500).
    """

    TASK_ID: str = ""
    TASK_NAME: str = ""
    GOAL_OBSERVABLE: bool = True

    def __init__(self, render_mode: Optional[str] = None, **kwargs: Any) -> None:
        kwargs.setdefault("goal_observable", self.GOAL_OBSERVABLE)
        super().__init__(self.TASK_ID, render_mode=render_mode, **kwargs)
        # Meta-World's observation: the 39 values, whose last three are the goal (zeros when
        # hidden); the task observation (the goal again) is left out.
        self.observation_space = self.observation_space["env_obs"]

    def _obs(self, env_obs, task_obs):
        return env_obs

    def set_task(self, task: Task) -> None:
        """Switches to a task variation from a benchmark's ``train_tasks``/``test_tasks``.

        A task named ``"reach-v3"`` fits an env of ``"reach"`` and back. Raises ``ValueError`` if the task belongs to another env class.
        """
        if _base_name(task.env_name) != _base_name(self.TASK_NAME):
            raise ValueError(f"task of '{task.env_name}' given to an env of '{self.TASK_NAME}'")
        self.set_task_state(json.loads(task.data))

    @property
    def task_name(self) -> str:
        """v3's env class name of this task (``"SawyerReachEnvV3"``), as v3's envs carry it."""
        return _V3_CLASS_NAMES[_base_name(self.TASK_NAME)]

    @property
    def max_path_length(self) -> int:
        """Episode length (Meta-World's name for it)."""
        return self.max_episode_steps


def _env_class(task_id: str, name: str, goal_observable: bool) -> Type[SawyerEnv]:
    class_name = "".join(part.capitalize() for part in re.split(r"[-_]", name)) + "Env"
    return type(class_name, (SawyerEnv,), {"TASK_ID": task_id, "TASK_NAME": name, "GOAL_OBSERVABLE": goal_observable})


def _task_id(name: str) -> str:
    """A manyworlds task id from a manyworlds or a versioned Meta-World name."""
    return re.sub(r"-v\d+$", "", name)


class Benchmark:
    """Base of the benchmarks: ``train_classes``, ``train_tasks``, ``test_classes``, ``test_tasks``."""

    def __init__(self) -> None:
        self.train_classes: EnvClasses = EnvClasses()
        self.test_classes: EnvClasses = EnvClasses()
        self.train_tasks: List[Task] = []
        self.test_tasks: List[Task] = []

    @staticmethod
    def _variations(bench_id: str, options: Dict[str, Any], names: Dict[str, str], goal_observable: bool):
        """(classes, tasks) of one split of a manyworlds benchmark env."""
        env = _core.Env(bench_id, options)
        classes = EnvClasses()
        tasks: List[Task] = []
        for task_id, states in env.evaluation_tasks():
            name = names.get(task_id, task_id)
            classes[name] = _env_class(task_id, name, goal_observable)
            for state in states:
                tasks.append(Task(name, json.dumps(state["params"]["state"])))
        return classes, tasks

    def __repr__(self) -> str:
        return (
            f"<{type(self).__name__}: {len(self.train_classes)} train classes, {len(self.train_tasks)} train tasks, "
            f"{len(self.test_classes)} test classes, {len(self.test_tasks)} test tasks>"
        )


class MT1(Benchmark):
    """One task, 50 train variations with the goal visible; no test set."""

    def __init__(self, env_name: str, seed: Optional[int] = None) -> None:
        super().__init__()
        task_id = _task_id(env_name)
        options = {"task": task_id, "benchmark_seed": int(seed or 0)}
        self.train_classes, self.train_tasks = self._variations("mt1", options, {task_id: env_name}, True)


class ML1(Benchmark):
    """One task: 50 train and 50 test variations, goal hidden."""

    def __init__(self, env_name: str, seed: Optional[int] = None) -> None:
        super().__init__()
        task_id = _task_id(env_name)
        names = {task_id: env_name}
        base = {"task": task_id, "benchmark_seed": int(seed or 0)}
        self.train_classes, self.train_tasks = self._variations("ml1", {**base, "split": "train"}, names, False)
        self.test_classes, self.test_tasks = self._variations("ml1", {**base, "split": "test"}, names, False)


class _PublishedMT(Benchmark):
    """A published multi-task benchmark: its tasks, 50 variations each, goal visible; no test set."""

    BENCHMARK_ID = ""

    def __init__(self, seed: Optional[int] = None) -> None:
        super().__init__()
        options = {"benchmark_seed": int(seed or 0)}
        self.train_classes, self.train_tasks = self._variations(self.BENCHMARK_ID, options, {}, True)


class _PublishedML(Benchmark):
    """A published meta-learning benchmark: train and held-out test tasks, 50 variations each, goal hidden."""

    BENCHMARK_ID = ""

    def __init__(self, seed: Optional[int] = None) -> None:
        super().__init__()
        base = {"benchmark_seed": int(seed or 0)}
        self.train_classes, self.train_tasks = self._variations(self.BENCHMARK_ID, {**base, "split": "train"}, {}, False)
        self.test_classes, self.test_tasks = self._variations(self.BENCHMARK_ID, {**base, "split": "test"}, {}, False)


class MT10(_PublishedMT):
    """The ten MT10 tasks, 50 variations each, goal visible; no test set."""

    BENCHMARK_ID = "mt10"


class MT25(_PublishedMT):
    """MT10 and 15 more tasks (Meta-World v3's MT25), 50 variations each, goal visible."""

    BENCHMARK_ID = "mt25"


class MT50(_PublishedMT):
    """All 50 tasks in Meta-World v3's order, 50 variations each, goal visible."""

    BENCHMARK_ID = "mt50"


class ML10(_PublishedML):
    """Ten train tasks and five held-out test tasks, 50 variations each, goal hidden."""

    BENCHMARK_ID = "ml10"


class ML25(_PublishedML):
    """MT25's tasks for training and five test tasks (v3's ML25: basketball is on both sides)."""

    BENCHMARK_ID = "ml25"


class ML45(_PublishedML):
    """45 train tasks and five held-out test tasks, 50 variations each, goal hidden."""

    BENCHMARK_ID = "ml45"


# {id: {"train": [...], "test": [...]}} from the C++ side (empty in a build without MuJoCo).
_SPLITS: Dict[str, Dict[str, List[str]]] = _core.benchmark_splits() if hasattr(_core, "benchmark_splits") else {}


def _splits(bench_id: str) -> Dict[str, List[str]]:
    return _SPLITS.get(bench_id, {"train": [], "test": []})


MT10_TASKS = _splits("mt10")["train"]
MT25_TASKS = _splits("mt25")["train"]
MT50_TASKS = _splits("mt50")["train"]
ML10_TRAIN_TASKS = _splits("ml10")["train"]
ML10_TEST_TASKS = _splits("ml10")["test"]
ML25_TRAIN_TASKS = _splits("ml25")["train"]
ML25_TEST_TASKS = _splits("ml25")["test"]
ML45_TRAIN_TASKS = _splits("ml45")["train"]
ML45_TEST_TASKS = _splits("ml45")["test"]


def __getattr__(name: str) -> Any:
    # v3's module-level make functions (``metaworld.make_mt_envs``), imported when first used
    if name in ("make_mt_envs", "make_ml_envs"):
        from manyworlds import metaworld_gym
        return getattr(metaworld_gym, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
