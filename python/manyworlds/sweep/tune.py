"""Hyperparameter search with Ray Tune, `manyworlds train` as the trainable.

A search file (YAML) names one training config, a search space over any of its keys and a
scheduler; every trial is a `manyworlds train` run whose evaluations (eval.jsonl, or
meta_test.jsonl for meta-RL) are reported to Tune as they are written, so ASHA can stop a poor
trial early (its program gets SIGTERM, checkpoints and stops).

    name: point-nav-ppo-lr         # optional (default: the file's name)
    config: configs/point_nav_ppo.yaml
    overrides: {experiment.eval_every: 2500}   # optional, every trial
    seed: 1                        # experiment.seed of every trial
    budget: {steps_per_task: 10000}            # optional
    space:                         # config key: {choice | grid: [..]} or {uniform | loguniform: [lo, hi]}
      agent.lr: {loguniform: [1.0e-4, 1.0e-2]}
      agent.clip_range: {choice: [0.1, 0.2, 0.3]}
    num_samples: 8                 # samples of the space (grid values are crossed with them)
    metric: mean_success           # a key of the reported rows; default mean_success (eval)
    source: eval                   # eval (eval.jsonl) or meta_test (meta_test.jsonl)
    mode: max                      # max or min
    scheduler: {asha: {grace_period: 1, reduction_factor: 2}}   # or none
    search_seed: 0                 # the sampler's seed: the same file samples the same trials
    resources: {num_cpus: auto}    # per trial; auto: the config's experiment.num_threads
    max_concurrent_trials: 0       # 0: as many as the CPUs allow
    loggers: []                    # Ray Tune's MLflow / Weights & Biases loggers: mlflow, wandb

The trial's report counts evaluations (training_iteration); ASHA's grace period and max_t are in
evaluations. Results: OUT/NAME/ (Tune's experiment folder, one trial folder each with its run
directory in run/) and OUT/NAME/search_results.json and .csv (every trial: its values, last and
best metric, evaluations, status), best first.
"""

from __future__ import annotations

import csv
import io
import json
import pathlib
import subprocess
import time
from typing import Any, Callable

from manyworlds.sweep import runner, spec

SEARCH_KEYS = {"name", "config", "overrides", "seed", "budget", "space", "num_samples", "metric",
               "source", "mode", "scheduler", "search_seed", "resources", "max_concurrent_trials",
               "loggers"}
# Ray Tune's logger callbacks: (module, class, the package they need)
LOGGERS = {"mlflow": ("ray.air.integrations.mlflow", "MLflowLoggerCallback", "mlflow"),
           "wandb": ("ray.air.integrations.wandb", "WandbLoggerCallback", "wandb")}
DISTRIBUTIONS = {"choice", "grid", "uniform", "loguniform"}
SOURCES = {"eval": "eval.jsonl", "meta_test": "meta_test.jsonl"}


def _fail(source: str, message: str) -> None:
    raise ValueError(f"{source}: {message}")


def load_search(path: str | pathlib.Path, config_root: str | pathlib.Path | None = None,
                steps_per_task: int | None = None) -> dict[str, Any]:
    """Reads and checks a search file; returns its settings with defaults filled in."""
    import yaml

    path = pathlib.Path(path)
    try:
        data = yaml.safe_load(path.read_text())
    except OSError as error:
        raise ValueError(f"cannot read the search file {path}: {error.strerror}") from None
    except yaml.YAMLError as error:
        raise ValueError(f"{path}: not valid YAML ({str(error).splitlines()[0]})") from None
    return parse_search(data, str(path), path.resolve().parent, config_root, steps_per_task)


