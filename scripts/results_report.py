#!/usr/bin/env python3
"""Turn manyworlds run directories into a results report (markdown, CSV, SVG).

Reads each run's eval.jsonl (required), metrics.jsonl and config.yaml
(optional) and writes mean_success.svg, per_task_success.svg, results.md and
results.csv into --out. Standard library only; run directories are only read.
--up-to compares runs at one budget while they go on; --history draws the runs
of an earlier report (its results.csv) beside them, dashed.

Example:
  python3 scripts/results_report.py runs/mt10_mtsac runs/mt10_multihead \\
      --out report --reference "MT-SAC (MTRL, MT10 at 2M steps)=0.61" \\
      --up-to 200000 --history old_report/results.csv
"""
import argparse
import csv
import io
import json
import math
import os
import statistics
import sys
import tempfile
from html import escape

COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
          "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22")
FONT = "font-family=\"Helvetica, Arial, sans-serif\""
GRID, AXIS, TEXT, REF = "#e6e6e6", "#555555", "#222222", "#444444"


class ReportError(Exception):
    """Bad input; reported as a one-line `error: ...` with exit code 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        print(f"error: {message}", file=sys.stderr)
        sys.exit(2)


# ---------------------------------------------------------------- loading
def read_jsonl(path):
    """JSON objects of a .jsonl file; unparsable (e.g. half-written) lines are skipped."""
    def parse(line):
        try:
            return json.loads(line)
        except ValueError:
            return None
    with open(path, encoding="utf-8", errors="replace") as f:
        return [obj for obj in map(parse, f) if isinstance(obj, dict)]


def read_config(path):
    """`section.key` -> value for the two-level YAML written by manyworlds."""
    out, section = {}, None
    if not os.path.isfile(path):
        return out
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            if not line.strip() or line.lstrip().startswith("#") or ":" not in line:
                continue
            key, _, value = line.strip().partition(":")
            if not line[0].isspace():
                section = key
            elif section and line.startswith("  ") and not line.startswith("   "):
                out[f"{section}.{key}"] = value.strip()
    return out


def _num(value):
    return float(value) if isinstance(value, (int, float)) else None


def parse_eval(row):
    """Normalise one eval.jsonl record, or None when it lacks the needed fields."""
    step, per_task = _num(row.get("step")), row.get("per_task")
    if step is None or not isinstance(per_task, dict):
        return None
    tasks = {name: (_num(v.get("success")), _num(v.get("return")))
             for name, v in per_task.items() if isinstance(v, dict)}
    def mean_of(key, idx):
        vals = [v[idx] for v in tasks.values() if v[idx] is not None]
        given = _num(row.get(key))
        return given if given is not None or not vals else sum(vals) / len(vals)
    mean_s, mean_r = mean_of("mean_success", 0), mean_of("mean_return", 1)
    if mean_s is None:
        return None
    return {"step": int(step), "success": mean_s, "return": mean_r, "tasks": tasks,
            "episodes": row.get("episodes_per_task")}


def load_run(path):
    """Everything the report needs from one run directory."""
    if not os.path.isdir(path):
        raise ReportError(f"run directory not found: {path}")
    eval_path = os.path.join(path, "eval.jsonl")
    if not os.path.isfile(eval_path):
        raise ReportError(f"no eval.jsonl in {path}")
    by_step = {}
    for row in read_jsonl(eval_path):
        ev = parse_eval(row)
        if ev:
            by_step[ev["step"]] = ev  # a resumed run may repeat steps: keep the latest
    if not by_step:
        raise ReportError(f"no complete evaluation records in {eval_path}")
    metrics_path = os.path.join(path, "metrics.jsonl")
    metrics = read_jsonl(metrics_path) if os.path.isfile(metrics_path) else []
    cfg = read_config(os.path.join(path, "config.yaml"))
    return {"path": path, "evals": [by_step[s] for s in sorted(by_step)], "metrics": metrics,
            "arch": cfg.get("agent.architecture", ""), "seed": cfg.get("experiment.seed", "")}


def load_history(path):
    """The runs of an earlier report's results.csv (run,step,task,success,return)."""
    if not os.path.isfile(path):
        raise ReportError(f"--history file not found: {path}")
    runs = {}
    with open(path, encoding="utf-8", errors="replace", newline="") as f:
        reader = csv.DictReader(f)
        expected = ["run", "step", "task", "success", "return"]
        if reader.fieldnames != expected:
            raise ReportError(f"--history {path}: expected the columns {','.join(expected)} "
                              f"of a results.csv, got {','.join(reader.fieldnames or [])}")
        for line, row in enumerate(reader, start=2):
            try:
                step = int(row["step"])
                success = float(row["success"]) if row["success"] else None
                ret = float(row["return"]) if row["return"] else None
            except ValueError:
                raise ReportError(f"--history {path} line {line}: step, success and return "
                                  "must be numbers") from None
            ev = runs.setdefault(row["run"], {}).setdefault(
                step, {"step": step, "success": None, "return": None, "tasks": {},
                       "episodes": None})
            if row["task"] == "mean":
                ev["success"], ev["return"] = success, ret
            else:
                ev["tasks"][row["task"]] = (success, ret)
    tag = os.path.basename(os.path.dirname(os.path.abspath(path)))
    out = []
    for name, by_step in runs.items():
        evals = [by_step[s] for s in sorted(by_step) if by_step[s]["success"] is not None]
        if evals:
            out.append({"path": path, "evals": evals, "metrics": [], "arch": "", "seed": "",
                        "history": name, "label": f"{name} ({tag})"})
    if not out:
        raise ReportError(f"--history {path} holds no mean-success rows")
    return out


