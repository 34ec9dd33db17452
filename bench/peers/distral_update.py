#!/usr/bin/env python3
"""The peer of `manyworlds bench agent --algo distral`: complete Distral updates in plain
PyTorch (Python), the same sizes and the same work, timed the same way.

Distral (Teh et al. 2017) as manyworlds' DistralLearner (src/manyworlds/agents/distral/): T task
agents, each a single-task SAC learner (actor, twin critics, twin target critics, a temperature,
Adam for the critics, the actor and the temperature), and a distilled policy pi_0 (the same
actor network, observation only, no task id) with its own Adam. c = `--distral-alpha` (1.0,
DistralConfig's default). One update (DistralLearner::Update with SacLearner's PolicyPrior):

- for each task t: its rows of the batch (index selection by task), then one SAC update of agent
  t on them, regularised towards pi_0:
  - critic target without gradients: y = r + discount (1 - done)
    (min(Q1', Q2') - (alpha + c) log pi(a'|s') + c log pi_0(a'|s')), a' = tanh(u') sampled from
    the agent's actor at s', log pi_0 the squashed density of pi_0 at u';
  - critic loss MSE(Q1, y) + MSE(Q2, y), one Adam step over both critics;
  - actor loss mean((alpha + c) log pi(a|s) - c log pi_0(a|s) - min(Q1, Q2)(s, a)), a
    reparameterised; pi_0's weights are detached (requires_grad off while the task agents
    update), so the gradient reaches pi_0's density through the action only; Adam step;
  - temperature loss mean(-log_alpha.exp() (log pi + target_entropy)), log pi detached; Adam;
  - Polyak update of both target critics (tau 0.005), parameter by parameter;
  - the agent's actor after its step, without gradients, on its rows: the (mean, log std) that
    pi_0 is distilled towards;
- distillation: loss c mean_rows KL(pi_t || pi_0) of the pre-tanh diagonal Gaussians over all
  rows (pi_t fixed), one backward and one Adam step of pi_0.

Networks: MLPs of `--layers` hidden layers of `--hidden` ReLU units (default 3 x 400); actors
obs -> (mean, raw log std), log std bounded to [-20, 2] by tanh; critics (obs, action) -> Q.
pi_0 starts as N(0, 1) in pre-tanh space (output weights and mean bias 0, the log-std bias at
the bounded value 0), as manyworlds initialises it. Adam lr 3e-4, betas (0.9, 0.999); initial
temperature 1, target entropy -action_dim.

Batches as `bench agent --algo distral`: `--batch` rows PER TASK, so T * batch rows with task
index row % T; four random batches (obs, action in (-1, 1), reward, next obs; done 0) cycled; 3
warm-up updates, then `--repeats` repeats of `--updates` updates; prints JSON with updates_per_s
(the median) and the samples.

What the peer does differently from manyworlds (as sac_update.py does for plain SAC): two critic
modules instead of one two-member ensemble of batched products, one torch.optim.Adam per group
and a parameter loop for Polyak, and, by default, the critics' weight gradients in the actor
loss computed and discarded (manyworlds never computes them; `--no-critic-weight-grads` turns
them off here too).

`--check`: shapes, parameter counts against manyworlds' layout (nn/mlp.cc), that a prior equal
to the agent's policy leaves the critic target equal to plain SAC's (the c terms cancel), that
distillation steps lower KL(pi_t || pi_0), and that every parameter stays finite over 2 updates.

    /usr/bin/python3 bench/peers/distral_update.py --tasks 10 --batch 32 --threads 1
    /usr/bin/python3 bench/peers/distral_update.py --tasks 10 --check
"""
import argparse
import os
import sys


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--tasks", type=int, default=10)
    p.add_argument("--batch", type=int, default=32, help="rows per task agent")
    p.add_argument("--hidden", type=int, default=400)
    p.add_argument("--layers", type=int, default=3)
    p.add_argument("--obs-dim", type=int, default=39)
    p.add_argument("--action-dim", type=int, default=4)
    p.add_argument("--distral-alpha", type=float, default=1.0, help="c, the KL weight")
    p.add_argument("--updates", type=int, default=20, help="timed updates per repeat")
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--threads", type=int, default=1, help="torch intra-op threads")
    p.add_argument("--blas-threads", type=int, default=0,
                   help="BLAS/OpenMP threads (0: as --threads)")
    p.add_argument("--no-critic-weight-grads", action="store_true",
                   help="actor loss: no gradients for the critics' weights")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--check", action="store_true",
                   help="check shapes, parameter counts and the prior terms; no timing")
    args = p.parse_args()
    if args.tasks < 1 or args.batch < 1:
        p.error("--tasks and --batch must be >= 1")
    if args.distral_alpha < 0:
        p.error("--distral-alpha must be >= 0")
    return args


