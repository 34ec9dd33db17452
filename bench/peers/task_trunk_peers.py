#!/usr/bin/env python3
"""SAC updates of the multi-task architectures (mlp = MT-SAC, multihead, task_encoder, moe,
soft_modular, paco, moore) against their plain PyTorch peer (bench/peers/sac_update.py),
interleaved in one run.

MT10 sizes: obs 39, action 4, 10 tasks (task index drawn uniformly per row), 3 x 400, one
temperature per task; batch 320 (32 per task, the shipped configs') and 1,280 (128 per task, the
authors'). Each round runs every configuration on both sides back to back, the side that goes
first alternating between rounds; both sides one thread: `--torch-threads 1 --blas-threads 1`
and `--threads 1`, with OPENBLAS_NUM_THREADS=OMP_NUM_THREADS=MKL_NUM_THREADS=1 for both.
Every run is `--repeats 3` of the configuration's `--updates` after 3 warm-up updates (the
same on both sides) and reports its median; the table gives the medians over rounds and the
per-round ratios (manyworlds / peer).

`bench agent` has no switch for SAC's task_reweight, so its soft_modular is timed without it
and the peer's soft_modular rows run with `--task-reweight off`; one more peer run per round
and batch with the reweighting on (`soft_modular + reweight`) shows what it costs the peer.

The C++ binary is copied aside before the first run (a rebuild during the run cannot change
it). Writes the log (commands, load averages, every run's JSON) to
bench/logs/task_trunk_peers_<UTC date>.log unless --log says otherwise.

    /usr/bin/python3 bench/peers/task_trunk_peers.py            # 3 rounds, about 9 minutes
    /usr/bin/python3 bench/peers/task_trunk_peers.py --only mlp,multihead   # those rows only
"""

import argparse

from interleave import Session

# (label, architecture, batch, updates per repeat): about 2-9 s per run on one core.
CONFIGS = [
    ("mlp", "mlp", 320, 10), ("mlp", "mlp", 1280, 3),
    ("multihead", "multihead", 320, 10), ("multihead", "multihead", 1280, 3),
    ("task_encoder", "task_encoder", 320, 10), ("task_encoder", "task_encoder", 1280, 3),
    ("moe", "moe", 320, 8), ("moe", "moe", 1280, 3),
    ("soft_modular", "soft_modular", 320, 5), ("soft_modular", "soft_modular", 1280, 2),
    ("paco", "paco", 320, 2), ("paco", "paco", 1280, 1),
    ("moore", "moore", 320, 3), ("moore", "moore", 1280, 2),
]
REWEIGHT = "soft_modular + reweight"


def main():
    labels = sorted({label for label, _, _, _ in CONFIGS})

    def architectures(text):
        names = text.split(",")
        unknown = sorted(set(names) - set(labels))
        if unknown:
            raise argparse.ArgumentTypeError(
                f"unknown architecture {unknown[0]!r}; allowed: {', '.join(labels)}")
        return names

    def add_arguments(p):
        p.add_argument("--only", type=architectures, default=labels,
                       help="comma-separated architectures to run "
                            f"(default all: {','.join(labels)})")

    s = Session("task_trunk_peers", __doc__.split("\n\n")[0], "sac_update.py", add_arguments)
    only = s.args.only
    configs = [c for c in CONFIGS if c[0] in only]

    def one_round(sides):
        for label, arch, batch, updates in configs:
            flags = ["--architecture", arch] + s.common(batch, updates)
            peer_extra = ["--task-reweight", "off"] if arch == "soft_modular" else []
            for side in sides:
                s.record(label, batch, side,
                         s.run(side, (["--disentangled-alpha"] + flags) if side == "cpp"
                               else flags + peer_extra))
            if arch == "soft_modular":
                s.record(REWEIGHT, batch, "py", s.run("py", flags + ["--task-reweight", "on"]))

    s.rounds(one_round)
    rows = [(label, batch, label, label) for label, _, batch, _ in configs]
    if "soft_modular" in only:
        rows += [(REWEIGHT, batch, "soft_modular", REWEIGHT) for batch in (320, 1280)]
    s.table("architecture", "batch", rows)


if __name__ == "__main__":
    main()
