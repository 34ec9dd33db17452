#!/usr/bin/env python3
"""The measured effect of our models on Meta-World's task definitions: scripted-policy success
and random-policy success and return, ours against the official package's, on every task.

    python3 scripts/fidelity_effect.py --out bench/logs/fidelity_effect_DATE  # ~35 min, loaded VM

Ours: `manyworlds rollout --env mt50` (the first N variations of each task; our scripted
policies, and uniform random actions). Theirs: python/tests/fidelity/metaworld_policy_stats.py
in the virtual environment with `metaworld` (.venv-metaworld/, made by scripts/python_test.sh;
MANYWORLDS_METAWORLD_PYTHON overrides), v3's own scripted policies on MT1's training goals.
Both sides run full 500-step episodes with reward version v2; success is the success flag at any
step. The variations differ (ours are drawn from our benchmark seed, v3's from its MT1 seed),
so rates are compared over many variations, not goal by goal.

Writes OUT.json (every episode) and OUT.md (one row per task).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def ours(cli, policy, episodes, seed):
    run = subprocess.run([cli, "rollout", "--env", "mt50", "--policy", policy, "--episodes",
                          str(episodes), "--seed", str(seed), "--json"],
                         check=True, stdout=subprocess.PIPE, text=True)
    data = json.loads(run.stdout)
    out, i = {}, 0
    for task in data["per_task"]:
        n = task["episodes"]
        out[task["task"]] = [{"return": e["return"], "success": bool(e["success"])}
                             for e in data["episodes"][i:i + n]]
        i += n
    return out


def theirs(python, tasks, scripted, random, seed):
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "stats.json"
        subprocess.run([python, str(REPO / "python/tests/fidelity/metaworld_policy_stats.py"),
                        "--tasks", ",".join(tasks), "--scripted", str(scripted), "--random",
                        str(random), "--seed", str(seed), "--out", str(out)],
                       check=True, stderr=subprocess.DEVNULL)
        return json.loads(out.read_text())


def rate(episodes):
    return sum(e["success"] for e in episodes), len(episodes)


def quartiles(episodes):
    q = statistics.quantiles([e["return"] for e in episodes], n=4, method="inclusive")
    return f"{q[1]:.0f} [{q[0]:.0f}, {q[2]:.0f}]"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cli", default=str(REPO / "build/manyworlds"))
    parser.add_argument("--python", default=os.environ.get(
        "MANYWORLDS_METAWORLD_PYTHON", str(REPO / ".venv-metaworld/bin/python")))
    parser.add_argument("--scripted", type=int, default=50, help="variations per task")
    parser.add_argument("--random", type=int, default=20, help="random episodes per task")
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--tasks", help="comma-separated subset (default: all of mt50)")
    parser.add_argument("--out", required=True, help="path prefix of OUT.json and OUT.md")
    args = parser.parse_args()

    start = time.time()
    our_scripted = ours(args.cli, "scripted", args.scripted, args.seed)
    our_random = ours(args.cli, "random", args.random, args.seed)
    tasks = args.tasks.split(",") if args.tasks else list(our_scripted)
    print(f"ours: {time.time() - start:.0f} s; now the official package ({len(tasks)} tasks)",
          file=sys.stderr)
    their = theirs(args.python, tasks, args.scripted, args.random, args.seed)
    result = {"date": time.strftime("%Y-%m-%d"), "official": their["package"],
              "scripted_variations": args.scripted, "random_episodes": args.random,
              "tasks": {t: {"ours": {"scripted": our_scripted[t], "random": our_random[t]},
                            "v3": their["tasks"][t]} for t in tasks}}
    Path(args.out + ".json").write_text(json.dumps(result))

    lines = [f"| task | scripted success: ours | v3 | random success: ours | v3 | "
             f"random return, median [quartiles]: ours | v3 |", "|---|---:|---:|---:|---:|---:|---:|"]
    for t in tasks:
        o, v = result["tasks"][t]["ours"], result["tasks"][t]["v3"]
        cells = [t]
        for side in (o, v):
            cells.append("%d/%d" % rate(side["scripted"]))
        for side in (o, v):
            cells.append("%d/%d" % rate(side["random"]))
        for side in (o, v):
            cells.append(quartiles(side["random"]))
        lines.append("| " + " | ".join(cells) + " |")
    Path(args.out + ".md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    print(f"{time.time() - start:.0f} s in all", file=sys.stderr)


if __name__ == "__main__":
    main()
