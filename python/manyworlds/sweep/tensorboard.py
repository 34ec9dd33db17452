"""A run's logged scalars as TensorBoard event files, written by tensorboardX.

``manyworlds train`` logs JSON lines; this turns them into event files so that
``tensorboard --logdir SWEEP_DIR/runs`` (or ``--logdir RUN_DIR``) shows every run::

    from manyworlds.sweep.tensorboard import export_run, export_sweep
    export_run("runs/mt10_mtsac")        # writes runs/mt10_mtsac/tensorboard/events.out.tfevents.*
    export_sweep("sweeps/mt10")          # every run directory under sweeps/mt10/runs

Tags, with the row's ``step`` as the x axis:

- ``metrics.jsonl`` -> ``train/<key>`` (``train/train_return``, ``train/actor_loss``, ...)
- ``eval.jsonl`` -> ``eval/mean_success``, ``eval/mean_return``, ``eval/<task>/success``,
  ``eval/<task>/return``, ... (``per_task`` is dropped from the tags, other nested objects
  are flattened with ``/``)
- ``meta_test.jsonl`` / ``meta_train.jsonl`` -> ``meta_test/success_rate``,
  ``meta_test/<task>/success``, ...

Only finite numbers are written (null, booleans, strings and NaN are skipped), as float32
``simple_value`` scalars, the form every TensorBoard reads. Exporting is idempotent: the new
event file replaces those of an earlier export in the same logdir, so it can run after every
run and again after a resume. Rows without a numeric ``step`` and lines cut short by a crash
are skipped.
"""

from __future__ import annotations

import contextlib
import glob
import math
import os
import re
import shutil
import tempfile
from typing import Any, Iterator, List, Optional, Tuple

from manyworlds.sweep.runner import read_jsonl

try:
    from tensorboardX import SummaryWriter
except ImportError as error:  # pragma: no cover - depends on the environment
    raise ImportError("manyworlds.sweep.tensorboard needs tensorboardX (pip install tensorboardX); "
                      f"importing it failed: {error}") from error

__all__ = ["LOG_FILES", "EVENT_FILE_PATTERN", "scalars_of_row", "export_run", "export_sweep"]

# log file -> tag prefix, in the order they are written
LOG_FILES = (("metrics.jsonl", "train"), ("eval.jsonl", "eval"),
             ("meta_test.jsonl", "meta_test"), ("meta_train.jsonl", "meta_train"))
EVENT_FILE_PATTERN = "events.out.tfevents.*"
DEFAULT_LOGDIR_NAME = "tensorboard"
# Characters TensorBoard does not take in a tag; tensorboardX would replace them with "_" and
# log a message for each value, so tags are cleaned here once, the same way.
_TAG_UNSAFE = re.compile(r"[^-/\w.]")


def _finite_number(value: Any) -> Optional[float]:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    value = float(value)
    return value if math.isfinite(value) else None


def scalars_of_row(row: dict, prefix: str) -> Iterator[Tuple[str, float]]:
    """``(tag, value)`` of every finite number in a log row, nested keys joined by ``/``.

    The ``step`` key is the x axis, not a scalar; a nested object's own ``step`` is kept.
    The tasks of a row's ``per_task`` object go right under ``prefix`` (``eval/<task>/success``).
    Characters other than letters, digits, ``_ - . /`` become ``_`` in tags.
    """
    def walk(node: dict, path: str, top: bool) -> Iterator[Tuple[str, float]]:
        for key, value in node.items():
            if top and key == "step":
                continue
            if top and key == "per_task" and isinstance(value, dict):
                # eval/<task>/success rather than eval/per_task/<task>/success
                yield from walk(value, path, False)
                continue
            tag = f"{path}/{_TAG_UNSAFE.sub('_', str(key))}"
            if isinstance(value, dict):
                yield from walk(value, tag, False)
            else:
                number = _finite_number(value)
                if number is not None:
                    yield tag, number
    yield from walk(row, prefix, True)


def _rows(path: str) -> Iterator[Tuple[int, dict]]:
    """``(step, row)`` of a .jsonl file; unparsable lines and rows without a step are skipped."""
    for row in read_jsonl(path):
        step = _finite_number(row.get("step"))
        if step is not None:
            yield int(step), row


def _log_paths(run_dir: str) -> List[Tuple[str, str]]:
    return [(os.path.join(run_dir, name), prefix) for name, prefix in LOG_FILES
            if os.path.isfile(os.path.join(run_dir, name))]


def export_run(run_dir: str, logdir: Optional[str] = None) -> str:
    """Writes the run's scalars to one event file in ``logdir`` (RUN_DIR/tensorboard/).

    Returns the event file's path. Event files of an earlier export in ``logdir`` are
    removed once the new one is in place. Raises ``ValueError`` when ``run_dir`` holds none
    of metrics.jsonl, eval.jsonl, meta_test.jsonl, meta_train.jsonl.
    """
    logs = _log_paths(run_dir)
    if not logs:
        raise ValueError(f"no {', '.join(name for name, _ in LOG_FILES)} in {run_dir}: "
                         "expected a manyworlds run directory")
    logdir = logdir or os.path.join(run_dir, DEFAULT_LOGDIR_NAME)
    os.makedirs(logdir, exist_ok=True)
    # Written in a private folder first: a reader never sees a half-written file beside the
    # old one, and the new file's name cannot be confused with an old one's.
    staging = tempfile.mkdtemp(dir=logdir, prefix=".export-")
    try:
        writer = SummaryWriter(logdir=staging, flush_secs=3600)
        try:
            for path, prefix in logs:
                for step, row in _rows(path):
                    for tag, value in scalars_of_row(row, prefix):
                        writer.add_scalar(tag, value, global_step=step)
        finally:
            writer.close()
        written = glob.glob(os.path.join(staging, EVENT_FILE_PATTERN))
        if len(written) != 1:
            raise RuntimeError(f"tensorboardX wrote {len(written)} event files, expected one")
        event_file = os.path.join(logdir, os.path.basename(written[0]))
        os.replace(written[0], event_file)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    for old in glob.glob(os.path.join(logdir, EVENT_FILE_PATTERN)):
        if os.path.abspath(old) != os.path.abspath(event_file):
            with contextlib.suppress(FileNotFoundError):
                os.remove(old)
    return event_file


def export_sweep(sweep_dir: str) -> List[str]:
    """Exports every run directory under SWEEP_DIR/runs that holds a log; returns the event files.

    Each run's events go to its own RUN_DIR/tensorboard/, so ``tensorboard --logdir
    SWEEP_DIR/runs`` lists the runs by their directory.
    """
    runs_root = os.path.join(sweep_dir, "runs")
    if not os.path.isdir(runs_root):
        raise ValueError(f"no runs/ in {sweep_dir}: expected a sweep directory")
    event_files = []
    for directory, subdirectories, _ in os.walk(runs_root):
        # A run's own tensorboard/ and checkpoints/ hold no logs to export.
        subdirectories[:] = sorted(d for d in subdirectories
                                   if d not in (DEFAULT_LOGDIR_NAME, "checkpoints")
                                   and not d.startswith("."))
        if _log_paths(directory):
            event_files.append(export_run(directory))
    return event_files
