#!/usr/bin/env python3
"""The peer of `manyworlds bench agent --algo sac`: complete SAC updates in plain PyTorch
(Python), the same sizes and work, timed the same way.

One update, as in manyworlds' SacLearner::Update and in the usual Python SACs (CleanRL's
sac_continuous_action.py, Stable-Baselines3's SAC):

- critic target without gradients: actor forward on next_obs, tanh-squashed Gaussian sample,
  both target critics, y = r + discount (1 - done) (min(Q1', Q2') - alpha log pi);
- critic loss MSE(Q1, y) + MSE(Q2, y), backward, one Adam step over both critics;
- actor: forward on obs, reparameterised sample, Q1 and Q2 of the sampled action,
  loss mean(alpha log pi - min(Q1, Q2)), backward, Adam step;
- temperature: loss mean(-log_alpha.exp() (log pi + target_entropy)) with log pi detached,
  Adam step on log_alpha;
- Polyak update of both target critics (tau 0.005), parameter by parameter.

Networks: actor MLP obs -> (mean, raw log std) and two critic MLPs (obs, action) -> Q, each
`--layers` hidden layers of `--hidden` ReLU units (default 3 x 400, as `bench agent`); log
std bounded to [-20, 2] by tanh as manyworlds does. Adam lr 3e-4, betas (0.9, 0.999).

Timing as `bench agent`: four random batches (obs 39, action 4, batch 128) cycled, 3
warm-up updates, then `--repeats` repeats of `--updates` updates; prints JSON with
updates_per_s (the median) and the samples.

Threads: `--threads N` sets torch's intra-op threads; `--blas-threads M` (default N) sets
OPENBLAS_NUM_THREADS / MKL_NUM_THREADS / OMP_NUM_THREADS before torch loads (Debian's torch
does its matrix products in OpenBLAS, PyPI's in MKL or oneDNN).

Variants (off by default, the plain update is the peer): `--no-critic-weight-grads` turns
off the critics' weight gradients in the actor loss (manyworlds never computes them; the
plain version computes and discards them), `--foreach` uses Adam's multi-tensor
implementation and torch._foreach ops for the Polyak update.

    python3 bench/peers/sac_update.py --threads 1
"""
import argparse
import os
import sys


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--batch", type=int, default=128)
    p.add_argument("--hidden", type=int, default=400)
    p.add_argument("--layers", type=int, default=3)
    p.add_argument("--obs-dim", type=int, default=39)
    p.add_argument("--action-dim", type=int, default=4)
    p.add_argument("--updates", type=int, default=20, help="timed updates per repeat")
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--threads", type=int, default=1, help="torch intra-op threads")
    p.add_argument("--blas-threads", type=int, default=0,
                   help="BLAS/OpenMP threads (0: as --threads)")
    p.add_argument("--no-critic-weight-grads", action="store_true",
                   help="actor loss: no gradients for the critics' weights")
    p.add_argument("--foreach", action="store_true",
                   help="multi-tensor Adam and Polyak update")
    p.add_argument("--seed", type=int, default=0)
    return p.parse_args()


