#!/usr/bin/env python3
"""The peer of `manyworlds bench agent --algo ppo`: one PPO optimisation epoch
in plain PyTorch (Python), the same sizes and work.

Per minibatch: Gaussian MLP policy (tanh hidden layers, learned state-
independent log std clamped to [log 0.5, log 1.5]) forward, clipped surrogate,
backward, Adam step; value MLP (tanh) forward, MSE, backward, Adam step.
Reports samples pushed through one epoch per second (median of the repeats)
as JSON, like the C++ command.

    python3 bench/peers/ppo_epoch.py --batch 10000 --minibatch 1000 --hidden 256 --layers 2
"""
import argparse
import json
import math
import statistics
import time

import torch
from torch import nn


def mlp(inp, out, hidden, layers):
    mods, width = [], inp
    for _ in range(layers):
        mods += [nn.Linear(width, hidden), nn.Tanh()]
        width = hidden
    mods.append(nn.Linear(width, out))
    return nn.Sequential(*mods)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--batch", type=int, default=10000)
    p.add_argument("--minibatch", type=int, default=1000)
    p.add_argument("--hidden", type=int, default=256)
    p.add_argument("--layers", type=int, default=2)
    p.add_argument("--obs-dim", type=int, default=39)
    p.add_argument("--action-dim", type=int, default=4)
    p.add_argument("--updates", type=int, default=5, help="epochs per repeat")
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--threads", type=int, default=0, help="torch threads (0: torch's default)")
    args = p.parse_args()
    if args.threads > 0:
        torch.set_num_threads(args.threads)
    torch.manual_seed(0)
    policy = mlp(args.obs_dim, args.action_dim, args.hidden, args.layers)
    log_std = nn.Parameter(torch.zeros(args.action_dim))
    value = mlp(args.obs_dim, 1, args.hidden, args.layers)
    popt = torch.optim.Adam(list(policy.parameters()) + [log_std], lr=3e-4)
    vopt = torch.optim.Adam(value.parameters(), lr=3e-4)
    b = args.batch
    obs = torch.randn(b, args.obs_dim)
    actions = torch.randn(b, args.action_dim)
    old_log_probs = torch.randn(b)
    advantages = torch.randn(b)
    returns = torch.randn(b)
    lo, hi = math.log(0.5), math.log(1.5)

    def epoch():
        perm = torch.randperm(b)
        for start in range(0, b, args.minibatch):
            rows = perm[start:start + args.minibatch]
            mean = policy(obs[rows])
            std = log_std.clamp(lo, hi).exp().expand_as(mean)
            dist = torch.distributions.Normal(mean, std)
            ratio = (dist.log_prob(actions[rows]).sum(-1) - old_log_probs[rows]).exp()
            adv = advantages[rows]
            loss = -torch.min(ratio * adv, ratio.clamp(0.8, 1.2) * adv).mean()
            popt.zero_grad()
            loss.backward()
            popt.step()
            vloss = (value(obs[rows]).squeeze(-1) - returns[rows]).pow(2).mean()
            vopt.zero_grad()
            vloss.backward()
            vopt.step()

    epoch()
    samples = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        for _ in range(args.updates):
            epoch()
        samples.append(b * args.updates / (time.perf_counter() - t0))
    print(json.dumps({"peer": "pytorch-python", "torch": torch.__version__,
                      "threads": torch.get_num_threads(), "batch": b,
                      "minibatch": args.minibatch, "hidden": args.hidden,
                      "layers": args.layers, "samples_per_s": statistics.median(samples),
                      "samples": samples}))


if __name__ == "__main__":
    main()
