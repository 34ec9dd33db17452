"""manyworlds-sweep: sweep files, runs on Ray equal to runs alone, and faults that lose nothing.

Every run here is a tiny SAC training on point navigation (a few seconds); the manyworlds
program comes from $MANYWORLDS_CLI or build/manyworlds. The Ray tests start local instances
(and one three-node cluster on this machine) sized for two cores.
"""

import json
import os
import pathlib
import re
import signal
import subprocess
import sys
import threading
import time

import pytest

from conftest import REPO, cli_path
from manyworlds.sweep import runner, spec

# no usage statistics from the Ray instances and clusters these tests start
os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")

needs_cli = pytest.mark.skipif(cli_path() is None, reason="the manyworlds program is not built "
                               "(build/manyworlds, or set MANYWORLDS_CLI)")

# One run: 3 tasks x 600 steps, checkpoints every 100 steps (so a killed run resumes), evaluations
# every 200. About 2 s on one core.
TINY_CONFIG = """\
env:
  id: point-nav
  num_tasks: 3
  options: {horizon: 50}
agent:
  algo: sac
  hidden_dim: 16
  num_layers: 2
  batch_size: 32
replay:
  capacity: 5000
experiment:
  steps_per_task: 600
  warmup_steps: 100
  eval_every: 200
  eval_episodes: 2
  checkpoint_every: 100
  keep_checkpoints: 1
  run_dir: runs/tiny
"""
# What differs between two runs of the same seed: timing and where the run lives.
VOLATILE = {"wall_s", "env_steps_per_s", "updates_per_s", "run_dir"}


def comparable(summary):
    """summary.json without its timings and run directory, nested ones included."""
    if isinstance(summary, dict):
        return {k: comparable(v) for k, v in summary.items() if k not in VOLATILE}
    return summary