def parse_search(data: Any, source: str, base_dir: pathlib.Path | None = None,
                 config_root: str | pathlib.Path | None = None,
                 steps_per_task: int | None = None) -> dict[str, Any]:
    data = spec._mapping(source, "the search file", data, SEARCH_KEYS)
    for key in ("config", "space"):
        if key not in data:
            _fail(source, f"the search file needs {key}:")
    search = [pathlib.Path.cwd()] + [pathlib.Path(p) for p in (base_dir, config_root) if p]
    config = spec._find_config(source, data["config"], search)
    name = data.get("name", pathlib.Path(source).stem)
    if not isinstance(name, str) or not name.replace("-", "").replace("_", "").isalnum():
        _fail(source, f"name must be letters, digits, _ and -, got {name!r}")
    overrides = spec._overrides(source, "overrides", data.get("overrides"))
    budget = spec._mapping(source, "budget", data.get("budget"), spec.BUDGET_KEYS)
    steps = steps_per_task if steps_per_task is not None else budget.get("steps_per_task")
    if steps is not None:
        if type(steps) is not int or steps < 1:
            _fail(source, f"budget.steps_per_task must be a positive integer, got {steps!r}")
        overrides["experiment.steps_per_task"] = steps
    seed = data.get("seed", 1)
    if type(seed) is not int or not 0 <= seed < 2**64:
        _fail(source, f"seed must be an integer in [0, 2^64), got {seed!r}")
    if not isinstance(data["space"], dict):
        _fail(source, f"space must be a mapping of config keys to distributions, "
                      f"got {type(data['space']).__name__}")
    space = spec._overrides(source, "space", {k: 0 for k in data["space"]})
    if not space:
        _fail(source, "space must name at least one config key")
    checked_space = {}
    for key, dist in data["space"].items():
        if not isinstance(dist, dict) or len(dist) != 1 or next(iter(dist)) not in DISTRIBUTIONS:
            _fail(source, f"space.{key} must be one of {{choice: [..]}}, {{grid: [..]}}, "
                          f"{{uniform: [lo, hi]}}, {{loguniform: [lo, hi]}}, got {dist!r}")
        (kind, values), = dist.items()
        if kind in ("choice", "grid"):
            if not isinstance(values, list) or not values or not spec._scalar_ok(values):
                _fail(source, f"space.{key}.{kind} must be a non-empty list of values")
        else:
            ok = (isinstance(values, list) and len(values) == 2 and
                  all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values) and
                  spec._scalar_ok(values) and values[0] < values[1] and
                  (kind == "uniform" or values[0] > 0))
            if not ok:
                _fail(source, f"space.{key}.{kind} must be [lo, hi] with lo < hi"
                              f"{' and lo > 0' if kind == 'loguniform' else ''}, got {values!r}")
        checked_space[key] = (kind, values)
    clash = sorted(set(checked_space) & set(overrides))
    if clash:
        _fail(source, f"{clash[0]} is both searched (space) and fixed (overrides)")
    num_samples = data.get("num_samples", 1)
    if type(num_samples) is not int or not 1 <= num_samples <= 100000:
        _fail(source, f"num_samples must be an integer in [1, 100000], got {num_samples!r}")
    source_kind = data.get("source", "eval")
    if source_kind not in SOURCES:
        _fail(source, f"source must be one of {', '.join(SOURCES)}, got {source_kind!r}")
    metric = data.get("metric", "mean_success" if source_kind == "eval" else "success_rate")
    if not isinstance(metric, str) or not metric:
        _fail(source, "metric must be the name of a reported value, e.g. mean_success")
    mode = data.get("mode", "max")
    if mode not in ("max", "min"):
        _fail(source, f"mode must be max or min, got {mode!r}")
    scheduler = data.get("scheduler", {"asha": {}})
    if scheduler in (None, "none"):
        scheduler = None
    else:
        scheduler = spec._mapping(source, "scheduler", scheduler, {"asha"})
        asha = spec._mapping(source, "scheduler.asha", scheduler.get("asha") or {},
                             {"grace_period", "reduction_factor", "max_t"})
        for key, low in (("grace_period", 1), ("reduction_factor", 2), ("max_t", 1)):
            value = asha.get(key)
            if value is not None and (type(value) is not int or value < low):
                _fail(source, f"scheduler.asha.{key} must be an integer >= {low}, got {value!r}")
        scheduler = {"asha": asha}
    search_seed = data.get("search_seed", 0)
    if type(search_seed) is not int or search_seed < 0:
        _fail(source, f"search_seed must be a non-negative integer, got {search_seed!r}")
    resources = spec._resources(source, data.get("resources"))
    concurrent = data.get("max_concurrent_trials", 0)
    if type(concurrent) is not int or concurrent < 0:
        _fail(source, f"max_concurrent_trials must be a non-negative integer, got {concurrent!r}")
    loggers = data.get("loggers", [])
    if not isinstance(loggers, list) or any(logger not in LOGGERS for logger in loggers):
        _fail(source, f"loggers must be a list of {', '.join(LOGGERS)}, got {loggers!r}")
    return {"name": name, "config": str(config), "overrides": overrides, "seed": seed,
            "space": checked_space, "num_samples": num_samples, "metric": metric,
            "source": source_kind, "mode": mode, "scheduler": scheduler,
            "search_seed": search_seed, "resources": resources,
            "max_concurrent_trials": concurrent, "loggers": loggers, "file": source}


