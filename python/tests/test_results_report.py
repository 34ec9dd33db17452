"""scripts/results_report.py: the report that docs/results is generated with.

Synthetic run directories (eval.jsonl, metrics.jsonl, config.yaml as `train` writes them) go
in; the tables, CSV and charts that come out are checked against the numbers put in.
"""

import csv
import json
import subprocess
import sys

import pytest

from conftest import REPO

SCRIPT = REPO / "scripts" / "results_report.py"
TASKS = ("push", "reach")


def report(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)],
                          capture_output=True, text=True, timeout=60)


def make_run(path, arch, successes, broken_tail=False):
    """A run with one evaluation per 10,000 steps; successes[i] = {task: success} at step i+1."""
    path.mkdir(parents=True)
    with open(path / "eval.jsonl", "w") as f:
        for i, per_task in enumerate(successes):
            row = {"step": 10000 * (i + 1), "episodes_per_task": 10,
                   "mean_success": sum(per_task.values()) / len(per_task),
                   "mean_return": 100.0 * (i + 1),
                   "per_task": {t: {"success": s, "return": 100.0 * (i + 1)}
                                for t, s in per_task.items()}}
            f.write(json.dumps(row) + "\n")
        if broken_tail:
            f.write('{"step": 99999, "per_ta')  # a line cut short by a crash
    with open(path / "metrics.jsonl", "w") as f:
        for i in range(len(successes)):
            f.write(json.dumps({"step": 10000 * (i + 1), "wall_s": 360.0 * (i + 1),
                                "updates_per_s": 20.0 + i}) + "\n")
    (path / "config.yaml").write_text(f"agent:\n  architecture: {arch}\nexperiment:\n  seed: 7\n")
    return path


@pytest.fixture
def runs(tmp_path):
    a = make_run(tmp_path / "runs" / "alpha_v2", "mlp",
                 [{"push": 0.0, "reach": 0.2}, {"push": 0.1, "reach": 0.9},
                  {"push": 0.3, "reach": 1.0}], broken_tail=True)
    b = make_run(tmp_path / "runs" / "beta", "multihead",
                 [{"push": 0.0, "reach": 0.0}, {"push": 0.2, "reach": 0.4}])
    return a, b


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_report_tables_and_csv_carry_the_runs_numbers(runs, tmp_path):
    out = tmp_path / "out"
    r = report(*runs, "--out", out, "--title", "Toy", "--reference", "paper=0.38")
    assert r.returncode == 0, r.stderr
    for name in ("mean_success.svg", "per_task_success.svg", "results.md", "results.csv"):
        assert (out / name).is_file()
    md = (out / "results.md").read_text()
    assert "## Toy" in md
    # alpha: final 0.65 at 30,000, best the same; 0.30 h; median of 20, 21, 22 updates/s
    assert "| `alpha_v2` | mlp | 7 | 30,000 | 0.65 (at 30,000) | 0.65 (at 30,000) | 0.30 | 21.0 |" in md
    assert "| `beta` | multihead | 7 | 20,000 | 0.30 (at 20,000) | 0.30 (at 20,000) | 0.20 | 20.5 |" in md
    assert "| reach | 1.00 | 0.40 |" in md
    assert "| paper | 0.38 |" in md
    rows = read_csv(out / "results.csv")
    assert len(rows) == (3 + 2) * (1 + len(TASKS))  # evaluations x (mean + tasks)
    assert {r["run"] for r in rows} == {"alpha_v2", "beta"}
    assert all(r["step"] != "99999" for r in rows), "the cut-short line must be skipped"
    svg = (out / "mean_success.svg").read_text()
    assert svg.startswith("<svg") and svg.count("<polyline") == 2
    assert "stroke-dasharray=\"5 4\"" not in svg  # no history, so no dashed run lines


def test_up_to_shows_every_run_at_one_budget(runs, tmp_path):
    out = tmp_path / "out"
    r = report(*runs, "--out", out, "--up-to", 20000)
    assert r.returncode == 0, r.stderr
    md = (out / "results.md").read_text()
    assert "| `alpha_v2` | mlp | 7 | 20,000 | 0.50 (at 20,000) |" in md
    assert "after 20,000 steps per task are left out" in md
    assert max(int(r["step"]) for r in read_csv(out / "results.csv")) == 20000


