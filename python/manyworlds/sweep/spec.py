"""Sweep files: which training runs a sweep holds.

A sweep file (YAML) names training configs, seeds, overrides and a grid; it expands to one run per
(group, grid point, seed). Every key is checked: an unknown key, an empty grid, a seed that is
not an integer or a config that does not exist is one ValueError naming it, before anything runs.

    name: classic                  # optional (default: the file's name without .yaml)
    seeds: [1, 2, 3]               # or {first: 1, count: 10}
    overrides:                     # optional: every run
      experiment.eval_episodes: 6
    grid:                          # optional: every run, the product of the value lists
      agent.lr: [1.0e-3, 3.0e-4]
    budget:                        # optional: steps_per_task for every run (smaller machines)
      steps_per_task: 20000
    resources:                     # optional, per run
      num_cpus: auto               # auto: the config's experiment.num_threads
      num_gpus: 0
    groups:                        # one entry per config (a string is {config: STRING})
      - config: configs/point_nav_ppo.yaml
        name: ppo                  # optional (default: the config file's stem)
        overrides: {agent.epochs: 5}
        grid: {agent.clip_range: [0.1, 0.2]}
      - configs/point_nav_trpo.yaml

A method is a group at one grid point ("ppo[agent.lr=0.001]"); its runs are its seeds. Config
paths are taken as given (absolute, or relative to the current directory), else relative to the
sweep file's folder, else relative to `config_root` (the sweep CLI's --config-root).
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import math
import pathlib
import re
from typing import Any

SWEEP_KEYS = {"name", "seeds", "overrides", "grid", "budget", "resources", "groups"}
GROUP_KEYS = {"config", "name", "overrides", "grid"}
BUDGET_KEYS = {"steps_per_task"}
RESOURCE_KEYS = {"num_cpus", "num_gpus"}
# Keys the sweep sets itself: an override of them would break the run-directory layout.
RESERVED_OVERRIDES = {"experiment.seed", "experiment.run_dir"}
MAX_RUNS = 100000


@dataclasses.dataclass(frozen=True)
class Run:
    """One training run of a sweep."""

    id: str  # "<method_dir>/seed_<n>", unique in the sweep
    method: str  # "<group>" or "<group>[key=value,...]"
    group: str
    grid_point: dict[str, Any]
    config: str  # absolute path of the training config
    seed: int
    overrides: dict[str, Any]  # sweep, grid and group overrides (not seed, run_dir)
    run_dir: str  # relative to the sweep directory

    def command_overrides(self, sweep_dir: pathlib.Path) -> list[str]:
        """The `key=value` arguments of `manyworlds train CONFIG ...` for this run."""
        pairs = dict(self.overrides)
        pairs["experiment.seed"] = self.seed
        pairs["experiment.run_dir"] = str(pathlib.Path(sweep_dir) / self.run_dir)
        return [f"{key}={format_value(value)}" for key, value in pairs.items()]

    def to_json(self) -> dict[str, Any]:
        return dataclasses.asdict(self)

    @staticmethod
    def from_json(data: dict[str, Any]) -> "Run":
        fields = {f.name for f in dataclasses.fields(Run)}
        if not isinstance(data, dict) or set(data) != fields:
            raise ValueError(f"a run of sweep.json must have exactly the keys {sorted(fields)}")
        return Run(**data)


@dataclasses.dataclass(frozen=True)
class Resources:
    num_cpus: float | None = None  # None: the config's experiment.num_threads
    num_gpus: float = 0.0


@dataclasses.dataclass(frozen=True)
class Sweep:
    name: str
    runs: tuple[Run, ...]
    resources: Resources
    source: str  # the sweep file

    @property
    def methods(self) -> list[str]:
        return list(dict.fromkeys(run.method for run in self.runs))

    def manifest(self) -> dict[str, Any]:
        """What sweep.json holds: the sweep's name and its expanded runs."""
        return {"format": 1, "name": self.name, "source": self.source,
                "resources": dataclasses.asdict(self.resources),
                "runs": [run.to_json() for run in self.runs]}