def _tune_space(space: dict[str, tuple[str, list[Any]]]) -> dict[str, Any]:
    from ray import tune

    make = {"choice": tune.choice, "grid": tune.grid_search,
            "uniform": lambda v: tune.uniform(*v), "loguniform": lambda v: tune.loguniform(*v)}
    return {key: make[kind](values) for key, (kind, values) in space.items()}


def _read_new_rows(path: pathlib.Path, offset: int) -> tuple[list[dict[str, Any]], int]:
    """Complete lines of a JSONL file past `offset` (a line still being written waits)."""
    try:
        with open(path, "rb") as f:
            f.seek(offset)
            data = f.read()
    except FileNotFoundError:
        return [], offset
    end = data.rfind(b"\n") + 1
    rows = [json.loads(line) for line in data[:end].splitlines() if line.strip()]
    return rows, offset + end


def _flat_scalars(row: dict[str, Any]) -> dict[str, float]:
    """The row's top-level numbers (per-task tables left out), for Tune's report."""
    return {k: float(v) for k, v in row.items()
            if isinstance(v, (int, float)) and not isinstance(v, bool)}


def make_trainable(cli: str, settings: dict[str, Any]) -> Callable[[dict[str, Any]], None]:
    """A Tune function trainable running `manyworlds train` for one trial's sampled values."""
    base = dict(settings["overrides"])
    base["experiment.seed"] = settings["seed"]
    rows_file = SOURCES[settings["source"]]

    def trainable(values: dict[str, Any]) -> None:
        from ray import tune

        trial_dir = pathlib.Path(tune.get_context().get_trial_dir())
        run_dir = trial_dir / "run"
        log = open(trial_dir / "train.log", "ab")
        state = runner.run_state(run_dir)
        if state == "started":  # a restored experiment: the trial continues its run
            command = [cli, "train", "--resume", str(run_dir)]
        else:
            pairs = {**base, **values, "experiment.run_dir": str(run_dir)}
            command = [cli, "train", settings["config"],
                       *[f"{k}={spec.format_value(v)}" for k, v in pairs.items()]]
        # rows already reported before a restore are reported again: Tune restarts the trial's
        # iteration count with it
        offset = 0
        child = subprocess.Popen(command, stdout=log, stderr=subprocess.PIPE,
                                 preexec_fn=runner._set_parent_death_signal)
        try:
            while True:
                finished = child.poll() is not None
                rows, offset = _read_new_rows(run_dir / rows_file, offset)
                for row in rows:
                    tune.report(_flat_scalars(row))
                if finished:
                    break
                time.sleep(0.2)
            err = child.stderr.read()
            log.write(err)
            if child.returncode != 0:
                lines = err.decode(errors="replace").strip().splitlines()
                raise RuntimeError(f"manyworlds train exited with code {child.returncode}: "
                                   f"{lines[-1] if lines else 'no message'}")
        finally:
            if child.poll() is None:  # stopped by the scheduler: checkpoint and stop
                child.terminate()
                child.wait()
            log.close()

    return trainable


def logger_callbacks(settings: dict[str, Any]) -> list[Any]:
    """Ray Tune's MLflow / W&B loggers the search file asks for (their settings, such as
    MLFLOW_TRACKING_URI or WANDB_API_KEY, come from the environment as those packages read it)."""
    import importlib

    callbacks = []
    for name in settings["loggers"]:
        module, cls, package = LOGGERS[name]
        try:
            importlib.import_module(package)
        except ImportError:
            raise ValueError(f"loggers: {name} needs the {package} package "
                             f"(pip install {package})") from None
        make = getattr(importlib.import_module(module), cls)
        callbacks.append(make(experiment_name=settings["name"]) if name == "mlflow"
                         else make(project=settings["name"]))
    return callbacks