def cut_at(run, step):
    """The run as it stood at `step` (evaluations and metrics rows after it dropped)."""
    run["evals"] = [e for e in run["evals"] if e["step"] <= step]
    run["metrics"] = [m for m in run["metrics"]
                      if not isinstance(m.get("step"), (int, float)) or m["step"] <= step]
    if not run["evals"]:
        raise ReportError(f"{run['path']}: no evaluation at or before --up-to {step:,}")


def label_runs(runs):
    """Colour by position; label = basename, parent/basename where basenames collide.

    A history run takes the colour of the first current run whose label starts with its name
    (mt10_mtsac_v3 pairs with an earlier mt10_mtsac), else with its name less the last
    "_" part (mt10_mtppo_v3 pairs with an earlier mt10_mtppo_200k), else the next colour
    after the current runs', round the palette.
    """
    current = [r for r in runs if "history" not in r]
    names = [os.path.basename(os.path.normpath(r["path"])) for r in current]
    for i, (run, name) in enumerate(zip(current, names)):
        if names.count(name) > 1:
            parent = os.path.basename(os.path.dirname(os.path.abspath(run["path"])))
            name = f"{parent}/{name}"
        run["label"], run["color"] = name, COLORS[i % len(COLORS)]

    def pair_of(name):
        prefixes = [name] + ([name.rsplit("_", 1)[0] + "_"] if "_" in name else [])
        for prefix in prefixes:
            match = next((c for c in current if c["label"].startswith(prefix)), None)
            if match:
                return match
        return None

    spare = len(current)
    for run in runs:
        if "history" in run:
            pair = pair_of(run["history"])
            if pair:
                run["color"] = pair["color"]
            else:
                run["color"] = COLORS[spare % len(COLORS)]
                spare += 1


def parse_reference(text):
    """`NAME=VALUE` -> (name, value); the last '=' separates them."""
    name, _, value = text.rpartition("=")
    try:
        number = float(value)
        if name.strip() and 0.0 <= number <= 1.0:
            return name.strip(), number
    except ValueError:
        pass
    raise ReportError(f"bad --reference {text!r}: expected NAME=VALUE with VALUE in [0, 1]")


# ---------------------------------------------------------------- svg
def nice_ticks(hi, target):
    """Round tick values 0..top (top >= hi) with about `target` intervals."""
    hi = hi if hi > 0 else 1.0
    raw = hi / target
    mag = 10 ** math.floor(math.log10(raw))
    step = next(m * mag for m in (1, 2, 2.5, 5, 10) if m * mag >= raw - 1e-12)
    n = math.ceil(hi / step - 1e-9)
    return [round(i * step, 9) for i in range(n + 1)]


def fmt_step(v):
    """10000 -> 10k, 1500000 -> 1.5M."""
    if v >= 1e6:
        return f"{v / 1e6:g}M"
    return f"{v / 1e3:g}k" if v >= 1e3 else f"{v:g}"


def text(x, y, s, size=12, anchor="start", color=TEXT, extra=""):
    return (f'<text x="{x:.1f}" y="{y:.1f}" font-size="{size}" fill="{color}" '
            f'text-anchor="{anchor}" {extra}>{escape(s)}</text>')


