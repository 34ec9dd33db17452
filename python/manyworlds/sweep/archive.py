"""A sweep's finished runs without their checkpoints: small enough to keep in a repository,
whole enough that `report` scores them and `run --resume` leaves them finished.

A run keeps its config, summary and logs (config.yaml, summary.json, and eval, metrics,
meta_test and meta_train .jsonl); its checkpoints (replay buffers: 150 MB for an MT10 run at
40,000 steps per task), its task states (tasks.json, which the program writes again), the CSV
copies of its .jsonl files and its TensorBoard files stay behind. The sweep keeps sweep.json
and each archived run's log. Runs that have not finished are not archived, so an archive
continued with `run --resume` (after copying it back) runs them from the start unless their
directories are copied along.
"""

from __future__ import annotations

import json
import pathlib
from typing import Any

from manyworlds.sweep.runner import MANIFEST, SweepError, run_state, write_atomically

RUN_FILES = ("config.yaml", "summary.json", "eval.jsonl", "metrics.jsonl", "meta_test.jsonl",
             "meta_train.jsonl")


def _copy_atomically(source: pathlib.Path, target: pathlib.Path) -> None:
    try:
        data = source.read_bytes()  # a run's logs: kilobytes
        if target.is_file() and target.read_bytes() == data:
            return  # archived before: archiving again as the sweep goes on rewrites nothing
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise SweepError(f"cannot copy {source} to {target}: {error.strerror}") from None
    write_atomically(target, data)


def archive_sweep(sweep_dir: str | pathlib.Path, out_dir: str | pathlib.Path) -> dict[str, Any]:
    """Copies SWEEP_DIR's manifest and finished runs (RUN_FILES, logs) into OUT_DIR.

    Returns {"archived": [run ids], "unfinished": [run ids]}. Files already in OUT_DIR are
    replaced where they differ, others left, so archiving a sweep again as it goes on adds its
    newly finished runs."""
    sweep_dir, out_dir = pathlib.Path(sweep_dir), pathlib.Path(out_dir)
    manifest_path = sweep_dir / MANIFEST
    try:
        manifest = json.loads(manifest_path.read_text())
        runs = manifest["runs"]
        ids = [(run["id"], run["run_dir"]) for run in runs]
    except FileNotFoundError:
        raise SweepError(f"{sweep_dir} is not a sweep directory (no {MANIFEST})") from None
    except (OSError, ValueError, KeyError, TypeError) as error:
        raise SweepError(f"{manifest_path} is unreadable or damaged: {error}") from None
    if out_dir.resolve() == sweep_dir.resolve() or sweep_dir.resolve() in out_dir.resolve().parents:
        raise SweepError(f"the archive {out_dir} must lie outside the sweep {sweep_dir}")
    archived, unfinished = [], []
    for run_id, run_dir in ids:
        source = sweep_dir / run_dir
        if run_state(source) != "finished":
            unfinished.append(run_id)
            continue
        for name in RUN_FILES:
            if (source / name).is_file():
                _copy_atomically(source / name, out_dir / run_dir / name)
        log = sweep_dir / "logs" / f"{run_id}.log"
        if log.is_file():
            _copy_atomically(log, out_dir / "logs" / f"{run_id}.log")
        archived.append(run_id)
    _copy_atomically(manifest_path, out_dir / MANIFEST)
    return {"archived": archived, "unfinished": unfinished}
