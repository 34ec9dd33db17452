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

from interleave import Session

# (label, gradnorm, batch, updates per repeat)
CONFIGS = [
    ("MT-SAC + GradNorm", True, 320, 10), ("MT-SAC + GradNorm", True, 1280, 3),
    ("MT-SAC", False, 320, 10), ("MT-SAC", False, 1280, 3),
]


def main():
    s = Session("gradnorm_peers", __doc__.split("\n\n")[0], "sac_update.py")

    def one_round(sides):
        for label, gradnorm, batch, updates in CONFIGS:
            flags = s.common(batch, updates) + (["--gradnorm"] if gradnorm else [])
            for side in sides:
                s.record(label, batch, side,
                         s.run(side, (["--disentangled-alpha"] + flags) if side == "cpp" else flags))

    s.rounds(one_round)
    s.table("learner", "batch", [(label, batch, label, label) for label, _, batch, _ in CONFIGS])


if __name__ == "__main__":
    main()
