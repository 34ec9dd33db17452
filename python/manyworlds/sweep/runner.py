"""Runs a sweep's training runs on Ray, each as `manyworlds train` in its own run directory.

    SWEEP_DIR/sweep.json       the expanded runs (spec.Sweep.manifest()); written once
    SWEEP_DIR/runs/M/seed_N/   one manyworlds run directory per run
    SWEEP_DIR/logs/M/seed_N.log  the program's output, every attempt appended
    SWEEP_DIR/attempts.jsonl   one line per launch and per exit: what ran where
    SWEEP_DIR/.sweep.lock      held by the sweep's driver: one driver per sweep directory

The run directories are the sweep's state: a run whose summary.json says finished is done, one
with a config.yaml continues with `train --resume` (from its newest intact checkpoint, or, if it
never wrote one, `--resume --restart`), any other starts. So a retried task (its worker or node
died: Ray reschedules it, up to `max_retries` times) and a resumed sweep (its driver died:
`manyworlds-sweep run SWEEP.yaml --resume`) lose at most the work since a run's last checkpoint,
never run a finished run again, and end with the numbers of an uninterrupted run, since
manyworlds resumes exactly.

Each `manyworlds train` is a child of its Ray worker that gets SIGTERM when the worker dies
(Linux's parent-death signal), so a killed worker or node leaves no orphan training on: the
program checkpoints and stops, and its run lock (flock, released when it exits) lets the retry in.
"""

from __future__ import annotations

import ctypes
import fcntl
import json
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import time
from typing import Any, Callable, Mapping, Sequence

from manyworlds.sweep import spec as spec_module

ATTEMPTS = "attempts.jsonl"
MANIFEST = "sweep.json"
LOCK = ".sweep.lock"
# How long a launch waits for a run directory's lock (a killed predecessor still checkpointing).
LOCK_WAIT_S = 120.0


class SweepError(Exception):
    """A sweep that cannot start or continue; the message is one line."""


def find_cli(cli: str | None = None) -> str:
    """The `manyworlds` program: `cli`, else $MANYWORLDS_CLI, else on PATH, else build/manyworlds."""
    for candidate in (cli, os.environ.get("MANYWORLDS_CLI"), shutil.which("manyworlds"),
                      "build/manyworlds"):
        if candidate and os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return os.path.abspath(candidate)
        if candidate == cli and cli:
            raise SweepError(f"--cli {cli}: not an executable file")
    raise SweepError("the manyworlds program was not found: pass --cli PATH, set $MANYWORLDS_CLI, "
                     "put it on PATH or run from a checkout with build/manyworlds")


def write_atomically(path: pathlib.Path, data: str | bytes) -> None:
    tmp = path.with_name(f".{path.name}.tmp.{os.getpid()}")
    try:
        with open(tmp, "wb" if isinstance(data, bytes) else "w") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except OSError as error:
        tmp.unlink(missing_ok=True)
        raise SweepError(f"cannot write {path}: {error.strerror}") from None


def read_summary(run_dir: pathlib.Path) -> dict[str, Any] | None:
    try:
        return json.loads((run_dir / "summary.json").read_text())
    except (OSError, ValueError):
        return None


def run_state(run_dir: pathlib.Path) -> str:
    """'finished', 'started' (a run directory to resume) or 'new'."""
    summary = read_summary(run_dir)
    if summary is not None and summary.get("finished") is True:
        return "finished"
    return "started" if (run_dir / "config.yaml").is_file() else "new"


def resolved_config(cli: str, run: spec_module.Run, sweep_dir: pathlib.Path) -> dict[str, Any]:
    """The run's config as `manyworlds train --print-config` resolves and validates it."""
    command = [cli, "train", run.config, *run.command_overrides(sweep_dir), "--print-config"]
    done = subprocess.run(command, capture_output=True, text=True, timeout=120)
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines() or [f"exit code {done.returncode}"]
        raise SweepError(f"{run.method}: {lines[-1]}")
    return json.loads(done.stdout)


