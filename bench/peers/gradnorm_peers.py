#!/usr/bin/env python3
"""MT-SAC with GradNorm (`bench agent --gradnorm`) against its plain PyTorch peer
(`bench/peers/sac_update.py --gradnorm`), interleaved in one run, with plain MT-SAC (no
GradNorm) on both sides in the same rounds for reference.

MT10 sizes: obs 39, action 4, 10 tasks, 3 x 400, one temperature per task
(`--disentangled-alpha`); batch 320 and 1,280 (equally many rows per task, shuffled, on both
sides with --gradnorm; the plain MT-SAC peer draws task indices uniformly, which costs the same).
The same machinery as task_trunk_peers.py: each round runs every configuration on both sides back
to back, the side that goes first alternating between rounds; one libtorch / torch thread and
one OpenBLAS thread each side (OPENBLAS_NUM_THREADS=OMP_NUM_THREADS=MKL_NUM_THREADS=1); every
run is `--repeats 3` of `--updates` after 3 warm-up updates and reports its median; the table
gives the medians over rounds and the per-round ratios (manyworlds / peer). The C++ binary is
copied aside before the first run. Writes the log to bench/logs/gradnorm_peers_<UTC date>.log
unless --log says otherwise.

    /usr/bin/python3 bench/peers/gradnorm_peers.py            # 3 rounds, about 3 minutes
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
# (label, gradnorm, batch, updates per repeat)
CONFIGS = [
    ("MT-SAC + GradNorm", True, 320, 10), ("MT-SAC + GradNorm", True, 1280, 3),
    ("MT-SAC", False, 320, 10), ("MT-SAC", False, 1280, 3),
]
REPEATS = 3
CPU_CMD = "lscpu | grep -m1 'Model name' | sed 's/.*: *//'"
SIZES = ["--hidden", "400", "--layers", "3", "--obs-dim", "39", "--action-dim", "4"]


def main():
    today = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--cli", default=os.path.join(ROOT, "build", "manyworlds"))
    p.add_argument("--python", default="/usr/bin/python3", help="the peer's Python (with torch)")
    p.add_argument("--tasks", type=int, default=10)
    p.add_argument("--log", default=os.path.join(ROOT, "bench", "logs",
                                                 f"gradnorm_peers_{today}.log"))
    args = p.parse_args()

    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    tmp = tempfile.mkdtemp()
    cli = os.path.join(tmp, "manyworlds")
    shutil.copy2(args.cli, cli)
    peer = os.path.join(ROOT, "bench", "peers", "sac_update.py")
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

    out(f"# gradnorm_peers.py, started {now()}")
    out(f"# argv: {' '.join(sys.argv)}")
    out(f"# repository: {sh(f'git -C {ROOT} rev-parse HEAD')}; uncommitted C++ sources: "
        f"{sh(f'git -C {ROOT} status --short -- src | wc -l')} paths")
    out(f"# C++ binary: {args.cli}, modified "
        f"{sh(f'date -u -r {args.cli} +%Y-%m-%dT%H:%M:%SZ')}, sha256 "
        f"{sh(f'sha256sum {cli}').split()[0]} (run from a copy)")
    out(f"# peer Python: {args.python}, " + sh(
        f"{args.python} -c 'import sys, torch; print(sys.version.split()[0], torch.__version__)'"))
    out(f"# CPU: {sh(CPU_CMD)}, "
        f"{os.cpu_count()} CPUs; {sh('. /etc/os-release; echo $PRETTY_NAME')}")
    out(f"# threads: torch 1 and OpenBLAS 1 on both sides; environment of every run: "
        f"OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 MKL_NUM_THREADS=1; nice {os.nice(0)}")
    out(f"# other processes (top by CPU): " + sh(
        "ps -eo ni,pcpu,comm --sort=-pcpu | head -6 | tail -5 | tr -s ' ' | paste -sd ';'"))

    def run(side, gradnorm, batch, updates):
        common = ["--tasks", str(args.tasks), "--batch", str(batch), "--updates", str(updates),
                  "--repeats", str(REPEATS)] + SIZES + (["--gradnorm"] if gradnorm else [])
        if side == "cpp":
            cmd = [cli, "bench", "agent", "--disentangled-alpha", "--torch-threads", "1",
                   "--blas-threads", "1", "--json"] + common
        else:
            cmd = [args.python, peer, "--threads", "1"] + common
        r = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
        result = json.loads(r.stdout)
        shown = ([os.path.relpath(args.cli, ROOT)] + cmd[1:] if side == "cpp"
                 else [args.python, os.path.relpath(peer, ROOT)] + cmd[2:])
        out(f"run {side}: {' '.join(shown)}")
        out(f"  {json.dumps(result)}")
        return result["updates_per_s"]

    rates = {}  # (label, batch, side) -> [rate per round]
    for rnd in range(args.rounds):
        out(f"\n## round {rnd + 1}/{args.rounds}, load average {loadavg()}")
        sides = ["cpp", "py"] if rnd % 2 == 0 else ["py", "cpp"]
        for label, gradnorm, batch, updates in CONFIGS:
            for side in sides:
                rates.setdefault((label, batch, side), []).append(
                    run(side, gradnorm, batch, updates))
        out(f"# round {rnd + 1}: " + ", ".join(
            f"{k[0]} {k[1]} {k[2]} {v[-1]:.2f}" for k, v in rates.items() if len(v) == rnd + 1))
    out(f"\n# finished {now()}, load average {loadavg()}")

    def fmt(values):
        return ", ".join(f"{v:.2f}" for v in values)

    out("\n| learner | batch | manyworlds (updates/s, median) | PyTorch peer | "
        "ratio (median of rounds) | range | manyworlds per round | peer per round |")
    out("|---|---:|---:|---:|---:|---|---|---|")
    for label, _, batch, _ in CONFIGS:
        cpp, py = rates[(label, batch, "cpp")], rates[(label, batch, "py")]
        ratios = [c / q for c, q in zip(cpp, py)]
        out(f"| {label} | {batch} | {statistics.median(cpp):.2f} | {statistics.median(py):.2f} | "
            f"{statistics.median(ratios):.2f} | {min(ratios):.2f}-{max(ratios):.2f} | "
            f"{fmt(cpp)} | {fmt(py)} |")
    log.close()
    shutil.rmtree(tmp)
    print(f"log: {os.path.relpath(args.log, ROOT)}")


if __name__ == "__main__":
    main()
