"""manyworlds.sweep.report and manyworlds.sweep.tensorboard: a sweep's statistics and event files.

The statistics are rliable's; these tests feed it scores whose answers are known (an IQM of
hand-picked values, numpy's mean and median) and synthetic sweep directories, laid out as the
sweep runner writes them, whose report must hold the numbers put in. The TensorBoard export is
read back with a reader written here (TFRecord framing, CRC-32C checked) and tensorboardX's
bundled Event protobuf, since the tensorboard package is not a dependency.
"""

import csv
import json
import os
import struct

import numpy as np
import pytest

pytest.importorskip("rliable")
pytest.importorskip("tensorboardX")

from manyworlds.sweep import report as sweep_report  # noqa: E402
from manyworlds.sweep import tensorboard as sweep_tensorboard  # noqa: E402

# Few repetitions keep the file fast; the intervals only need to be well defined here.
REPS = 1000
FAST = dict(reps=REPS, curve_reps=200, improvement_reps=200)
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


# ------------------------------------------------------------------------------ statistics
def test_aggregates_match_known_values():
    # Sorted, the 12 scores are 0, 0, 0, .1, .2, .3, .6, .8, .9, 1, 1, 1: the middle half is
    # .1 .. .9, IQM 2.9 / 6; mean, median of the task means and optimality gap all differ.
    scores = np.array([[0.0, 0.3, 1.0], [1.0, 0.1, 0.9], [0.2, 1.0, 0.0], [0.6, 0.0, 0.8]])
    result = sweep_report.aggregate_scores({"m": scores}, reps=REPS, seed=0)["m"]
    assert result["iqm"]["estimate"] == pytest.approx(2.9 / 6)
    assert result["mean"]["estimate"] == pytest.approx(np.mean(scores))
    assert result["median"]["estimate"] == pytest.approx(np.median(scores.mean(axis=0)))
    assert result["optimality_gap"]["estimate"] == pytest.approx(1.0 - np.mean(scores))
    for aggregate in result.values():
        assert aggregate["ci_low"] <= aggregate["estimate"] <= aggregate["ci_high"]
        assert aggregate["ci_high"] - aggregate["ci_low"] > 0.0


def test_interval_contains_the_population_value():
    # Uniform(0, 1) scores: IQM, mean and median of the population are all 0.5.
    scores = np.random.default_rng(7).uniform(size=(20, 10))
    result = sweep_report.aggregate_scores({"m": scores}, reps=REPS, seed=0)["m"]
    for name in ("iqm", "mean", "median"):
        assert result[name]["ci_low"] < 0.5 < result[name]["ci_high"], name
        assert result[name]["ci_high"] - result[name]["ci_low"] < 0.25, name


def test_aggregates_are_seeded_and_leave_numpys_global_rng_alone():
    scores = {"m": np.random.default_rng(1).uniform(size=(5, 3))}
    np.random.seed(123)
    expected_draw = np.random.rand()
    np.random.seed(123)
    first = sweep_report.aggregate_scores(scores, reps=REPS, seed=0)
    assert np.random.rand() == expected_draw
    assert sweep_report.aggregate_scores(scores, reps=REPS, seed=0) == first
    other_seed = sweep_report.aggregate_scores(scores, reps=REPS, seed=1)
    assert other_seed["m"]["iqm"]["ci_low"] != first["m"]["iqm"]["ci_low"]
    assert other_seed["m"]["iqm"]["estimate"] == first["m"]["iqm"]["estimate"]


def test_a_methods_interval_does_not_depend_on_the_other_methods():
    rng = np.random.default_rng(2)
    a, b = rng.uniform(size=(5, 3)), rng.uniform(size=(5, 3))
    alone = sweep_report.aggregate_scores({"a": a}, reps=REPS, seed=0)["a"]
    together = sweep_report.aggregate_scores({"b": b, "a": a}, reps=REPS, seed=0)["a"]
    assert alone == together


def test_perfect_scores_have_no_optimality_gap():
    result = sweep_report.aggregate_scores({"m": np.ones((3, 4))}, reps=REPS, seed=0)["m"]
    assert result["optimality_gap"] == {"estimate": 0.0, "ci_low": 0.0, "ci_high": 0.0}
    assert result["iqm"]["estimate"] == 1.0
    assert "optimality_gap" not in sweep_report.aggregate_scores(
        {"m": np.ones((3, 4))}, reps=REPS, seed=0, gamma=None)["m"]