def format_value(value: Any) -> str:
    """A YAML scalar or list as the C++ override parser reads it."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float, str)):
        return repr(value) if isinstance(value, float) else str(value)
    return json.dumps(value)


def _fail(source: str, message: str) -> None:
    raise ValueError(f"{source}: {message}")


def _mapping(source: str, where: str, value: Any, allowed: set[str]) -> dict[str, Any]:
    if value is None:
        return {}
    if not isinstance(value, dict):
        _fail(source, f"{where} must be a mapping, got {type(value).__name__}")
    unknown = sorted(str(k) for k in value if k not in allowed)
    if unknown:
        _fail(source, f"unknown key {unknown[0]!r} in {where}; allowed: {', '.join(sorted(allowed))}")
    return value


def _scalar_ok(value: Any) -> bool:
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, (bool, int, str)):
        return True
    if isinstance(value, list):
        return all(_scalar_ok(v) for v in value)
    return False


def _overrides(source: str, where: str, value: Any) -> dict[str, Any]:
    if value is None:
        return {}
    if not isinstance(value, dict):
        _fail(source, f"{where} must be a mapping of config keys to values, "
                      f"got {type(value).__name__}")
    for key, item in value.items():
        if not isinstance(key, str) or not re.fullmatch(r"\+?[A-Za-z_][\w]*(\.[\w-]+)+", key):
            _fail(source, f"{where}: {key!r} is not a dotted config key such as agent.lr")
        if key.lstrip("+") in RESERVED_OVERRIDES:
            _fail(source, f"{where}: {key} is set by the sweep (seeds: and the sweep directory)")
        if not _scalar_ok(item):
            _fail(source, f"{where}: {key} must be a number, string, boolean or a list of them "
                          f"(finite numbers), got {item!r}")
    return dict(value)


def _grid(source: str, where: str, value: Any) -> dict[str, list[Any]]:
    grid = _overrides(source, where, value)
    for key, values in grid.items():
        if not isinstance(values, list) or not values:
            _fail(source, f"{where}: {key} must be a non-empty list of values, got {values!r}")
        if len(set(map(format_value, values))) != len(values):
            _fail(source, f"{where}: {key} lists a value twice")
    return grid


def _seeds(source: str, value: Any) -> list[int]:
    if isinstance(value, dict):
        _mapping(source, "seeds", value, {"first", "count"})
        first, count = value.get("first", 1), value.get("count")
        if type(first) is not int or type(count) is not int or count < 1:
            _fail(source, f"seeds: {{first: INT, count: INT >= 1}}, got {value!r}")
        value = list(range(first, first + count))
    if not isinstance(value, list) or not value:
        _fail(source, f"seeds must be a non-empty list of integers or {{first, count}}, got {value!r}")
    for seed in value:
        if type(seed) is not int or not 0 <= seed < 2**64:
            _fail(source, f"seeds: {seed!r} is not an integer in [0, 2^64)")
    if len(set(value)) != len(value):
        _fail(source, "seeds lists a seed twice")
    return value


def _resources(source: str, value: Any) -> Resources:
    value = _mapping(source, "resources", value, RESOURCE_KEYS)
    cpus = value.get("num_cpus", "auto")
    gpus = value.get("num_gpus", 0)
    if cpus != "auto" and (isinstance(cpus, bool) or not isinstance(cpus, (int, float))
                           or not 0 < cpus <= 1024):
        _fail(source, f"resources.num_cpus must be auto or a number in (0, 1024], got {cpus!r}")
    if isinstance(gpus, bool) or not isinstance(gpus, (int, float)) or not 0 <= gpus <= 64:
        _fail(source, f"resources.num_gpus must be a number in [0, 64], got {gpus!r}")
    return Resources(num_cpus=None if cpus == "auto" else float(cpus), num_gpus=float(gpus))


def _find_config(source: str, path: Any, search: list[pathlib.Path]) -> pathlib.Path:
    if not isinstance(path, str) or not path:
        _fail(source, f"a group's config must be a file path, got {path!r}")
    given = pathlib.Path(path)
    candidates = [given] if given.is_absolute() else [base / given for base in search]
    for candidate in candidates:
        if candidate.is_file():
            return candidate.resolve()
    _fail(source, f"config {path!r} not found (looked in {', '.join(str(c) for c in candidates)})")
    raise AssertionError  # unreachable


def _dir_name(text: str) -> str:
    """A folder name for a method: characters other than letters, digits, . _ = - become _."""
    return re.sub(r"[^A-Za-z0-9._=-]", "_", text)


def parse(data: Any, source: str = "<sweep>", base_dir: pathlib.Path | None = None,
          config_root: pathlib.Path | None = None, steps_per_task: int | None = None) -> Sweep:
    """The sweep a parsed sweep file describes. `steps_per_task` overrides the file's budget."""
    data = _mapping(source, "the sweep file", data, SWEEP_KEYS)
    if "groups" not in data:
        _fail(source, "the sweep file needs groups: (a list of configs)")
    if "seeds" not in data:
        _fail(source, "the sweep file needs seeds: (a list of integers or {first, count})")
    name = data.get("name", pathlib.Path(source).stem if source != "<sweep>" else "sweep")
    if not isinstance(name, str) or not re.fullmatch(r"[\w.-]+", name):
        _fail(source, f"name must be letters, digits, _ . -, got {name!r}")
    seeds = _seeds(source, data["seeds"])
    overrides = _overrides(source, "overrides", data.get("overrides"))
    grid = _grid(source, "grid", data.get("grid"))
    budget = _mapping(source, "budget", data.get("budget"), BUDGET_KEYS)
    if steps_per_task is None:
        steps_per_task = budget.get("steps_per_task")
    if steps_per_task is not None:
        if type(steps_per_task) is not int or steps_per_task < 1:
            _fail(source, f"budget.steps_per_task must be a positive integer, got {steps_per_task!r}")
        overrides["experiment.steps_per_task"] = steps_per_task
    resources = _resources(source, data.get("resources"))
    groups = data["groups"]
    if not isinstance(groups, list) or not groups:
        _fail(source, "groups must be a non-empty list of configs")

    search = [pathlib.Path.cwd()]
    if base_dir is not None:
        search.append(pathlib.Path(base_dir))
    if config_root is not None:
        search.append(pathlib.Path(config_root))
    runs: list[Run] = []
    method_dirs: dict[str, str] = {}
    for index, group in enumerate(groups):
        where = f"groups[{index}]"
        if isinstance(group, str):
            group = {"config": group}
        group = _mapping(source, where, group, GROUP_KEYS)
        if "config" not in group:
            _fail(source, f"{where} needs config:")
        config = _find_config(source, group["config"], search)
        group_name = group.get("name", config.stem)
        if not isinstance(group_name, str) or not group_name:
            _fail(source, f"{where}.name must be a non-empty string")
        group_overrides = _overrides(source, f"{where}.overrides", group.get("overrides"))
        group_grid = _grid(source, f"{where}.grid", group.get("grid"))
        both = sorted(set(grid) & set(group_grid))
        if both:
            _fail(source, f"{where}.grid repeats the sweep's grid key {both[0]}")
        full_grid = {**grid, **group_grid}
        keys = list(full_grid)
        for values in itertools.product(*(full_grid[k] for k in keys)):
            point = dict(zip(keys, values))
            label = ",".join(f"{k}={format_value(v)}" for k, v in point.items())
            method = f"{group_name}[{label}]" if point else group_name
            method_dir = _dir_name(f"{group_name}_{label}" if point else group_name)
            if method_dir in method_dirs:
                _fail(source, f"methods {method_dirs[method_dir]!r} and {method!r} share the "
                              f"folder {method_dir!r}; give the groups distinct names")
            method_dirs[method_dir] = method
            run_overrides = {**overrides, **group_overrides, **point}
            for seed in seeds:
                runs.append(Run(id=f"{method_dir}/seed_{seed}", method=method, group=group_name,
                                grid_point=point, config=str(config), seed=seed,
                                overrides=run_overrides, run_dir=f"runs/{method_dir}/seed_{seed}"))
                if len(runs) > MAX_RUNS:
                    _fail(source, f"the sweep expands to more than {MAX_RUNS} runs")
    return Sweep(name=name, runs=tuple(runs), resources=resources, source=source)


def load(path: str | pathlib.Path, config_root: str | pathlib.Path | None = None,
         steps_per_task: int | None = None) -> Sweep:
    """Reads and checks a sweep file (see the module's docstring)."""
    import yaml

    path = pathlib.Path(path)
    try:
        text = path.read_text()
    except OSError as error:
        raise ValueError(f"cannot read the sweep file {path}: {error.strerror}") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as error:
        first = str(error).splitlines()[0] if str(error) else "syntax error"
        raise ValueError(f"{path}: not valid YAML ({first})") from None
    return parse(data, source=str(path), base_dir=path.resolve().parent,
                 config_root=None if config_root is None else pathlib.Path(config_root),
                 steps_per_task=steps_per_task)