def main():
    args = parse_args()
    blas = str(args.blas_threads if args.blas_threads > 0 else args.threads)
    for var in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS"):
        os.environ[var] = blas  # before torch (and its BLAS) load
    import json
    import math
    import statistics
    import time

    import torch
    from torch import nn
    from torch.nn import functional as F

    torch.set_num_threads(args.threads)
    torch.set_num_interop_threads(1)
    torch.manual_seed(args.seed)

    o, a, c = args.obs_dim, args.action_dim, args.distral_alpha
    log_std_min, log_std_max = -20.0, 2.0
    discount, tau, target_entropy = 0.99, 0.005, -float(a)
    adam = dict(lr=3e-4, betas=(0.9, 0.999))

    def mlp(inp, out):
        mods, width = [], inp
        for _ in range(args.layers):
            mods += [nn.Linear(width, args.hidden), nn.ReLU()]
            width = args.hidden
        mods.append(nn.Linear(width, out))
        return nn.Sequential(*mods)

    class Policy(nn.Module):
        def __init__(self):
            super().__init__()
            self.net = mlp(o, 2 * a)

        def forward(self, obs):
            mean, raw = self.net(obs).chunk(2, -1)
            log_std = log_std_min + 0.5 * (log_std_max - log_std_min) * (torch.tanh(raw) + 1)
            return mean, log_std

        def sample(self, obs):
            """Squashed action, its log-density and the pre-tanh u."""
            mean, log_std = self(obs)
            u = mean + log_std.exp() * torch.randn_like(mean)
            return torch.tanh(u), log_density(u, mean, log_std), u

    def log_density(u, mean, log_std):
        """log density of tanh(u), u ~ N(mean, exp(log_std)^2) diagonal: (B)."""
        log_prob = (-0.5 * ((u - mean) * torch.exp(-log_std)).pow(2) - log_std
                    - 0.5 * math.log(2 * math.pi)).sum(-1)
        # log |d tanh(u) / du| = 2 (log 2 - u - softplus(-2u)), numerically stable
        return log_prob - (2 * (math.log(2) - u - F.softplus(-2 * u))).sum(-1)

    def gaussian_kl(mean1, log_std1, mean2, log_std2):
        """KL(N1 || N2) of diagonal Gaussians, summed over the last dim."""
        var1, var2 = (2 * log_std1).exp(), (2 * log_std2).exp()
        return (log_std2 - log_std1 + (var1 + (mean1 - mean2).pow(2)) / (2 * var2) - 0.5).sum(-1)

    class TaskAgent:
        """One single-task SAC learner."""

        def __init__(self):
            self.actor = Policy()
            self.qf1, self.qf2 = mlp(o + a, 1), mlp(o + a, 1)
            self.qf1_target, self.qf2_target = mlp(o + a, 1), mlp(o + a, 1)
            self.qf1_target.load_state_dict(self.qf1.state_dict())
            self.qf2_target.load_state_dict(self.qf2.state_dict())
            self.targets = list(self.qf1_target.parameters()) + list(self.qf2_target.parameters())
            for p in self.targets:
                p.requires_grad_(False)
            self.q_params = list(self.qf1.parameters()) + list(self.qf2.parameters())
            self.log_alpha = torch.zeros(1, requires_grad=True)  # temperature 1
            self.q_optimizer = torch.optim.Adam(self.q_params, **adam)
            self.actor_optimizer = torch.optim.Adam(self.actor.parameters(), **adam)
            self.a_optimizer = torch.optim.Adam([self.log_alpha], **adam)

        def min_q(self, q1, q2, obs, action):
            x = torch.cat([obs, action], 1)
            return torch.min(q1(x), q2(x)).squeeze(-1)

        def critic_target(self, reward, next_obs, done, alpha, prior):
            with torch.no_grad():
                next_action, next_log_prob, next_u = self.actor.sample(next_obs)
                soft_q = self.min_q(self.qf1_target, self.qf2_target, next_obs, next_action)
                if prior is None:
                    soft_q = soft_q - alpha * next_log_prob
                else:
                    soft_q = (soft_q - (alpha + c) * next_log_prob
                              + c * prior(next_obs, next_u))
                return reward + discount * (1 - done) * soft_q

        def update(self, obs, action, reward, next_obs, done, prior):
            """prior(obs, u): log pi_0(tanh(u) | obs), or None (plain SAC)."""
            alpha = self.log_alpha.exp().detach()
            y = self.critic_target(reward, next_obs, done, alpha, prior)
            q_in = torch.cat([obs, action], 1)
            q_loss = (F.mse_loss(self.qf1(q_in).squeeze(-1), y)
                      + F.mse_loss(self.qf2(q_in).squeeze(-1), y))
            self.q_optimizer.zero_grad()
            q_loss.backward()
            self.q_optimizer.step()

            if args.no_critic_weight_grads:
                for p in self.q_params:
                    p.requires_grad_(False)
            pi, log_prob, u = self.actor.sample(obs)
            per_sample = alpha * log_prob - self.min_q(self.qf1, self.qf2, obs, pi)
            if prior is not None:
                per_sample = per_sample + c * (log_prob - prior(obs, u))
            actor_loss = per_sample.mean()
            self.actor_optimizer.zero_grad()
            actor_loss.backward()
            self.actor_optimizer.step()
            if args.no_critic_weight_grads:
                for p in self.q_params:
                    p.requires_grad_(True)

            alpha_loss = (-self.log_alpha.exp() * (log_prob.detach() + target_entropy)).mean()
            self.a_optimizer.zero_grad()
            alpha_loss.backward()
            self.a_optimizer.step()

            with torch.no_grad():
                for tp, p in zip(self.targets, self.q_params):
                    tp.mul_(1 - tau).add_(p, alpha=tau)

    agents = [TaskAgent() for _ in range(args.tasks)]
    distilled = Policy()
    with torch.no_grad():  # pi_0 = N(0, 1) before tanh, for every observation
        last = distilled.net[-1]
        last.weight.zero_()
        last.bias[:a].zero_()
        last.bias[a:].fill_(math.atanh(max(-0.999, min(
            0.999, (0.0 - log_std_min) / (0.5 * (log_std_max - log_std_min)) - 1.0))))
    distilled_optimizer = torch.optim.Adam(distilled.parameters(), **adam)

    def prior_log_prob(obs, u):
        mean, log_std = distilled(obs)
        return log_density(u, mean, log_std)

    prior = prior_log_prob if c > 0 else None

    def update(batch):
        obs, action, reward, next_obs, done, task = batch
        for p in distilled.parameters():  # pi_0's weights detached in the task agents' losses
            p.requires_grad_(False)
        means, log_stds, row_lists = [], [], []
        for t, agent in enumerate(agents):
            rows = (task == t).nonzero(as_tuple=True)[0]
            if len(rows) == 0:
                continue
            task_obs = obs[rows]
            agent.update(task_obs, action[rows], reward[rows], next_obs[rows], done[rows],
                         prior)
            with torch.no_grad():
                mean, log_std = agent.actor(task_obs)
            means.append(mean)
            log_stds.append(log_std)
            row_lists.append(rows)
        for p in distilled.parameters():
            p.requires_grad_(True)
        mean0, log_std0 = distilled(obs[torch.cat(row_lists)])
        kl = gaussian_kl(torch.cat(means), torch.cat(log_stds), mean0, log_std0).mean()
        if c > 0:
            distilled_optimizer.zero_grad()
            (c * kl).backward()
            distilled_optimizer.step()
        return kl.detach()

    g = torch.Generator().manual_seed(args.seed + 1)
    rows_total = args.batch * args.tasks

    def random_batch():
        b = rows_total
        return (torch.randn(b, o, generator=g), torch.rand(b, a, generator=g) * 2 - 1,
                torch.randn(b, generator=g), torch.randn(b, o, generator=g), torch.zeros(b),
                torch.arange(b) % args.tasks)

    batches = [random_batch() for _ in range(4)]
    if args.check:
        check(args, torch, agents, distilled, distilled_optimizer, prior_log_prob, batches,
              update, gaussian_kl)
        return
    for i in range(3):
        update(batches[i % 4])
    samples = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        for i in range(args.updates):
            update(batches[i % 4])
        samples.append(args.updates / (time.perf_counter() - t0))
    print(json.dumps({
        "peer": "pytorch-python-distral",
        "python": sys.version.split()[0],
        "torch": torch.__version__,
        "threads": torch.get_num_threads(),
        "blas_threads": int(blas),
        "variant": {"no_critic_weight_grads": args.no_critic_weight_grads},
        "tasks": args.tasks, "batch_per_task": args.batch, "hidden": args.hidden,
        "layers": args.layers, "obs_dim": o, "action_dim": a, "distral_alpha": c,
        "unit": "one update (every task agent's SAC update, one distillation step)",
        "updates_per_repeat": args.updates, "repeats": args.repeats,
        "updates_per_s": statistics.median(samples),
        "ms_per_update": 1000.0 / statistics.median(samples),
        "samples": samples,
    }))