def test_aggregates_reject_empty_or_nan_scores():
    with pytest.raises(ValueError, match="shape"):
        sweep_report.aggregate_scores({"m": np.zeros((0, 3))}, reps=REPS)
    with pytest.raises(ValueError, match="NaN"):
        sweep_report.aggregate_scores({"m": np.array([[np.nan, 1.0]])}, reps=REPS)


def test_performance_profile_counts_scores_above_each_threshold():
    scores = np.array([[0.0, 0.5], [1.0, 0.25]])
    profile = sweep_report.performance_profiles({"m": scores}, [0.0, 0.3, 0.5, 1.0],
                                                reps=REPS, seed=0)["m"]
    assert profile["fraction"] == [0.75, 0.5, 0.25, 0.0]  # scores strictly above tau
    assert all(lo <= f <= hi for lo, f, hi in
               zip(profile["ci_low"], profile["fraction"], profile["ci_high"]))


def test_probability_of_improvement_is_mirrored_and_favours_the_better_method():
    rng = np.random.default_rng(3)
    good, bad = rng.uniform(0.6, 1.0, size=(5, 3)), rng.uniform(0.0, 0.4, size=(4, 3))
    pairs = sweep_report.probability_of_improvement({"good": good, "bad": bad}, reps=300, seed=0)
    by_pair = {(p["x"], p["y"]): p for p in pairs}
    assert set(by_pair) == {("good", "bad"), ("bad", "good")}
    assert by_pair["good", "bad"]["estimate"] == 1.0
    assert by_pair["bad", "good"]["estimate"] == 0.0
    # Overlapping scores: P(X > Y) strictly inside (0, 1), and the mirror sums to one.
    x, y = rng.uniform(size=(5, 3)), rng.uniform(size=(5, 3))
    forward, backward = sweep_report.probability_of_improvement({"x": x, "y": y}, reps=300)
    assert 0.0 < forward["estimate"] < 1.0
    assert forward["estimate"] + backward["estimate"] == pytest.approx(1.0)
    assert forward["ci_low"] == pytest.approx(1.0 - backward["ci_high"])
    assert forward["ci_low"] <= forward["estimate"] <= forward["ci_high"]
    with pytest.raises(ValueError, match="same tasks"):
        sweep_report.probability_of_improvement({"x": x, "y": y[:, :2]}, reps=10)


def test_learning_curve_is_the_iqm_at_each_step():
    # (runs, tasks, steps); at step 0 the 8 scores are 0..7 (IQM 3.5), at step 1 all are 2.
    array = np.stack([np.arange(8.0).reshape(4, 2), np.full((4, 2), 2.0)], axis=-1)
    curve = sweep_report.learning_curves({"m": ([100, 200], array)}, reps=300, seed=0)["m"]
    assert curve["steps"] == [100, 200]
    assert curve["iqm"] == pytest.approx([3.5, 2.0])
    assert curve["ci_low"][1] == curve["ci_high"][1] == 2.0
    assert curve["ci_low"][0] < 3.5 < curve["ci_high"][0]


# ------------------------------------------------------------------------------ sweep directories
TASKS = ("push", "reach/0", "window-open")


def per_task(successes, returns=None):
    return {task: {"success": s, "return": (returns or {}).get(task, 10.0 * (s or 0)),
                   "length": 100.0} for task, s in successes.items()}


def eval_row(step, successes, returns=None):
    values = [s for s in successes.values() if s is not None]
    return {"step": step, "episodes_per_task": 1, "wall_s": 0.1,
            "mean_success": sum(values) / len(values) if values else None,
            "mean_return": 1.0, "per_task": per_task(successes, returns)}


def meta_row(step, successes):
    return {"step": step, "success_rate": sum(successes.values()) / len(successes),
            "return": -5.0, "per_task": {t: {"success": s, "return": -5.0,
                                             "pre_adaptation_success": 0.0}
                                         for t, s in successes.items()}}


def write_jsonl(path, rows, cut_tail=False):
    with open(path, "w") as f:
        for row in rows:
            f.write(json.dumps(row) + "\n")
        if cut_tail:
            f.write('{"step": 999, "per_ta')  # a line cut short by a crash


