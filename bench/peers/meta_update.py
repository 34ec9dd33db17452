#!/usr/bin/env python3
"""The peers of `manyworlds bench agent --algo rl2|maml|pearl`: the same meta-RL
updates in plain PyTorch (Python), the same sizes and work, on random trials.

rl2: one PPO epoch of RL2 over N trials of T steps: the input [obs,
previous action (clipped), reward, episode end], garage's linear feature
baseline (predict, then least-squares refit), the entropy-'max' reward term,
GAE over the trial, then minibatches of M whole trials through a GRU
(torch.nn.GRU, width H) and a linear Gaussian head (learned log std clamped
to [log 0.5, log 1.5]), clipped surrogate, Adam.

maml: one outer MAML-TRPO step on N task instances of T/2 steps before and
T/2 after adaptation: per instance and phase a linear feature baseline fit
and GAE (lambda 1, centred), the inner vanilla policy-gradient step (lr 0.1)
with create_graph, the post-adaptation surrogate, its gradient, 10
conjugate-gradient iterations on Fisher-vector products through the inner
step, and one line-search candidate (the C++ side runs with one too).

pearl: one PEARL update (oyster's rlkit/torch/sac/sac.py _take_step) on
--tasks tasks, each with --minibatch context and --batch RL transitions:
encoder MLP 3 x 200 to (mu, softplus var) per transition, product of
Gaussians, reparameterised z, KL to N(0, I); twin Q and V (--layers x
--hidden, ReLU) on [obs, action, z] and [obs, z] with a target V; Q loss
backpropagated into the encoder; V loss on the stepped critics' min Q minus
log pi; Polyak target; tanh-Gaussian policy loss with mean/std regularisers;
one Adam per network (torch.optim.Adam, as oyster).

Reports updates per second (median of the repeats) as JSON, like the C++
command.

    python3 bench/peers/meta_update.py --algo rl2 --batch 20 --trial-length 200 --minibatch 5 --hidden 256
    python3 bench/peers/meta_update.py --algo maml --batch 10 --trial-length 200 --hidden 64 --layers 2
    python3 bench/peers/meta_update.py --algo pearl --tasks 16 --batch 256 --minibatch 64 --hidden 300 --layers 3
"""
import argparse
import json
import math
import statistics
import time

import torch
from torch import nn

LO, HI = math.log(0.5), math.log(1.5)
LOG_SQRT_2PI = 0.5 * math.log(2 * math.pi)


def gaussian_log_prob(mean, log_std, actions):
    z = (actions - mean) * torch.exp(-log_std)
    return (-0.5 * z * z - log_std - LOG_SQRT_2PI).sum(-1)


def baseline_features(x, t):
    c = x.clamp(-10, 10)
    t = (t / 100.0).unsqueeze(-1)
    return torch.cat([c, c * c, t, t * t, t * t * t, torch.ones_like(t)], -1)


def fit_baseline(features, returns, reg=1e-5):
    """Least squares in float64, with garage's regularisation."""
    f = features.double()
    a = f.transpose(-1, -2) @ f
    b = f.transpose(-1, -2) @ returns.double().unsqueeze(-1)
    eye = torch.eye(a.shape[-1], dtype=torch.float64)
    return torch.linalg.solve(a + reg * eye, b).squeeze(-1).float()


def gae(rewards, values, ended, gamma, lam):
    """(T, N) tensors; every end is terminal (no bootstrap)."""
    adv = torch.zeros_like(rewards)
    last = torch.zeros(rewards.shape[1])
    for t in range(rewards.shape[0] - 1, -1, -1):
        not_end = 1.0 - ended[t]
        next_value = values[t + 1] * not_end if t + 1 < rewards.shape[0] else torch.zeros_like(last)
        delta = rewards[t] + gamma * next_value - values[t]
        last = delta + gamma * lam * not_end * last
        adv[t] = last
    return adv


