"""Statistics of a finished sweep: IQM over seeds with stratified-bootstrap confidence intervals.

Multi-task and meta-RL results are reported the way the field does since Agarwal et al. (2021,
"Deep RL at the Edge of the Statistical Precipice") and Meta-World+: per method, the
interquartile mean (IQM), mean, median and optimality gap of the per-task scores over all
(seed, task) pairs, each with a 95 % stratified-bootstrap confidence interval; performance
profiles; the probability that one method improves on another; and IQM curves over training.
Every statistic is computed by rliable (``rliable.library``, ``rliable.metrics``) and drawn
with ``rliable.plot_utils``; this module only gathers the scores and writes the files::

    from manyworlds.sweep.report import write_report
    report = write_report("sweeps/mt10")     # writes sweeps/mt10/report/
    report["methods"]["mtsac"]["aggregates"]["iqm"]   # {"estimate", "ci_low", "ci_high"}

The files: ``report.json`` (everything, the dict returned), ``scores.csv`` (one row per run
and task), ``aggregates.csv``, ``summary.md`` (Meta-World+-style tables) and the plots
``curves``, ``aggregates``, ``profiles`` and ``improvement`` as PNG and SVG.

Scores. A run's score on a task is its final success rate (``metric="success"``) or final
return (``metric="return"``), read from the run's ``summary.json``: ``final_meta_test``
(held-out tasks, after adaptation) where the run has one, else ``final_eval``
(``source="auto"``); ``source="eval"|"meta_test"|"meta_train"`` picks one. A method (one
``method`` of ``sweep.json``, i.e. one grid point) has a score matrix of shape
(finished runs, tasks), tasks in sorted order. Runs that did not finish, or lack the source
or the metric, are left out of the statistics and listed with the reason.

Optimality gap: ``gamma - mean(min(score, gamma))``, with gamma = 1 for success rates. Returns
have no natural optimum, so for ``metric="return"`` the gap is reported only when a
``target`` return is given (it is then gamma).

Bootstrap repetitions. rliable's papers use 50,000. The Monte-Carlo error of a percentile
interval's endpoint is about 0.06 / sqrt(reps / 2,000) of the bootstrap standard deviation,
i.e. ~1.4 % of the interval's half-width at 10,000 reps, well under the two decimals a
table shows; so final-score aggregates and performance profiles default to 10,000
(about two seconds a method). Probability of improvement (one Mann-Whitney U test per task
per repetition, ~5 ms a repetition at 10 tasks) and curves (one IQM per logged step per
repetition) default to 2,000, rliable's own default for profiles (~3 % of the half-width).
All are seeded: the same inputs and ``seed`` give the same report, and a method's
intervals do not change when other methods are added to the sweep.

Lower-level functions take score matrices directly, e.g. for synthetic scores::

    aggregate_scores({"a": np.array([[0.1, 0.9], [0.5, 0.7]])}, reps=2000, seed=0)

Errors in the input (no or malformed ``sweep.json``, no finished run, a method whose seeds
score different task sets) raise ``ValueError`` with a one-line message.
"""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import io
import json
import math
import os
import sys
import tempfile
import zlib
from collections import Counter
from typing import Any, Dict, Iterator, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from manyworlds.sweep.runner import read_jsonl as _read_jsonl

try:
    from rliable import library as rly_library
    from rliable import metrics as rly_metrics
except ImportError as error:  # pragma: no cover - depends on the environment
    raise ImportError("manyworlds.sweep.report needs rliable (pip install 'rliable>=1.2'); "
                      f"importing it failed: {error}") from error

__all__ = [
    "DEFAULT_REPS", "DEFAULT_CURVE_REPS", "DEFAULT_IMPROVEMENT_REPS", "METRICS", "SOURCES",
    "AGGREGATES", "MethodScores", "load_sweep", "run_scores", "scores_from_runs",
    "aggregate_scores", "performance_profiles", "probability_of_improvement",
    "curve_scores", "learning_curves", "write_report",
]

DEFAULT_REPS = 10_000
DEFAULT_CURVE_REPS = 2_000
DEFAULT_IMPROVEMENT_REPS = 2_000
CONFIDENCE = 0.95
METRICS = ("success", "return")
SOURCES = ("auto", "eval", "meta_test", "meta_train")
AGGREGATES = ("iqm", "mean", "median", "optimality_gap")
AGGREGATE_TITLES = {"iqm": "IQM", "mean": "Mean", "median": "Median",
                    "optimality_gap": "Optimality gap"}
PROFILE_THRESHOLDS = 21  # points on the score axis of the performance profiles

_SUMMARY_KEY = {"eval": "final_eval", "meta_test": "final_meta_test",
                "meta_train": "final_meta_train"}
_CURVE_FILE = {"eval": "eval.jsonl", "meta_test": "meta_test.jsonl",
               "meta_train": "meta_train.jsonl"}