def main():
    args = parse_args()
    blas = str(args.blas_threads if args.blas_threads > 0 else args.threads)
    # Before torch (and its BLAS) load.
    for var in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS"):
        os.environ[var] = blas
    import json
    import math
    import statistics
    import time

    import torch
    from torch import nn

    torch.set_num_threads(args.threads)
    torch.set_num_interop_threads(1)
    torch.manual_seed(args.seed)

    def mlp(inp, out):
        mods, width = [], inp
        for _ in range(args.layers):
            mods += [nn.Linear(width, args.hidden), nn.ReLU()]
            width = args.hidden
        mods.append(nn.Linear(width, out))
        return nn.Sequential(*mods)

    o, a, b = args.obs_dim, args.action_dim, args.batch
    actor = mlp(o, 2 * a)
    qf1, qf2 = mlp(o + a, 1), mlp(o + a, 1)
    qf1_target, qf2_target = mlp(o + a, 1), mlp(o + a, 1)
    qf1_target.load_state_dict(qf1.state_dict())
    qf2_target.load_state_dict(qf2.state_dict())
    for p in list(qf1_target.parameters()) + list(qf2_target.parameters()):
        p.requires_grad_(False)
    log_alpha = torch.zeros(1, requires_grad=True)
    adam = dict(lr=3e-4, betas=(0.9, 0.999))
    if args.foreach:
        adam["foreach"] = True
    q_params = list(qf1.parameters()) + list(qf2.parameters())
    q_optimizer = torch.optim.Adam(q_params, **adam)
    actor_optimizer = torch.optim.Adam(actor.parameters(), **adam)
    a_optimizer = torch.optim.Adam([log_alpha], **adam)
    target_entropy = -float(a)
    discount, tau = 0.99, 0.005
    log_std_min, log_std_max = -20.0, 2.0
    online = q_params
    targets = list(qf1_target.parameters()) + list(qf2_target.parameters())

    def sample(x):
        out = actor(x)
        mean, raw = out[:, :a], out[:, a:]
        log_std = log_std_min + 0.5 * (log_std_max - log_std_min) * (torch.tanh(raw) + 1)
        std = log_std.exp()
        u = mean + std * torch.randn_like(mean)
        action = torch.tanh(u)
        log_prob = (-0.5 * ((u - mean) / std).pow(2) - log_std
                    - 0.5 * math.log(2 * math.pi)).sum(-1)
        # log |d tanh(u) / du| = 2 (log 2 - u - softplus(-2u)), numerically stable
        log_prob = log_prob - (2 * (math.log(2) - u - nn.functional.softplus(-2 * u))).sum(-1)
        return action, log_prob

    def update(batch):
        obs, action, reward, next_obs, done = batch
        alpha = log_alpha.exp().detach()
        with torch.no_grad():
            next_action, next_log_prob = sample(next_obs)
            next_in = torch.cat([next_obs, next_action], 1)
            min_q = torch.min(qf1_target(next_in), qf2_target(next_in)).squeeze(-1)
            y = reward + discount * (1 - done) * (min_q - alpha * next_log_prob)
        q_in = torch.cat([obs, action], 1)
        q1 = qf1(q_in).squeeze(-1)
        q2 = qf2(q_in).squeeze(-1)
        q_loss = nn.functional.mse_loss(q1, y) + nn.functional.mse_loss(q2, y)
        q_optimizer.zero_grad()
        q_loss.backward()
        q_optimizer.step()

        if args.no_critic_weight_grads:
            for p in q_params:
                p.requires_grad_(False)
        pi, log_prob = sample(obs)
        pi_in = torch.cat([obs, pi], 1)
        min_q_pi = torch.min(qf1(pi_in), qf2(pi_in)).squeeze(-1)
        actor_loss = (alpha * log_prob - min_q_pi).mean()
        actor_optimizer.zero_grad()
        actor_loss.backward()
        actor_optimizer.step()
        if args.no_critic_weight_grads:
            for p in q_params:
                p.requires_grad_(True)

        alpha_loss = (-log_alpha.exp() * (log_prob.detach() + target_entropy)).mean()
        a_optimizer.zero_grad()
        alpha_loss.backward()
        a_optimizer.step()

        with torch.no_grad():
            if args.foreach:
                torch._foreach_mul_(targets, 1 - tau)
                torch._foreach_add_(targets, online, alpha=tau)
            else:
                for tp, p in zip(targets, online):
                    tp.mul_(1 - tau).add_(p, alpha=tau)

    g = torch.Generator().manual_seed(args.seed + 1)
    batches = [(torch.randn(b, o, generator=g),
                torch.rand(b, a, generator=g) * 2 - 1,
                torch.randn(b, generator=g),
                torch.randn(b, o, generator=g),
                (torch.rand(b, generator=g) < 0.01).float()) for _ in range(4)]
    for i in range(3):
        update(batches[i % 4])
    samples = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        for i in range(args.updates):
            update(batches[i % 4])
        samples.append(args.updates / (time.perf_counter() - t0))
    print(json.dumps({
        "peer": "pytorch-python-sac",
        "python": sys.version.split()[0],
        "torch": torch.__version__,
        "threads": torch.get_num_threads(),
        "blas_threads": int(blas),
        "variant": {"no_critic_weight_grads": args.no_critic_weight_grads,
                    "foreach": args.foreach},
        "batch": b, "hidden": args.hidden, "layers": args.layers,
        "obs_dim": o, "action_dim": a,
        "updates_per_repeat": args.updates, "repeats": args.repeats,
        "updates_per_s": statistics.median(samples),
        "ms_per_update": 1000.0 / statistics.median(samples),
        "samples": samples,
    }))


if __name__ == "__main__":
    main()
