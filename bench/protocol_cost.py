"""What a published protocol costs on this machine, projected from a few minutes of real training.

    python3 bench/protocol_cost.py [--protocol mt10 mt50] [--rounds 2] [--eval-episodes 5]
        [--threads N] [--json OUT]

For each protocol it runs `manyworlds train` with the protocol's config at the published batch
(128 transitions per task per update, MTRL's and Meta-World+'s) for one warm-up round and
--rounds rounds of updates (a round is one episode length of loop steps), then one evaluation of
--eval-episodes episodes per task. From the run's own metrics.jsonl and eval.jsonl:

  loop step   wall seconds per loop step once updates run (env step of every env, the actions,
              one update, the replay sampling), over the update rounds;
  warm-up     wall seconds per loop step before updates start (start-up included);
  evaluation  wall seconds of one evaluation, scaled to the config's episodes per task. An
              untrained policy never succeeds, so every episode runs its whole length: an upper
              bound, since the protocol's evaluations end an episode at its first success.

and projects: warm-up steps x warm-up + (steps per task - warm-up steps) x loop step
+ (steps per task / eval_every) evaluations. Checkpoints are left out (the configs write one every
50,000 steps per task, a few seconds each). Threads: --threads executor threads and as many BLAS
threads (the products' threads), as one run alone on the machine would use.
"""

import argparse
import json
import math
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

REPO = pathlib.Path(__file__).resolve().parent.parent

# The published budgets: Meta-World+ (arXiv 2505.11289) runs 2M steps per task; MTRL's MT10
# command and Meta-World+'s MT-SAC baseline use batches of 128 per task.
PROTOCOLS = {
    "mt10": {"config": "configs/mt10_mtsac.yaml", "steps_per_task": 2_000_000, "batch_per_task": 128},
    "mt50": {"config": "configs/mt50_mtsac.yaml", "steps_per_task": 2_000_000, "batch_per_task": 128},
}


def _read_jsonl(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def measure_rates(metrics, evaluation, eval_episodes, warmup_steps):
    """Seconds per warm-up loop step, per loop step with updates, and per evaluation episode per
    task, from a run's metrics.jsonl rows (a row per round), its last eval.jsonl row, and the
    warm-up steps it ran with."""
    warm = [row for row in metrics if row["step"] <= warmup_steps]
    if not warm or warm[-1]["step"] != warmup_steps:
        raise ValueError(f"no round ends at the warm-up's end (step {warmup_steps})")
    warm_step_s = warm[-1]["wall_s"] / warm[-1]["step"]
    update_wall = update_steps = update_s = updates = 0.0
    for before, row in zip(metrics, metrics[1:]):
        if before["step"] < warmup_steps:
            continue
        update_wall += row["wall_s"] - before["wall_s"]
        update_steps += row["step"] - before["step"]
        update_s += row["time_update_s"]
        updates += row["updates"] - before["updates"]
    if update_steps == 0:
        raise ValueError("no round ran updates for its whole length: raise --rounds")
    return {
        "warmup_step_s": warm_step_s,
        "loop_step_s": update_wall / update_steps,
        "updates_per_s": updates / update_wall,
        "learner_share": update_s / update_wall,
        "eval_s_per_episode": evaluation["wall_s"] / eval_episodes,
    }


def project(rates, steps_per_task, warmup_steps, eval_every, eval_episodes):
    """Wall seconds of a whole run at the given budget, by part."""
    warmup = min(warmup_steps, steps_per_task)
    evaluations = math.ceil(steps_per_task / eval_every) if eval_every > 0 else 1
    parts = {
        "warmup_s": warmup * rates["warmup_step_s"],
        "training_s": (steps_per_task - warmup) * rates["loop_step_s"],
        "evaluation_s": evaluations * eval_episodes * rates["eval_s_per_episode"],
    }
    parts["total_s"] = sum(parts.values())
    parts["evaluations"] = evaluations
    return parts


def _resolved_config(cli, config):
    """The config with every default filled in, as the trainer resolves it."""
    done = subprocess.run([cli, "train", config, "--print-config"], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"protocol_cost.py: {config}: {done.stderr.strip().splitlines()[-1:]}")
    return json.loads(done.stdout)


def _human(seconds):
    if seconds >= 2 * 86400:
        return f"{seconds / 86400:.1f} days"
    if seconds >= 2 * 3600:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 60:.1f} min"


