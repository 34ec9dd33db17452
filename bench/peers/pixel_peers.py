#!/usr/bin/env python3
"""Pixel learners' updates (`manyworlds bench agent --algo sac_ae|deepmdp|hipbmdp`) against their
plain PyTorch peer (bench/peers/pixel_update.py), interleaved in one run.

Sizes: MTRL's DeepMind Control networks (2 x 1024 actor and critics, 4 x 32 convolutions to 50
features, action 2 as the finger's) on 9-channel frames (3 stacked RGB) of 84 x 84 (MTEnv's) with
32 rows, and of 48 x 48 with 128 rows; hipbmdp with 4 tasks (rows split between them). Each round
runs every configuration on both sides back to back, the side that goes first alternating between
rounds; one thread each side. The C++ binary is copied aside first. Writes the log to
bench/logs/pixel_peers_<UTC date>.log unless --log says otherwise.

    /usr/bin/python3 bench/peers/pixel_peers.py            # 3 rounds, about 10 minutes
"""

from interleave import Session

# (frame, rows in all, updates per repeat)
CONFIGS = [(84, 32, 2), (48, 128, 2)]
ALGOS = ["sac_ae", "deepmdp", "hipbmdp"]


def main():
    s = Session("pixel_peers", __doc__.split("\n\n")[0], "pixel_update.py")

    def flags(algo, frame, rows, updates):
        tasks = 4 if algo == "hipbmdp" else 1
        return ["--algo", algo, "--tasks", str(tasks), "--batch", str(rows // tasks), "--frame",
                str(frame), "--channels", "9", "--hidden", "1024", "--layers", "2",
                "--action-dim", "2", "--updates", str(updates), "--repeats", "3"]

    def one_round(sides):
        for frame, rows, updates in CONFIGS:
            for algo in ALGOS:
                for side in sides:
                    s.record(algo, f"{rows} x {frame}^2", side,
                             s.run(side, flags(algo, frame, rows, updates)))

    s.rounds(one_round)
    s.table("learner", "rows x frame",
            [(algo, f"{rows} x {frame}^2", algo, algo) for frame, rows, _ in CONFIGS
             for algo in ALGOS])


if __name__ == "__main__":
    main()