def make_sweep(root, methods, name="synthetic"):
    """methods: {method: [run, ...]}, run = dict(seed, final=..., curve=[...], meta=..., ...)."""
    runs = []
    for method, method_runs in methods.items():
        for run in method_runs:
            run_dir = f"runs/{method}/seed_{run['seed']}"
            runs.append({"id": f"{method}/seed_{run['seed']}", "method": method,
                         "group": method, "grid_point": {}, "config": "/abs/config.yaml",
                         "seed": run["seed"], "overrides": {}, "run_dir": run_dir})
            path = root / run_dir
            path.mkdir(parents=True)
            if run.get("curve") is not None:
                write_jsonl(path / "eval.jsonl", [eval_row(step, s) for step, s in run["curve"]],
                            cut_tail=True)
            if run.get("meta_curve") is not None:
                write_jsonl(path / "meta_test.jsonl",
                            [meta_row(step, s) for step, s in run["meta_curve"]])
            if run.get("final") is None:
                continue  # still running: no summary.json yet
            summary = {"algo": "sac", "finished": run.get("finished", True), "step": 300,
                       "total_env_steps": 900, "final_eval": eval_row(300, run["final"]),
                       "final_meta_test": None, "final_meta_train": None}
            if run.get("meta") is not None:
                summary["final_meta_test"] = meta_row(300, run["meta"])
            (path / "summary.json").write_text(json.dumps(summary))
    (root / "sweep.json").write_text(json.dumps({"format": 1, "name": name, "runs": runs}))
    return root


GOOD = [{"push": 0.9, "reach/0": 1.0, "window-open": 0.8},
        {"push": 1.0, "reach/0": 0.9, "window-open": 0.9},
        {"push": 0.8, "reach/0": 1.0, "window-open": 1.0},
        {"push": 0.9, "reach/0": 0.8, "window-open": 0.9}]
BAD = [{"push": 0.1, "reach/0": 0.3, "window-open": 0.0},
       {"push": 0.2, "reach/0": 0.1, "window-open": 0.1},
       {"push": 0.0, "reach/0": 0.2, "window-open": 0.3}]


def curve_of(final, steps=(100, 200, 300)):
    """Success rising to `final`: half of it at the first step."""
    return [(step, {t: v * (i + 1) / len(steps) for t, v in final.items()})
            for i, step in enumerate(steps)]


@pytest.fixture(scope="module")
def two_method_sweep(tmp_path_factory):
    root = tmp_path_factory.mktemp("sweep")
    good = [dict(seed=i + 1, final=f, curve=curve_of(f)) for i, f in enumerate(GOOD)]
    good[0]["curve"].append((400, GOOD[0]))  # a step only one run logged: not on the curve
    bad = [dict(seed=i + 1, final=f, curve=curve_of(f)) for i, f in enumerate(BAD)]
    bad.append(dict(seed=4, final=None, curve=curve_of(BAD[0])[:1]))    # still running
    bad.append(dict(seed=5, final=BAD[0], finished=False, curve=None))  # stopped early
    make_sweep(root, {"good": good, "bad": bad})
    report = sweep_report.write_report(str(root), seed=0, **FAST)
    return root, report


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_report_writes_every_file(two_method_sweep):
    root, report = two_method_sweep
    out = root / "report"
    for name in ("report.json", "scores.csv", "aggregates.csv", "summary.md"):
        assert (out / name).stat().st_size > 0, name
    for stem in ("curves", "aggregates", "profiles", "improvement"):
        assert (out / f"{stem}.png").read_bytes()[:8] == PNG_SIGNATURE, stem
        svg = (out / f"{stem}.svg").read_text()
        assert "<svg" in svg and svg.rstrip().endswith("</svg>"), stem
        assert f"{stem}.png" in report["files"] and f"{stem}.svg" in report["files"]
    assert json.loads((out / "report.json").read_text()) == report
    assert not [p for p in os.listdir(out) if p.endswith(".tmp")]  # no temp file left


