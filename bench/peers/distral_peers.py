#!/usr/bin/env python3
"""Distral updates (`manyworlds bench agent --algo distral`) against their plain PyTorch peer
(bench/peers/distral_update.py), interleaved in one run; the driver of task_trunk_peers.py for
Distral, whose command lines differ (--algo distral, --batch per task agent, no architecture).

MT10 sizes: obs 39, action 4, 10 task agents, 3 x 400, distral_alpha 1.0 (both sides' default);
32 rows per task agent (320 rows, the shipped MT10 configs' batch) and 128 (1,280 rows, the
authors'). Each round runs every configuration on both sides back to back, the side that goes
first alternating between rounds; both sides one thread: `--torch-threads 1 --blas-threads 1`
and `--threads 1`, with OPENBLAS_NUM_THREADS=OMP_NUM_THREADS=MKL_NUM_THREADS=1 for both. Every
run is `--repeats 3` of the configuration's `--updates` after 3 warm-up updates (the same on
both sides) and reports its median; the table gives the medians over rounds and the per-round
ratios (manyworlds / peer). One more peer run per round and batch with
`--no-critic-weight-grads` (the critics' weight gradients in the actor losses not computed,
as manyworlds does) shows what that part of the peer's extra work costs.

The C++ binary is copied aside before the first run (a rebuild during the run cannot change
it). Writes the log (commands, load averages, every run's JSON) to
bench/logs/distral_peers_<UTC date>.log unless --log says otherwise.

    /usr/bin/python3 bench/peers/distral_peers.py            # 3 rounds, about 1-2 minutes
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
# (rows per task agent, updates per repeat): about 1-4 s per run on one core.
CONFIGS = [(32, 10), (128, 4)]
REPEATS = 3
SIZES = ["--hidden", "400", "--layers", "3", "--obs-dim", "39", "--action-dim", "4"]
VARIANT = "no critic weight grads"


def main():
    today = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--cli", default=os.path.join(ROOT, "build", "manyworlds"))
    p.add_argument("--python", default="/usr/bin/python3", help="the peer's Python (with torch)")
    p.add_argument("--tasks", type=int, default=10)
    p.add_argument("--log", default=os.path.join(ROOT, "bench", "logs",
                                                 f"distral_peers_{today}.log"))
    args = p.parse_args()

    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    tmp = tempfile.mkdtemp()
    cli = os.path.join(tmp, "manyworlds")
    shutil.copy2(args.cli, cli)
    peer = os.path.join(ROOT, "bench", "peers", "distral_update.py")
    log = open(args.log, "w")

    def out(line=""):
        print(line, flush=True)
        log.write(line + "\n")
        log.flush()

    def sh(cmd):
        return subprocess.run(cmd, shell=True, capture_output=True, text=True).stdout.strip()

    def loadavg():
        with open("/proc/loadavg") as f:
            return " ".join(f.read().split()[:3])

    def now():
        return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")

    cpu = sh("lscpu | grep -m1 'Model name' | sed 's/.*: *//'")
    out(f"# distral_peers.py, started {now()}")
    out(f"# argv: {' '.join(sys.argv)}")
    out(f"# repository: {sh(f'git -C {ROOT} rev-parse HEAD')}; uncommitted C++ sources: "
        f"{sh(f'git -C {ROOT} status --short -- src | wc -l')} paths")
    out(f"# C++ binary: {args.cli}, modified "
        f"{sh(f'date -u -r {args.cli} +%Y-%m-%dT%H:%M:%SZ')}, sha256 "
        f"{sh(f'sha256sum {cli}').split()[0]} (run from a copy)")
    out(f"# peer Python: {args.python}, " + sh(
        f"{args.python} -c 'import sys, torch; print(sys.version.split()[0], torch.__version__)'"))
    out(f"# CPU: {cpu}, {os.cpu_count()} CPUs; {sh('. /etc/os-release; echo $PRETTY_NAME')}")
    out(f"# threads: torch 1 and OpenBLAS 1 on both sides; environment of every run: "
        f"OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 MKL_NUM_THREADS=1; nice {os.nice(0)}")
    out(f"# other processes using CPU at the start (pid, nice, %cpu, command):\n# " + sh(
        "ps -eo pid,ni,pcpu,comm --sort=-pcpu --no-headers | head -6").replace("\n", "\n# "))

    def run(side, batch, updates, extra=()):
        common = ["--tasks", str(args.tasks), "--batch", str(batch), "--updates", str(updates),
                  "--repeats", str(REPEATS)] + SIZES
        if side == "cpp":
            cmd = [cli, "bench", "agent", "--algo", "distral", "--torch-threads", "1",
                   "--blas-threads", "1", "--json"] + common
        else:
            cmd = [args.python, peer, "--threads", "1"] + common + list(extra)
        r = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
        result = json.loads(r.stdout)
        shown = ([os.path.relpath(args.cli, ROOT)] + cmd[1:] if side == "cpp"
                 else [args.python, os.path.relpath(peer, ROOT)] + cmd[2:])
        out(f"run {side}: {' '.join(shown)}")
        out(f"  {json.dumps(result, separators=(',', ':'))}")
        return result["updates_per_s"]

    rates = {}  # (label, batch, side) -> [rate per round]
    for rnd in range(args.rounds):
        out(f"\n## round {rnd + 1}/{args.rounds}, load average {loadavg()}")
        sides = ["cpp", "py"] if rnd % 2 == 0 else ["py", "cpp"]
        for batch, updates in CONFIGS:
            for side in sides:
                rates.setdefault(("distral", batch, side), []).append(run(side, batch, updates))
            rates.setdefault((VARIANT, batch, "py"), []).append(
                run("py", batch, updates, ["--no-critic-weight-grads"]))
        out(f"# round {rnd + 1}: " + ", ".join(
            f"{k[0]} {k[1]} {k[2]} {v[-1]:.2f}" for k, v in rates.items() if len(v) == rnd + 1))
    out(f"\n# finished {now()}, load average {loadavg()}")

    def fmt(values):
        return ", ".join(f"{v:.2f}" for v in values)

    out("\n| peer | rows per task | manyworlds (updates/s, median) | PyTorch peer | "
        "ratio (median of rounds) | range | manyworlds per round | peer per round |")
    out("|---|---:|---:|---:|---:|---|---|---|")
    for label in ("distral", VARIANT):
        for batch, _ in CONFIGS:
            cpp = rates[("distral", batch, "cpp")]
            py = rates[(label, batch, "py")]
            ratios = [x / y for x, y in zip(cpp, py)]
            out(f"| {label} | {batch} | {statistics.median(cpp):.2f} | "
                f"{statistics.median(py):.2f} | {statistics.median(ratios):.2f} | "
                f"{min(ratios):.2f}-{max(ratios):.2f} | {fmt(cpp)} | {fmt(py)} |")
    log.close()
    shutil.rmtree(tmp)
    print(f"log: {os.path.relpath(args.log, ROOT)}")


if __name__ == "__main__":
    main()
