"""Shared machinery of the interleaved learner drivers (task_trunk_peers.py, distral_peers.py,
gradnorm_peers.py): `manyworlds bench agent` against a PyTorch-in-Python peer script, every
configuration on both sides back to back in each round, the side that goes first alternating
between rounds, one thread each side (`--torch-threads 1 --blas-threads 1` and `--threads 1`,
OPENBLAS_NUM_THREADS=OMP_NUM_THREADS=MKL_NUM_THREADS=1 in every run's environment).

The C++ binary is copied aside before the first run (a rebuild during the run cannot change it).
The log (header with repository, binary hash, Python, CPU and load; every command and its JSON;
the table) goes to bench/logs/<name>_<UTC date>.log unless --log says otherwise.
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
REPEATS = 3
CPU_CMD = "lscpu | grep -m1 'Model name' | sed 's/.*: *//'"
ENV = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")


def _now():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")


def _sh(cmd):
    return subprocess.run(cmd, shell=True, capture_output=True, text=True).stdout.strip()


def _loadavg():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


class Session:
    """Parses the common flags, copies the binary, opens the log and writes its header."""

    def __init__(self, name, description, peer_script, add_arguments=None):
        today = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")
        p = argparse.ArgumentParser(description=description)
        p.add_argument("--rounds", type=int, default=3)
        p.add_argument("--cli", default=os.path.join(ROOT, "build", "manyworlds"))
        p.add_argument("--python", default="/usr/bin/python3",
                       help="the peer's Python (with torch)")
        p.add_argument("--tasks", type=int, default=10)
        p.add_argument("--log", default=os.path.join(ROOT, "bench", "logs", f"{name}_{today}.log"))
        if add_arguments:  # the script's own flags
            add_arguments(p)
        self.args = p.parse_args()
        self.tmp = tempfile.mkdtemp()
        self.cli = os.path.join(self.tmp, "manyworlds")
        shutil.copy2(self.args.cli, self.cli)
        self.peer = os.path.join(ROOT, "bench", "peers", peer_script)
        self.log = open(self.args.log, "w")
        self.rates = {}  # (label, batch, side) -> [rate per round]
        a = self.args
        self.out(f"# {name}.py, started {_now()}")
        self.out(f"# argv: {' '.join(sys.argv)}")
        self.out(f"# repository: {_sh(f'git -C {ROOT} rev-parse HEAD')}; uncommitted C++ sources: "
                 f"{_sh(f'git -C {ROOT} status --short -- src | wc -l')} paths")
        self.out(f"# C++ binary: {a.cli}, modified "
                 f"{_sh(f'date -u -r {a.cli} +%Y-%m-%dT%H:%M:%SZ')}, sha256 "
                 f"{_sh(f'sha256sum {self.cli}').split()[0]} (run from a copy)")
        self.out(f"# peer Python: {a.python}, " + _sh(
            f"{a.python} -c 'import sys, torch; print(sys.version.split()[0], torch.__version__)'"))
        self.out(f"# CPU: {_sh(CPU_CMD)}, "
                 f"{os.cpu_count()} CPUs; {_sh('. /etc/os-release; echo $PRETTY_NAME')}")
        self.out("# threads: torch 1 and OpenBLAS 1 on both sides; environment of every run: "
                 f"OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 MKL_NUM_THREADS=1; nice {os.nice(0)}")
        self.out("# other processes using CPU at the start (pid, nice, %cpu, command):\n# " + _sh(
            "ps -eo pid,ni,pcpu,comm --sort=-pcpu --no-headers | head -6").replace("\n", "\n# "))

    def out(self, line=""):
        print(line, flush=True)
        self.log.write(line + "\n")
        self.log.flush()

    def common(self, batch, updates):
        """--tasks, --batch, --updates, --repeats and the MT10 network sizes."""
        return ["--tasks", str(self.args.tasks), "--batch", str(batch), "--updates", str(updates),
                "--repeats", str(REPEATS)] + SIZES

    def run(self, side, flags):
        """One run: side "cpp" is `manyworlds bench agent --torch-threads 1 --blas-threads 1
        --json FLAGS`, "py" is `PEER --threads 1 FLAGS`. Logs it; returns its updates/s."""
        if side == "cpp":
            cmd = [self.cli, "bench", "agent", "--torch-threads", "1", "--blas-threads", "1",
                   "--json"] + flags
            shown = [os.path.relpath(self.args.cli, ROOT)] + cmd[1:]
        else:
            cmd = [self.args.python, self.peer, "--threads", "1"] + flags
            shown = [self.args.python, os.path.relpath(self.peer, ROOT)] + cmd[2:]
        result = json.loads(subprocess.run(cmd, env=ENV, capture_output=True, text=True,
                                           check=True).stdout)
        self.out(f"run {side}: {' '.join(shown)}")
        self.out(f"  {json.dumps(result, separators=(',', ':'))}")
        return result["updates_per_s"]

    def record(self, label, batch, side, rate):
        self.rates.setdefault((label, batch, side), []).append(rate)

    def rounds(self, one_round):
        """Calls one_round(sides) per round, sides ["cpp", "py"] or reversed in alternate rounds."""
        for rnd in range(self.args.rounds):
            self.out(f"\n## round {rnd + 1}/{self.args.rounds}, load average {_loadavg()}")
            one_round(["cpp", "py"] if rnd % 2 == 0 else ["py", "cpp"])
            self.out(f"# round {rnd + 1}: " + ", ".join(
                f"{k[0]} {k[1]} {k[2]} {v[-1]:.2f}" for k, v in self.rates.items()
                if len(v) == rnd + 1))
        self.out(f"\n# finished {_now()}, load average {_loadavg()}")

    def table(self, first_column, batch_column, rows):
        """rows: (label, batch, cpp label, peer label); prints the Markdown table, closes."""
        def fmt(values):
            return ", ".join(f"{v:.2f}" for v in values)
        self.out(f"\n| {first_column} | {batch_column} | manyworlds (updates/s, median) | "
                 "PyTorch peer | ratio (median of rounds) | range | manyworlds per round | "
                 "peer per round |")
        self.out("|---|---:|---:|---:|---:|---|---|---|")
        for label, batch, cpp_label, py_label in rows:
            cpp = self.rates[(cpp_label, batch, "cpp")]
            py = self.rates[(py_label, batch, "py")]
            ratios = [c / q for c, q in zip(cpp, py)]
            self.out(f"| {label} | {batch} | {statistics.median(cpp):.2f} | "
                     f"{statistics.median(py):.2f} | {statistics.median(ratios):.2f} | "
                     f"{min(ratios):.2f}-{max(ratios):.2f} | {fmt(cpp)} | {fmt(py)} |")
        self.log.close()
        shutil.rmtree(self.tmp)
        print(f"log: {os.path.relpath(self.args.log, ROOT)}")