def range_ticks(lo, hi, target):
    """Round tick values covering [lo, hi] (any signs) with about `target` intervals."""
    if hi <= lo:
        lo, hi = lo - 1.0, hi + 1.0
    raw = (hi - lo) / target
    mag = 10 ** math.floor(math.log10(raw))
    step = next(m * mag for m in (1, 2, 2.5, 5, 10) if m * mag >= raw - 1e-12)
    first, last = math.floor(lo / step + 1e-9), math.ceil(hi / step - 1e-9)
    return [round(i * step, 9) for i in range(first, last + 1)]


def panel(x0, y0, w, h, series, xticks, yticks, refs=(), size=11, dashed=()):
    """One chart: grid, ticks, dashed reference lines and one polyline per (color, points).

    The y axis spans yticks[0]..yticks[-1]; series whose index is in `dashed` are drawn dashed.
    """
    xmax = xticks[-1]
    ylo, yhi = yticks[0], yticks[-1]
    px = lambda x: x0 + w * x / xmax
    py = lambda y: y0 + h * (1 - (min(max(y, ylo), yhi) - ylo) / (yhi - ylo))
    out = [f'<rect x="{x0}" y="{y0}" width="{w}" height="{h}" fill="white"/>']
    for t in xticks:
        out.append(f'<line x1="{px(t):.1f}" y1="{y0}" x2="{px(t):.1f}" y2="{y0 + h}" stroke="{GRID}"/>')
        out.append(text(px(t), y0 + h + size + 5, fmt_step(t), size, "middle"))
    for t in yticks:
        out.append(f'<line x1="{x0}" y1="{py(t):.1f}" x2="{x0 + w}" y2="{py(t):.1f}" stroke="{GRID}"/>')
        out.append(text(x0 - 6, py(t) + size * 0.35, f"{t:g}", size, "end"))
    out.append(f'<path d="M{x0},{y0}V{y0 + h}H{x0 + w}" fill="none" stroke="{AXIS}"/>')
    labels, placed = [], []  # reference labels go on top of the data, left-aligned
    for name, value in sorted(refs, key=lambda r: -r[1]):
        y, label, x = py(value), f"{name}: {value:g}", x0 + 6
        out.append(f'<line x1="{x0}" y1="{y:.1f}" x2="{x0 + w}" y2="{y:.1f}" stroke="{REF}" '
                   f'stroke-width="1.5" stroke-dasharray="6 4"/>')
        x = max([x] + [end + 16 for end, ly in placed if abs(ly - y) < size + 3])
        placed.append((x + len(label) * size * 0.6, y))
        labels.append(text(x, y - 5, label, size, "start", REF,
                           'stroke="white" stroke-width="3" paint-order="stroke"'))
    for i, (color, pts) in enumerate(series):
        coords = " ".join(f"{px(x):.1f},{py(y):.1f}" for x, y in pts)
        dash = ' stroke-dasharray="5 4"' if i in dashed else ""
        out.append(f'<polyline points="{coords}" fill="none" stroke="{color}" '
                   f'stroke-width="2" stroke-linejoin="round"{dash}/>')
        if len(pts) <= 40:
            out.extend(f'<circle cx="{px(x):.1f}" cy="{py(y):.1f}" r="2.8" fill="{color}"/>'
                       for x, y in pts)
    return out + labels


def legend(x0, y0, max_w, entries, size=12):
    """Flowing legend rows of (color, label[, dashed]); returns (svg parts, height used)."""
    out, x, y = [], x0, y0
    for color, label, *style in entries:
        w = 30 + len(label) * size * 0.6
        if x > x0 and x + w > x0 + max_w:
            x, y = x0, y + size + 8
        dash = ' stroke-dasharray="5 3"' if style and style[0] else ""
        out.append(f'<line x1="{x}" y1="{y - size * 0.35:.1f}" x2="{x + 20}" '
                   f'y2="{y - size * 0.35:.1f}" stroke="{color}" stroke-width="3"{dash}/>')
        out.append(text(x + 25, y, label, size))
        x += w + 14
    return out, y - y0 + size + 8


def svg_doc(width, height, parts):
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height:.0f}" '
            f'viewBox="0 0 {width} {height:.0f}" {FONT}>\n'
            f'<rect width="100%" height="100%" fill="white"/>\n' + "\n".join(parts) + "\n</svg>\n")


def dashed_runs(runs):
    return {i for i, r in enumerate(runs) if "history" in r}


def legend_entries(runs):
    return [(r["color"], r["label"], "history" in r) for r in runs]