def test_report_holds_the_scores_put_in(two_method_sweep):
    root, report = two_method_sweep
    good = report["methods"]["good"]
    assert good["tasks"] == sorted(TASKS) and good["source"] == "eval"
    for task in TASKS:
        column = [run[task] for run in GOOD]
        assert good["per_task"][task]["mean"] == pytest.approx(np.mean(column))
        assert good["per_task"][task]["std"] == pytest.approx(np.std(column, ddof=1))
        assert good["per_task"][task]["n"] == 4
    all_good = np.array([[run[t] for t in sorted(TASKS)] for run in GOOD])
    assert good["aggregates"]["mean"]["estimate"] == pytest.approx(all_good.mean())
    assert good["aggregates"]["optimality_gap"]["estimate"] == pytest.approx(1 - all_good.mean())

    rows = read_csv(root / "report" / "scores.csv")
    assert len(rows) == (4 + 3) * len(TASKS)
    got = {(r["method"], int(r["seed"]), r["task"]): float(r["score"]) for r in rows}
    assert got[("good", 3, "window-open")] == 1.0
    assert got[("bad", 2, "reach/0")] == 0.1
    assert all(seed <= 3 for method, seed, _ in got if method == "bad")

    aggregates = read_csv(root / "report" / "aggregates.csv")
    assert {(r["method"], r["metric"]) for r in aggregates} == {
        (m, a) for m in ("good", "bad") for a in sweep_report.AGGREGATES}
    for row in aggregates:
        expected = report["methods"][row["method"]]["aggregates"][row["metric"]]
        assert float(row["estimate"]) == expected["estimate"]
        assert float(row["ci_low"]) == expected["ci_low"]
        assert float(row["ci_high"]) == expected["ci_high"]


def test_report_counts_unfinished_runs_as_missing(two_method_sweep):
    _, report = two_method_sweep
    bad = report["methods"]["bad"]
    assert (bad["runs_finished"], bad["runs_total"]) == (3, 5)
    reasons = {r["id"]: r["reason"] for r in bad["runs_missing"]}
    assert set(reasons) == {"bad/seed_4", "bad/seed_5"}
    assert "no summary.json" in reasons["bad/seed_4"]
    assert "did not finish" in reasons["bad/seed_5"]
    assert (report["runs_finished"], report["runs_total"]) == (7, 9)


def test_report_ranks_the_dominant_method_first(two_method_sweep):
    root, report = two_method_sweep
    by_pair = {(p["x"], p["y"]): p for p in report["probability_of_improvement"]}
    assert by_pair["good", "bad"]["estimate"] > 0.9
    assert by_pair["bad", "good"]["estimate"] < 0.1
    good, bad = report["methods"]["good"]["aggregates"], report["methods"]["bad"]["aggregates"]
    assert good["iqm"]["ci_low"] > bad["iqm"]["ci_high"]
    profile = report["performance_profile"]
    assert profile["thresholds"][0] == 0.0 and profile["thresholds"][-1] == 1.0
    half = profile["thresholds"].index(0.5)
    assert profile["methods"]["good"]["fraction"][half] == 1.0
    assert profile["methods"]["bad"]["fraction"][half] == 0.0


def test_report_curves_use_the_steps_every_run_logged(two_method_sweep):
    _, report = two_method_sweep
    curve = report["methods"]["good"]["curve"]
    assert curve["steps"] == [100, 200, 300]  # 400 is in one run only
    all_good = np.array([[run[t] for t in sorted(TASKS)] for run in GOOD])
    # At the last step the curve's scores are the final scores.
    assert curve["iqm"][-1] == pytest.approx(report["methods"]["good"]["aggregates"]["iqm"]
                                             ["estimate"])
    assert curve["iqm"][0] < curve["iqm"][-1]
    assert curve["iqm"][0] == pytest.approx(
        sweep_report.aggregate_scores({"g": all_good / 3}, reps=10)["g"]["iqm"]["estimate"])


def test_summary_markdown_has_a_row_per_method(two_method_sweep):
    root, report = two_method_sweep
    summary = (root / "report" / "summary.md").read_text()
    lines = summary.splitlines()
    header = next(line for line in lines if line.startswith("| Method"))
    assert "IQM [95 % CI]" in header and "Optimality gap" in header
    good_row = next(line for line in lines if line.startswith("| good |"))
    iqm = report["methods"]["good"]["aggregates"]["iqm"]
    assert f"{iqm['estimate']:.2f} [{iqm['ci_low']:.2f}, {iqm['ci_high']:.2f}]" in good_row
    assert good_row.endswith("| 4 of 4 |")
    assert next(line for line in lines if line.startswith("| bad |")).endswith("| 3 of 5 |")
    window_row = next(line for line in lines if line.startswith("| window-open |"))
    assert f"{np.mean([r['window-open'] for r in GOOD]):.2f} ±" in window_row
    assert "Probability of improvement" in summary
    assert "bad/seed_4" in summary and "bad/seed_5" in summary