def test_history_draws_an_earlier_report_dashed_in_its_runs_colour(runs, tmp_path):
    old = tmp_path / "old_report"
    assert report(runs[0].parent / "beta", runs[0], "--out", old).returncode == 0
    # A rerun named alpha_v2_rerun pairs with the earlier alpha_v2 and takes its colour.
    rerun = make_run(tmp_path / "new" / "alpha_v2_rerun", "mlp", [{"push": 0.5, "reach": 0.5}])
    out = tmp_path / "out"
    r = report(rerun, "--out", out, "--history", old / "results.csv", "--up-to", 20000)
    assert r.returncode == 0, r.stderr
    md = (out / "results.md").read_text()
    assert "| `alpha_v2 (old_report)` | n/a | n/a | 20,000 | 0.50 (at 20,000) |" in md
    assert "| `beta (old_report)` | n/a | n/a | 20,000 | 0.30 (at 20,000) |" in md
    assert "earlier report's, read from its results.csv" in md
    svg = (out / "mean_success.svg").read_text()
    lines = [line for line in svg.splitlines() if line.startswith("<polyline")]
    assert len(lines) == 3
    colour = lambda line: line.split('stroke="')[1].split('"')[0]
    rerun_line, beta_old, alpha_old = lines  # history in its CSV's order
    assert "stroke-dasharray" not in rerun_line
    assert "stroke-dasharray" in alpha_old and "stroke-dasharray" in beta_old
    assert colour(alpha_old) == colour(rerun_line) != colour(beta_old)


def test_history_pairs_by_name_stem_and_unpaired_runs_get_distinct_colours(tmp_path):
    one = [{"push": 0.1, "reach": 0.3}]
    old_runs = [make_run(tmp_path / "old_report_src" / n, "mlp", one)
                for n in ("gamma_200k", "delta", "epsilon")]
    old = tmp_path / "old_report"
    assert report(*old_runs, "--out", old).returncode == 0
    rerun = make_run(tmp_path / "new" / "gamma_v3", "mlp", one)
    out = tmp_path / "out"
    r = report(rerun, "--out", out, "--history", old / "results.csv")
    assert r.returncode == 0, r.stderr
    svg = (out / "mean_success.svg").read_text()
    lines = [line for line in svg.splitlines() if line.startswith("<polyline")]
    colour = lambda line: line.split('stroke="')[1].split('"')[0]
    rerun_line, gamma_old, delta_old, epsilon_old = lines
    # gamma_200k has no run named like it, but its stem gamma_ pairs it with gamma_v3.
    assert colour(gamma_old) == colour(rerun_line)
    assert len({colour(rerun_line), colour(delta_old), colour(epsilon_old)}) == 3


@pytest.mark.parametrize("extra, message", [
    (["--up-to", "0"], "--up-to must be a positive step count"),
    (["--up-to", "5000"], "no evaluation at or before --up-to 5,000"),
    (["--history", "missing.csv"], "--history file not found"),
    (["--reference", "paper=1.5"], "expected NAME=VALUE with VALUE in [0, 1]"),
])
def test_bad_options_give_one_error_line_and_exit_2(runs, tmp_path, extra, message):
    r = report(runs[0], "--out", tmp_path / "out", *extra)
    assert r.returncode == 2
    assert r.stderr.startswith("error: ") and message in r.stderr
    assert r.stderr.count("\n") == 1 and "Traceback" not in r.stderr
    assert not (tmp_path / "out" / "results.md").exists()


def test_bad_inputs_are_reported_not_raised(runs, tmp_path):
    bad_csv = tmp_path / "bad.csv"
    bad_csv.write_text("run,step,task,success,return\nx,ten,mean,0.5,1\n")
    cases = [
        ([tmp_path / "nowhere", "--out", tmp_path / "o1"], "run directory not found"),
        ([tmp_path, "--out", tmp_path / "o2"], "no eval.jsonl"),
        ([runs[0], "--out", tmp_path / "o3", "--history", runs[0] / "config.yaml"],
         "expected the columns run,step,task,success,return"),
        ([runs[0], "--out", tmp_path / "o4", "--history", bad_csv], "line 2: step, success"),
        ([runs[0], "--out", runs[0] / "report"], "--out must not be inside run directory"),
    ]
    for args, message in cases:
        r = report(*args)
        assert r.returncode == 2, (args, r.stderr)
        assert r.stderr.startswith("error: ") and message in r.stderr, r.stderr
        assert "Traceback" not in r.stderr
