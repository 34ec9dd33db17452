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

from interleave import Session

# (rows per task agent, updates per repeat): about 1-4 s per run on one core.
CONFIGS = [(32, 10), (128, 4)]
VARIANT = "no critic weight grads"


def main():
    s = Session("distral_peers", __doc__.split("\n\n")[0], "distral_update.py")

    def one_round(sides):
        for batch, updates in CONFIGS:
            flags = s.common(batch, updates)
            for side in sides:
                s.record("distral", batch, side,
                         s.run(side, (["--algo", "distral"] + flags) if side == "cpp" else flags))
            s.record(VARIANT, batch, "py", s.run("py", flags + ["--no-critic-weight-grads"]))

    s.rounds(one_round)
    s.table("peer", "rows per task",
            [(label, batch, "distral", label) for label in ("distral", VARIANT)
             for batch, _ in CONFIGS])


if __name__ == "__main__":
    main()