def write(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def standalone(tmp_path, config, seed, overrides, name):
    """The same run started alone with `manyworlds train`, on one product thread as a sweep's run
    is; its summary.json."""
    run_dir = tmp_path / "alone" / name
    args = [f"{k}={spec.format_value(v)}" for k, v in overrides.items()]
    done = subprocess.run([cli_path(), "train", str(config), *args, f"experiment.seed={seed}",
                           f"experiment.run_dir={run_dir}"], capture_output=True, text=True,
                          timeout=300, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    assert done.returncode == 0, done.stderr
    return json.loads((run_dir / "summary.json").read_text())


def sweep_cli(*args, timeout=600, **kwargs):
    env = dict(os.environ, MANYWORLDS_CLI=cli_path() or "")
    return subprocess.run([sys.executable, "-m", "manyworlds.sweep", *args], capture_output=True,
                          text=True, timeout=timeout, env=env, **kwargs)


# --- sweep files --------------------------------------------------------------------------------

def test_a_sweep_file_expands_to_one_run_per_group_grid_point_and_seed(tmp_path):
    config = write(tmp_path / "tiny.yaml", TINY_CONFIG)
    sweep = spec.parse({"seeds": [1, 2, 3], "grid": {"agent.lr": [1e-3, 3e-4]},
                        "overrides": {"experiment.eval_episodes": 1},
                        "groups": [{"config": str(config), "name": "sac",
                                    "overrides": {"agent.batch_size": 16}}]})
    assert len(sweep.runs) == 6
    assert sweep.methods == ["sac[agent.lr=0.001]", "sac[agent.lr=0.0003]"]
    run = sweep.runs[0]
    assert run.run_dir == "runs/sac_agent.lr=0.001/seed_1"
    assert run.overrides == {"experiment.eval_episodes": 1, "agent.batch_size": 16,
                             "agent.lr": 1e-3}
    args = run.command_overrides(tmp_path)
    assert "agent.lr=0.001" in args and "experiment.seed=1" in args
    assert f"experiment.run_dir={tmp_path}/runs/sac_agent.lr=0.001/seed_1" in args
    first_count = spec.parse({"seeds": {"first": 5, "count": 2}, "groups": [str(config)]})
    assert [r.seed for r in first_count.runs] == [5, 6]
    budget = spec.parse({"seeds": [1], "budget": {"steps_per_task": 7}, "groups": [str(config)]})
    assert budget.runs[0].overrides == {"experiment.steps_per_task": 7}
    assert spec.parse({"seeds": [1], "budget": {"steps_per_task": 7}, "groups": [str(config)]},
                      steps_per_task=9).runs[0].overrides == {"experiment.steps_per_task": 9}


def test_runs_are_submitted_seed_major_so_an_early_stop_leaves_every_method_its_first_seeds(
        tmp_path):
    config = write(tmp_path / "tiny.yaml", TINY_CONFIG)
    sweep = spec.parse({"seeds": [3, 1, 2], "groups": [{"config": str(config), "name": "a"},
                                                       {"config": str(config), "name": "b"}]})
    assert [r.id for r in sweep.runs][:2] == ["a/seed_3", "a/seed_1"]  # the file's order
    order = [r.id for r in runner.submission_order(sweep.runs)]
    assert order == ["a/seed_3", "b/seed_3", "a/seed_1", "b/seed_1", "a/seed_2", "b/seed_2"]
    # on a resume, the finished runs are left out and the rest keep that order
    pending = [r for r in sweep.runs if r.id not in {"a/seed_3", "b/seed_1"}]
    assert [r.id for r in runner.submission_order(sweep.runs, pending)] == [
        "b/seed_3", "a/seed_1", "a/seed_2", "b/seed_2"]


def test_the_eta_counts_the_runs_going_and_the_slots(tmp_path):
    # two slots, one run of 62 minutes finished, its twin nearly done, eight waiting: four more
    # waves of 62 minutes (the rate of finished runs alone said 9h18m)
    eta = runner.estimate_eta({"a": [3720.0]}, [("a", 3700.0)], ["a"] * 8, 2)
    assert eta == pytest.approx((20 + 8 * 3720) / 2)
    assert runner.estimate_eta({}, [("a", 10.0)], ["a"] * 3, 2) is None  # nothing finished
    assert runner.estimate_eta({"a": [10.0]}, [("a", 2.0)], [], 4) == pytest.approx(8.0)
    assert runner.estimate_eta({"a": [10.0]}, [("a", 30.0)], [], 1) == 0.0  # overdue: not < 0
    # methods of different cost: each run takes its own method's mean, a method with no finished
    # run the mean of all (MT10: MT-SAC's 60 minutes against MOORE's 150)
    finished = {"mt-sac": [3600.0, 3600.0], "moore": [9000.0]}
    eta = runner.estimate_eta(finished, [("moore", 1000.0)], ["mt-sac", "moore", "paco"], 2)
    assert eta == pytest.approx((8000 + 3600 + 9000 + 5400) / 2)
    # the times come from attempts.jsonl: this driver's launches, failed attempts not counted
    lines = [{"run": "a/seed_1", "event": "start", "time": 50.0},    # an earlier driver's
             {"run": "a/seed_1", "event": "start", "time": 100.0},
             {"run": "b/seed_1", "event": "resume", "time": 110.0},
             {"run": "a/seed_1", "event": "pid", "pid": 7, "time": 100.5},
             {"run": "a/seed_1", "event": "exit", "code": 0, "time": 160.0},
             {"run": "c/seed_1", "event": "start", "time": 120.0},
             {"run": "c/seed_1", "event": "exit", "code": 1, "time": 130.0}]
    (tmp_path / runner.ATTEMPTS).write_text("".join(json.dumps(line) + "\n" for line in lines))
    durations, running = runner._run_times(tmp_path, since=90.0)
    assert durations == {"a/seed_1": 60.0}
    assert running == {"b/seed_1": 110.0}


def test_a_sweep_directory_from_another_checkout_resumes_but_not_another_sweep(tmp_path):
    config = write(tmp_path / "tiny.yaml", TINY_CONFIG)
    sweep = spec.parse({"seeds": [1, 2], "groups": [{"config": str(config), "name": "a"}]})
    out = tmp_path / "sweep"
    out.mkdir()
    # the manifest as another checkout wrote it: the same runs, the config at another path
    manifest = sweep.manifest()
    for run in manifest["runs"]:
        run["config"] = "/elsewhere/checkout/configs/tiny.yaml"
    (out / runner.MANIFEST).write_text(json.dumps(manifest))
    runner.prepare(sweep, out, resume=True)
    manifest["runs"][1]["overrides"] = {"agent.lr": 0.1}
    (out / runner.MANIFEST).write_text(json.dumps(manifest))
    with pytest.raises(runner.SweepError, match="holds another sweep"):
        runner.prepare(sweep, out, resume=True)


@pytest.mark.parametrize("change, needle", [
    ({"sedes": [1]}, "unknown key 'sedes'"),
    ({"seeds": []}, "seeds must be a non-empty list"),
    ({"seeds": [1, "two"]}, "'two' is not an integer"),
    ({"seeds": [1.5]}, "1.5 is not an integer"),
    ({"seeds": [1, 1]}, "seeds lists a seed twice"),
    ({"grid": {"agent.lr": []}}, "agent.lr must be a non-empty list"),
    ({"grid": {"agent.lr": 0.1}}, "agent.lr must be a non-empty list"),
    ({"overrides": {"experiment.seed": 3}}, "experiment.seed is set by the sweep"),
    ({"overrides": {"lr": 3}}, "'lr' is not a dotted config key"),
    ({"overrides": {"agent.lr": float("nan")}}, "finite numbers"),
    ({"groups": [{"config": "nowhere.yaml"}]}, "config 'nowhere.yaml' not found"),
    ({"groups": [{"cofig": "x.yaml"}]}, "unknown key 'cofig' in groups[0]"),
    ({"groups": []}, "groups must be a non-empty list"),
    ({"resources": {"num_cpus": -1}}, "resources.num_cpus"),
    ({"budget": {"steps_per_task": 0}}, "budget.steps_per_task must be a positive integer"),
])
def test_bad_sweep_files_are_one_error_naming_the_problem(tmp_path, change, needle):
    config = write(tmp_path / "tiny.yaml", TINY_CONFIG)
    data = {"seeds": [1], "groups": [str(config)], **change}
    with pytest.raises(ValueError, match=pytest.importorskip("re").escape(needle)):
        spec.parse(data)


def test_two_groups_of_one_name_are_refused(tmp_path):
    config = write(tmp_path / "tiny.yaml", TINY_CONFIG)
    with pytest.raises(ValueError, match="share the folder"):
        spec.parse({"seeds": [1], "groups": [str(config), str(config)]})


@needs_cli
def test_the_command_line_refuses_a_bad_sweep_before_starting(tmp_path):
    config = write(tmp_path / "tiny.yaml", TINY_CONFIG)
    cases = {
        "unknown key": ("seeds: [1]\ngroups: [tiny.yaml]\ngird: {agent.lr: [1]}\n", "gird"),
        "bad yaml": ("seeds: [1\n", "not valid YAML"),
        # the program resolves every method's config first: a key it does not know stops all
        "unknown config key": ("seeds: [1]\ngroups: [{config: tiny.yaml, overrides: "
                               "{agent.hiden_dim: 3}}]\n", "hidden_dim"),
    }
    for name, (text, needle) in cases.items():
        sweep_file = write(tmp_path / f"{name.replace(' ', '_')}.yaml", text)
        out = tmp_path / "out" / name.replace(" ", "_")
        done = sweep_cli("run", str(sweep_file), "--out", str(out), cwd=tmp_path, timeout=120)
        assert done.returncode == 2, (name, done.stderr)
        lines = done.stderr.strip().splitlines()
        assert len(lines) == 1 and needle in lines[0], (name, done.stderr)
        assert not (out / "runs").exists(), name
    assert config.exists()


@needs_cli
def test_every_preset_resolves_with_the_program(tmp_path):
    """Each shipped sweep file parses and every method's config resolves (`--print-config`)."""
    from manyworlds.sweep import cli, tune

    presets = sorted(cli.PRESETS.glob("*.yaml"))
    assert len(presets) >= 7
    methods = 0
    for path in presets:
        if "search" in path.stem:
            settings = tune.load_search(path, config_root=REPO)
            assert pathlib.Path(settings["config"]).is_file()
            continue
        sweep = spec.load(path, config_root=REPO)
        assert {run.seed for run in sweep.runs} >= {1, 2, 3}, path.stem
        for run in {run.method: run for run in sweep.runs}.values():
            runner.resolved_config(cli_path(), run, tmp_path)
            methods += 1
    assert methods >= 15


def test_the_docs_list_every_preset():
    """docs/sweeps.md's preset table has a row for each shipped sweep file, and none for a file
    that does not exist."""
    from manyworlds.sweep import cli

    shipped = {path.stem for path in cli.PRESETS.glob("*.yaml")}
    text = (REPO / "docs" / "sweeps.md").read_text()
    table = text[text.index("## Presets"):]
    listed = set(re.findall(r"^\| `([a-z0-9_]+)` \|", table, flags=re.M))
    assert listed == shipped, (f"missing from docs/sweeps.md: {sorted(shipped - listed)}; "
                               f"listed but not shipped: {sorted(listed - shipped)}")


# --- runs on Ray --------------------------------------------------------------------------------

@pytest.fixture
def local_ray(monkeypatch):
    ray = pytest.importorskip("ray")
    # the suite's own one-thread settings (conftest.py) are not what the runs should rely on:
    # Ray's workers start without them, so that a run's one product thread is Ray's doing
    for variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"):
        monkeypatch.delenv(variable, raising=False)
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False,
             object_store_memory=100 * 2**20, configure_logging=False)
    yield ray
    ray.shutdown()


@needs_cli
def test_a_sweep_on_ray_gives_each_run_the_numbers_of_the_run_alone(tmp_path, local_ray):
    config = write(tmp_path / "tiny.yaml", TINY_CONFIG)
    sweep = spec.parse({"seeds": [1, 2, 3], "grid": {"agent.actor_lr": [1e-3, 3e-3]},
                        "groups": [{"config": str(config), "name": "sac"}]})
    out = tmp_path / "sweep"
    lines = []
    result = runner.run_sweep(sweep, out, cli=cli_path(), progress=lines.append)
    assert not result["failed"] and len(result["finished"]) == 6
    assert "6/6 runs done" in lines[-1] and "ETA" in lines[-1]
    for run in sweep.runs:
        ours = json.loads((out / run.run_dir / "summary.json").read_text())
        alone = standalone(tmp_path, config, run.seed, run.overrides, run.id.replace("/", "_"))
        assert comparable(ours) == comparable(alone), run.id
    # the two learning rates and the seeds are different runs
    finals = {run.id: json.loads((out / run.run_dir / "summary.json").read_text())
              ["final_eval"]["mean_return"] for run in sweep.runs}
    assert len(set(finals.values())) == 6
    starts = [a["run"] for a in runner.attempts(out) if a["event"] == "start"]
    assert sorted(starts) == sorted(r.id for r in sweep.runs)
    # a one-CPU run computes its products on one thread (Ray's OMP_NUM_THREADS=1, which OpenBLAS
    # and so the products follow): two product threads per run beside the others spin and run
    # many times slower (docs/benchmarks.md, "BLAS threads on a shared machine")
    for run in sweep.runs:
        state = sorted((out / run.run_dir / "checkpoints").glob("step_*/state.json"))[-1]
        assert json.loads(state.read_text())["threads"]["blas_threads"] == 1, run.id
    # TensorBoard event files beside each run
    assert list((out / sweep.runs[0].run_dir / "tensorboard").glob("events.out.tfevents.*"))

    # the report of the sweep (success is 0 in runs this short: score the return)
    shown = sweep_cli("report", str(out), "--metric", "return", "--reps", "500", "--curve-reps",
                      "100", "--improvement-reps", "100", timeout=300)
    assert shown.returncode == 0, shown.stderr
    for method in sweep.methods:
        assert method in shown.stdout
    scores = (out / "report" / "scores.csv").read_text().splitlines()
    assert len(scores) == 1 + 6 * 3  # a row per run and task
    assert (out / "report" / "aggregates.png").read_bytes().startswith(b"\x89PNG")

    # run again with --resume: nothing is run twice
    again = runner.run_sweep(sweep, out, resume=True, cli=cli_path())
    assert sorted(again["skipped"]) == sorted(r.id for r in sweep.runs)
    assert len([a for a in runner.attempts(out) if a["event"] == "start"]) == 6
    # without --resume the directory is refused; another sweep file is refused too
    with pytest.raises(runner.SweepError, match="already holds a sweep; continue it with --resume"):
        runner.run_sweep(sweep, out, cli=cli_path())
    other = spec.parse({"seeds": [1, 2], "groups": [{"config": str(config), "name": "sac"}]})
    with pytest.raises(runner.SweepError, match="holds another sweep"):
        runner.run_sweep(other, out, resume=True, cli=cli_path())


@needs_cli
def test_a_failing_run_is_reported_and_the_others_finish(tmp_path, local_ray):
    config = write(tmp_path / "tiny.yaml", TINY_CONFIG)
    # env options are checked when the envs are made: this run fails once it has started
    sweep = spec.parse({"seeds": [1], "grid": {"env.options.horizon": [50, 0]},
                        "groups": [{"config": str(config), "name": "sac"}]})
    result = runner.run_sweep(sweep, tmp_path / "sweep", cli=cli_path())
    assert result["finished"] == ["sac_env.options.horizon=50/seed_1"]
    (failed, message), = result["failed"].items()
    assert failed == "sac_env.options.horizon=0/seed_1"
    assert "exited with code 2" in message and "horizon" in message and "log:" in message


@needs_cli
def test_a_second_driver_on_one_sweep_directory_is_refused(tmp_path):
    sweep_dir = tmp_path / "sweep"
    sweep_dir.mkdir()
    held = runner.SweepLock(sweep_dir)
    try:
        config = write(tmp_path / "tiny.yaml", TINY_CONFIG)
        sweep = spec.parse({"seeds": [1], "groups": [str(config)]})
        with pytest.raises(runner.SweepError, match=f"in use by another sweep driver \\(pid "
                                                    f"{os.getpid()}\\)"):
            runner.run_sweep(sweep, sweep_dir, cli=cli_path())
    finally:
        held.close()


def wait_for(predicate, timeout_s, what):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"timed out after {timeout_s} s waiting for {what}")