def test_report_is_deterministic(tmp_path, two_method_sweep):
    root, report = two_method_sweep
    again = sweep_report.write_report(str(root), out_dir=str(tmp_path), seed=0, plots=False,
                                      **FAST)
    report_without_plots = dict(report, files=again["files"])
    assert again == report_without_plots


def test_meta_rl_runs_are_scored_on_their_held_out_tasks(tmp_path):
    tasks = {"reach": 1.0, "push": 0.5}
    runs = [dict(seed=s, final={"reach": 0.0, "push": 0.0},
                 meta={"reach": 1.0, "push": 0.5 * s / 3},
                 meta_curve=[(100, {t: 0.0 for t in tasks}), (200, {"reach": 1.0, "push": 0.5})])
            for s in (1, 2, 3)]
    make_sweep(tmp_path, {"rl2": runs})
    report = sweep_report.write_report(str(tmp_path), plots=False, **FAST)
    rl2 = report["methods"]["rl2"]
    assert rl2["source"] == "meta_test"
    assert rl2["per_task"]["reach"]["mean"] == 1.0
    assert rl2["per_task"]["push"]["mean"] == pytest.approx(np.mean([0.5 * s / 3
                                                                     for s in (1, 2, 3)]))
    assert rl2["curve"]["steps"] == [100, 200] and rl2["curve"]["iqm"][0] == 0.0
    # The training-task evaluation is still there when asked for.
    on_eval = sweep_report.write_report(str(tmp_path), plots=False, source="eval", **FAST)
    assert on_eval["methods"]["rl2"]["source"] == "eval"
    assert on_eval["methods"]["rl2"]["per_task"]["reach"]["mean"] == 0.0


def test_return_metric_for_envs_without_success(tmp_path):
    runs = [dict(seed=s, final={"pole": None}, curve=None) for s in (1, 2, 3)]
    make_sweep(tmp_path, {"ppo": runs})
    for run, ret in zip(runs, (100.0, 200.0, 300.0)):
        path = tmp_path / "runs" / "ppo" / f"seed_{run['seed']}" / "summary.json"
        summary = json.loads(path.read_text())
        summary["final_eval"]["per_task"]["pole"]["return"] = ret
        path.write_text(json.dumps(summary))
    with pytest.raises(ValueError, match="no success signal: score it by return"):
        sweep_report.write_report(str(tmp_path), plots=False, **FAST)
    report = sweep_report.write_report(str(tmp_path), metric="return", **FAST)
    ppo = report["methods"]["ppo"]
    assert ppo["aggregates"]["mean"]["estimate"] == pytest.approx(200.0)
    assert "optimality_gap" not in ppo["aggregates"]
    assert ppo["curve"] is None and "eval.jsonl" in ppo["curve_missing"]
    assert "left out" in (tmp_path / "report" / "summary.md").read_text()
    with_target = sweep_report.write_report(str(tmp_path), metric="return", target=250.0,
                                            plots=False, **FAST)
    gap = with_target["methods"]["ppo"]["aggregates"]["optimality_gap"]["estimate"]
    assert gap == pytest.approx(250.0 - np.mean([100.0, 200.0, 250.0]))


# ------------------------------------------------------------------------------ bad input
def test_missing_sweep_json_is_reported(tmp_path):
    with pytest.raises(ValueError, match="no sweep.json in"):
        sweep_report.write_report(str(tmp_path), plots=False, **FAST)


def test_malformed_sweep_json_is_reported(tmp_path):
    (tmp_path / "sweep.json").write_text('{"format": 1, "runs": [')
    with pytest.raises(ValueError, match="not valid JSON"):
        sweep_report.write_report(str(tmp_path), plots=False, **FAST)
    (tmp_path / "sweep.json").write_text('{"format": 1, "runs": [{"method": "a"}]}')
    with pytest.raises(ValueError, match="'run_dir'"):
        sweep_report.write_report(str(tmp_path), plots=False, **FAST)
    (tmp_path / "sweep.json").write_text('{"format": 2, "runs": []}')
    with pytest.raises(ValueError, match="format 2"):
        sweep_report.write_report(str(tmp_path), plots=False, **FAST)