def run_protocol(cli, name, spec, args):
    config = str(REPO / spec["config"])  # --config's path is absolute
    round_steps = args.round_steps
    experiment = _resolved_config(cli, config)["experiment"]
    eval_every, eval_episodes = experiment["eval_every"], experiment["eval_episodes"]
    warmup_steps = experiment["warmup_steps"]
    steps_per_task = spec.get("steps_per_task") or experiment["steps_per_task"]
    work = pathlib.Path(tempfile.mkdtemp(prefix=f"protocol_cost_{name}_"))
    overrides = [
        f"experiment.warmup_steps={round_steps}",
        f"experiment.steps_per_task={round_steps * (1 + args.rounds)}",
        "experiment.eval_every=0",  # one evaluation, at the end
        f"experiment.eval_episodes={args.eval_episodes}",
        "experiment.checkpoint_every=0",
        f"experiment.num_threads={args.threads}",
        f"experiment.run_dir={work}/run",
    ]
    if spec.get("batch_per_task"):
        overrides.append(f"agent.batch_size={spec['batch_per_task']}")
    overrides += args.override
    env = dict(os.environ, OPENBLAS_NUM_THREADS=str(args.threads))
    print(f"[{name}] {cli} train {config} {' '.join(overrides)}", file=sys.stderr, flush=True)
    done = subprocess.run([cli, "train", config, *overrides], env=env, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"protocol_cost.py: training {name} failed: {done.stderr.strip().splitlines()[-1:]}")
    metrics = _read_jsonl(work / "run" / "metrics.jsonl")
    evaluation = _read_jsonl(work / "run" / "eval.jsonl")[-1]
    rates = measure_rates(metrics, evaluation, args.eval_episodes, round_steps)
    parts = project(rates, steps_per_task, warmup_steps, eval_every, eval_episodes)
    summary = json.loads((work / "run" / "summary.json").read_text())
    if not args.keep:
        shutil.rmtree(work)
    return {
        "protocol": name, "config": spec["config"], "steps_per_task": steps_per_task,
        "batch_per_task": spec.get("batch_per_task"), "eval_every": eval_every,
        "eval_episodes": eval_episodes, "threads": args.threads, "rates": rates,
        "projection": parts, "batch": (spec.get("batch_per_task") or 0) * summary["num_envs"],
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=__doc__.split("\n\n", 2)[2])
    parser.add_argument("--protocol", nargs="+", choices=sorted(PROTOCOLS), default=["mt10", "mt50"])
    parser.add_argument("--config", help="instead of --protocol: any off-policy config, at its own "
                        "budget and batch")
    parser.add_argument("--rounds", type=int, default=2, help="rounds of updates measured (default 2)")
    parser.add_argument("--round-steps", type=int, default=500,
                        help="loop steps per round: the envs' episode length (Meta-World: 500)")
    parser.add_argument("--eval-episodes", type=int, default=5,
                        help="evaluation episodes per task measured, scaled to the config's")
    parser.add_argument("--threads", type=int, default=os.cpu_count(),
                        help="executor and BLAS threads (default: every core)")
    parser.add_argument("--override", action="append", default=[], metavar="KEY=VALUE",
                        help="an extra config override for every protocol's run")
    parser.add_argument("--cli", default=os.environ.get("MANYWORLDS_CLI", str(REPO / "build/manyworlds")))
    parser.add_argument("--keep", action="store_true", help="keep the measured runs' directories")
    parser.add_argument("--json", help="write the measurements and projections here")
    args = parser.parse_args()
    if args.rounds < 1 or args.round_steps < 1 or args.eval_episodes < 1 or args.threads < 1:
        parser.error("--rounds, --round-steps, --eval-episodes and --threads must be at least 1")
    cli = os.path.abspath(args.cli)
    if not os.access(cli, os.X_OK):
        parser.error(f"--cli {cli}: not an executable (build the project, or pass --cli)")
    if args.config:
        if not os.path.isfile(args.config):
            parser.error(f"--config {args.config}: no such file")
        runs = [("config", {"config": os.path.abspath(args.config)})]
    else:
        runs = [(name, PROTOCOLS[name]) for name in args.protocol]
    results = [run_protocol(cli, name, spec, args) for name, spec in runs]
    print("| protocol | batch | threads | updates/s | learner share | loop step | "
          "training | evaluations (upper bound) | total |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in results:
        p, rates = r["projection"], r["rates"]
        print(f"| {r['protocol'].upper()}, {r['steps_per_task'] / 1e6:g}M steps/task | {r['batch'] or 'config'} | "
              f"{r['threads']} | {rates['updates_per_s']:.1f} | {rates['learner_share']:.0%} | "
              f"{rates['loop_step_s'] * 1e3:.1f} ms | {_human(p['warmup_s'] + p['training_s'])} | "
              f"{p['evaluations']} x {r['eval_episodes']} eps: {_human(p['evaluation_s'])} | "
              f"{_human(p['total_s'])} |")
    if args.json:
        path = pathlib.Path(args.json)
        tmp = path.with_suffix(path.suffix + ".tmp")
        tmp.write_text(json.dumps(results, indent=2) + "\n")
        tmp.replace(path)


if __name__ == "__main__":
    main()