def kill_group(pid):
    """SIGKILL to the process group of `pid` (a Ray worker and the training it launched)."""
    try:
        os.killpg(os.getpgid(pid), signal.SIGKILL)
    except ProcessLookupError:
        pass


def checkpoints(run_dir):
    return sorted((run_dir / "checkpoints").glob("step_*"))


@needs_cli
def test_a_sweep_whose_driver_dies_resumes_without_repeating_a_run(tmp_path):
    pytest.importorskip("ray")
    config = write(tmp_path / "tiny.yaml", TINY_CONFIG)
    sweep_file = write(tmp_path / "sweep.yaml",
                       "seeds: [1, 2, 3]\noverrides: {experiment.steps_per_task: 1500}\n"
                       "groups: [{config: tiny.yaml, name: sac}]\n")
    out = tmp_path / "sweep"
    # one CPU: the runs go one after another. While the second trains, after its first
    # checkpoint, the driver and everything it started (its Ray instance, the worker, the
    # training) are killed at once with SIGKILL, as when the driver's machine goes down. (Ray's
    # workers run in process groups of their own; the training is in its worker's.)
    driver = subprocess.Popen([sys.executable, "-m", "manyworlds.sweep", "run", str(sweep_file),
                               "--out", str(out), "--num-cpus", "1"], cwd=tmp_path,
                              env=dict(os.environ, MANYWORLDS_CLI=cli_path()),
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                              start_new_session=True)
    try:
        def second_run_checkpointed():
            events = runner.attempts(out)
            done = [a["run"] for a in events if a["event"] == "exit" and a["code"] == 0]
            started = [a["run"] for a in events if a["event"] == "start"]
            if len(done) == 1 and len(started) == 2:
                return checkpoints(out / "runs" / started[1])
            return None
        wait_for(second_run_checkpointed, 240, "the second run's first checkpoint")
    finally:
        os.killpg(driver.pid, signal.SIGKILL)
        driver.wait()
        for worker in {a["worker_pid"] for a in runner.attempts(out) if "worker_pid" in a}:
            kill_group(worker)
    events = runner.attempts(out)
    finished_before = {a["run"] for a in events if a["event"] == "exit" and a["code"] == 0}
    assert len(finished_before) == 1

    resumed = sweep_cli("run", str(sweep_file), "--out", str(out), "--resume", "--num-cpus", "1",
                        cwd=tmp_path)
    assert resumed.returncode == 0, resumed.stderr
    assert "1 finished already, 2 to run" in resumed.stderr
    events = runner.attempts(out)
    starts = [a["run"] for a in events if a["event"] == "start"]
    assert len(starts) == len(set(starts)) <= 3, events  # no run started twice
    resumes = [a["run"] for a in events if a["event"] == "resume"]
    assert len(resumes) == 1 and resumes[0] not in finished_before
    # every run finished; the interrupted one with the numbers of the same run alone
    for seed in (1, 2, 3):
        assert runner.run_state(out / "runs" / "sac" / f"seed_{seed}") == "finished"
    interrupted = out / "runs" / resumes[0]
    ours = json.loads((interrupted / "summary.json").read_text())
    seed = int(resumes[0].rsplit("_", 1)[1])
    alone = standalone(tmp_path, config, seed, {"experiment.steps_per_task": 1500}, "alone")
    assert comparable(ours) == comparable(alone)