def rl2_peer(args):
    T, N, D, A, H = args.trial_length, args.batch, args.obs_dim, args.action_dim, args.hidden
    obs = torch.randn(T, N, D)
    actions = torch.randn(T, N, A)
    log_probs = torch.randn(T, N) - 4.0
    rewards = torch.randn(T, N)
    ended = torch.zeros(T, N)
    ended[-1] = 1.0
    gru = nn.GRU(D + A + 2, H)
    head = nn.Linear(H, A)
    log_std = nn.Parameter(torch.zeros(A))
    opt = torch.optim.Adam(list(gru.parameters()) + list(head.parameters()) + [log_std], lr=5e-4)
    coef = torch.zeros(2 * (D + A + 2) + 4)

    def update():
        nonlocal coef
        ctx = torch.zeros(T, N, A + 2)
        ctx[1:] = torch.cat([actions[:-1].clamp(-1, 1), rewards[:-1].unsqueeze(-1),
                             ended[:-1].unsqueeze(-1)], -1)
        x = torch.cat([obs, ctx], -1)
        steps = torch.arange(T, dtype=torch.float32).unsqueeze(1).expand(T, N)
        feats = baseline_features(x, steps)
        values = feats @ coef
        r = rewards - 5e-6 * log_probs
        adv = gae(r, values, ended, 0.99, 0.95)
        mc = gae(r, torch.zeros_like(values), ended, 0.99, 1.0)
        coef = fit_baseline(feats.reshape(T * N, -1), mc.reshape(-1))
        perm = torch.randperm(N)
        for lo in range(0, N, args.minibatch):
            cols = perm[lo:lo + args.minibatch]
            out, _ = gru(x[:, cols])
            mean = head(out)
            ls = log_std.clamp(LO, HI).expand_as(mean)
            lp = gaussian_log_prob(mean, ls, actions[:, cols])
            ratio = (lp - log_probs[:, cols]).exp()
            a = adv[:, cols]
            loss = -torch.min(ratio * a, ratio.clamp(0.8, 1.2) * a).mean()
            opt.zero_grad()
            loss.backward()
            opt.step()

    return update


def maml_peer(args):
    T, N, D, A = args.trial_length, args.batch, args.obs_dim, args.action_dim
    half = T // 2
    sizes = [D] + [args.hidden] * args.layers + [A]
    params = []
    for i in range(len(sizes) - 1):
        w = torch.empty(sizes[i + 1], sizes[i])
        nn.init.orthogonal_(w, math.sqrt(2) if i + 2 < len(sizes) else 0.01)
        params += [w.requires_grad_(), torch.zeros(sizes[i + 1], requires_grad=True)]
    params.append(torch.zeros(A, requires_grad=True))  # log std

    def forward(x, p):
        h = x
        for i in range(0, len(p) - 1, 2):
            h = torch.nn.functional.linear(h, p[i], p[i + 1])
            if i + 3 < len(p):
                h = torch.tanh(h)
        return h, p[-1].clamp(LO, HI).expand_as(h)

    def phase():
        o = torch.randn(half, N, D)
        a = torch.randn(half, N, A)
        r = torch.randn(half, N)
        e = torch.zeros(half, N)
        e[-1] = 1.0
        return o, a, r, e

    pre, post = phase(), phase()
    post_old_lp = torch.randn(half, N) - 4.0

    def advantages(o, r, e):
        steps = torch.arange(half, dtype=torch.float32).unsqueeze(1).expand(half, N)
        mc = gae(r, torch.zeros_like(r), e, 0.99, 1.0)
        feats = baseline_features(o, steps).transpose(0, 1)  # (N, T, F)
        coef = fit_baseline(feats, mc.t())                  # one fit per instance
        values = (feats @ coef.unsqueeze(-1)).squeeze(-1).t()
        adv = gae(r, values, e, 0.99, 1.0)
        return (adv - adv.mean(0)) / (adv.std(0) + 1e-8)

    def inner(p, i, adv_pre, create_graph):
        mean, ls = forward(pre[0][:, i], p)
        loss = -(gaussian_log_prob(mean, ls, pre[1][:, i]) * adv_pre[:, i]).mean()
        grads = torch.autograd.grad(loss, p, create_graph=create_graph, allow_unused=True)
        return [q - 0.1 * g if g is not None else q for q, g in zip(p, grads)]

    def flat(grads):
        return torch.cat([g.reshape(-1) if g is not None else torch.zeros(q.numel())
                          for g, q in zip(grads, params)])

    def update():
        adv_pre = advantages(pre[0], pre[2], pre[3])
        adv_post = advantages(post[0], post[2], post[3])
        old = []
        for i in range(N):
            m, ls = forward(post[0][:, i], inner(params, i, adv_pre, False))
            old.append((m.detach(), ls.detach()))

        def objective(create_graph, with_kl):
            surr, kl = 0.0, 0.0
            for i in range(N):
                m, ls = forward(post[0][:, i], inner(params, i, adv_pre, create_graph))
                lp = gaussian_log_prob(m, ls, post[1][:, i])
                surr = surr + ((lp - post_old_lp[:, i]).exp() * adv_post[:, i]).mean()
                if with_kl:
                    m0, ls0 = old[i]
                    var0, var1 = torch.exp(2 * ls0), torch.exp(2 * ls)
                    kl = kl + (ls - ls0 + (var0 + (m0 - m) ** 2) / (2 * var1) - 0.5).sum(-1).mean()
            return surr / N, kl / N

        surr, _ = objective(True, False)
        g = flat(torch.autograd.grad(surr, params, retain_graph=True, allow_unused=True))

        def fisher(v):
            _, kl = objective(True, True)
            kg = flat(torch.autograd.grad(kl, params, create_graph=True, allow_unused=True))
            hv = flat(torch.autograd.grad((kg * v).sum(), params, allow_unused=True))
            return hv + 1e-5 * v

        x = torch.zeros_like(g)
        r = g.clone()
        p = g.clone()
        rr = r.dot(r).item()
        for _ in range(10):
            if rr <= 1e-10:
                break
            ap = fisher(p)
            alpha = rr / (p.dot(ap).item() + 1e-12)
            x += alpha * p
            r -= alpha * ap
            nxt = r.dot(r).item()
            p = r + (nxt / rr) * p
            rr = nxt
        shs = x.dot(fisher(x)).item()
        if shs > 0:
            step = x * math.sqrt(2 * 0.01 / shs)
            before = [q.detach().clone() for q in params]
            with torch.no_grad():
                offset = 0
                for q in params:
                    q.add_(step[offset:offset + q.numel()].view_as(q))
                    offset += q.numel()
            value, kl = objective(False, True)
            if not (kl.item() <= 0.01 and value.item() > surr.item()):
                with torch.no_grad():
                    for q, b in zip(params, before):
                        q.copy_(b)

    return update