_PLOT_FORMATS = ("png", "svg")


# ------------------------------------------------------------------------------ reading runs
@dataclasses.dataclass
class MethodScores:
    """The final scores of one method (one grid point of the sweep) over its finished runs.

    ``scores[i, j]`` is run ``run_ids[i]``'s score on ``tasks[j]``; ``missing`` lists
    ``(run id, reason)`` of the method's runs that are left out.
    """

    method: str
    group: Optional[str]
    source: Optional[str]
    tasks: List[str]
    run_ids: List[str]
    seeds: List[Any]
    run_dirs: List[str]
    scores: np.ndarray
    missing: List[Tuple[str, str]]

    @property
    def total_runs(self) -> int:
        return len(self.run_ids) + len(self.missing)


def load_sweep(sweep_dir: str) -> dict:
    """The parsed ``SWEEP_DIR/sweep.json``, checked for the fields the report reads."""
    path = os.path.join(sweep_dir, "sweep.json")
    if not os.path.isfile(path):
        raise ValueError(f"no sweep.json in {sweep_dir}: expected a sweep directory written by "
                         "`manyworlds sweep` (sweep.json beside runs/)")
    try:
        with open(path, encoding="utf-8") as f:
            sweep = json.load(f)
    except (OSError, ValueError) as error:
        raise ValueError(f"{path} is not valid JSON ({error}): expected "
                         '{"format": 1, "name": ..., "runs": [...]}') from None
    if not isinstance(sweep, dict) or not isinstance(sweep.get("runs"), list):
        raise ValueError(f"{path} has no list 'runs': expected "
                         '{"format": 1, "name": ..., "runs": [...]}')
    if sweep.get("format") != 1:
        raise ValueError(f"{path} has format {sweep.get('format')!r}: this report reads format 1")
    if not sweep["runs"]:
        raise ValueError(f"{path} lists no runs: expected at least one entry in 'runs'")
    for index, run in enumerate(sweep["runs"]):
        if not isinstance(run, dict):
            raise ValueError(f"{path}: runs[{index}] is not an object")
        for key in ("method", "run_dir"):
            if not isinstance(run.get(key), str) or not run[key]:
                raise ValueError(f"{path}: runs[{index}] has no string '{key}'")
    return sweep