@needs_cli
def test_a_run_on_a_killed_node_finishes_on_another_with_the_uninterrupted_numbers(tmp_path):
    ray = pytest.importorskip("ray")
    from ray.cluster_utils import Cluster

    # a head that runs nothing and two one-CPU worker nodes, all on this machine
    cluster = Cluster(initialize_head=True, head_node_args={
        "num_cpus": 0, "include_dashboard": False, "object_store_memory": 80 * 2**20})
    nodes = [cluster.add_node(num_cpus=1, object_store_memory=80 * 2**20) for _ in range(2)]
    try:
        ray.init(address=cluster.address, log_to_driver=False, configure_logging=False)
        config = write(tmp_path / "tiny.yaml", TINY_CONFIG)
        overrides = {"experiment.steps_per_task": 3000}
        sweep = spec.parse({"seeds": [4], "overrides": overrides,
                            "groups": [{"config": str(config), "name": "sac"}]})
        out = tmp_path / "sweep"
        outcome = {}
        driver = threading.Thread(target=lambda: outcome.update(
            runner.run_sweep(sweep, out, cli=cli_path(), max_retries=2)))
        driver.start()
        run_dir = out / sweep.runs[0].run_dir
        wait_for(lambda: checkpoints(run_dir), 240, "the run's first checkpoint")
        start = next(a for a in runner.attempts(out) if a["event"] == "start")
        node_id = start["node"]
        victim = next(n for n in nodes if n.node_id == node_id)
        # the node is lost: its raylet and every process on it, the worker and training included
        cluster.remove_node(victim, allow_graceful=False)
        kill_group(start["worker_pid"])
        driver.join(timeout=300)
        assert not driver.is_alive()
        assert not outcome["failed"], outcome
        events = runner.attempts(out)
        launches = [a for a in events if a["event"] in ("start", "resume", "restart")]
        assert [a["event"] for a in launches] == ["start", "resume"], events
        assert launches[1]["node"] != node_id  # the survivor took it over
        ours = json.loads((run_dir / "summary.json").read_text())
        alone = standalone(tmp_path, config, 4, overrides, "node")
        assert comparable(ours) == comparable(alone)
    finally:
        ray.shutdown()
        cluster.shutdown()