def mean_chart(runs, refs, title, width=720):
    """Line chart of mean success vs env steps per task, one line per run."""
    left, top, plot_w, plot_h = 62, 44, width - 62 - 24, 290
    xt = nice_ticks(max(e["step"] for r in runs for e in r["evals"]), 6)
    series = [(r["color"], [(e["step"], e["success"]) for e in r["evals"]]) for r in runs]
    parts = [text(width / 2, 26, title, 16, "middle", extra='font-weight="bold"')]
    parts += panel(left, top, plot_w, plot_h, series, xt, [i / 5 for i in range(6)], refs, 12,
                   dashed_runs(runs))
    parts.append(text(left + plot_w / 2, top + plot_h + 38, "environment steps per task", 13, "middle"))
    parts.append(text(18, top + plot_h / 2, "mean success rate", 13, "middle",
                      extra=f'transform="rotate(-90 18 {top + plot_h / 2})"'))
    leg, leg_h = legend(left, top + plot_h + 66, plot_w, legend_entries(runs))
    return svg_doc(width, top + plot_h + 54 + leg_h, parts + leg)


def task_chart(runs, tasks, title, cols=5, cell_w=200, cell_h=168):
    """Small multiples: one panel per task, one line per run."""
    cols = min(cols, len(tasks))
    rows = math.ceil(len(tasks) / cols)
    width, top = cols * cell_w + 20, 52
    xt = nice_ticks(max(e["step"] for r in runs for e in r["evals"]), 3)
    parts = [text(width / 2, 26, title, 16, "middle", extra='font-weight="bold"')]
    for i, task in enumerate(tasks):
        cx, cy = 10 + (i % cols) * cell_w, top + (i // cols) * cell_h
        label = task if len(task) <= 28 else task[:27] + "\u2026"
        parts.append(text(cx + 36 + (cell_w - 48) / 2, cy + 12, label, 11, "middle",
                          extra='font-weight="bold"'))
        series = [(r["color"], [(e["step"], e["tasks"][task][0]) for e in r["evals"]
                                if e["tasks"].get(task, (None,))[0] is not None]) for r in runs]
        parts += panel(cx + 36, cy + 22, cell_w - 48, cell_h - 66, series, xt, [0, 0.5, 1],
                       size=10, dashed=dashed_runs(runs))
    bottom = top + rows * cell_h - 4
    parts.append(text(width / 2, bottom, "environment steps per task; y = success rate", 12, "middle"))
    leg, leg_h = legend(46, bottom + 26, width - 60, legend_entries(runs))
    return svg_doc(width, bottom + 16 + leg_h, parts + leg)


# ---------------------------------------------------------------- tables
def run_summary(run):
    """Figures for the summary table row of one run."""
    evals, metrics = run["evals"], run["metrics"]
    best = max(evals, key=lambda e: e["success"])  # first maximum = earliest step
    steps = [m["step"] for m in metrics if isinstance(m.get("step"), (int, float))]
    walls = [m["wall_s"] for m in metrics if isinstance(m.get("wall_s"), (int, float))]
    ups = [m["updates_per_s"] for m in metrics
           if isinstance(m.get("updates_per_s"), (int, float)) and m["updates_per_s"] > 0]
    return {"reached": max([evals[-1]["step"]] + steps), "final": evals[-1], "best": best,
            "hours": walls[-1] / 3600 if walls else None,
            "ups": statistics.median(ups) if ups else None}


def md_table(header, rows, left=1):
    """Markdown table lines; the first `left` columns left-aligned, the rest right."""
    align = ["---"] * left + ["---:"] * (len(header) - left)
    return ["| " + " | ".join(c.replace("|", "\\|") for c in line) + " |"
            for line in [header, align] + rows]


def results_md(runs, tasks, refs, title, up_to=None):
    """Markdown fragment: summary table, final per-task table, references."""
    na = "n/a"
    out = [f"## {title}", "", "![mean success](mean_success.svg)", ""]
    rows = []
    for r in runs:
        s = run_summary(r)
        rows.append([f"`{r['label']}`", r["arch"] or na, r["seed"] or na, f"{s['reached']:,}",
                     f"{s['final']['success']:.2f} (at {s['final']['step']:,})",
                     f"{s['best']['success']:.2f} (at {s['best']['step']:,})",
                     f"{s['hours']:.2f}" if s["hours"] is not None else na,
                     f"{s['ups']:.1f}" if s["ups"] is not None else na])
    out += md_table(["run", "architecture", "seed", "steps per task reached", "final mean success",
                     "best mean success", "wall-clock h", "updates/s (median)"], rows, left=3)
    episodes = {str(r["evals"][-1]["episodes"]) for r in runs if r["evals"][-1]["episodes"]}
    out += ["", "Steps are environment steps per task. Success is the fraction of evaluation "
            f"episodes solved ({'/'.join(sorted(episodes)) or 'n/a'} per task); updates/s excludes "
            "warm-up rounds without updates."]
    if up_to is not None:
        out += ["", f"Evaluations after {up_to:,} steps per task are left out (`--up-to`), so "
                "every run is shown at the same budget or less."]
    if any("history" in r for r in runs):
        out += ["", "Runs labelled with a folder name in parentheses (dashed lines) are an "
                "earlier report's, read from its results.csv (`--history`)."]
    out += ["", "### Per-task success at the final evaluation", "",
            "![per-task success](per_task_success.svg)", ""]
    header = ["task"] + [f"`{r['label']}` ({r['evals'][-1]['step']:,})" for r in runs]
    rows = []
    for task in tasks + ["**mean**"]:
        vals = [r["evals"][-1]["success"] if task == "**mean**" else
                r["evals"][-1]["tasks"].get(task, (None,))[0] for r in runs]
        rows.append([task] + [f"{v:.2f}" if v is not None else na for v in vals])
    out += md_table(header, rows)
    if refs:
        out += ["", "### Reference numbers (published)", ""]
        out += md_table(["reference", "mean success"], [[n, f"{v:.2f}"] for n, v in refs])
    return "\n".join(out) + "\n"


def results_csv(runs):
    """Long-format CSV: run,step,task,success,return (task=mean for the means)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["run", "step", "task", "success", "return"])
    cell = lambda v: "" if v is None else f"{v:.6g}"
    for r in runs:
        for e in r["evals"]:
            w.writerow([r["label"], e["step"], "mean", cell(e["success"]), cell(e["return"])])
            for task in sorted(e["tasks"]):
                s, ret = e["tasks"][task]
                w.writerow([r["label"], e["step"], task, cell(s), cell(ret)])
    return buf.getvalue()


# ---------------------------------------------------------------- main
def write_atomic(out_dir, name, content):
    """Write via a temp file in out_dir, then os.replace (readers never see partial files)."""
    fd, tmp = tempfile.mkstemp(dir=out_dir, prefix=f".{name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(content)
        os.chmod(tmp, 0o644)
        os.replace(tmp, os.path.join(out_dir, name))
    except BaseException:
        os.unlink(tmp)
        raise


def main(argv=None):
    p = _Parser(description=__doc__.split("\n\n")[0],
                epilog="Writes mean_success.svg, per_task_success.svg, results.md, results.csv.")
    p.add_argument("runs", nargs="+", metavar="RUN_DIR", help="run directory with eval.jsonl")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created)")
    p.add_argument("--title", default="Results", help="report / chart title (default: Results)")
    p.add_argument("--reference", action="append", default=[], metavar="NAME=VALUE",
                   help="published mean success to draw as a dashed line (repeatable)")
    p.add_argument("--up-to", type=int, metavar="STEP",
                   help="leave out evaluations after STEP steps per task (compare at one budget)")
    p.add_argument("--history", action="append", default=[], metavar="RESULTS_CSV",
                   help="an earlier report's results.csv whose runs are drawn dashed beside "
                        "these, labelled with its folder's name (repeatable)")
    args = p.parse_args(argv)
    try:
        if args.up_to is not None and args.up_to <= 0:
            raise ReportError(f"--up-to must be a positive step count, got {args.up_to}")
        refs = [parse_reference(t) for t in args.reference]
        runs = [load_run(d) for d in args.runs]
        runs += [h for path in args.history for h in load_history(path)]
        if args.up_to is not None:
            for r in runs:
                cut_at(r, args.up_to)
        out = os.path.abspath(args.out)
        for r in runs:
            if "history" in r:
                continue
            rd = os.path.abspath(r["path"])
            if os.path.commonpath([out, rd]) == rd:
                raise ReportError(f"--out must not be inside run directory {r['path']}")
        label_runs(runs)
        tasks = sorted({t for r in runs for e in r["evals"] for t in e["tasks"]})
        try:
            os.makedirs(out, exist_ok=True)
        except OSError as e:
            raise ReportError(f"cannot create output directory {args.out}: {e.strerror}") from None
        write_atomic(out, "mean_success.svg", mean_chart(runs, refs, f"{args.title}: mean success over tasks"))
        if tasks:
            write_atomic(out, "per_task_success.svg", task_chart(runs, tasks, f"{args.title}: success per task"))
        write_atomic(out, "results.md", results_md(runs, tasks, refs, args.title, args.up_to))
        write_atomic(out, "results.csv", results_csv(runs))
    except ReportError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    print(f"wrote report for {len(runs)} run(s) to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