def test_a_sweep_without_finished_runs_is_reported(tmp_path):
    make_sweep(tmp_path, {"ppo": [dict(seed=1, final=None), dict(seed=2, final=None)]})
    with pytest.raises(ValueError, match=r"no run to score .*0 of 2 runs finished.*no summary"):
        sweep_report.write_report(str(tmp_path), plots=False, **FAST)
    assert not (tmp_path / "report").exists()


def test_seeds_with_different_task_sets_are_reported(tmp_path):
    make_sweep(tmp_path, {"ppo": [dict(seed=1, final={"push": 1.0, "reach": 0.0}),
                                  dict(seed=2, final={"push": 1.0, "door": 0.0})]})
    with pytest.raises(ValueError, match=r"'ppo' scores different task sets .*door"):
        sweep_report.write_report(str(tmp_path), plots=False, **FAST)


def test_bad_arguments_are_reported(tmp_path):
    make_sweep(tmp_path, {"ppo": [dict(seed=1, final={"push": 1.0})]})
    with pytest.raises(ValueError, match="metric 'reward'"):
        sweep_report.write_report(str(tmp_path), metric="reward")
    with pytest.raises(ValueError, match="source 'test'"):
        sweep_report.write_report(str(tmp_path), source="test")
    with pytest.raises(ValueError, match="target"):
        sweep_report.write_report(str(tmp_path), target=1.0)


# ------------------------------------------------------------------------------ TensorBoard
def crc32c(data):
    crc = 0xFFFFFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ (0x82F63B78 if crc & 1 else 0)
    return crc ^ 0xFFFFFFFF


def masked_crc32c(data):
    crc = crc32c(data)
    return (((crc >> 15) | (crc << 17)) + 0xA282EAD8) & 0xFFFFFFFF


def read_scalars(event_file):
    """{tag: [(step, value), ...]} of an event file, the TFRecord framing checked by hand."""
    from tensorboardX.proto.event_pb2 import Event
    data = open(event_file, "rb").read()
    scalars, offset, records = {}, 0, 0
    while offset < len(data):
        header = data[offset:offset + 8]
        (length,) = struct.unpack("<Q", header)
        (header_crc,) = struct.unpack("<I", data[offset + 8:offset + 12])
        assert header_crc == masked_crc32c(header)
        payload = data[offset + 12:offset + 12 + length]
        (payload_crc,) = struct.unpack("<I", data[offset + 12 + length:offset + 16 + length])
        assert payload_crc == masked_crc32c(payload)
        offset += 16 + length
        records += 1
        event = Event.FromString(payload)
        for value in event.summary.value:
            scalars.setdefault(value.tag, []).append((event.step, value.simple_value))
    assert offset == len(data) and records > 0
    return scalars


def test_crc32c_of_the_reader_is_right():
    assert crc32c(b"123456789") == 0xE3069283  # the CRC-32C check value


def make_logged_run(path):
    path.mkdir(parents=True)
    write_jsonl(path / "metrics.jsonl", [
        {"step": 10, "train_return": 1.5, "train_success": None, "algo": "sac", "done": True,
         "env_steps": 100},
        {"step": 20, "train_return": 2.5, "train_success": 0.25, "algo": "sac", "done": False,
         "env_steps": 200}], cut_tail=True)
    write_jsonl(path / "eval.jsonl", [
        eval_row(10, {"point-nav/0": 0.0, "point-nav/1": 1.0}),
        eval_row(20, {"point-nav/0": 1.0, "point-nav/1": None})])
    write_jsonl(path / "meta_test.jsonl", [meta_row(20, {"reach": 0.5})])
    return path