# --- search with Ray Tune -----------------------------------------------------------------------

@needs_cli
def test_a_search_reports_each_evaluation_and_asha_stops_the_poor_trial(tmp_path):
    pytest.importorskip("ray.tune")
    from manyworlds.sweep import tune

    write(tmp_path / "tiny.yaml", TINY_CONFIG)
    # a longer episode has a lower return whatever the policy learns (-distance per step), so
    # the second trial trails the first at its first evaluation; one trial at a time keeps the
    # order (ASHA keeps the first trial to reach a rung)
    search_file = write(tmp_path / "search.yaml", """\
config: tiny.yaml
space:
  env.options.horizon: {grid: [50, 200]}
metric: mean_return
mode: max
scheduler: {asha: {grace_period: 1, reduction_factor: 2}}
max_concurrent_trials: 1
""")
    settings = tune.load_search(search_file)
    trials = tune.run_search(settings, tmp_path / "searches", cli=cli_path(), num_cpus=2)
    assert [t["values"] for t in trials] == [{"env.options.horizon": 50},
                                             {"env.options.horizon": 200}]
    best, stopped = trials
    rows = [json.loads(line) for line in
            pathlib.Path(best["run_dir"], "eval.jsonl").read_text().splitlines()]
    # every evaluation the run wrote was reported, the last one as the trial's last value
    assert best["evaluations"] == len(rows) == 3 and best["error"] is None
    assert best["last"] == pytest.approx(rows[-1]["mean_return"])
    assert runner.run_state(pathlib.Path(best["run_dir"])) == "finished"
    # the trailing trial was stopped after its first evaluation, its run not finished
    assert stopped["evaluations"] == 1 and stopped["best"] < best["best"]
    assert runner.run_state(pathlib.Path(stopped["run_dir"])) != "finished"
    saved = json.loads((tmp_path / "searches" / "search" / "search_results.json").read_text())
    assert saved["trials"] == trials
    assert (tmp_path / "searches" / "search" / "search_results.csv").read_text().startswith(
        "trial,env.options.horizon,evaluations,last_mean_return,best_mean_return,error")


