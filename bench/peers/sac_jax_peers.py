#!/usr/bin/env python3
"""SAC updates of manyworlds against both Python peers in one run: PyTorch eager
(bench/peers/sac_update.py, Debian's torch) and JAX with the whole update under `jax.jit`
(bench/peers/sac_update_jax.py, in the JAX environment named by --jax-python).

Sizes: obs 39, action 4, 3 x 400; plain SAC at batch 128, and MT-SAC (one-hot of 10 tasks, one
temperature per task) at batch 320 and 1,280. One thread on every side: `bench agent
--torch-threads 1 --blas-threads 1`, `sac_update.py --threads 1`, and the JAX peer bound to one
core (`--threads 1`), with OPENBLAS_NUM_THREADS=OMP_NUM_THREADS=MKL_NUM_THREADS=1. Each round
runs every configuration on the three sides back to back, the order rotating between rounds;
every run is the median of 3 repeats after 3 warm-up updates. The table gives the medians over
rounds and the median and range of the per-round ratios (manyworlds / peer). The log (every
command and its JSON) goes to bench/logs/sac_jax_peers_<UTC date>.log unless --log says
otherwise.

    python3 -m venv .venv-jax && .venv-jax/bin/pip install "jax[cpu]" optax
    /usr/bin/python3 bench/peers/sac_jax_peers.py --jax-python .venv-jax/bin/python
"""
import argparse
import datetime
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SIZES = ["--hidden", "400", "--layers", "3", "--obs-dim", "39", "--action-dim", "4"]
ENV = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
# (label, tasks, batch, updates per repeat)
CONFIGS = [("sac", 1, 128, 20), ("mt-sac", 10, 320, 10), ("mt-sac", 10, 1280, 3)]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--jax-python", required=True, help="a Python with jax and optax")
    p.add_argument("--cli", default=os.path.join(ROOT, "build", "manyworlds"))
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--log")
    args = p.parse_args()
    if args.rounds < 1:
        p.error("--rounds must be >= 1")
    for path in (args.cli, args.jax_python):
        if not os.access(path, os.X_OK):
            p.error(f"not an executable: {path}")
    date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")
    log_path = args.log or os.path.join(ROOT, "bench", "logs", f"sac_jax_peers_{date}.log")
    tmp = tempfile.mkdtemp()
    cli = os.path.join(tmp, "manyworlds")
    shutil.copy2(args.cli, cli)  # a rebuild during the run cannot change what is measured
    log = open(log_path, "w")

    def say(line):
        print(line)
        log.write(line + "\n")
        log.flush()

    cpu = subprocess.run("lscpu | grep -m1 'Model name' | sed 's/.*: *//'", shell=True,
                         capture_output=True, text=True).stdout.strip()
    say(f"# {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M:%S} UTC; {cpu}; "
        f"load {open('/proc/loadavg').read().split()[:3]}; binary {args.cli}")

    def command(side, tasks, batch, updates):
        common = ["--batch", str(batch), "--updates", str(updates), "--repeats", "3"] + SIZES
        if side == "manyworlds":
            extra = ["--tasks", str(tasks)] + (["--disentangled-alpha"] if tasks > 1 else [])
            return [cli, "bench", "agent", "--torch-threads", "1", "--blas-threads", "1",
                    "--json"] + extra + common
        script = "sac_update.py" if side == "pytorch" else "sac_update_jax.py"
        python = "/usr/bin/python3" if side == "pytorch" else args.jax_python
        return [python, os.path.join(ROOT, "bench", "peers", script), "--threads", "1",
                "--tasks", str(tasks)] + common

    sides = ["manyworlds", "pytorch", "jax"]
    rates = {}
    for r in range(args.rounds):
        order = sides[r % 3:] + sides[:r % 3]
        for label, tasks, batch, updates in CONFIGS:
            for side in order:
                cmd = command(side, tasks, batch, updates)
                run = subprocess.run(cmd, capture_output=True, text=True, env=ENV)
                if run.returncode != 0:
                    say(f"failed: {' '.join(cmd)}\n{run.stderr[-2000:]}")
                    sys.exit(1)
                try:  # bench agent prints one JSON document, the peers a line of it last
                    result = json.loads(run.stdout)
                except json.JSONDecodeError:
                    result = json.loads(run.stdout.strip().splitlines()[-1])
                say(f"round {r + 1}: {' '.join(cmd)}\n  {json.dumps(result, sort_keys=True)}")
                rates.setdefault((label, batch, side), []).append(result["updates_per_s"])
    say("")
    say("| update | batch | manyworlds | PyTorch eager | JAX jit | ours / PyTorch | ours / JAX |")
    say("|---|---:|---:|---:|---:|---:|---:|")
    for label, _, batch, _ in CONFIGS:
        ours = rates[(label, batch, "manyworlds")]
        cells = []
        for peer in ("pytorch", "jax"):
            ratios = [a / b for a, b in zip(ours, rates[(label, batch, peer)])]
            cells.append(f"{statistics.median(ratios):.2f} ({min(ratios):.2f}-{max(ratios):.2f})")
        say(f"| {label} | {batch} | {statistics.median(ours):.2f} | "
            f"{statistics.median(rates[(label, batch, 'pytorch')]):.2f} | "
            f"{statistics.median(rates[(label, batch, 'jax')]):.2f} | {cells[0]} | {cells[1]} |")
    say(f"log: {log_path}")


if __name__ == "__main__":
    main()