def expected_scalars():
    def f32(value):  # simple_value is a 32-bit float
        return float(np.float32(value))

    return {
        "train/train_return": [(10, 1.5), (20, 2.5)],
        "train/train_success": [(20, 0.25)],
        "train/env_steps": [(10, 100.0), (20, 200.0)],
        "train/wall_s": None,  # not logged in metrics here: must be absent
        "eval/mean_success": [(10, 0.5), (20, 1.0)],
        "eval/mean_return": [(10, 1.0), (20, 1.0)],
        "eval/episodes_per_task": [(10, 1.0), (20, 1.0)],
        "eval/wall_s": [(10, f32(0.1)), (20, f32(0.1))],
        "eval/point-nav/0/success": [(10, 0.0), (20, 1.0)],
        "eval/point-nav/1/success": [(10, 1.0)],
        "eval/point-nav/1/return": [(10, 10.0), (20, 0.0)],
        "eval/point-nav/0/length": [(10, 100.0), (20, 100.0)],
        "meta_test/success_rate": [(20, 0.5)],
        "meta_test/return": [(20, -5.0)],
        "meta_test/reach/success": [(20, 0.5)],
        "meta_test/reach/pre_adaptation_success": [(20, 0.0)],
    }


def test_tensorboard_export_round_trips_the_logs(tmp_path):
    run = make_logged_run(tmp_path / "run")
    event_file = sweep_tensorboard.export_run(str(run))
    assert os.path.dirname(event_file) == str(run / "tensorboard")
    scalars = read_scalars(event_file)
    for tag, points in expected_scalars().items():
        if points is None:
            assert tag not in scalars
        else:
            assert scalars[tag] == points, tag
    # Strings, booleans and nulls are not scalars; `step` is the x axis, not a value.
    assert not [t for t in scalars if t.endswith(("/algo", "/done", "/step"))]
    assert len([t for t in scalars if t.startswith("train/")]) == 3


def test_tensorboard_reexport_replaces_the_event_file(tmp_path):
    run = make_logged_run(tmp_path / "run")
    first = sweep_tensorboard.export_run(str(run))
    with open(run / "metrics.jsonl", "a") as f:  # the run resumed and logged on
        f.write("\n" + json.dumps({"step": 30, "train_return": 3.5}) + "\n")
    second = sweep_tensorboard.export_run(str(run))
    event_files = [p for p in os.listdir(run / "tensorboard") if "tfevents" in p]
    assert event_files == [os.path.basename(second)]
    assert not [p for p in os.listdir(run / "tensorboard") if p.startswith(".")]
    assert read_scalars(second)["train/train_return"] == [(10, 1.5), (20, 2.5), (30, 3.5)]
    assert first == second or not os.path.exists(first)


def test_tensorboard_export_of_a_sweep_and_of_a_run_without_logs(tmp_path):
    make_logged_run(tmp_path / "runs" / "a" / "seed_1")
    make_logged_run(tmp_path / "runs" / "b" / "seed_1")
    (tmp_path / "runs" / "c" / "seed_1").mkdir(parents=True)  # never started
    event_files = sweep_tensorboard.export_sweep(str(tmp_path))
    assert sorted(os.path.relpath(p, tmp_path).split(os.sep)[:4] for p in event_files) == [
        ["runs", "a", "seed_1", "tensorboard"], ["runs", "b", "seed_1", "tensorboard"]]
    assert len(sweep_tensorboard.export_sweep(str(tmp_path))) == 2  # again: still one each
    assert len(list((tmp_path / "runs" / "a" / "seed_1" / "tensorboard").iterdir())) == 1
    with pytest.raises(ValueError, match="metrics.jsonl"):
        sweep_tensorboard.export_run(str(tmp_path / "runs" / "c" / "seed_1"))


# ------------------------------------------------------------------------------ published results
def test_the_published_mt10_report_comes_from_the_committed_runs(tmp_path):
    """docs/results' MT10 two-core table: its point estimates and the scores behind it are what
    the report computes from the runs kept in docs/results/mt10_two_cores/sweep."""
    from conftest import REPO

    results = REPO / "docs" / "results" / "mt10_two_cores"
    # the point estimates do not depend on the bootstrap: few resamples keep this fast
    fresh = sweep_report.write_report(str(results / "sweep"), out_dir=str(tmp_path), seed=0,
                                      plots=False, reps=50, curve_reps=10, improvement_reps=10)
    published = json.loads((results / "report" / "report.json").read_text())
    assert fresh["runs_finished"] == published["runs_finished"] == 10
    for method in ("mt-sac", "mh-sac"):
        for name in ("iqm", "mean", "median", "optimality_gap"):
            ours = fresh["methods"][method]["aggregates"][name]["estimate"]
            assert ours == pytest.approx(
                published["methods"][method]["aggregates"][name]["estimate"], abs=1e-12), name
    assert (tmp_path / "scores.csv").read_text() == (results / "report" / "scores.csv").read_text()
    # the table in docs/results/README.md shows these estimates
    table = (REPO / "docs" / "results" / "README.md").read_text()
    for label, method in (("MT-SAC", "mt-sac"), ("Multi-head SAC", "mh-sac")):
        iqm = published["methods"][method]["aggregates"]["iqm"]
        row = next(line for line in table.splitlines() if line.startswith(f"| {label} |"))
        assert f"{iqm['estimate']:.2f} [{iqm['ci_low']:.2f}, {iqm['ci_high']:.2f}]" in row, row