def _read_json(path: str) -> Any:
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def _number(value: Any) -> Optional[float]:
    """``value`` as a finite float, or None for null, booleans, strings and NaN."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    value = float(value)
    return value if math.isfinite(value) else None


def _check_choice(name: str, value: str, choices: Sequence[str]) -> None:
    if value not in choices:
        raise ValueError(f"{name} {value!r} is not one of {', '.join(choices)}")


def run_scores(summary: Mapping[str, Any], metric: str = "success",
               source: str = "auto") -> Tuple[str, Dict[str, float]]:
    """``(source used, {task: score})`` of one finished run's ``summary.json``.

    Raises ``ValueError`` saying why the run cannot be scored (no such evaluation, a null
    metric as in envs without a success signal).
    """
    _check_choice("metric", metric, METRICS)
    _check_choice("source", source, SOURCES)
    if source == "auto":
        source = "meta_test" if summary.get("final_meta_test") else "eval"
    evaluation = summary.get(_SUMMARY_KEY[source])
    if not isinstance(evaluation, dict) or not isinstance(evaluation.get("per_task"), dict) \
            or not evaluation["per_task"]:
        raise ValueError(f"summary.json has no {_SUMMARY_KEY[source]} with per_task scores")
    scores = {}
    for task, result in evaluation["per_task"].items():
        score = _number(result.get(metric)) if isinstance(result, dict) else None
        if score is None:
            hint = " (no success signal: score it by return)" if metric == "success" else ""
            raise ValueError(f"{_SUMMARY_KEY[source]} has no {metric} for task {task}{hint}")
        scores[task] = score
    return source, scores


def _method_source(summaries: Sequence[Mapping[str, Any]], source: str) -> str:
    """One source for all runs of a method: ``auto`` means meta_test if any run has it."""
    if source != "auto":
        return source
    return "meta_test" if any(s.get("final_meta_test") for s in summaries) else "eval"


def _describe_task_difference(run_a: str, tasks_a: Sequence[str], run_b: str,
                              tasks_b: Sequence[str]) -> str:
    def some(names: set) -> str:
        names = sorted(names)
        return ", ".join(names[:3]) + (f" and {len(names) - 3} more" if len(names) > 3 else "")
    parts = []
    if set(tasks_a) - set(tasks_b):
        parts.append(f"{run_a} has {some(set(tasks_a) - set(tasks_b))} that {run_b} lacks")
    if set(tasks_b) - set(tasks_a):
        parts.append(f"{run_b} has {some(set(tasks_b) - set(tasks_a))} that {run_a} lacks")
    return "; ".join(parts)


def scores_from_runs(sweep_dir: str, runs: Sequence[Mapping[str, Any]],
                     metric: str = "success", source: str = "auto") -> Dict[str, MethodScores]:
    """Score matrices by method (in order of first appearance) of ``sweep.json``'s ``runs``.

    Unfinished or unscorable runs are listed in ``MethodScores.missing``; a method whose
    scored runs evaluate different task sets raises ``ValueError``.
    """
    _check_choice("metric", metric, METRICS)
    _check_choice("source", source, SOURCES)
    by_method: Dict[str, List[Mapping[str, Any]]] = {}
    for run in runs:
        by_method.setdefault(run["method"], []).append(run)

    methods = {}
    for method, method_runs in by_method.items():
        missing: List[Tuple[str, str]] = []
        finished: List[Tuple[Mapping[str, Any], str, dict]] = []
        for run in method_runs:
            run_id = str(run.get("id", run["run_dir"]))
            run_dir = os.path.join(sweep_dir, run["run_dir"])
            summary_path = os.path.join(run_dir, "summary.json")
            if not os.path.isfile(summary_path):
                missing.append((run_id, "no summary.json (not finished)"))
                continue
            try:
                summary = _read_json(summary_path)
            except (OSError, ValueError):
                missing.append((run_id, "summary.json is not valid JSON"))
                continue
            if not isinstance(summary, dict) or summary.get("finished") is not True:
                missing.append((run_id, "summary.json says the run did not finish"))
                continue
            finished.append((run, run_dir, summary))

        method_source = _method_source([summary for _, _, summary in finished], source)
        run_ids, seeds, run_dirs, rows = [], [], [], []
        tasks: Optional[List[str]] = None
        for run, run_dir, summary in finished:
            run_id = str(run.get("id", run["run_dir"]))
            try:
                _, task_scores = run_scores(summary, metric, method_source)
            except ValueError as reason:
                missing.append((run_id, str(reason)))
                continue
            run_tasks = sorted(task_scores)
            if tasks is None:
                tasks = run_tasks
            elif run_tasks != tasks:
                raise ValueError(
                    f"method {method!r} scores different task sets across its runs ("
                    + _describe_task_difference(run_ids[0], tasks, run_id, run_tasks)
                    + "): every seed of a method must evaluate the same tasks")
            run_ids.append(run_id)
            seeds.append(run.get("seed"))
            run_dirs.append(run_dir)
            rows.append([task_scores[task] for task in run_tasks])
        methods[method] = MethodScores(
            method=method, group=method_runs[0].get("group"),
            source=method_source if rows else None, tasks=tasks or [], run_ids=run_ids,
            seeds=seeds, run_dirs=run_dirs,
            scores=np.array(rows, dtype=float).reshape(len(rows), len(tasks or [])),
            missing=missing)
    return methods


# ------------------------------------------------------------------------------ statistics
@contextlib.contextmanager
def _seeded_bootstrap(seed: int, *purpose: str) -> Iterator[None]:
    """Seeds the bootstrap for one computation, and puts numpy's global RNG back afterwards.

    rliable 1.2's stratified bootstraps draw their indices from numpy's global RNG
    (``np.random.choice``), not from the ``random_state`` they accept, so the global state is
    seeded here (their ``random_state`` is left unset: arch deprecates it and it would not be
    used). The seed mixes in ``purpose`` (e.g. the method's name) so that a method's
    interval does not depend on which other methods are in the sweep.
    """
    derived = zlib.crc32("\0".join((str(seed),) + purpose).encode("utf-8"))
    saved = np.random.get_state()
    np.random.seed(derived)
    try:
        yield
    finally:
        np.random.set_state(saved)


def _check_matrix(name: str, scores: Any, ndim: int = 2) -> np.ndarray:
    matrix = np.asarray(scores, dtype=float)
    if matrix.ndim != ndim or 0 in matrix.shape:
        raise ValueError(f"scores of {name!r} have shape {matrix.shape}: expected a non-empty "
                         + ("(runs, tasks)" if ndim == 2 else "(runs, tasks, steps)") + " array")
    if not np.all(np.isfinite(matrix)):
        raise ValueError(f"scores of {name!r} hold NaN or infinite values")
    return matrix


def _interval(estimate: Any, low: Any, high: Any) -> Dict[str, float]:
    return {"estimate": float(estimate), "ci_low": float(low), "ci_high": float(high)}


def _aggregate_functions(gamma: Optional[float]):
    functions = [("iqm", rly_metrics.aggregate_iqm), ("mean", rly_metrics.aggregate_mean),
                 ("median", rly_metrics.aggregate_median)]
    if gamma is not None:
        functions.append(("optimality_gap",
                          lambda scores: rly_metrics.aggregate_optimality_gap(scores, gamma)))
    return functions


def aggregate_scores(scores: Mapping[str, Any], reps: int = DEFAULT_REPS, seed: int = 0,
                     gamma: Optional[float] = 1.0,
                     confidence: float = CONFIDENCE) -> Dict[str, Dict[str, Dict[str, float]]]:
    """IQM, mean, median and optimality gap (at ``gamma``; left out when None) per method.

    ``scores``: method -> (runs, tasks) array. Returns method -> aggregate ->
    ``{"estimate", "ci_low", "ci_high"}``, the interval a stratified bootstrap over runs
    (rliable's ``get_interval_estimates``, percentile method) at ``confidence``.
    """
    functions = _aggregate_functions(gamma)

    def all_aggregates(matrix: np.ndarray) -> np.ndarray:
        return np.array([function(matrix) for _, function in functions])

    result = {}
    for method, method_scores in scores.items():
        matrix = _check_matrix(method, method_scores)
        with _seeded_bootstrap(seed, "aggregates", method):
            points, intervals = rly_library.get_interval_estimates(
                {method: matrix}, all_aggregates, reps=reps,
                confidence_interval_size=confidence)
        result[method] = {name: _interval(points[method][i], *intervals[method][:, i])
                          for i, (name, _) in enumerate(functions)}
    return result


def default_thresholds(scores: Mapping[str, Any], metric: str = "success") -> np.ndarray:
    """The score axis of the performance profiles: 0..1 for success, the observed range else."""
    if metric == "success":
        return np.linspace(0.0, 1.0, PROFILE_THRESHOLDS)
    values = np.concatenate([np.asarray(m, dtype=float).ravel() for m in scores.values()])
    low, high = float(values.min()), float(values.max())
    if high <= low:
        high = low + 1.0
    return np.linspace(low, high, PROFILE_THRESHOLDS)


def performance_profiles(scores: Mapping[str, Any], thresholds: Sequence[float],
                         reps: int = DEFAULT_REPS, seed: int = 0,
                         confidence: float = CONFIDENCE) -> Dict[str, Dict[str, List[float]]]:
    """Score distributions: per method the fraction of (run, task) scores above each threshold.

    rliable's ``create_performance_profile``; returns method -> ``{"fraction", "ci_low",
    "ci_high"}``, lists aligned with ``thresholds``.
    """
    thresholds = np.asarray(thresholds, dtype=float)
    result = {}
    for method, method_scores in scores.items():
        matrix = _check_matrix(method, method_scores)
        with _seeded_bootstrap(seed, "profiles", method):
            profiles, intervals = rly_library.create_performance_profile(
                {method: matrix}, thresholds, reps=reps, confidence_interval_size=confidence)
        result[method] = {"fraction": [float(v) for v in profiles[method]],
                          "ci_low": [float(v) for v in intervals[method][0]],
                          "ci_high": [float(v) for v in intervals[method][1]]}
    return result


def probability_of_improvement(scores: Mapping[str, Any], reps: int = DEFAULT_IMPROVEMENT_REPS,
                               seed: int = 0, confidence: float = CONFIDENCE) -> List[dict]:
    """P(X > Y) for every ordered pair of methods, with a stratified independent bootstrap CI.

    rliable's ``probability_of_improvement`` (Mann-Whitney U per task, averaged over tasks).
    Both methods must score the same tasks in the same order. Ties count one half, so
    P(Y > X) = 1 - P(X > Y) on every bootstrap sample: each unordered pair is bootstrapped
    once and mirrored. Returns ``[{"x", "y", "estimate", "ci_low", "ci_high"}, ...]``.
    """
    names = list(scores)
    matrices = {name: _check_matrix(name, scores[name]) for name in names}
    pairs = []
    for i, x in enumerate(names):
        for y in names[i + 1:]:
            if matrices[x].shape[1] != matrices[y].shape[1]:
                raise ValueError(f"methods {x!r} and {y!r} score {matrices[x].shape[1]} and "
                                 f"{matrices[y].shape[1]} tasks: probability of improvement "
                                 "compares methods on the same tasks")
            key = f"{x} > {y}"
            with _seeded_bootstrap(seed, "improvement", x, y):
                points, intervals = rly_library.get_interval_estimates(
                    {key: [matrices[x], matrices[y]]}, rly_metrics.probability_of_improvement,
                    reps=reps, confidence_interval_size=confidence)
            estimate = float(points[key])
            low, high = (float(v) for v in np.ravel(intervals[key]))
            pairs.append({"x": x, "y": y, **_interval(estimate, low, high)})
            pairs.append({"x": y, "y": x, **_interval(1.0 - estimate, 1.0 - high, 1.0 - low)})
    return pairs


def curve_scores(method_scores: MethodScores, metric: str = "success"
                 ) -> Tuple[List[int], Optional[np.ndarray], Optional[str]]:
    """``(steps, array (runs, tasks, steps), None)`` from the logs of a method's scored runs.

    Reads each run's eval.jsonl (meta_test.jsonl, meta_train.jsonl for those sources); keeps
    the steps that every run logged with a score for every task (a resumed run's repeated
    step counts once, its last row). Returns ``([], None, reason)`` when there is no curve.
    """
    if not method_scores.run_ids or method_scores.source is None:
        return [], None, "no scored run"
    file_name = _CURVE_FILE[method_scores.source]
    tasks = method_scores.tasks
    per_run: List[Dict[int, List[float]]] = []
    for run_dir in method_scores.run_dirs:
        path = os.path.join(run_dir, file_name)
        if not os.path.isfile(path):
            return [], None, f"no {file_name} in {run_dir}"
        by_step: Dict[int, List[float]] = {}
        for row in _read_jsonl(path):
            step, per_task = _number(row.get("step")), row.get("per_task")
            if step is None or not isinstance(per_task, dict):
                continue
            values = [_number(per_task[t].get(metric)) if isinstance(per_task.get(t), dict)
                      else None for t in tasks]
            if None not in values:
                by_step[int(step)] = values
        per_run.append(by_step)
    steps = sorted(set.intersection(*(set(by_step) for by_step in per_run)))
    if not steps:
        return [], None, (f"no step with a {metric} for every task is logged in every "
                          f"run's {file_name}")
    array = np.array([[by_step[step] for step in steps] for by_step in per_run], dtype=float)
    return steps, array.transpose(0, 2, 1), None


def learning_curves(curves: Mapping[str, Tuple[Sequence[int], Any]],
                    reps: int = DEFAULT_CURVE_REPS, seed: int = 0,
                    confidence: float = CONFIDENCE) -> Dict[str, Dict[str, List[float]]]:
    """IQM over (run, task) at each logged step, with stratified-bootstrap CIs.

    ``curves``: method -> (steps, array (runs, tasks, steps)). Returns method ->
    ``{"steps", "iqm", "ci_low", "ci_high"}``.
    """
    def iqm_per_step(array: np.ndarray) -> np.ndarray:
        return np.array([rly_metrics.aggregate_iqm(array[..., i]) for i in range(array.shape[-1])])

    result = {}
    for method, (steps, method_curve) in curves.items():
        array = _check_matrix(method, method_curve, ndim=3)
        if array.shape[-1] != len(steps):
            raise ValueError(f"curve of {method!r} has {array.shape[-1]} points for "
                             f"{len(steps)} steps")
        with _seeded_bootstrap(seed, "curves", method):
            points, intervals = rly_library.get_interval_estimates(
                {method: array}, iqm_per_step, reps=reps, confidence_interval_size=confidence)
        result[method] = {"steps": [int(s) for s in steps],
                          "iqm": [float(v) for v in points[method]],
                          "ci_low": [float(v) for v in intervals[method][0]],
                          "ci_high": [float(v) for v in intervals[method][1]]}
    return result


# ------------------------------------------------------------------------------ writing files
def _write_atomic(path: str, data: bytes) -> None:
    """Writes via a temp file in the same directory, then os.replace: no reader sees half a file."""
    directory, name = os.path.split(path)
    fd, tmp = tempfile.mkstemp(dir=directory, prefix=f".{name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _csv_text(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> bytes:
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(rows)
    return out.getvalue().encode("utf-8")


def _md_cell(text: str) -> str:
    return str(text).replace("|", "\\|")


def _md_table(header: Sequence[str], rows: Sequence[Sequence[str]], left: int = 1) -> str:
    """A Markdown table: the first ``left`` columns (names) left-aligned, numbers right."""
    lines = ["| " + " | ".join(map(_md_cell, header)) + " |",
             "|" + "|".join(["---"] * left + ["---:"] * (len(header) - left)) + "|"]
    lines += ["| " + " | ".join(map(_md_cell, row)) + " |" for row in rows]
    return "\n".join(lines)


def _summary_markdown(report: dict) -> str:
    digits = 2 if report["metric"] == "success" else 1

    def fmt(value: float) -> str:
        return f"{value:.{digits}f}"

    def with_ci(interval: Mapping[str, float]) -> str:
        return (f"{fmt(interval['estimate'])} [{fmt(interval['ci_low'])}, "
                f"{fmt(interval['ci_high'])}]")

    methods = report["methods"]
    aggregates = [name for name in AGGREGATES
                  if any(m["aggregates"] and name in m["aggregates"] for m in methods.values())]
    score_name = "success rate" if report["metric"] == "success" else "return"
    percent = f"{100 * report['confidence']:g} %"
    sources = ", ".join(sorted(set(m["source"] for m in methods.values() if m["source"])))
    lines = [f"# Sweep {report['sweep']}: final {score_name}", "",
             f"{report['runs_finished']} of {report['runs_total']} runs finished and scored. "
             f"Each run's score on a task is its final {score_name} ({sources}); aggregates "
             f"are over all (seed, task) scores of a method; each cell is estimate [{percent} "
             f"stratified-bootstrap confidence interval] (rliable, {report['reps']:,} "
             f"repetitions, seed {report['seed']}).", ""]
    header = ["Method"] + [AGGREGATE_TITLES[a] + (f" [{percent} CI]" if a == "iqm" else "")
                           for a in aggregates] + ["Runs"]
    rows = []
    for name, method in methods.items():
        cells = [with_ci(method["aggregates"][a]) if method["aggregates"] else "—"
                 for a in aggregates]
        rows.append([name] + cells + [f"{method['runs_finished']} of {method['runs_total']}"])
    lines += [_md_table(header, rows), ""]
    if report["metric"] == "return" and "optimality_gap" not in aggregates:
        lines += ["Optimality gap is left out: returns have no natural optimum "
                  "(give a target return to report it).", ""]

    scored = {name: m for name, m in methods.items() if m["per_task"]}
    if scored:
        tasks = sorted({task for m in scored.values() for task in m["per_task"]})
        lines += [f"## Per-task {score_name} (mean ± std over seeds)", ""]
        rows = []
        for task in tasks:
            row = [task]
            for method in scored.values():
                cell = method["per_task"].get(task)
                row.append(f"{fmt(cell['mean'])} ± {fmt(cell['std'])}" if cell else "—")
            rows.append(row)
        lines += [_md_table(["Task"] + list(scored), rows), ""]

    if report["probability_of_improvement"]:
        lines += ["## Probability of improvement", "",
                  "P(X > Y): the probability that a run of X scores higher than a run of Y on "
                  "a task drawn at random (ties count one half).", ""]
        rows = [[p["x"], p["y"], with_ci(p)] for p in report["probability_of_improvement"]]
        lines += [_md_table(["X", "Y", f"P(X > Y) [{percent} CI]"], rows, left=2), ""]
    lines += [f"Note: {note}" for note in report["notes"]] + ([""] if report["notes"] else [])
    missing = [(name, run_id, reason) for name, m in methods.items()
               for run_id, reason in ((r["id"], r["reason"]) for r in m["runs_missing"])]
    if missing:
        lines += ["## Runs left out", ""]
        lines += [f"- {run_id} ({name}): {reason}" for name, run_id, reason in missing]
    return "\n".join(lines).rstrip("\n") + "\n"


# ------------------------------------------------------------------------------ plots
def _pyplot():
    """pyplot on the Agg backend unless the caller already chose a backend (e.g. a notebook)."""
    import matplotlib
    if "matplotlib.pyplot" not in sys.modules:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _save_figure(figure, out_dir: str, stem: str) -> List[str]:
    paths = []
    for fmt in _PLOT_FORMATS:
        buffer = io.BytesIO()
        # No date in the SVG, fixed ids: the same report gives the same file.
        metadata = {"Date": None} if fmt == "svg" else {"Software": None}
        with _pyplot().rc_context({"svg.hashsalt": "manyworlds"}):
            figure.savefig(buffer, format=fmt, bbox_inches="tight", dpi=120, metadata=metadata)
        path = os.path.join(out_dir, f"{stem}.{fmt}")
        _write_atomic(path, buffer.getvalue())
        paths.append(path)
    _pyplot().close(figure)
    return paths


def _method_colors(names: Sequence[str]) -> Dict[str, Any]:
    import seaborn  # rliable's plots depend on it; the same palette keeps colours consistent
    return dict(zip(names, seaborn.color_palette("colorblind", n_colors=max(len(names), 1))))


def _plot_everything(report: dict, out_dir: str) -> List[str]:
    plt = _pyplot()
    from rliable import plot_utils

    score_label = "Success rate" if report["metric"] == "success" else "Return"
    methods = {n: m for n, m in report["methods"].items() if m["aggregates"]}
    colors = _method_colors(list(methods))
    written = []

    figure, axis = plt.subplots(figsize=(7, 5))
    drawn = False
    for name, method in methods.items():
        curve = method["curve"]
        if not curve:
            continue
        plot_utils.plot_sample_efficiency_curve(
            np.array(curve["steps"]), {name: np.array(curve["iqm"])},
            {name: np.array([curve["ci_low"], curve["ci_high"]])}, algorithms=[name],
            colors=colors, ax=axis, xlabel="Step (env steps per env)",
            ylabel=f"IQM {score_label.lower()}", labelsize="large", ticklabelsize="medium")
        drawn = True
    if drawn:
        axis.legend(fontsize="medium")
    else:
        axis.text(0.5, 0.5, "no curve: see report.json", ha="center", transform=axis.transAxes)
    written += _save_figure(figure, out_dir, "curves")

    names = list(methods)
    aggregate_names = [a for a in AGGREGATES if a in methods[names[0]]["aggregates"]]
    points = {n: np.array([methods[n]["aggregates"][a]["estimate"] for a in aggregate_names])
              for n in names}
    intervals = {n: np.array([[methods[n]["aggregates"][a]["ci_low"] for a in aggregate_names],
                              [methods[n]["aggregates"][a]["ci_high"] for a in aggregate_names]])
                 for n in names}
    # At least 1.5 in tall, and the x label half an inch under the axes (rliable puts it at a
    # fixed fraction of the height, which lands on the tick labels of a short figure).
    row_height = max(0.6, 1.5 / len(names))
    figure, _ = plot_utils.plot_interval_estimates(
        points, intervals, metric_names=[AGGREGATE_TITLES[a] for a in aggregate_names],
        algorithms=names, colors=colors, xlabel=score_label, row_height=row_height,
        subfigure_width=3.4, xlabel_y_coordinate=-0.5 / (row_height * len(names)))
    written += _save_figure(figure, out_dir, "aggregates")

    profile = report["performance_profile"]
    figure, axis = plt.subplots(figsize=(7, 5))
    plot_utils.plot_performance_profiles(
        {n: np.array(profile["methods"][n]["fraction"]) for n in names},
        np.array(profile["thresholds"]),
        performance_profile_cis={n: (np.array(profile["methods"][n]["ci_low"]),
                                     np.array(profile["methods"][n]["ci_high"])) for n in names},
        colors=colors, ax=axis, xlabel=f"{score_label} (τ)",
        ylabel=r"Fraction of (run, task) scores $> \tau$", labelsize="large",
        ticklabelsize="medium")
    axis.legend(fontsize="medium")
    written += _save_figure(figure, out_dir, "profiles")

    # One bar per unordered pair (X listed first in the sweep), as rliable draws them.
    pairs = [p for p in report["probability_of_improvement"]
             if names.index(p["x"]) < names.index(p["y"])] if len(names) > 1 else []
    if pairs:
        separator = next(s for s in (" > ", " >> ", "\x1f") if all(s not in n for n in names))
        figure, axis = plt.subplots(figsize=(5, 0.6 + 0.5 * len(pairs)))
        plot_utils.plot_probability_of_improvement(
            {p["x"] + separator + p["y"]: p["estimate"] for p in pairs},
            {p["x"] + separator + p["y"]: (p["ci_low"], p["ci_high"]) for p in pairs},
            pair_separator=separator, ax=axis, xticks=[0.0, 0.25, 0.5, 0.75, 1.0],
            ticklabelsize="medium", labelsize="medium")
        axis.set_xlim(0.0, 1.0)
        written += _save_figure(figure, out_dir, "improvement")
    else:  # one method (or none comparable): no pairs, and no plot left from an earlier report
        for fmt in _PLOT_FORMATS:
            with contextlib.suppress(FileNotFoundError):
                os.remove(os.path.join(out_dir, f"improvement.{fmt}"))
    return written


# ------------------------------------------------------------------------------ the report
def _json_ready(value: Any) -> Any:
    """Plain JSON: numpy scalars as Python numbers, NaN/inf as null."""
    if isinstance(value, dict):
        return {str(k): _json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_ready(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def write_report(sweep_dir: str, out_dir: Optional[str] = None, metric: str = "success",
                 source: str = "auto", reps: int = DEFAULT_REPS, seed: int = 0,
                 target: Optional[float] = None, curve_reps: int = DEFAULT_CURVE_REPS,
                 improvement_reps: int = DEFAULT_IMPROVEMENT_REPS,
                 confidence: float = CONFIDENCE, plots: bool = True) -> dict:
    """Writes the report of the sweep in ``sweep_dir`` into ``out_dir`` (SWEEP_DIR/report/).

    ``metric``: "success" or "return"; ``source``: "auto" (meta_test where a run has it,
    else eval), "eval", "meta_test" or "meta_train"; ``reps``: bootstrap repetitions of the
    final-score aggregates and profiles, ``curve_reps`` / ``improvement_reps`` those of the
    curves and the probability of improvement; ``seed``: the bootstraps' seed; ``target``:
    the return counted as optimal in the optimality gap (metric "return" only).
    Returns the dict written to report.json.
    """
    _check_choice("metric", metric, METRICS)
    _check_choice("source", source, SOURCES)
    if target is not None and metric != "return":
        raise ValueError("target is the optimal return of the optimality gap: it needs metric "
                         "'return' (success rates use 1)")
    for name, value in (("reps", reps), ("curve_reps", curve_reps),
                        ("improvement_reps", improvement_reps)):
        if int(value) < 1:
            raise ValueError(f"{name} must be at least 1, not {value}")
    sweep = load_sweep(sweep_dir)
    method_scores = scores_from_runs(sweep_dir, sweep["runs"], metric, source)
    runs_total = sum(m.total_runs for m in method_scores.values())
    runs_finished = sum(len(m.run_ids) for m in method_scores.values())
    if runs_finished == 0:
        reasons = Counter(reason for m in method_scores.values() for _, reason in m.missing)
        reason, count = reasons.most_common(1)[0]
        raise ValueError(f"no run to score in {sweep_dir}: 0 of {runs_total} runs finished "
                         f"with {metric} scores ({count} runs: {reason})")

    scored = {name: m.scores for name, m in method_scores.items() if m.run_ids}
    gamma = 1.0 if metric == "success" else target
    aggregates = aggregate_scores(scored, reps=reps, seed=seed, gamma=gamma,
                                  confidence=confidence)
    thresholds = default_thresholds(scored, metric)
    profiles = performance_profiles(scored, thresholds, reps=reps, seed=seed,
                                    confidence=confidence)

    notes = []
    by_tasks: Dict[Tuple[str, ...], Dict[str, np.ndarray]] = {}
    for name in scored:
        by_tasks.setdefault(tuple(method_scores[name].tasks), {})[name] = scored[name]
    improvement = []
    for group in by_tasks.values():
        improvement += probability_of_improvement(group, reps=improvement_reps, seed=seed,
                                                  confidence=confidence)
    if len(by_tasks) > 1:
        notes.append("methods score different task sets; probability of improvement compares "
                     "only methods with the same tasks")

    curve_inputs, curve_reasons = {}, {}
    for name in scored:
        steps, array, reason = curve_scores(method_scores[name], metric)
        if array is None:
            curve_reasons[name] = reason
        else:
            curve_inputs[name] = (steps, array)
    curves = learning_curves(curve_inputs, reps=curve_reps, seed=seed, confidence=confidence)

    methods_report = {}
    for name, m in method_scores.items():
        per_task = {}
        for j, task in enumerate(m.tasks):
            column = m.scores[:, j]
            per_task[task] = {"mean": float(column.mean()),
                              "std": float(column.std(ddof=1)) if len(column) > 1 else 0.0,
                              "n": int(len(column))}
        methods_report[name] = {
            "group": m.group, "source": m.source, "tasks": list(m.tasks),
            "runs_total": m.total_runs, "runs_finished": len(m.run_ids),
            "runs_missing": [{"id": run_id, "reason": reason} for run_id, reason in m.missing],
            "aggregates": aggregates.get(name),
            "per_task": per_task,
            "runs": [{"id": run_id, "seed": seed_value,
                      "run_dir": os.path.relpath(run_dir, sweep_dir),
                      "scores": dict(zip(m.tasks, map(float, m.scores[i])))}
                     for i, (run_id, seed_value, run_dir)
                     in enumerate(zip(m.run_ids, m.seeds, m.run_dirs))],
            "curve": curves.get(name),
            "curve_missing": curve_reasons.get(name),
        }

    out_dir = out_dir or os.path.join(sweep_dir, "report")
    os.makedirs(out_dir, exist_ok=True)
    report = {
        "format": 1, "sweep": sweep.get("name") or os.path.basename(os.path.abspath(sweep_dir)),
        "sweep_dir": os.path.abspath(sweep_dir), "metric": metric, "source": source,
        "reps": int(reps), "curve_reps": int(curve_reps),
        "improvement_reps": int(improvement_reps), "seed": int(seed),
        "confidence": float(confidence), "target": target,
        "optimality_gap_gamma": gamma,
        "runs_total": runs_total, "runs_finished": runs_finished,
        "methods": methods_report,
        "performance_profile": {"thresholds": [float(t) for t in thresholds],
                                "methods": profiles},
        "probability_of_improvement": improvement,
        "notes": notes,
    }
    report = _json_ready(report)

    files = ["report.json", "scores.csv", "aggregates.csv", "summary.md"]
    _write_atomic(os.path.join(out_dir, "scores.csv"), _csv_text(
        ["method", "run", "seed", "task", "score"],
        [[name, run_id, "" if seed_value is None else seed_value, task, repr(float(score))]
         for name, m in method_scores.items()
         for run_id, seed_value, row in zip(m.run_ids, m.seeds, m.scores)
         for task, score in zip(m.tasks, row)]))
    _write_atomic(os.path.join(out_dir, "aggregates.csv"), _csv_text(
        ["method", "metric", "estimate", "ci_low", "ci_high"],
        [[name, aggregate, repr(v["estimate"]), repr(v["ci_low"]), repr(v["ci_high"])]
         for name, per_method in aggregates.items() for aggregate, v in per_method.items()]))
    _write_atomic(os.path.join(out_dir, "summary.md"),
                  _summary_markdown(report).encode("utf-8"))
    if plots:
        files += [os.path.basename(p) for p in _plot_everything(report, out_dir)]
    report["files"] = files
    _write_atomic(os.path.join(out_dir, "report.json"),
                  (json.dumps(report, indent=1, allow_nan=False) + "\n").encode("utf-8"))
    return report
