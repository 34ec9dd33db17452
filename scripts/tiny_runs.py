#!/usr/bin/env python3
"""Tiny training runs of every config in configs/, to check that a change keeps behaviour.

  scripts/tiny_runs.py run --cli build/manyworlds --out runs/tiny_after [--only mt10_mtsac ...]
  scripts/tiny_runs.py compare runs/tiny_before runs/tiny_after [--table]

`run` trains each config for one iteration (off-policy: one round with a short warm-up and
a tenth of an update per step; on-policy and meta-RL: one iteration with the fewest rounds
the algorithm allows), with one evaluation episode per task at the end and a one-trial
meta-test where the config has held-out tasks. Every run has a fixed seed (the config's), so
two builds that behave alike write the same summary.json numbers. `compare` prints every
number that differs between two such trees (timings, rates and paths are left out) and exits
1 if any does; --table prints the compared numbers of every config as a Markdown table.
"""
import argparse
import json
import math
import pathlib
import re
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent

# Keys whose values depend on the machine or the clock.
VOLATILE = re.compile(r"(time|wall|_per_s|elapsed|rate_|seconds|date|run_dir|path|host|threads)")


def algo_of(config: pathlib.Path) -> str:
    text = config.read_text()
    agent = re.search(r"^agent:\s*\n((?:[ \t]+.*\n|\s*\n)*)", text, re.M)
    if agent:
        m = re.search(r"^\s+algo:\s*([A-Za-z0-9_]+)", agent.group(1), re.M)
        if m:
            return m.group(1)
    return "sac"


def meta_test_overrides(config: pathlib.Path) -> list:
    """The fewest meta-test episodes the config's protocol allows."""
    if re.search(r"^\s+protocol:\s*per_variation", config.read_text(), re.M):
        return ["meta_test.trials_per_task=1", "meta_test.exploration_episodes=1"]
    return ["meta_test.num_evals=1", "meta_test.adaptation_episodes=1"]


def overrides_for(algo: str, out_dir: pathlib.Path) -> list:
    common = [
        "experiment.steps_per_task=1",
        "experiment.eval_every=0",
        "experiment.eval_episodes=1",
        "experiment.checkpoint_every=0",
        f"experiment.run_dir={out_dir}",
        "meta_test.evaluation_episodes=1",
    ]
    per_algo = {
        "sac": ["experiment.warmup_steps=50", "experiment.updates_per_step=0.1"],
        "pearl": ["experiment.warmup_steps=0", "agent.updates_per_iteration=5"],
        "ppo": ["agent.rollout_rounds=1"],
        "trpo": ["agent.rollout_rounds=1"],
        "te_ppo": ["agent.rollout_rounds=1"],
        "rl2": ["agent.episodes_per_trial=2"],
        "maml": ["agent.episodes_per_task=1"],
    }
    return common + per_algo.get(algo, [])


def run(args) -> int:
    out = pathlib.Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    # training configs only (demo.yaml is `manyworlds demo`'s)
    configs = [c for c in sorted((ROOT / "configs").glob("*.yaml"))
               if re.search(r"^(env|agent|experiment):", c.read_text(), re.M)]
    if args.only:
        configs = [c for c in configs if c.stem in set(args.only)]
    failures = 0
    for i, config in enumerate(configs, 1):
        run_dir = out / config.stem
        if (run_dir / "summary.json").exists():
            continue
        if run_dir.exists():
            subprocess.run(["rm", "-rf", str(run_dir)], check=True)
        algo = algo_of(config)
        cmd = ([args.cli, "train", str(config)] + overrides_for(algo, run_dir)
               + meta_test_overrides(config))
        t0 = time.time()
        proc = subprocess.run(cmd, capture_output=True, text=True)
        took = time.time() - t0
        status = "ok" if proc.returncode == 0 else f"exit {proc.returncode}"
        print(f"[{i}/{len(configs)}] {config.stem} ({algo}): {status}, {took:.0f} s", flush=True)
        if proc.returncode != 0:
            failures += 1
            (out / f"{config.stem}.err").write_text(proc.stdout + proc.stderr)
    return 1 if failures else 0


def numbers(tree, prefix=""):
    """Flattens the non-volatile numbers and strings of a JSON tree into {dotted key: value}."""
    flat = {}
    if isinstance(tree, dict):
        for k, v in tree.items():
            key = f"{prefix}.{k}" if prefix else k
            if VOLATILE.search(k):
                continue
            flat.update(numbers(v, key))
    elif isinstance(tree, list):
        for i, v in enumerate(tree):
            flat.update(numbers(v, f"{prefix}[{i}]"))
    else:
        flat[prefix] = tree
    return flat


def same(a, b) -> bool:
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return a == b


def compare(args) -> int:
    before, after = pathlib.Path(args.before), pathlib.Path(args.after)
    names = sorted({p.parent.name for p in before.glob("*/summary.json")} |
                   {p.parent.name for p in after.glob("*/summary.json")})
    differ = 0
    rows = []
    for name in names:
        a_path, b_path = before / name / "summary.json", after / name / "summary.json"
        if not a_path.exists() or not b_path.exists():
            print(f"{name}: summary.json only in {'after' if b_path.exists() else 'before'}")
            differ += 1
            continue
        a, b = numbers(json.loads(a_path.read_text())), numbers(json.loads(b_path.read_text()))
        diffs = [(k, a.get(k), b.get(k)) for k in sorted(set(a) | set(b))
                 if not same(a.get(k), b.get(k))]
        for k, va, vb in diffs:
            print(f"{name}: {k}: {va} -> {vb}")
        differ += bool(diffs)
        headline = {k: v for k, v in b.items()
                    if re.search(r"(mean_success|mean_return|success_rate|^step$|^updates$)", k)
                    and not re.search(r"per_task", k)}
        rows.append((name, len(a), "same" if not diffs else f"{len(diffs)} differ", headline))
    if args.table:
        print("| config | numbers compared | before -> after | headline numbers (after) |")
        print("|---|---:|---|---|")
        for name, n, verdict, headline in rows:
            shown = ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                              for k, v in sorted(headline.items()))
            print(f"| {name} | {n} | {verdict} | {shown} |")
    print(f"{len(names)} configs, {differ} with differences", file=sys.stderr)
    return 1 if differ else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="train every config for one tiny iteration")
    r.add_argument("--cli", required=True, help="the manyworlds program")
    r.add_argument("--out", required=True, help="directory for the run directories")
    r.add_argument("--only", nargs="*", help="config names (without .yaml)")
    c = sub.add_parser("compare", help="compare the summary.json numbers of two trees")
    c.add_argument("before")
    c.add_argument("after")
    c.add_argument("--table", action="store_true", help="print a Markdown table")
    args = parser.parse_args()
    return run(args) if args.command == "run" else compare(args)


if __name__ == "__main__":
    sys.exit(main())