# --- archive: finished runs without checkpoints ---------------------------------------------------

def test_an_archive_keeps_what_report_and_resume_read_and_nothing_else(tmp_path):
    from manyworlds.sweep import archive, cli, runner

    sweep = make_sweep(tmp_path / "sweep", {
        "good": [dict(seed=i + 1, final=f, curve=curve_of(f)) for i, f in enumerate(GOOD)],
        "bad": [dict(seed=1, final=BAD[0], curve=curve_of(BAD[0])),
                dict(seed=2, final=None, curve=curve_of(BAD[1])[:1])]})  # still running
    for run_dir in (sweep / "runs").glob("*/seed_*"):
        (run_dir / "config.yaml").write_text("agent: {algo: sac}\n")
        (run_dir / "checkpoints" / "step_000000000300").mkdir(parents=True)
        (run_dir / "checkpoints" / "step_000000000300" / "replay.bin").write_bytes(b"x" * 1000)
        (run_dir / "tasks.json").write_text("{}")
        (run_dir / "eval.csv").write_text("step\n")
    (sweep / "logs" / "good").mkdir(parents=True)
    (sweep / "logs" / "good" / "seed_1.log").write_text("== start\n")

    out = tmp_path / "kept"
    assert cli.main(["archive", str(sweep), str(out)]) == 0
    kept = sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file())
    assert "sweep.json" in kept and "logs/good/seed_1.log" in kept
    assert "runs/good/seed_1/summary.json" in kept and "runs/good/seed_1/config.yaml" in kept
    assert not [p for p in kept if "checkpoints" in p or p.endswith(("tasks.json", ".csv"))], kept
    assert not any(p.startswith("runs/bad/seed_2/") for p in kept)  # not finished: left out
    assert runner.run_state(out / "runs" / "good" / "seed_3") == "finished"

    # the archive scores as the sweep does
    runs = json.loads((sweep / "sweep.json").read_text())["runs"]
    ours = sweep_report.scores_from_runs(str(out), runs)
    theirs = sweep_report.scores_from_runs(str(sweep), runs)
    assert list(ours) == ["good", "bad"]
    for method in ours:
        assert ours[method].run_ids == theirs[method].run_ids
        np.testing.assert_array_equal(ours[method].scores, theirs[method].scores)
    assert len(ours["good"].run_ids) == 4 and len(ours["bad"].run_ids) == 1

    # archiving again as the sweep goes on adds the run that finished since
    (sweep / "runs" / "bad" / "seed_2" / "summary.json").write_text(
        (sweep / "runs" / "bad" / "seed_1" / "summary.json").read_text())
    before = (out / "runs" / "good" / "seed_1" / "summary.json").stat().st_ino
    result = archive.archive_sweep(sweep, out)
    assert result["unfinished"] == [] and len(result["archived"]) == 6
    assert (out / "runs" / "bad" / "seed_2" / "summary.json").is_file()
    # what was archived before and has not changed is not written again
    assert (out / "runs" / "good" / "seed_1" / "summary.json").stat().st_ino == before


def test_an_archive_needs_a_sweep_and_a_place_outside_it(tmp_path, capsys):
    from manyworlds.sweep import cli

    assert cli.main(["archive", str(tmp_path), str(tmp_path / "out")]) == 2
    assert "not a sweep directory" in capsys.readouterr().err
    sweep = make_sweep(tmp_path / "sweep", {"good": [dict(seed=1, final=GOOD[0])]})
    assert cli.main(["archive", str(sweep), str(sweep / "kept")]) == 2
    assert "must lie outside the sweep" in capsys.readouterr().err
    (sweep / "sweep.json").write_text("{not json")
    assert cli.main(["archive", str(sweep), str(tmp_path / "out")]) == 2
    assert "unreadable or damaged" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()