def run_search(settings: dict[str, Any], out_dir: str | pathlib.Path, *, cli: str | None = None,
               address: str | None = None, num_cpus: int | None = None, resume: bool = False,
               object_store_mb: int = 200) -> list[dict[str, Any]]:
    """Runs the search; returns every trial's summary, best first (also written to
    OUT/NAME/search_results.json and .csv)."""
    from ray import tune
    from ray.tune.schedulers import ASHAScheduler
    from ray.tune.search import BasicVariantGenerator

    cli = runner.find_cli(cli)
    out_dir = pathlib.Path(out_dir).resolve()
    experiment_dir = out_dir / settings["name"]
    if experiment_dir.exists() and not resume:
        raise runner.SweepError(f"{experiment_dir} already holds a search; continue it with "
                                f"--resume or choose another --out")
    if resume and not experiment_dir.exists():
        raise runner.SweepError(f"{experiment_dir} holds no search to resume")
    # the base config must resolve before any trial starts (a bad override fails here)
    probe = spec.Run(id="probe", method="probe", group="probe", grid_point={},
                     config=settings["config"], seed=settings["seed"],
                     overrides=settings["overrides"], run_dir="probe")
    config = runner.resolved_config(cli, probe, out_dir)
    cpus = settings["resources"].num_cpus or int(config["experiment"]["num_threads"])

    runner.ensure_ray(address, num_cpus, object_store_mb)
    trainable = tune.with_resources(make_trainable(cli, settings),
                                    {"cpu": cpus, "gpu": settings["resources"].num_gpus})
    scheduler = None
    if settings["scheduler"]:
        asha = settings["scheduler"]["asha"]
        scheduler = ASHAScheduler(time_attr="training_iteration",
                                  grace_period=asha.get("grace_period", 1),
                                  reduction_factor=asha.get("reduction_factor", 2),
                                  max_t=asha.get("max_t", 10**9))
    run_config = tune.RunConfig(name=settings["name"], storage_path=str(out_dir), verbose=0,
                                callbacks=logger_callbacks(settings))
    if resume:
        tuner = tune.Tuner.restore(str(experiment_dir), trainable=trainable,
                                   resume_unfinished=True, resume_errored=True)
    else:
        tuner = tune.Tuner(
            trainable, param_space=_tune_space(settings["space"]),
            tune_config=tune.TuneConfig(
                metric=settings["metric"], mode=settings["mode"], scheduler=scheduler,
                num_samples=settings["num_samples"],
                # the generator takes the limit itself (Tune ignores max_concurrent_trials
                # beside a generator)
                search_alg=BasicVariantGenerator(random_state=settings["search_seed"],
                                                 max_concurrent=settings["max_concurrent_trials"])),
            run_config=run_config)
    results = tuner.fit()
    return write_search_results(results, settings, experiment_dir)


def write_search_results(results: Any, settings: dict[str, Any],
                         experiment_dir: pathlib.Path) -> list[dict[str, Any]]:
    metric, mode = settings["metric"], settings["mode"]
    trials = []
    for result in results:
        history = result.metrics_dataframe
        values = [] if history is None or metric not in history else \
            [float(v) for v in history[metric].dropna()]
        best = (max(values) if mode == "max" else min(values)) if values else None
        trials.append({"trial": pathlib.Path(result.path).name, "values": result.config,
                       "evaluations": len(values), "last": values[-1] if values else None,
                       "best": best, "error": None if result.error is None else
                       str(result.error).strip().splitlines()[-1],
                       "run_dir": str(pathlib.Path(result.path) / "run")})
    sign = -1 if mode == "max" else 1
    trials.sort(key=lambda t: (t["best"] is None, sign * (t["best"] or 0.0)))
    runner.write_atomically(experiment_dir / "search_results.json",
                            json.dumps({"metric": metric, "mode": mode, "trials": trials},
                                       indent=2) + "\n")
    keys = list(settings["space"])
    text = io.StringIO()
    writer = csv.writer(text)
    writer.writerow(["trial", *keys, "evaluations", f"last_{metric}", f"best_{metric}", "error"])
    for t in trials:
        writer.writerow([t["trial"], *[t["values"].get(k) for k in keys], t["evaluations"],
                         t["last"], t["best"], t["error"] or ""])
    runner.write_atomically(experiment_dir / "search_results.csv", text.getvalue())
    return trials
