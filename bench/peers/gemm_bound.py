#!/usr/bin/env python3
"""How close a PPO epoch can get to the CPU's matrix-multiply limit.

A PPO epoch of `bench agent --algo ppo` (Gaussian policy and value MLPs with
`--layers` tanh layers of `--hidden`, `--obs-dim` inputs, `--action-dim`
outputs, minibatch `--minibatch`) spends its FLOPs in matrix products: per
linear layer one forward product, one weight-gradient product and, except for
the first layer (observations need no gradient), one input-gradient product.
This times exactly those products, each shape on its own with torch.mm, on
`--threads` threads, and reports:

- the epoch's FLOPs per sample;
- the products' rate (GFLOP/s) at these shapes;
- `bound_samples_per_s`: samples per second if an epoch did nothing but these
  products at that rate (no elementwise work, no optimizer, no overhead).

Compare `bench agent --algo ppo --json` and `bench/peers/ppo_epoch.py` with the
bound, from the same process count and threads, on the same machine.

    python3 bench/peers/gemm_bound.py --minibatch 1000 --hidden 256 --layers 2 --threads 1
"""
import argparse
import json
import statistics
import time

import torch


def layer_products(m, widths):
    """(rows, inner, cols) of every product of one network's fwd + bwd."""
    shapes = []
    for i in range(len(widths) - 1):
        k, n = widths[i], widths[i + 1]
        shapes.append((m, k, n))          # forward: x (m, k) @ W^T (k, n)
        shapes.append((n, m, k))          # weight gradient: g^T (n, m) @ x (m, k)
        if i > 0:
            shapes.append((m, n, k))      # input gradient: g (m, n) @ W (n, k)
    return shapes


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--minibatch", type=int, default=1000)
    p.add_argument("--hidden", type=int, default=256)
    p.add_argument("--layers", type=int, default=2)
    p.add_argument("--obs-dim", type=int, default=39)
    p.add_argument("--action-dim", type=int, default=4)
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--repeats", type=int, default=7)
    args = p.parse_args()
    torch.set_num_threads(args.threads)
    m = args.minibatch
    hidden = [args.hidden] * args.layers
    shapes = (layer_products(m, [args.obs_dim] + hidden + [args.action_dim]) +
              layer_products(m, [args.obs_dim] + hidden + [1]))
    flops = sum(2 * a * b * c for a, b, c in shapes)
    mats = [(torch.randn(a, b), torch.randn(b, c), torch.empty(a, c)) for a, b, c in shapes]

    def once():
        for x, w, out in mats:
            torch.mm(x, w, out=out)

    for _ in range(20):
        once()
    times = []
    for _ in range(args.repeats):
        reps = 50
        t0 = time.perf_counter()
        for _ in range(reps):
            once()
        times.append((time.perf_counter() - t0) / reps)
    t = statistics.median(times)
    print(json.dumps({
        "minibatch": m, "hidden": args.hidden, "layers": args.layers, "threads": args.threads,
        "flops_per_sample": flops / m,
        "gemm_gflops": flops / t / 1e9,
        "bound_samples_per_s": m / t,
        "torch": torch.__version__,
    }))


if __name__ == "__main__":
    main()
