#!/usr/bin/env python3
"""Adaptation curves of meta-RL runs: return (and success) before and after adaptation.

Reads each run's meta_test.jsonl (written at every evaluation of a run with an eval_env) and
writes into --out: meta_test_return.svg (solid: after adaptation, dashed: before, the
exploration episodes), meta_test_success.svg when the env reports success, meta_test.md (the
final meta-test of each run) and meta_test.csv (every evaluation). Standard library only.

Example:
  python3 scripts/meta_test_report.py runs/cheetah_vel_maml runs/cheetah_vel_pearl \\
      --out docs/results/cheetah_vel --title "Half-cheetah velocity"
"""
import argparse
import csv
import io
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import results_report as rr  # noqa: E402  (shared SVG and table helpers)


def load_run(path):
    """{step: record} of a run's meta-test log; the latest record wins for a repeated step."""
    if not os.path.isdir(path):
        raise rr.ReportError(f"run directory not found: {path}")
    log = os.path.join(path, "meta_test.jsonl")
    if not os.path.isfile(log):
        raise rr.ReportError(f"no meta_test.jsonl in {path} (only runs with an eval_env have one)")
    by_step = {}
    for row in rr.read_jsonl(log):
        step = rr._num(row.get("step"))
        if step is not None and rr._num(row.get("return")) is not None:
            by_step[int(step)] = row
    if not by_step:
        raise rr.ReportError(f"no complete meta-test records in {log}")
    cfg = rr.read_config(os.path.join(path, "config.yaml"))
    return {"path": path, "tests": [by_step[s] for s in sorted(by_step)],
            "algo": cfg.get("agent.algo", ""), "seed": cfg.get("experiment.seed", "")}


def curve_chart(runs, key, title, ylabel, width=720):
    """One solid line (after adaptation) and one dashed (before) per run."""
    before = {"return": "pre_adaptation_return", "success_rate": "pre_adaptation_success_rate"}[key]
    series, dashed = [], set()
    for r in runs:
        for k in (key, before):
            pts = [(t["step"], t[k]) for t in r["tests"] if rr._num(t.get(k)) is not None]
            if k == before:
                dashed.add(len(series))
            series.append((r["color"], pts))
    values = [y for _, pts in series for _, y in pts]
    yt = [i / 5 for i in range(6)] if key == "success_rate" else rr.range_ticks(min(values), max(values), 5)
    left, top, plot_w, plot_h = 70, 44, width - 70 - 24, 290
    xt = rr.nice_ticks(max(t["step"] for r in runs for t in r["tests"]), 6)
    parts = [rr.text(width / 2, 26, title, 16, "middle", extra='font-weight="bold"')]
    parts += rr.panel(left, top, plot_w, plot_h, series, xt, yt, size=12, dashed=dashed)
    parts.append(rr.text(left + plot_w / 2, top + plot_h + 38, "environment steps per env", 13, "middle"))
    parts.append(rr.text(18, top + plot_h / 2, ylabel, 13, "middle",
                         extra=f'transform="rotate(-90 18 {top + plot_h / 2})"'))
    entries = [(r["color"], r["label"]) for r in runs] + [(rr.AXIS, "solid: after adaptation, dashed: before")]
    leg, leg_h = rr.legend(left, top + plot_h + 66, plot_w, entries)
    return rr.svg_doc(width, top + plot_h + 54 + leg_h, parts + leg)


def fmt(v, digits=2):
    return "n/a" if rr._num(v) is None else f"{v:.{digits}f}"


def episodes_label(test):
    """Episodes before + after adaptation, as the test's protocol counts them."""
    if test.get("protocol", "per_variation") == "metalearning_evaluation":
        return (f"{test.get('adaptation_episodes', '?')} per env + "
                f"{test.get('evaluation_episodes', '?')} per task, {test.get('num_evals', '?')} rounds")
    return f"{test.get('exploration_episodes', '?')} + {test.get('evaluation_episodes', '?')}"


def report_md(runs, title, has_success):
    out = [f"## {title}", "", "![return before and after adaptation](meta_test_return.svg)", ""]
    if has_success:
        out += ["![success before and after adaptation](meta_test_success.svg)", ""]
    rows = []
    for r in runs:
        t = r["tests"][-1]
        rows.append([f"`{r['label']}`", r["algo"] or "n/a", r["seed"] or "n/a", f"{t['step']:,}",
                     fmt(t.get("pre_adaptation_return")), fmt(t.get("return")),
                     fmt(t.get("pre_adaptation_success_rate")), fmt(t.get("success_rate")),
                     episodes_label(t)])
    out += rr.md_table(["run", "algo", "seed", "step", "return before", "return after",
                        "success before", "success after", "episodes (explore + evaluate)"],
                       rows, left=3)
    return "\n".join(out) + "\n"


def report_csv(runs):
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    keys = ["pre_adaptation_return", "return", "pre_adaptation_success_rate", "success_rate",
            "trial_return"]
    w.writerow(["run", "step"] + keys)
    for r in runs:
        for t in r["tests"]:
            w.writerow([r["label"], t["step"]] + ["" if rr._num(t.get(k)) is None else f"{t[k]:.6g}"
                                                   for k in keys])
    return buf.getvalue()


def main(argv=None):
    p = rr._Parser(description=__doc__.split("\n\n")[0])
    p.add_argument("runs", nargs="+", metavar="RUN_DIR", help="run directory with meta_test.jsonl")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created)")
    p.add_argument("--title", default="Meta-test", help="report / chart title")
    args = p.parse_args(argv)
    try:
        runs = [load_run(d) for d in args.runs]
        rr.label_runs(runs)
        os.makedirs(args.out, exist_ok=True)
        rr.write_atomic(args.out, "meta_test_return.svg",
                        curve_chart(runs, "return", f"{args.title}: return", "mean episode return"))
        has_success = any(rr._num(t.get("success_rate")) is not None for r in runs for t in r["tests"])
        if has_success:
            rr.write_atomic(args.out, "meta_test_success.svg",
                            curve_chart(runs, "success_rate", f"{args.title}: success", "success rate"))
        rr.write_atomic(args.out, "meta_test.md", report_md(runs, args.title, has_success))
        rr.write_atomic(args.out, "meta_test.csv", report_csv(runs))
    except (rr.ReportError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    print(f"wrote meta-test report for {len(runs)} run(s) to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