def mlp(n_in, n_out, hidden, layers):
    mods, d = [], n_in
    for _ in range(layers):
        mods += [nn.Linear(d, hidden), nn.ReLU()]
        d = hidden
    mods.append(nn.Linear(d, n_out))
    return nn.Sequential(*mods)


def pearl_peer(args):
    t, b, c, z_dim = args.tasks, args.batch, args.minibatch, 5
    o_dim, a_dim = args.obs_dim, args.action_dim
    encoder = mlp(o_dim + a_dim + 1, 2 * z_dim, 200, 3)
    policy = mlp(o_dim + z_dim, 2 * a_dim, args.hidden, args.layers)
    qf1 = mlp(o_dim + a_dim + z_dim, 1, args.hidden, args.layers)
    qf2 = mlp(o_dim + a_dim + z_dim, 1, args.hidden, args.layers)
    vf = mlp(o_dim + z_dim, 1, args.hidden, args.layers)
    target_vf = mlp(o_dim + z_dim, 1, args.hidden, args.layers)
    target_vf.load_state_dict(vf.state_dict())
    opt = {name: torch.optim.Adam(net.parameters(), lr=3e-4)
           for name, net in [("enc", encoder), ("pi", policy), ("q1", qf1), ("q2", qf2), ("v", vf)]}
    context = torch.randn(t, c, o_dim + a_dim + 1)
    obs = torch.randn(t * b, o_dim)
    actions = torch.rand(t * b, a_dim) * 2 - 1
    rewards = torch.randn(t * b, 1)
    next_obs = torch.randn(t * b, o_dim)
    terms = torch.zeros(t * b, 1)

    def update():
        params = encoder(context.view(t * c, -1)).view(t, c, -1)
        mu = params[..., :z_dim]
        var = torch.nn.functional.softplus(params[..., z_dim:]).clamp(min=1e-7)
        z_var = 1.0 / torch.sum(1.0 / var, dim=1)
        z_mean = z_var * torch.sum(mu / var, dim=1)
        z = z_mean + z_var.sqrt() * torch.randn_like(z_mean)
        kl = 0.5 * (z_var + z_mean ** 2 - 1 - z_var.log()).sum()
        task_z = z.repeat_interleave(b, 0)
        out = policy(torch.cat([obs, task_z.detach()], 1))
        mean, log_std = out[:, :a_dim], out[:, a_dim:].clamp(-20, 2)
        std = log_std.exp()
        u = mean + std * torch.randn_like(mean)
        new_actions = torch.tanh(u)
        log_pi = (-0.5 * ((u - mean) / std) ** 2 - log_std - LOG_SQRT_2PI).sum(1, keepdim=True)
        log_pi = log_pi - (2 * (math.log(2) - u - torch.nn.functional.softplus(-2 * u))).sum(1, keepdim=True)
        q_in = torch.cat([obs, actions, task_z], 1)
        q1, q2 = qf1(q_in), qf2(q_in)
        v_pred = vf(torch.cat([obs, task_z.detach()], 1))
        with torch.no_grad():
            target_v = target_vf(torch.cat([next_obs, task_z], 1))
        opt["enc"].zero_grad()
        (0.1 * kl).backward(retain_graph=True)
        opt["q1"].zero_grad()
        opt["q2"].zero_grad()
        q_target = rewards * 5.0 + (1.0 - terms) * 0.99 * target_v
        qf_loss = torch.mean((q1 - q_target) ** 2) + torch.mean((q2 - q_target) ** 2)
        qf_loss.backward()
        opt["q1"].step()
        opt["q2"].step()
        opt["enc"].step()
        new_in = torch.cat([obs, new_actions, task_z.detach()], 1)
        min_q = torch.min(qf1(new_in), qf2(new_in))
        vf_loss = torch.mean((v_pred - (min_q - log_pi).detach()) ** 2)
        opt["v"].zero_grad()
        vf_loss.backward()
        opt["v"].step()
        with torch.no_grad():
            for tp, p in zip(target_vf.parameters(), vf.parameters()):
                tp.mul_(0.995).add_(p, alpha=0.005)
        policy_loss = (log_pi - min_q).mean() + 1e-3 * (mean ** 2).mean() + 1e-3 * (log_std ** 2).mean()
        opt["pi"].zero_grad()
        policy_loss.backward()
        opt["pi"].step()

    return update


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--algo", choices=["rl2", "maml", "pearl"], required=True)
    p.add_argument("--batch", type=int, default=20,
                   help="trials (task instances); pearl: RL transitions per task")
    p.add_argument("--tasks", type=int, default=16, help="pearl: the meta-batch")
    p.add_argument("--trial-length", type=int, default=200)
    p.add_argument("--minibatch", type=int, default=5,
                   help="rl2: trials per minibatch; pearl: context transitions per task")
    p.add_argument("--hidden", type=int, default=256)
    p.add_argument("--layers", type=int, default=2)
    p.add_argument("--obs-dim", type=int, default=39)
    p.add_argument("--action-dim", type=int, default=4)
    p.add_argument("--updates", type=int, default=3)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--threads", type=int, default=1)
    args = p.parse_args()
    torch.set_num_threads(args.threads)
    torch.manual_seed(0)
    update = {"rl2": rl2_peer, "maml": maml_peer, "pearl": pearl_peer}[args.algo](args)
    update()
    rates = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        for _ in range(args.updates):
            update()
        rates.append(args.updates / (time.perf_counter() - t0))
    median = statistics.median(rates)
    if args.algo == "pearl":
        print(json.dumps({"algo": "pearl", "tasks": args.tasks, "batch": args.batch,
                          "context": args.minibatch, "hidden": args.hidden,
                          "layers": args.layers, "updates_per_s": median, "updates": rates,
                          "torch": torch.__version__, "threads": args.threads}))
        return
    print(json.dumps({"algo": args.algo, "trials": args.batch, "trial_length": args.trial_length,
                      "hidden": args.hidden, "updates_per_s": median,
                      "samples_per_s": median * args.batch * args.trial_length,
                      "updates": rates, "torch": torch.__version__, "threads": args.threads}))


if __name__ == "__main__":
    main()
