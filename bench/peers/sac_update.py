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

Multi-task architectures (`--architecture`, `--tasks T`), the peer of `bench agent
--architecture X --tasks T --disentangled-alpha`: every batch row gets a task index drawn
uniformly (`--batch` is the whole batch, as in `bench agent`); with T > 1 the temperature is one
per task (log_alpha of size T, alpha and the temperature loss per row). The actor is one network
obs -> 2 * action_dim, the critics two networks (obs, action) -> 1, as in manyworlds' SAC; the
observation goes in without a one-hot and the networks read the task index of each row:

- `mlp` (MT-SAC; the default, and with T = 1 exactly the plain update above): the MLPs see the
  observation followed by a one-hot of the task when T > 1.
- `multihead` (multi-head SAC, MTRL's `should_use_multi_head_policy`): the MLPs of `mlp`
  without the one-hot, their last layer T x out wide, each row reading its task's head (as
  manyworlds' heads: all computed, one gathered).
- `task_encoder` (MTRL's task encoder): the MLPs read [obs, e(task)], e = TaskEncoder
  (Embedding(T, `--task-embedding-dim`), ReLU, MLP E-E-E-E) trained by the critic loss; the
  actor reads it detached; the target critics read the online encoder (task_encoders()).
- `moe` (CARE's mixture of encoders, MTRL's `moe` encoder): the MLPs read [mix(obs), e(task)],
  mix = sum_k w_k expert_k(obs) over `--num-experts` experts obs-D-D-D (D =
  `--encoder-dim`), w = softmax(selector(e(task))) with the encoding detached; the critic loss
  trains encoder, experts and selector; the target critics read a target copy of the mixture
  (Polyak with the critics'). One Adam covers critics and encoders (manyworlds: one each, the
  same settings).
- `soft_modular` (Soft Modularization, Yang et al. 2020; manyworlds' nn/soft_modular.h): base
  Linear(in, H) ReLU Linear(H, H); task embedding Linear(one-hot, H) times the base output,
  ReLU, a routing MLP of `--routing-layers` x `--routing-hidden`; routing softmaxes
  p_1 = softmax(W_1 relu(z)) (n x n per row), p_l = softmax(W_l relu(U_l [p_1..p_{l-1}] * z)),
  output weights q = softmax(W_q relu(U_q [p_1..p_{L-1}] * z)) over the last layer's modules;
  `--module-layers` layers of `--num-modules` Linear(., `--module-hidden`) modules, each an
  nn.Linear in an nn.ModuleList looped over (as the authors write it; n = 2), ReLU of the routed
  mixture in front of each layer; output Linear(M, out). With `--architecture soft_modular` the
  per-sample critic and actor losses are weighted by T softmax(-log_alpha)[task] (the trainer's
  task reweighting, `task_reweight: true` in configs/mt10_soft_modular.yaml); `--task-reweight
  off` drops it (`bench agent` has no flag for it and times the learner without it).
- `paco` (PaCo, Sun et al. 2022; nn/paco.h): every linear map holds K = `--num-param-sets`
  parameter sets, written as one nn.Linear(in, K * out) whose K pre-activations are combined by
  the row's task weights (nn.Embedding(T, K), i.e. a bias-free linear map of the one-hot);
  `--layers` hidden layers of `--hidden`, ReLU, linear output; the K sets start identical.
  Each update computes the per-task mean critic loss and masks tasks above
  `--paco-reset-threshold` (3000, the MT10 config's), resetting their task weights to random
  convex combinations of the others' after the update, as manyworlds does; on these random
  batches it never fires.
- `moore` (MOORE, Hendawy et al. 2024; nn/moore.h): k = `--num-experts` expert MLPs of
  `--layers` linear maps of width `--hidden` (ReLU between, the last linear), written as
  batched parameters (k, in, out) with one torch.baddbmm per layer (the fast way to write k
  equal MLPs; a ModuleList of k MLPs does k times as many small products); Gram-Schmidt over
  the k outputs of each row (a Python loop over k, F.normalize for the norms); task weights
  nn.Embedding(T, k); tanh of the mixture; one output head per task as one nn.Linear(H, T *
  out) whose row's head is picked by indexing.

GradNorm (`--gradnorm`, `mlp` only, `--tasks` > 1), the peer of `bench agent --gradnorm`
(Chen et al. 2018, as MTRL's gradnorm.py computes it): per-task loss weights w (one set for the
critics, one for the actor, starting at 1). Each update, in the critic phase and again in the
actor phase, a Python loop over the tasks present takes the task's mean per-sample loss L_t
(critic: (Q1 - y)^2 + (Q2 - y)^2; actor: alpha log pi - min(Q1, Q2)) and G_t, the norm of
dL_t/dW for W the last weight matrix (both critics' last weights together; the actor's last
weight), with torch.autograd.grad(L_t, W, retain_graph=True); the per-sample loss is then
weighted by w[task], averaged, backward and the usual Adam step. Then the GradNorm rule on w in
closed form (no autograd): r_t = L_t / L_t(first update), target_t = mean(w G) (r_t /
mean r)^alpha, d/dw_t = sign(w_t G_t - target_t) G_t / (tasks present); an Adam step on w
(`--gradnorm-lr` 1e-6, `--gradnorm-alpha` 1.0, manyworlds' defaults), clamp at 1e-4 and
renormalise to sum T. With `--gradnorm` the batches hold equally many rows per task in random
order when the batch divides into the tasks, as `bench agent` draws them (without it, task
indices are drawn uniformly as above).

Sizes default to manyworlds' SacConfig defaults (2 modules, 2 module layers of 256, routing
2 x 256; 5 parameter sets; 4 experts); `bench agent` has no flags for them. What the peer does
differently from manyworlds: separate critic modules instead of one two-member ensemble of
batched products, per-module optimizers and a parameter loop for Polyak (as for plain SAC), and
the critics' weight gradients in the actor loss are computed and discarded (as above).

`--check` builds the networks at the given sizes, checks output shapes, that the outputs depend
on the task (same observation, different task), that MOORE's basis is orthonormal and SM's
routing rows sum to 1, runs two updates and checks that every parameter stays finite, and
prints each network's parameter count beside the count of manyworlds' parameter layout
(`specs()`, computed from the layout formulas transcribed from nn/soft_modular.cc, paco.cc,
moore.cc and mlp.cc into `cpp_layout_params` below), failing if they differ. At the MT10 sizes
(obs 39, action 4, 10 tasks, 3 x 400) both sides hold, actor / one critic / twin critics:

    mlp (one-hot input)  344,008 / 342,801 /   685,602
    soft_modular         691,022 / 690,823 / 1,381,646
    paco               1,700,090 / 1,694,055 / 3,388,110
    moore              1,379,320 / 1,357,650 / 2,715,300

    python3 bench/peers/sac_update.py --threads 1
    python3 bench/peers/sac_update.py --architecture moore --tasks 10 --batch 320 --threads 1
    python3 bench/peers/sac_update.py --architecture paco --tasks 10 --check
"""
import argparse
import os
import sys

ARCHITECTURES = ("mlp", "multihead", "task_encoder", "moe", "soft_modular", "paco", "moore")
# The architectures whose learned task encodings (and CARE's mixture) feed plain MLPs.
ENCODED = ("task_encoder", "moe")


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
    p.add_argument("--architecture", choices=ARCHITECTURES, default="mlp",
                   help="actor and critic networks (mlp: MT-SAC with a one-hot when --tasks > 1)")
    p.add_argument("--tasks", type=int, default=1,
                   help="tasks; rows draw task indices uniformly, one temperature per task")
    p.add_argument("--task-reweight", choices=("auto", "on", "off"), default="auto",
                   help="losses weighted by T softmax(-log_alpha)[task] (auto: soft_modular)")
    p.add_argument("--paco-reset-threshold", type=float, default=3000.0,
                   help="paco: mask and reset tasks whose mean critic loss exceeds this "
                        "(<= 0: off)")
    p.add_argument("--num-modules", type=int, default=2, help="soft_modular")
    p.add_argument("--module-layers", type=int, default=2, help="soft_modular")
    p.add_argument("--module-hidden", type=int, default=256, help="soft_modular")
    p.add_argument("--routing-layers", type=int, default=2, help="soft_modular")
    p.add_argument("--routing-hidden", type=int, default=256, help="soft_modular")
    p.add_argument("--num-param-sets", type=int, default=5, help="paco")
    p.add_argument("--num-experts", type=int, default=4, help="moore, moe")
    p.add_argument("--task-embedding-dim", type=int, default=50, help="task_encoder, moe")
    p.add_argument("--encoder-dim", type=int, default=50, help="moe: the experts' width")
    p.add_argument("--gradnorm", action="store_true",
                   help="mlp: GradNorm task weights for the critic and actor losses")
    p.add_argument("--gradnorm-lr", type=float, default=1e-6, help="gradnorm: Adam lr of w")
    p.add_argument("--gradnorm-alpha", type=float, default=1.0, help="gradnorm: asymmetry")
    p.add_argument("--check", action="store_true",
                   help="check shapes, task dependence and parameter counts; no timing")
    args = p.parse_args()
    if args.tasks < 1:
        p.error("--tasks must be >= 1")
    if args.task_reweight == "on" and args.tasks < 2:
        p.error("--task-reweight on needs --tasks > 1 (one temperature per task)")
    if args.gradnorm and args.architecture != "mlp":
        p.error("--gradnorm is for --architecture mlp only")
    if args.gradnorm and args.tasks < 2:
        p.error("--gradnorm needs --tasks > 1")
    if args.architecture == "soft_modular" and args.module_layers < 2:
        p.error("--module-layers must be >= 2")
    return args


def cpp_layout_params(args, inp, out):
    """Parameters of one member of manyworlds' network (the sizes of its `specs()` layout),
    from the layout code of nn/mlp.cc (AppendMlpLayout), soft_modular.cc (Layout), paco.cc and
    moore.cc; `inp` excludes the one-hot that manyworlds' MT-SAC appends for `mlp`."""
    def linear(i, o):
        return i * o + o

    t, h = args.tasks, args.hidden
    if args.architecture == "mlp" or args.architecture in ENCODED:
        one_hot = t if args.architecture == "mlp" and t > 1 else 0  # encodings are in inp
        widths = [inp + one_hot] + [h] * args.layers + [out]
        return sum(linear(i, o) for i, o in zip(widths, widths[1:]))
    if args.architecture == "multihead":
        widths = [inp] + [h] * args.layers + [t * out]
        return sum(linear(i, o) for i, o in zip(widths, widths[1:]))
    if args.architecture == "soft_modular":
        n, m, g = args.num_modules, args.module_hidden, args.routing_hidden
        layers = args.module_layers
        total = linear(inp, h) + linear(h, h) + linear(t, h)  # base0, base1, embed
        total += sum(linear(h if i == 0 else g, g) for i in range(args.routing_layers))
        total += linear(g, n * n)  # logit0
        total += sum(linear(l * n * n, g) + linear(g, n * n) for l in range(1, layers - 1))
        total += linear((layers - 1) * n * n, g) + linear(g, n)  # condq, logitq
        total += linear(h, n * m) + (layers - 1) * n * linear(m, m) + linear(m, out)
        return total
    if args.architecture == "paco":
        k = args.num_param_sets
        widths = [inp] + [h] * args.layers + [out]
        return sum(i * k * o + k * o for i, o in zip(widths, widths[1:])) + t * k
    k = args.num_experts  # moore
    widths = [inp] + [h] * args.layers
    return (k * sum(linear(i, o) for i, o in zip(widths, widths[1:])) + t * k
            + h * t * out + t * out)


def cpp_encoder_params(args, name):
    """Parameters of manyworlds' TaskEncoder ("task") or MixtureEncoder ("mixture") as
    nn/task_conditioning.cc sizes them (task_encoder.cc's layouts)."""
    def mlp(widths, members=1):
        return members * sum(i * o + o for i, o in zip(widths, widths[1:]))

    t, e, k, d = args.tasks, args.task_embedding_dim, args.num_experts, args.encoder_dim
    if name == "task":
        return t * e + mlp([e, e, e, e])
    return mlp([args.obs_dim, d, d, d], k) + mlp([e, e, e, k])


def task_networks():
    """The multi-task networks as nn.Modules, forward(x, task) with x (B, in) and task (B)
    int64. Defined in a function because torch may load only after the thread variables are
    set (main)."""
    import math

    import torch
    from torch import nn
    from torch.nn import functional as F

    def init_hidden(layer):
        # Soft Modularization's initialiser: U(+-1/sqrt(size(0))) of the (out, in) weight, bias 0.1.
        nn.init.uniform_(layer.weight, -1 / math.sqrt(layer.weight.size(0)),
                         1 / math.sqrt(layer.weight.size(0)))
        nn.init.constant_(layer.bias, 0.1)

    def init_last(layer):
        nn.init.uniform_(layer.weight, -3e-3, 3e-3)
        nn.init.uniform_(layer.bias, -3e-3, 3e-3)

    class SoftModularNet(nn.Module):
        def __init__(self, inp, out, tasks, hidden, num_modules, module_layers, module_hidden,
                     routing_layers, routing_hidden):
            super().__init__()
            n, g = num_modules, routing_hidden
            self.tasks, self.n = tasks, n
            self.base = nn.Sequential(nn.Linear(inp, hidden), nn.ReLU(), nn.Linear(hidden, hidden))
            self.embed = nn.Linear(tasks, hidden)
            route = []
            for i in range(routing_layers):
                route += [nn.Linear(hidden if i == 0 else g, g), nn.ReLU()]
            self.route = nn.Sequential(*route[:-1])  # no ReLU after the last routing layer
            # U_l reads the flattened p_1..p_{l-1}; W_l gives layer l's n x n logits, W_q n.
            self.conds = nn.ModuleList(nn.Linear(l * n * n, g) for l in range(1, module_layers))
            self.logits = nn.ModuleList([nn.Linear(g, n * n) for _ in range(module_layers - 1)]
                                        + [nn.Linear(g, n)])
            self.module_layers = nn.ModuleList(
                nn.ModuleList(nn.Linear(hidden if l == 0 else module_hidden, module_hidden)
                              for _ in range(n))
                for l in range(module_layers))
            self.out = nn.Linear(module_hidden, out)
            for layer in [self.base[0], self.base[2], self.embed, *self.conds,
                          *(m for m in self.route if isinstance(m, nn.Linear)),
                          *(m for layer in self.module_layers for m in layer)]:
                init_hidden(layer)
            for layer in [*self.logits, self.out]:
                init_last(layer)

        def routing(self, base, task):
            """The n x n routing matrices of the module layers, then the output weights (B, n)."""
            n = self.n
            z = self.route(F.relu(self.embed(F.one_hot(task, self.tasks).float()) * base))
            probs = [F.softmax(self.logits[0](F.relu(z)).view(-1, n, n), -1)]
            for l, (cond, logit) in enumerate(zip(self.conds, self.logits[1:])):
                c = F.relu(cond(torch.cat([p.flatten(1) for p in probs], -1)) * z)
                last = l + 1 == len(self.conds)  # the output weights (B, n)
                probs.append(F.softmax(logit(c) if last else logit(c).view(-1, n, n), -1))
            return probs

        def forward(self, x, task):
            base = self.base(x)
            probs = self.routing(base, task)
            h = F.relu(base)
            outs = torch.stack([module(h) for module in self.module_layers[0]], 1)  # (B, n, M)
            for p, layer in zip(probs[:-1], self.module_layers[1:]):
                mixed = F.relu(p @ outs)  # module j reads sum_i p[j, i] out_i
                outs = torch.stack([module(mixed[:, j]) for j, module in enumerate(layer)], 1)
            return self.out(F.relu((probs[-1].unsqueeze(1) @ outs).squeeze(1)))

    class PacoNet(nn.Module):
        def __init__(self, inp, out, tasks, hidden, layers, num_param_sets):
            super().__init__()
            k = self.k = num_param_sets
            widths = [inp] + [hidden] * layers + [out]
            # Layer l's K parameter sets side by side: set j is outputs [j out, (j + 1) out).
            self.maps = nn.ModuleList(nn.Linear(i, k * o) for i, o in zip(widths, widths[1:]))
            self.task_weights = nn.Embedding(tasks, k)  # a bias-free linear map of the one-hot
            with torch.no_grad():
                for layer, o in zip(self.maps, widths[1:]):
                    first = nn.init.orthogonal_(torch.empty(o, layer.in_features))
                    layer.weight.copy_(first.repeat(k, 1))  # K identical sets
                    layer.bias.zero_()
                nn.init.normal_(self.task_weights.weight, 0.0, 1 / math.sqrt(tasks))

        def forward(self, x, task):
            w = self.task_weights(task).unsqueeze(1)  # (B, 1, K)
            h = x
            for i, layer in enumerate(self.maps):
                h = (w @ layer(h).view(h.size(0), self.k, -1)).squeeze(1)  # sum_k w_k (x W_k + b_k)
                if i + 1 < len(self.maps):
                    h = F.relu(h)
            return h

    class MooreNet(nn.Module):
        def __init__(self, inp, out, tasks, hidden, layers, num_experts):
            super().__init__()
            k = self.k = num_experts
            self.tasks, self.out_dim = tasks, out
            widths = [inp] + [hidden] * layers
            # k expert MLPs as batched parameters: layer l's weights (k, in, out), biases
            # (k, 1, out).
            self.weights = nn.ParameterList(nn.Parameter(torch.empty(k, i, o))
                                            for i, o in zip(widths, widths[1:]))
            self.biases = nn.ParameterList(nn.Parameter(torch.zeros(k, 1, o)) for o in widths[1:])
            self.task_weights = nn.Embedding(tasks, k)  # bias-free linear map of the one-hot
            self.heads = nn.Linear(hidden, tasks * out)  # head t is outputs [t out, (t + 1) out)
            with torch.no_grad():
                for i, w in enumerate(self.weights):  # Xavier-uniform, ReLU gain but the last
                    gain = 1.0 if i + 1 == len(self.weights) else math.sqrt(2.0)
                    bound = gain * math.sqrt(6.0 / (w.size(1) + w.size(2)))
                    w.uniform_(-bound, bound)
                bound = math.sqrt(6.0 / (tasks + k))
                self.task_weights.weight.uniform_(-bound, bound)
                bound = math.sqrt(6.0 / (hidden + out))
                self.heads.weight.uniform_(-bound, bound)
                self.heads.bias.zero_()

        def basis(self, x):
            """(B, k, H): the experts' outputs of each row, orthonormalised by Gram-Schmidt."""
            h = x.expand(self.k, *x.shape)
            for i, (w, b) in enumerate(zip(self.weights, self.biases)):
                h = torch.baddbmm(b, h, w)
                if i + 1 < len(self.weights):
                    h = F.relu(h)
            basis = []
            for v in h.unbind(0):
                for u in basis:
                    v = v - (v * u).sum(-1, keepdim=True) * u
                basis.append(F.normalize(v, dim=-1))
            return torch.stack(basis, 1)

        def forward(self, x, task):
            w = self.task_weights(task).unsqueeze(1)  # (B, 1, k)
            features = torch.tanh((w @ self.basis(x)).squeeze(1))
            heads = self.heads(features).view(x.size(0), self.tasks, self.out_dim)
            return heads[torch.arange(x.size(0)), task]

    class MultiHeadNet(nn.Module):
        """MTRL's multi-head networks (`should_use_multi_head_policy`): one MLP whose last
        linear layer gives every task's outputs, each row reading its own task's head."""

        def __init__(self, inp, out, tasks, hidden, layers):
            super().__init__()
            mods, width = [], inp
            for _ in range(layers):
                mods += [nn.Linear(width, hidden), nn.ReLU()]
                width = hidden
            mods.append(nn.Linear(width, tasks * out))  # head t is outputs [t out, (t + 1) out)
            self.body = nn.Sequential(*mods)
            self.tasks, self.out_dim = tasks, out

        def forward(self, x, task):
            heads = self.body(x).view(x.size(0), self.tasks, self.out_dim)
            return heads[torch.arange(x.size(0)), task]

    return {"multihead": MultiHeadNet, "soft_modular": SoftModularNet, "paco": PacoNet,
            "moore": MooreNet}


def task_encoders(torch, args, obs_dim):
    """task_encoder and moe: MTRL's TaskEncoder (Embedding(T, E), ReLU, MLP E-E-E-E; every
    task's encoding at once, rows picked per sample) and, for moe, CARE's mixture of K
    encoders of the observation (each an MLP obs-D-D-D, the K run as one batched product as
    MTRL's moe_layer.FeedForward does) mixed per row by softmax(selector(e(task))), the
    selector an MLP E-E-E-K reading the encoding detached, with a target copy for the target
    critics. Returns {"task": module() -> (T, E), "mixture": module(obs, z, task) -> (B, D),
    "mixture_target"}; sizes as manyworlds' nn/task_conditioning.cc."""
    import copy
    import math

    from torch import nn

    t, e, k, d = args.tasks, args.task_embedding_dim, args.num_experts, args.encoder_dim

    def mlp(widths):
        mods = []
        for i, o in zip(widths, widths[1:]):
            mods += [nn.Linear(i, o), nn.ReLU()]
        return nn.Sequential(*mods[:-1])

    class TaskEncoder(nn.Module):
        def __init__(self):
            super().__init__()
            self.embedding = nn.Embedding(t, e)
            self.mlp = mlp([e, e, e, e])

        def forward(self):
            return self.mlp(torch.relu(self.embedding.weight))

    class Mixture(nn.Module):
        def __init__(self):
            super().__init__()
            widths = [obs_dim, d, d, d]
            self.weights = nn.ParameterList(nn.Parameter(torch.empty(k, i, o))
                                            for i, o in zip(widths, widths[1:]))
            self.biases = nn.ParameterList(nn.Parameter(torch.zeros(k, 1, o)) for o in widths[1:])
            with torch.no_grad():
                for w in self.weights:
                    bound = 1 / math.sqrt(w.size(1))
                    w.uniform_(-bound, bound)
            self.selector = mlp([e, e, e, k])

        def forward(self, x, z, task):
            weights = torch.softmax(self.selector(z), -1)[task]  # (B, K)
            h = x.expand(k, *x.shape)
            for i, (w, b) in enumerate(zip(self.weights, self.biases)):
                h = torch.baddbmm(b, h, w)
                if i + 1 < len(self.weights):
                    h = torch.relu(h)
            return (weights.t().unsqueeze(-1) * h).sum(0)

    encoders = {"task": TaskEncoder()}
    if args.architecture == "moe":
        encoders["mixture"] = Mixture()
        encoders["mixture_target"] = copy.deepcopy(encoders["mixture"])
        for p in encoders["mixture_target"].parameters():
            p.requires_grad_(False)
    return encoders


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

    arch, num_tasks = args.architecture, args.tasks
    multitask = arch != "mlp" or num_tasks > 1  # the plain update when False
    disentangled = num_tasks > 1
    reweight = (args.task_reweight == "on"
                or (args.task_reweight == "auto" and arch == "soft_modular" and disentangled))
    paco_resets = arch == "paco" and args.paco_reset_threshold > 0

    if arch == "mlp" or arch in ENCODED:
        one_hot = arch == "mlp" and num_tasks > 1
        net = mlp
    else:
        one_hot = False
        cls = task_networks()[arch]
        sizes = {"multihead": (args.hidden, args.layers),
                 "soft_modular": (args.hidden, args.num_modules, args.module_layers,
                                  args.module_hidden, args.routing_layers, args.routing_hidden),
                 "paco": (args.hidden, args.layers, args.num_param_sets),
                 "moore": (args.hidden, args.layers, args.num_experts)}[arch]

        def net(inp, out):
            return cls(inp, out, num_tasks, *sizes)

    o, a, b = args.obs_dim, args.action_dim, args.batch
    # the network input without the action
    e_dim = args.task_embedding_dim
    width = {"task_encoder": o + e_dim, "moe": args.encoder_dim + e_dim}.get(
        arch, o + (num_tasks if one_hot else 0))
    encoders = task_encoders(torch, args, o) if arch in ENCODED else {}
    actor = net(width, 2 * a)
    qf1, qf2 = net(width + a, 1), net(width + a, 1)
    qf1_target, qf2_target = net(width + a, 1), net(width + a, 1)
    qf1_target.load_state_dict(qf1.state_dict())
    qf2_target.load_state_dict(qf2.state_dict())
    for p in list(qf1_target.parameters()) + list(qf2_target.parameters()):
        p.requires_grad_(False)
    log_alpha = torch.zeros(num_tasks if disentangled else 1, requires_grad=True)
    adam = dict(lr=3e-4, betas=(0.9, 0.999))
    if args.foreach:
        adam["foreach"] = True
    q_params = list(qf1.parameters()) + list(qf2.parameters())
    # the critic loss trains the encoders too (their own Adams in manyworlds, same settings)
    encoder_params = [p for name in ("task", "mixture") if name in encoders
                      for p in encoders[name].parameters()]
    q_optimizer = torch.optim.Adam(q_params + encoder_params, **adam)
    actor_optimizer = torch.optim.Adam(actor.parameters(), **adam)
    a_optimizer = torch.optim.Adam([log_alpha], **adam)
    target_entropy = -float(a)
    discount, tau = 0.99, 0.005
    log_std_min, log_std_max = -20.0, 2.0
    online = q_params
    targets = list(qf1_target.parameters()) + list(qf2_target.parameters())
    if "mixture" in encoders:  # CARE's mixture has a target copy, updated with the critics'
        online = online + list(encoders["mixture"].parameters())
        targets = targets + list(encoders["mixture_target"].parameters())

    if arch == "mlp" or arch in ENCODED:
        def forward(module, x, task):
            return module(x)
    else:
        def forward(module, x, task):
            return module(x, task)

    def net_input(obs, task, target=False):
        """x(obs, task); `target`: with the target mixture (the target critics' input)."""
        if one_hot:
            return torch.cat([obs, nn.functional.one_hot(task, num_tasks).to(obs.dtype)], 1)
        if arch == "task_encoder":
            return torch.cat([obs, encoders["task"]()[task]], 1)
        if arch == "moe":
            z = encoders["task"]()  # (T, E): every task's encoding, rows picked per sample
            mixture = encoders["mixture_target" if target else "mixture"]
            return torch.cat([mixture(obs, z.detach(), task), z[task]], 1)
        return obs

    def sample(x, task):
        out = forward(actor, x, task)
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

    def reset_task_weights(tasks):
        """PaCo: the task weights of `tasks` become random convex combinations of the others'."""
        with torch.no_grad():
            normal = torch.ones(num_tasks, dtype=torch.bool)
            normal[tasks] = False
            if not normal.any():
                return
            for module in (actor, qf1, qf2):
                w = module.task_weights.weight
                mix = torch.rand(len(tasks), int(normal.sum()))
                w[tasks] = (mix / mix.sum(1, keepdim=True)) @ w[normal]

    paco_reset_count = [0]  # task resets so far (reported; none expected on random batches)

    if args.gradnorm:
        # One GradNorm state per loss: weights w (T), the first loss of each task (NaN until
        # seen), Adam on w; and the last weight matrices whose gradients' norms it balances.
        def gradnorm_state(last_weights):
            w = torch.ones(num_tasks)
            return {"w": w, "initial": torch.full((num_tasks,), float("nan")),
                    "optimizer": torch.optim.Adam([w], lr=args.gradnorm_lr, betas=(0.9, 0.999)),
                    "last": last_weights}

        gradnorm = {"critic": gradnorm_state([qf1[-1].weight, qf2[-1].weight]),
                    "actor": gradnorm_state([actor[-1].weight])}

    def task_loss_norms(per_sample, task, last_weights):
        """Each present task's mean loss and the norm of its gradient in the last layer."""
        losses, norms = torch.zeros(num_tasks), torch.zeros(num_tasks)
        for t in range(num_tasks):
            rows = task == t
            if not rows.any():
                continue
            loss = per_sample[rows].mean()
            grads = torch.autograd.grad(loss, last_weights, retain_graph=True)
            losses[t] = loss.detach()
            norms[t] = torch.sqrt(sum(g.pow(2).sum() for g in grads))
        return losses, norms

    def gradnorm_step(state, losses, norms, present):
        """GradNorm's update of w in closed form, an Adam step, clamp and renormalise."""
        w, initial = state["w"], state["initial"]
        with torch.no_grad():
            n = present.sum()
            if n == 0:
                return
            initial.copy_(torch.where(present & initial.isnan(), losses, initial))
            zero = torch.zeros_like(losses)
            ratio = torch.where(present, losses / initial, zero)
            inverse_rate = ratio / (ratio.sum() / n + 1e-8)
            weighted = w * norms
            target = torch.where(present, weighted, zero).sum() / n * inverse_rate.pow(
                args.gradnorm_alpha)
            diff = torch.where(present, weighted - target, zero)
            w.grad = torch.sign(diff) * norms / n
        state["optimizer"].step()
        with torch.no_grad():
            w.clamp_(min=1e-4)
            w.mul_(num_tasks / w.sum())

    def update(batch):
        obs, action, reward, next_obs, done, task = batch
        alpha = log_alpha.exp().detach()
        if disentangled:
            alpha = alpha[task]
        weights = None  # per-sample loss weights
        if reweight:
            weights = num_tasks * torch.softmax(-log_alpha.detach(), 0)[task]
        x = net_input(obs, task)
        with torch.no_grad():
            next_x = net_input(next_obs, task)
            next_action, next_log_prob = sample(next_x, task)
            next_x_target = net_input(next_obs, task, target=True) if arch == "moe" else next_x
            next_in = torch.cat([next_x_target, next_action], 1)
            min_q = torch.min(forward(qf1_target, next_in, task),
                              forward(qf2_target, next_in, task)).squeeze(-1)
            y = reward + discount * (1 - done) * (min_q - alpha * next_log_prob)
        q_in = torch.cat([x, action], 1)
        q1 = forward(qf1, q_in, task).squeeze(-1)
        q2 = forward(qf2, q_in, task).squeeze(-1)
        extreme = None
        if args.gradnorm:
            per_sample = (q1 - y).pow(2) + (q2 - y).pow(2)
            present = torch.bincount(task, minlength=num_tasks) > 0
            critic_losses, critic_norms = task_loss_norms(per_sample, task,
                                                          gradnorm["critic"]["last"])
            q_loss = (per_sample * gradnorm["critic"]["w"][task]).mean()
        elif weights is None and not paco_resets:
            q_loss = nn.functional.mse_loss(q1, y) + nn.functional.mse_loss(q2, y)
        else:
            per_sample = (q1 - y).pow(2) + (q2 - y).pow(2)
            if paco_resets:
                with torch.no_grad():
                    sums = torch.zeros(num_tasks).index_add_(0, task, per_sample)
                    counts = torch.bincount(task, minlength=num_tasks).clamp(min=1)
                    extreme = (sums / counts > args.paco_reset_threshold).nonzero().flatten()
                if len(extreme) > 0:  # mask those tasks out of this update (rare)
                    keep = torch.ones(num_tasks)
                    keep[extreme] = 0.0
                    weights = keep[task] if weights is None else weights * keep[task]
            q_loss = (per_sample if weights is None else per_sample * weights).mean()
        q_optimizer.zero_grad()
        q_loss.backward()
        q_optimizer.step()
        if args.gradnorm:
            gradnorm_step(gradnorm["critic"], critic_losses, critic_norms, present)

        if args.no_critic_weight_grads:
            for p in q_params:
                p.requires_grad_(False)
        if encoders:
            x = x.detach()  # the actor reads the encodings detached
        pi, log_prob = sample(x, task)
        pi_in = torch.cat([x, pi], 1)
        min_q_pi = torch.min(forward(qf1, pi_in, task), forward(qf2, pi_in, task)).squeeze(-1)
        if args.gradnorm:
            per_sample = alpha * log_prob - min_q_pi
            actor_losses, actor_norms = task_loss_norms(per_sample, task,
                                                        gradnorm["actor"]["last"])
            actor_loss = (per_sample * gradnorm["actor"]["w"][task]).mean()
        elif weights is None:
            actor_loss = (alpha * log_prob - min_q_pi).mean()
        else:
            actor_loss = ((alpha * log_prob - min_q_pi) * weights).mean()
        actor_optimizer.zero_grad()
        actor_loss.backward()
        actor_optimizer.step()
        if args.gradnorm:
            gradnorm_step(gradnorm["actor"], actor_losses, actor_norms, present)
        if args.no_critic_weight_grads:
            for p in q_params:
                p.requires_grad_(True)

        if disentangled:
            alpha_loss = (-log_alpha[task].exp() * (log_prob.detach() + target_entropy)).mean()
        else:
            alpha_loss = (-log_alpha.exp() * (log_prob.detach() + target_entropy)).mean()
        a_optimizer.zero_grad()
        alpha_loss.backward()
        a_optimizer.step()

        if extreme is not None and len(extreme) > 0:
            reset_task_weights(extreme)
            paco_reset_count[0] += len(extreme)
        with torch.no_grad():
            if args.foreach:
                torch._foreach_mul_(targets, 1 - tau)
                torch._foreach_add_(targets, online, alpha=tau)
            else:
                for tp, p in zip(targets, online):
                    tp.mul_(1 - tau).add_(p, alpha=tau)

    g = torch.Generator().manual_seed(args.seed + 1)

    def random_batch():
        obs, act = torch.randn(b, o, generator=g), torch.rand(b, a, generator=g) * 2 - 1
        reward, next_obs = torch.randn(b, generator=g), torch.randn(b, o, generator=g)
        done = (torch.rand(b, generator=g) < 0.01).float()
        if args.gradnorm and b % num_tasks == 0:  # balanced, shuffled, as `bench agent`
            task = (torch.arange(b) % num_tasks)[torch.randperm(b, generator=g)]
        else:
            task = (torch.randint(num_tasks, (b,), generator=g) if num_tasks > 1
                    else torch.zeros(b, dtype=torch.int64))
        return obs, act, reward, next_obs, done, task

    batches = [random_batch() for _ in range(4)]
    if args.check:
        check(args, torch, actor, qf1, qf2, width, a, batches, update,
              paco_reset_count if paco_resets else None, net_input, forward, encoders)
        return
    for i in range(3):
        update(batches[i % 4])
    samples = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        for i in range(args.updates):
            update(batches[i % 4])
        samples.append(args.updates / (time.perf_counter() - t0))
    result = {
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
    }
    if multitask:
        result.update(architecture=arch, tasks=num_tasks, disentangled_alpha=disentangled,
                      task_reweight=reweight, paco_reset_threshold=(
                          args.paco_reset_threshold if arch == "paco" else None),
                      paco_resets=paco_reset_count[0],
                      params={"actor": count(actor), "critics": count(qf1) + count(qf2)})
    if args.gradnorm:
        result.update(gradnorm={"lr": args.gradnorm_lr, "alpha": args.gradnorm_alpha,
                                "critic_weights": gradnorm["critic"]["w"].tolist(),
                                "actor_weights": gradnorm["actor"]["w"].tolist()})
    print(json.dumps(result))


def count(module):
    return sum(p.numel() for p in module.parameters())


def check(args, torch, actor, qf1, qf2, inp, a, batches, update, paco_reset_count, net_input,
          forward, encoders):
    """--check: shapes, task dependence, the architectures' invariants, finite parameters after
    two updates, parameter counts against manyworlds' layout. Prints JSON; raises on failure."""
    import json

    arch, t = args.architecture, args.tasks
    obs, action, _, _, _, task = batches[0]
    b = obs.size(0)
    report = {"architecture": arch, "tasks": t, "params": {}, "checks": []}
    with torch.no_grad():
        for name, module, width, out in (("actor", actor, inp, 2 * a),
                                         ("critic", qf1, inp + a, 1)):
            def output(task_index):
                xi = net_input(obs, task_index)
                if name == "critic":
                    xi = torch.cat([xi, action], 1)
                return forward(module, xi, task_index)

            y = output(task)
            assert y.shape == (b, out), f"{name}: output {tuple(y.shape)}, expected {(b, out)}"
            report["checks"].append(f"{name} output {tuple(y.shape)}")
            if t > 1:
                yo = output((task + 1) % t)
                diff = (y - yo).abs().max().item()
                assert diff > 0, f"{name}: the output does not depend on the task"
                report["checks"].append(
                    f"{name} output changes with the task (max |diff| {diff:.3g})")
            cpp = cpp_layout_params(args, width - (t if arch == "mlp" and t > 1 else 0), out)
            ours = count(module)
            report["params"][name] = {"pytorch": ours, "manyworlds_layout": cpp}
            assert ours == cpp, f"{name}: {ours} parameters, manyworlds' layout has {cpp}"
        report["params"]["twin_critics"] = {
            "pytorch": count(qf1) + count(qf2),
            "manyworlds_layout": 2 * report["params"]["critic"]["manyworlds_layout"]}
        for name in ("task", "mixture"):
            if name in encoders:
                ours, cpp = count(encoders[name]), cpp_encoder_params(args, name)
                report["params"][f"{name} encoder"] = {"pytorch": ours, "manyworlds_layout": cpp}
                assert ours == cpp, f"{name} encoder: {ours} parameters, manyworlds' has {cpp}"
        if arch == "moore":
            basis = actor.basis(obs)
            gram = basis @ basis.transpose(1, 2)
            err = (gram - torch.eye(args.num_experts)).abs().max().item()
            assert err < 1e-4, f"moore: basis not orthonormal ({err})"
            report["checks"].append(f"moore basis orthonormal (max |B B^T - I| {err:.2g})")
        if arch == "soft_modular":
            probs = actor.routing(actor.base(obs), task)
            err = max((p.sum(-1) - 1).abs().max().item() for p in probs)
            assert err < 1e-5 and len(probs) == args.module_layers
            report["checks"].append(f"soft_modular routing: {len(probs)} softmaxes, rows sum to 1")
            if t > 1:  # at initialisation (logits U(+-3e-3)) the output barely moves; routing does
                other = actor.routing(actor.base(obs), (task + 1) % t)
                diff = max((p - q).abs().max().item() for p, q in zip(probs, other))
                assert diff > 0, "soft_modular: routing does not depend on the task"
                report["checks"].append(f"soft_modular routing changes with the task "
                                        f"(max |diff| {diff:.3g})")
    for k in range(2):
        update(batches[k])
    if paco_reset_count is not None:
        report["paco_resets"] = paco_reset_count[0]
    for name, module in (("actor", actor), ("critic 1", qf1), ("critic 2", qf2)):
        assert all(torch.isfinite(p).all() for p in module.parameters()), f"{name}: not finite"
    report["checks"].append("all parameters finite after 2 updates")
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
