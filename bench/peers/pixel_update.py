#!/usr/bin/env python3
"""The peer of `manyworlds bench agent --algo sac_ae|deepmdp|hipbmdp`: complete pixel-learner
updates in plain PyTorch (Python), the same sizes and the same work, timed the same way.

The learners as manyworlds builds them (src/manyworlds/agents/{sac_ae,deepmdp,hipbmdp}/, after
MTRL's agents): frames (C, H, W) uint8 -> /255 -> 3x3 convolutions of 32 channels (the first of
stride 2, `--conv-layers` in all, ReLU) -> Linear(50) -> LayerNorm -> tanh: the features. Actor
and twin critics are MLPs of `--layers` x `--hidden` ReLU units on the features (critics also on
the action); log std tanh-bounded to [-10, 2]. One update:

- SAC on the features: critic target with the actor on the online features and the target
  critics on a target encoder's; critic loss MSE(Q1, y) + MSE(Q2, y) into critics and encoder
  (one Adam over both, lr 1e-3); every 2nd update the actor (on the features of the encoder
  just stepped, computed again without gradients, as MTRL's actor does) and the
  temperature (Adam 1e-4), then the Polyak updates of critics (tau 0.01) and encoder (0.05);
- sac_ae: reconstruction MSE(decoder(h), preprocess(o)) + 1e-6 mean 0.5 |h|^2 into encoder
  (its own Adam, 1e-3) and a deconvolutional decoder (Adam 1e-3, weight decay 1e-7);
- deepmdp: a transition model [h, a] -> 512 -> LayerNorm -> ReLU -> h' and a reward model
  h -> 512 -> LayerNorm -> ReLU -> 1 trained with the encoder on 0.5 (mu - h(o'))^2 + MSE(R(mu), r);
  then the decoder drawing o' from mu, into transition, decoder and encoder;
- hipbmdp: deepmdp with a per-task parameter theta (Embedding(50) -> ReLU -> 100 -> ReLU -> 50)
  concatenated to the features (detached for actor and critics), and the contrastive loss
  0.01 (|theta - flip theta| - |mu(theta) - mu(flip theta)|)^2, one Adam step of theta.

Batches as `bench agent`: `--batch` rows per task, `--tasks` tasks (task index row % T); four
random batches of frames, next frames, actions in (-1, 1), rewards (done 0) cycled; 3 warm-up
updates, then `--repeats` repeats of `--updates` updates; prints JSON with updates_per_s (the
median) and the samples. What differs from manyworlds: torch.optim.Adam per parameter group and
per-parameter Polyak loops (manyworlds: fused loops over flat buffers), two critic modules
(manyworlds: one two-member ensemble of batched products).
"""

import argparse
import json
import statistics
import time

import torch
import torch.nn as nn
import torch.nn.functional as F


def mlp(inp, hidden, layers, out):
    mods, width = [], inp
    for _ in range(layers):
        mods += [nn.Linear(width, hidden), nn.ReLU()]
        width = hidden
    mods.append(nn.Linear(width, out))
    return nn.Sequential(*mods)


def side(frame, layers):
    return (frame - 3) // 2 + 1 - 2 * (layers - 1)


class Encoder(nn.Module):
    def __init__(self, c, frame, layers, filters=32, features=50):
        super().__init__()
        self.convs = nn.ModuleList([nn.Conv2d(c, filters, 3, stride=2)] +
                                   [nn.Conv2d(filters, filters, 3) for _ in range(layers - 1)])
        self.fc = nn.Linear(filters * side(frame, layers) ** 2, features)
        self.ln = nn.LayerNorm(features)

    def forward(self, o):
        x = o.float() / 255.0
        for conv in self.convs:
            x = torch.relu(conv(x))
        return torch.tanh(self.ln(self.fc(x.flatten(1))))


class Decoder(nn.Module):
    def __init__(self, c, frame, layers, inp, filters=32):
        super().__init__()
        self.s, self.f = side(frame, layers), filters
        self.fc = nn.Linear(inp, filters * self.s ** 2)
        self.deconvs = nn.ModuleList([nn.ConvTranspose2d(filters, filters, 3)
                                      for _ in range(layers - 1)])
        first = (frame - 3) // 2 + 1
        self.last = nn.ConvTranspose2d(filters, c, 3, stride=2, output_padding=frame - 2 * first - 1)

    def forward(self, h):
        x = torch.relu(self.fc(h)).view(-1, self.f, self.s, self.s)
        for d in self.deconvs:
            x = torch.relu(d(x))
        return self.last(x)