def count(module):
    return sum(p.numel() for p in module.parameters())


def check(args, torch, agents, distilled, distilled_optimizer, prior_log_prob, batches, update,
          gaussian_kl):
    """--check: prints JSON; raises on failure."""
    import json

    o, a, h, t = args.obs_dim, args.action_dim, args.hidden, args.tasks

    def mlp_params(inp, out):  # nn/mlp.cc's layout: weights and biases of every linear map
        widths = [inp] + [h] * args.layers + [out]
        return sum(i * j + j for i, j in zip(widths, widths[1:]))

    report = {"tasks": t, "params": {}, "checks": []}
    agent = agents[0]
    for name, module, expected in (("actor", agent.actor, mlp_params(o, 2 * a)),
                                   ("critic", agent.qf1, mlp_params(o + a, 1)),
                                   ("distilled", distilled, mlp_params(o, 2 * a))):
        report["params"][name] = {"pytorch": count(module), "manyworlds_layout": expected}
        assert count(module) == expected, f"{name}: {count(module)} parameters, {expected} expected"
    obs, action, reward, next_obs, done, task = batches[0]
    with torch.no_grad():
        mean, log_std = agent.actor(obs)
        assert mean.shape == (len(obs), a) and log_std.shape == (len(obs), a)
        mean0, log_std0 = distilled(obs)
        assert mean0.abs().max() == 0 and log_std0.abs().max() < 1e-5, "pi_0 is not N(0, 1)"
    report["checks"].append(f"actor output 2 x {tuple(mean.shape)}; pi_0 starts as N(0, 1)")

    # A prior equal to the agent's own policy: c log pi_0 - c log pi = 0 in the target.
    rows = (task == 0).nonzero(as_tuple=True)[0]
    saved = {k: v.clone() for k, v in distilled.state_dict().items()}
    distilled.load_state_dict(agent.actor.state_dict())
    alpha = agent.log_alpha.exp().detach()
    torch.manual_seed(7)
    y_prior = agent.critic_target(reward[rows], next_obs[rows], done[rows], alpha, prior_log_prob)
    torch.manual_seed(7)
    y_plain = agent.critic_target(reward[rows], next_obs[rows], done[rows], alpha, None)
    diff = (y_prior - y_plain).abs().max().item()
    assert diff < 1e-3, f"a prior equal to the policy changes the target by {diff}"
    distilled.load_state_dict(saved)
    torch.manual_seed(7)
    y_n01 = agent.critic_target(reward[rows], next_obs[rows], done[rows], alpha, prior_log_prob)
    moved = (y_n01 - y_plain).abs().max().item()
    assert moved > 1e-3, "the N(0, 1) prior does not change the target"
    report["checks"].append(f"prior = policy leaves the target unchanged (max |diff| {diff:.2g}); "
                            f"the N(0, 1) prior moves it ({moved:.3g})")

    for k in range(2):
        kl = update(batches[k])
    for i, ag in enumerate(agents):
        for m in (ag.actor, ag.qf1, ag.qf2, ag.qf1_target, ag.qf2_target):
            assert all(torch.isfinite(p).all() for p in m.parameters()), f"agent {i}: not finite"
    assert all(torch.isfinite(p).all() for p in distilled.parameters()), "pi_0: not finite"
    report["checks"].append(f"all parameters finite after 2 updates (distill KL {kl.item():.3g})")

    # Distillation alone (task policies fixed) lowers the KL.
    with torch.no_grad():
        targets = [ag.actor(obs[(task == i).nonzero(as_tuple=True)[0]])
                   for i, ag in enumerate(agents)]
        order = torch.cat([(task == i).nonzero(as_tuple=True)[0] for i in range(t)])
        m1 = torch.cat([m for m, _ in targets])
        s1 = torch.cat([s for _, s in targets])

    def kl_now():
        m0, s0 = distilled(obs[order])
        return gaussian_kl(m1, s1, m0, s0).mean()

    before = kl_now().item()
    for _ in range(20):
        loss = kl_now()  # c KL with c = 1 (the direction does not depend on c > 0)
        distilled_optimizer.zero_grad()
        loss.backward()
        distilled_optimizer.step()
    after = kl_now().item()
    assert after < before, f"distillation did not lower the KL ({before} -> {after})"
    report["checks"].append(f"20 distillation steps: KL {before:.4g} -> {after:.4g}")
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