def _set_parent_death_signal() -> None:
    """In the child, before exec: SIGTERM when the worker that launched it dies."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        pr_set_pdeathsig = 1
        libc.prctl(pr_set_pdeathsig, signal.SIGTERM)
    except (OSError, AttributeError):
        pass  # not Linux: a dying worker may leave its training running


def _append_line(path: pathlib.Path, record: dict[str, Any]) -> None:
    # one write() of one line with O_APPEND: lines of concurrent runs do not interleave
    line = (json.dumps(record, sort_keys=True) + "\n").encode()
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
    try:
        os.write(fd, line)
    finally:
        os.close(fd)


def _wait_for_run_lock(run_dir: pathlib.Path, timeout_s: float) -> None:
    """Returns once no process holds RUN_DIR/.lock (or there is none); SweepError on timeout."""
    lock = run_dir / ".lock"
    deadline = time.monotonic() + timeout_s
    while True:
        try:
            fd = os.open(lock, os.O_RDONLY)
        except FileNotFoundError:
            return
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return  # released when fd closes, just below
        except BlockingIOError:
            pass
        finally:
            os.close(fd)
        if time.monotonic() > deadline:
            raise SweepError(f"{run_dir} is in use by another process (its .lock is held) for "
                             f"over {timeout_s:.0f} s: is another sweep or `manyworlds train` "
                             f"writing it?")
        time.sleep(0.5)


def train_run(cli: str, run_json: dict[str, Any], sweep_dir: str,
              node_id: str = "") -> dict[str, Any]:
    """Brings one run to its end: starts, resumes or leaves it (finished). Returns its summary.

    The body of the sweep's Ray task, usable without Ray too. Raises SweepError when the
    program fails (exit code and its last error line)."""
    run = spec_module.Run.from_json(run_json)
    sweep_path = pathlib.Path(sweep_dir)
    run_dir = sweep_path / run.run_dir
    log_path = sweep_path / "logs" / f"{run.id}.log"
    log_path.parent.mkdir(parents=True, exist_ok=True)
    attempts = sweep_path / ATTEMPTS
    state = run_state(run_dir)
    if state == "finished":
        return read_summary(run_dir)
    _wait_for_run_lock(run_dir, LOCK_WAIT_S)
    state = run_state(run_dir)  # the predecessor may have finished meanwhile
    if state == "finished":
        return read_summary(run_dir)
    actions = ["start"] if state == "new" else ["resume", "restart"]
    for action in actions:
        if action == "start":
            command = [cli, "train", run.config, *run.command_overrides(sweep_path)]
        else:
            command = [cli, "train", "--resume", str(run_dir)]
            if action == "restart":
                command.append("--restart")
        _append_line(attempts, {"run": run.id, "event": action, "node": node_id,
                                "host": os.uname().nodename, "worker_pid": os.getpid(),
                                "time": time.time()})
        with open(log_path, "ab") as log:
            log.write(f"== {action}: {' '.join(command)}\n".encode())
            log.flush()
            child = subprocess.Popen(command, stdout=log, stderr=subprocess.PIPE,
                                     preexec_fn=_set_parent_death_signal)
            _append_line(attempts, {"run": run.id, "event": "pid", "pid": child.pid,
                                    "time": time.time()})
            try:
                _, err = child.communicate()
            except BaseException:
                # the task is being cancelled: the program checkpoints on SIGTERM and stops
                child.terminate()
                child.wait()
                raise
            log.write(err)
        _append_line(attempts, {"run": run.id, "event": "exit", "code": child.returncode,
                                "time": time.time()})
        if child.returncode == 0:
            break
        message = err.decode(errors="replace").strip().splitlines()
        last = message[-1] if message else ""
        # a run that never reached a checkpoint: `--resume` says to add --restart
        if action == "resume" and child.returncode == 2 and "--restart" in last:
            continue
        raise SweepError(f"{run.id}: manyworlds train exited with code {child.returncode}: "
                         f"{last or 'no message'} (log: {log_path})")
    summary = read_summary(run_dir)
    if summary is None or summary.get("finished") is not True:
        raise SweepError(f"{run.id}: manyworlds train ended without a finished summary.json "
                         f"(log: {log_path})")
    try:
        from manyworlds.sweep import tensorboard
        tensorboard.export_run(run_dir)
    except ImportError:
        pass  # tensorboardX is part of the sweep extra; without it no event files
    return summary


class SweepLock:
    """flock on SWEEP_DIR/.sweep.lock for the driver's lifetime: one driver per sweep."""

    def __init__(self, sweep_dir: pathlib.Path):
        self.fd = os.open(sweep_dir / LOCK, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(self.fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(self.fd, 32, 0).decode(errors="replace").strip()
            os.close(self.fd)
            raise SweepError(f"{sweep_dir} is in use by another sweep driver"
                             f"{f' (pid {holder})' if holder else ''}; wait for it or stop it, "
                             f"then continue with --resume") from None
        os.ftruncate(self.fd, 0)
        os.pwrite(self.fd, f"{os.getpid()}\n".encode(), 0)

    def close(self) -> None:
        os.close(self.fd)


def _portable(runs: Any) -> Any:
    """The runs of a manifest as a resumed sweep compares them: each config by its file name,
    so that a sweep directory copied to another checkout or machine resumes there (the program
    reads the config from the sweep file's folder either way)."""
    if not isinstance(runs, list):
        return runs
    return [{**run, "config": pathlib.PurePath(str(run.get("config", ""))).name}
            if isinstance(run, dict) else run for run in runs]


def prepare(sweep: spec_module.Sweep, sweep_dir: pathlib.Path, resume: bool) -> None:
    """Creates SWEEP_DIR and its manifest, or checks that a resumed sweep is the same sweep."""
    manifest_path = sweep_dir / MANIFEST
    manifest = sweep.manifest()
    if manifest_path.exists():
        if not resume:
            raise SweepError(f"{sweep_dir} already holds a sweep; continue it with --resume or "
                             f"choose another --out")
        try:
            stored = json.loads(manifest_path.read_text())
        except (OSError, ValueError) as error:
            raise SweepError(f"{manifest_path} is unreadable or damaged: {error}") from None
        if _portable(stored.get("runs")) != _portable(manifest["runs"]):
            stored_ids = [r.get("id") for r in stored.get("runs", []) if isinstance(r, dict)]
            ours = [r["id"] for r in manifest["runs"]]
            differ = sorted(set(stored_ids) ^ set(ours)) or ["(same runs, other settings)"]
            raise SweepError(f"{sweep_dir} holds another sweep (its runs differ, e.g. "
                             f"{differ[0]}); resume it with the sweep file that made it")
        return
    if resume:
        raise SweepError(f"{sweep_dir} holds no sweep to resume (no {MANIFEST})")
    write_atomically(manifest_path, json.dumps(manifest, indent=2) + "\n")


def ensure_ray(address: str | None, num_cpus: int | None, object_store_mb: int) -> None:
    """Connects to Ray unless connected: `address` joins a cluster, None starts a local
    instance with `num_cpus` CPUs (default all) and a small object store."""
    import ray

    if ray.is_initialized():
        return
    # no usage statistics sent from a sweep's own instance (unless the user set otherwise)
    os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
    init: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False,
                            "configure_logging": False}
    if address:
        init["address"] = address
    else:
        init["num_cpus"] = num_cpus or os.cpu_count()
        init["object_store_memory"] = object_store_mb * 2**20
    ray.init(**init)


def read_jsonl(path: str | pathlib.Path) -> list[dict[str, Any]]:
    """The objects of a .jsonl file; unparsable lines (a writer killed mid-line) are skipped."""
    rows = []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            try:
                row = json.loads(line)
            except ValueError:
                continue
            if isinstance(row, dict):
                rows.append(row)
    return rows


def estimate_eta(finished_s: Mapping[str, Sequence[float]], running: Sequence[tuple[str, float]],
                 waiting: Sequence[str], slots: int) -> float | None:
    """Seconds until the sweep ends: the runs still going (`running`: (method, how long it has
    run)) and the runs not started yet (`waiting`: their methods), on `slots` runs at a time.
    A run takes the mean duration of its method's finished runs (`finished_s`: method ->
    durations), or of all finished runs while its method has none: the methods of one sweep can
    differ several times in cost. None before any run has finished."""
    everything = [d for durations in finished_s.values() for d in durations]
    if not everything:
        return None
    overall = sum(everything) / len(everything)

    def duration(method: str) -> float:
        own = finished_s.get(method)
        return sum(own) / len(own) if own else overall

    left = [max(duration(method) - elapsed, 0.0) for method, elapsed in running]
    work = sum(left) + sum(duration(method) for method in waiting)
    return max(work / max(slots, 1), max(left, default=0.0))


def _run_times(sweep_dir: pathlib.Path, since: float) -> tuple[dict[str, float], dict[str, float]]:
    """From attempts.jsonl, for this driver's launches (after `since`, a time.time()): the
    durations of the runs that exited 0 and the start times of the runs still going."""
    started: dict[str, float] = {}
    durations: dict[str, float] = {}
    try:
        events = attempts(sweep_dir)
    except OSError:  # progress only: an unreadable log leaves the time left unknown
        events = []
    for event in events:
        run, when = event.get("run"), event.get("time")
        if not isinstance(run, str) or not isinstance(when, (int, float)) or when < since:
            continue
        if event.get("event") in ("start", "resume", "restart"):
            started.setdefault(run, float(when))
        elif event.get("event") == "exit" and run in started:
            if event.get("code") == 0:
                durations[run] = float(when) - started[run]
            started.pop(run)
    return durations, started


def _format_duration(seconds: float) -> str:
    seconds = int(round(seconds))
    return f"{seconds // 3600}h{seconds % 3600 // 60:02d}m" if seconds >= 3600 else \
        f"{seconds // 60}m{seconds % 60:02d}s"


def submission_order(runs: Sequence[spec_module.Run],
                     pending: Sequence[spec_module.Run] | None = None) -> list[spec_module.Run]:
    """`pending` (default: all of `runs`) seed-major: every method's first seed before any
    method's second, seeds and methods ranked in the order the sweep's `runs` list them.

    A sweep stopped early (a machine's hours, a session's end) then leaves the same seeds of
    every method, which compare, rather than every seed of the first method and none of the
    others."""
    method_rank: dict[str, int] = {}
    seed_rank: dict[int, int] = {}
    for run in runs:
        method_rank.setdefault(run.method, len(method_rank))
        seed_rank.setdefault(run.seed, len(seed_rank))
    return sorted(runs if pending is None else pending,
                  key=lambda run: (seed_rank[run.seed], method_rank[run.method]))


def run_sweep(sweep: spec_module.Sweep, sweep_dir: str | pathlib.Path, *, resume: bool = False,
              address: str | None = None, cli: str | None = None, num_cpus: int | None = None,
              max_retries: int = 3, object_store_mb: int = 200,
              progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """Runs every unfinished run of `sweep` on Ray; returns {"finished", "failed", "skipped"}.

    address: None starts a local Ray instance for the sweep (num_cpus: its CPUs, default all);
    "auto" or HOST:PORT joins a running cluster. Raises SweepError before anything runs if the
    sweep directory is taken or another sweep's, or a run's config does not resolve."""
    import ray

    say = progress or (lambda line: None)
    cli = find_cli(cli)
    sweep_dir = pathlib.Path(sweep_dir).resolve()
    sweep_dir.mkdir(parents=True, exist_ok=True)
    lock = SweepLock(sweep_dir)
    try:
        prepare(sweep, sweep_dir, resume)
        # every method's config, resolved and validated by the program before anything runs
        threads: dict[str, int] = {}
        for run in sweep.runs:
            if run.method not in threads:
                config = resolved_config(cli, run, sweep_dir)
                threads[run.method] = int(config["experiment"]["num_threads"])
        skipped = [r.id for r in sweep.runs if run_state(sweep_dir / r.run_dir) == "finished"]
        pending = [r for r in sweep.runs if r.id not in set(skipped)]
        say(f"sweep {sweep.name}: {len(sweep.runs)} runs, {len(skipped)} finished already, "
            f"{len(pending)} to run")
        result: dict[str, Any] = {"finished": list(skipped), "failed": {}, "skipped": skipped}
        if not pending:
            return result
        ensure_ray(address, num_cpus, object_store_mb)
        task = ray.remote(_remote_train_run)
        futures = {}
        for run in submission_order(sweep.runs, pending):
            cpus = sweep.resources.num_cpus or threads[run.method]
            options = {"num_cpus": cpus, "max_retries": max_retries, "retry_exceptions": False}
            if sweep.resources.num_gpus:
                options["num_gpus"] = sweep.resources.num_gpus
            futures[task.options(**options).remote(cli, run.to_json(), str(sweep_dir))] = run
        start = time.monotonic()
        since = time.time()
        # runs at once: the cluster's CPUs over a run's (the mean over the pending runs)
        per_run = sum(sweep.resources.num_cpus or threads[r.method] for r in pending) / len(pending)
        slots = max(1, int(ray.cluster_resources().get("CPU", 1) // max(per_run, 1e-9)))
        remaining = list(futures)
        method_of = {r.id: r.method for r in sweep.runs}
        while remaining:
            ready, remaining = ray.wait(remaining, num_returns=1)
            run = futures[ready[0]]
            try:
                ray.get(ready[0])
                result["finished"].append(run.id)
            except Exception as error:  # the task's SweepError, or Ray's: a run's failure
                cause = getattr(error, "cause", None) or error
                result["failed"][run.id] = str(cause).strip().splitlines()[-1]
            done = len(futures) - len(remaining)
            elapsed = time.monotonic() - start
            durations, running = _run_times(sweep_dir, since)
            now = time.time()
            by_method: dict[str, list[float]] = {}
            for run_id, seconds in durations.items():
                by_method.setdefault(method_of.get(run_id, ""), []).append(seconds)
            eta = estimate_eta(
                by_method, [(method_of.get(r, ""), now - t) for r, t in running.items()],
                [futures[f].method for f in remaining if futures[f].id not in running], slots)
            say(f"sweep {sweep.name}: {done}/{len(futures)} runs done "
                f"({len(result['failed'])} failed) in {_format_duration(elapsed)}, "
                f"{60 * done / elapsed if elapsed > 0 else 0.0:.2f} runs/min, "
                f"ETA {'unknown' if eta is None else _format_duration(eta)}: {run.id} "
                f"{'failed' if run.id in result['failed'] else 'finished'}")
        return result
    finally:
        lock.close()


def _remote_train_run(cli: str, run_json: dict[str, Any], sweep_dir: str) -> dict[str, Any]:
    import ray

    try:
        node_id = ray.get_runtime_context().get_node_id()
    except Exception:  # outside a Ray worker
        node_id = ""
    try:
        return train_run(cli, run_json, sweep_dir, node_id=node_id)
    except SweepError as error:
        # a plain exception type every process can unpickle, with the one-line message
        raise RuntimeError(str(error)) from None


def attempts(sweep_dir: str | pathlib.Path) -> list[dict[str, Any]]:
    """The records of SWEEP_DIR/attempts.jsonl, oldest first."""
    path = pathlib.Path(sweep_dir) / ATTEMPTS
    return read_jsonl(path) if path.exists() else []


if __name__ == "__main__":  # pragma: no cover
    sys.exit("use manyworlds-sweep (python -m manyworlds.sweep)")