class LatentModel(nn.Module):
    def __init__(self, inp, out, width=512):
        super().__init__()
        self.fc, self.ln, self.out = nn.Linear(inp, width), nn.LayerNorm(width), nn.Linear(width, out)

    def forward(self, x):
        return self.out(torch.relu(self.ln(self.fc(x))))


def preprocess(o):
    x = torch.floor(o.float() / 8.0) / 32.0
    return x + torch.rand_like(x) / 32.0 - 0.5


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--algo", choices=["sac_ae", "deepmdp", "hipbmdp"], default="sac_ae")
    p.add_argument("--tasks", type=int, default=1)
    p.add_argument("--batch", type=int, default=128, help="rows per task")
    p.add_argument("--frame", type=int, default=84)
    p.add_argument("--channels", type=int, default=9)
    p.add_argument("--conv-layers", type=int, default=4)
    p.add_argument("--hidden", type=int, default=1024)
    p.add_argument("--layers", type=int, default=2)
    p.add_argument("--action-dim", type=int, default=2)
    p.add_argument("--updates", type=int, default=5)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--seed", type=int, default=0)
    a = p.parse_args()
    torch.set_num_threads(a.threads)
    torch.manual_seed(a.seed)
    A, T, c, fr = a.action_dim, a.tasks, a.channels, a.frame
    hip, model = a.algo == "hipbmdp", a.algo in ("deepmdp", "hipbmdp")
    theta_dim = 50 if hip else 0
    feat = 50
    latent = feat + theta_dim
    enc = Encoder(c, fr, a.conv_layers)
    enc_t = Encoder(c, fr, a.conv_layers)
    enc_t.load_state_dict(enc.state_dict())
    actor = mlp(latent, a.hidden, a.layers, 2 * A)
    q1, q2 = mlp(latent + A, a.hidden, a.layers, 1), mlp(latent + A, a.hidden, a.layers, 1)
    q1_t, q2_t = mlp(latent + A, a.hidden, a.layers, 1), mlp(latent + A, a.hidden, a.layers, 1)
    q1_t.load_state_dict(q1.state_dict())
    q2_t.load_state_dict(q2.state_dict())
    for m in (enc_t, q1_t, q2_t):
        m.requires_grad_(False)
    log_alpha = torch.tensor([0.1]).log().requires_grad_(True)
    dec = Decoder(c, fr, a.conv_layers, latent)
    critic_opt = torch.optim.Adam(list(q1.parameters()) + list(q2.parameters()) +
                                  list(enc.parameters()), lr=1e-3)
    actor_opt = torch.optim.Adam(actor.parameters(), lr=1e-3)
    alpha_opt = torch.optim.Adam([log_alpha], lr=1e-4)
    enc_opt = torch.optim.Adam(enc.parameters(), lr=1e-3)
    dec_opt = torch.optim.Adam(dec.parameters(), lr=1e-3, weight_decay=1e-7)
    if model:
        trans = LatentModel(latent + A, latent)
        rew = LatentModel(latent, 1)
        trans_opt = torch.optim.Adam(trans.parameters(), lr=1e-3, weight_decay=1e-7)
        rew_opt = torch.optim.Adam(rew.parameters(), lr=1e-3, weight_decay=1e-7)
    if hip:
        emb = nn.Embedding(T, 50)
        theta_mlp = nn.Sequential(nn.ReLU(), nn.Linear(50, 100), nn.ReLU(), nn.Linear(100, 50))
        theta_opt = torch.optim.Adam(list(emb.parameters()) + list(theta_mlp.parameters()), lr=1e-3)
    b = a.batch * T
    batches = []
    for _ in range(4):
        batches.append(dict(o=torch.randint(0, 256, (b, c, fr, fr), dtype=torch.uint8),
                            o2=torch.randint(0, 256, (b, c, fr, fr), dtype=torch.uint8),
                            a=torch.rand(b, A) * 2 - 1, r=torch.randn(b), d=torch.zeros(b),
                            t=torch.arange(b) % T))
    target_entropy = -float(A)
    count = [0]

    def policy(x):
        mean, log_std = actor(x).chunk(2, -1)
        log_std = -10 + 0.5 * 12 * (torch.tanh(log_std) + 1)
        u = mean + log_std.exp() * torch.randn_like(mean)
        act = torch.tanh(u)
        logp = (-0.5 * ((u - mean) / log_std.exp()) ** 2 - log_std - 0.5 * torch.log(
            torch.tensor(2 * torch.pi))).sum(-1) - torch.log(1 - act ** 2 + 1e-6).sum(-1)
        return act, logp

    def update(bt):
        o, o2, act, r, d, t = bt["o"], bt["o2"], bt["a"], bt["r"], bt["d"], bt["t"]
        theta = theta_mlp(emb(t)) if hip else None

        def with_theta(h, grad=False):
            if not hip:
                return h
            return torch.cat([h, theta if grad else theta.detach()], 1)
        alpha = log_alpha.exp().detach()
        with torch.no_grad():
            h2 = with_theta(enc(o2))
            a2, logp2 = policy(h2)
            h2_t = with_theta(enc_t(o2))
            x2 = torch.cat([h2_t, a2], 1)
            y = r + 0.99 * (1 - d) * (torch.min(q1_t(x2), q2_t(x2)).squeeze(1) - alpha * logp2)
        h = with_theta(enc(o))
        x = torch.cat([h, act], 1)
        critic_loss = F.mse_loss(q1(x).squeeze(1), y) + F.mse_loss(q2(x).squeeze(1), y)
        critic_opt.zero_grad()
        critic_loss.backward()
        critic_opt.step()
        if count[0] % 2 == 0:
            # the actor reads the encoder after the critic's step, detached (MTRL: the actor's
            # forward with detach_encoder=True; manyworlds: the same)
            with torch.no_grad():
                hd = with_theta(enc(o))
            pi, logp = policy(hd)
            xp = torch.cat([hd, pi], 1)
            actor_loss = (alpha * logp - torch.min(q1(xp), q2(xp)).squeeze(1)).mean()
            actor_opt.zero_grad()
            actor_loss.backward()
            actor_opt.step()
            alpha_loss = (log_alpha.exp() * (-logp.detach() - target_entropy)).mean()
            alpha_opt.zero_grad()
            alpha_loss.backward()
            alpha_opt.step()
            with torch.no_grad():
                for src, dst, tau in ((q1, q1_t, 0.01), (q2, q2_t, 0.01), (enc, enc_t, 0.05)):
                    for ps, pt in zip(src.parameters(), dst.parameters()):
                        pt.mul_(1 - tau).add_(tau * ps)
        if hip:
            theta_opt.zero_grad()
        if model:
            hg = with_theta(enc(o), grad=True)
            with torch.no_grad():
                nh = with_theta(enc(o2))
            mu = trans(torch.cat([hg, act], 1))
            loss = (0.5 * (mu - nh) ** 2).mean() + F.mse_loss(rew(mu).squeeze(1), r)
            for opt in (trans_opt, rew_opt, enc_opt):
                opt.zero_grad()
            loss.backward(retain_graph=hip)
            for opt in (trans_opt, rew_opt, enc_opt):
                opt.step()
        hg = with_theta(enc(o), grad=True)
        target_frames = o2 if model else o
        source = trans(torch.cat([hg, act], 1)) if model else hg
        rec = dec(source)
        loss = F.mse_loss(rec, preprocess(target_frames)) + 1e-6 * (0.5 * hg.pow(2).sum(1)).mean()
        for opt in ((trans_opt,) if model else ()) + (dec_opt, enc_opt):
            opt.zero_grad()
        loss.backward(retain_graph=hip)
        for opt in ((trans_opt,) if model else ()) + (dec_opt, enc_opt):
            opt.step()
        if hip:
            th = theta_mlp(emb(t))
            fl = th.flip(0)
            with torch.no_grad():
                phi = enc(o)
                gap = (trans(torch.cat([phi, th, act], 1)) - trans(torch.cat([phi, fl, act], 1))).norm()
            closs = 0.01 * ((th - fl).norm() - gap) ** 2
            closs.backward()
            theta_opt.step()
        count[0] += 1

    n = [0]

    def step():
        update(batches[n[0] % 4])
        n[0] += 1
    for _ in range(3):
        step()
    rates = []
    for _ in range(a.repeats):
        start = time.perf_counter()
        for _ in range(a.updates):
            step()
        rates.append(a.updates / (time.perf_counter() - start))
    print(json.dumps({"agent": a.algo, "peer": "pytorch", "torch": torch.__version__,
                      "batch": b, "frame": [c, fr, fr], "updates_per_s": statistics.median(rates),
                      "updates": rates}))


if __name__ == "__main__":
    main()