def test_bad_search_files_are_one_error_naming_the_problem(tmp_path):
    from manyworlds.sweep import tune

    write(tmp_path / "tiny.yaml", TINY_CONFIG)
    cases = {
        "space:\n  agent.actor_lr: {logunifrm: [1, 2]}\n": "space.agent.actor_lr must be one of",
        "space:\n  agent.actor_lr: {loguniform: [0, 2]}\n": "lo > 0",
        "space:\n  agent.actor_lr: {uniform: [2, 1]}\n": "lo < hi",
        "space: {}\n": "space must name at least one config key",
        "space:\n  agent.actor_lr: {choice: [1]}\nnum_sampels: 3\n": "unknown key 'num_sampels'",
        "space:\n  agent.actor_lr: {choice: [1]}\nmode: maximum\n": "mode must be max or min",
        "space:\n  agent.actor_lr: {choice: [1]}\noverrides: {agent.actor_lr: 2}\n":
            "both searched (space) and fixed (overrides)",
        "space:\n  agent.actor_lr: {choice: [1]}\nloggers: [neptune]\n":
            "loggers must be a list of mlflow, wandb",
    }
    for text, needle in cases.items():
        path = write(tmp_path / "search.yaml", "config: tiny.yaml\n" + text)
        with pytest.raises(ValueError, match=pytest.importorskip("re").escape(needle)):
            tune.load_search(path)
