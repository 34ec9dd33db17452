"""What manyworlds-sweep costs over `manyworlds train` alone, and whether it keeps the cores busy.

    .venv-py/bin/python bench/sweep_overhead.py [--runs 8] [--cpus 2] [--steps 3000] [--repeats 3]

A point-navigation SAC config of about 4 s per run (one thread). Per repeat, interleaved:
  alone: the runs one after another with `manyworlds train` (each run's wall time);
  sweep: the same runs (other seeds' directories) as one sweep on a local Ray instance with
         --cpus CPUs, Ray's start and stop included.
Printed: the median of the runs' times alone, the sweep's wall time, the ideal wall time
(sum alone / cpus), and the overhead per run: (sweep wall x cpus - sum alone) / runs, which
counts Ray's start, scheduling, the launches and any idle core. Medians over repeats.
"""

import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

CONFIG = """\
env:
  id: point-nav
  num_tasks: 3
  options: {horizon: 50}
agent: {algo: sac, hidden_dim: 16, num_layers: 2, batch_size: 32}
replay: {capacity: 5000}
experiment:
  warmup_steps: 100
  eval_every: 1000
  eval_episodes: 2
  checkpoint_every: 1000
  num_threads: 1
"""


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=8)
    parser.add_argument("--cpus", type=int, default=os.cpu_count())
    parser.add_argument("--steps", type=int, default=3000, help="steps per task of each run")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--cli", default=os.environ.get("MANYWORLDS_CLI", "build/manyworlds"))
    args = parser.parse_args()
    cli = os.path.abspath(args.cli)
    work = pathlib.Path(tempfile.mkdtemp(prefix="sweep_overhead_"))
    config = work / "config.yaml"
    config.write_text(CONFIG)
    env = dict(os.environ, MANYWORLDS_CLI=cli, OPENBLAS_NUM_THREADS="1")
    rows = []
    for repeat in range(args.repeats):
        alone = []
        for i in range(args.runs):
            start = time.perf_counter()
            subprocess.run([cli, "train", str(config), f"experiment.steps_per_task={args.steps}",
                            f"experiment.seed={i + 1}",
                            f"experiment.run_dir={work}/alone_{repeat}_{i}"],
                           check=True, capture_output=True, env=env)
            alone.append(time.perf_counter() - start)
        sweep_file = work / f"sweep_{repeat}.yaml"
        sweep_file.write_text(f"seeds: {{first: 1, count: {args.runs}}}\n"
                              f"budget: {{steps_per_task: {args.steps}}}\n"
                              f"groups: [{config}]\n")
        start = time.perf_counter()
        subprocess.run([sys.executable, "-m", "manyworlds.sweep", "run", str(sweep_file),
                        "--out", str(work / f"sweep_{repeat}"), "--num-cpus", str(args.cpus)],
                       check=True, capture_output=True, env=env)
        sweep_wall = time.perf_counter() - start
        overhead = (sweep_wall * args.cpus - sum(alone)) / args.runs
        rows.append({"alone_median_s": statistics.median(alone), "alone_sum_s": sum(alone),
                     "sweep_wall_s": sweep_wall, "ideal_wall_s": sum(alone) / args.cpus,
                     "overhead_per_run_s": overhead})
        print(json.dumps(rows[-1]), flush=True)
    summary = {key: statistics.median(row[key] for row in rows) for key in rows[0]}
    summary.update(runs=args.runs, cpus=args.cpus, steps_per_task=args.steps,
                   repeats=args.repeats)
    print(f"{args.runs} runs of {summary['alone_median_s']:.2f} s (median alone) on {args.cpus} "
          f"CPUs: sweep {summary['sweep_wall_s']:.1f} s against {summary['ideal_wall_s']:.1f} s "
          f"ideal; overhead {summary['overhead_per_run_s']:.2f} s per run (medians of "
          f"{args.repeats})")
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
