#!/usr/bin/env python3
"""The JAX peer of `manyworlds bench agent --algo sac` (and of bench/peers/sac_update.py): one
complete SAC update compiled as a whole with `jax.jit`, the same sizes and work, timed the same
way.

One update, as in sac_update.py (and manyworlds' SacLearner::Update):

- critic target without gradients: actor forward on next_obs, tanh-squashed Gaussian sample,
  both target critics, y = r + discount (1 - done) (min(Q1', Q2') - alpha log pi);
- critic loss MSE(Q1, y) + MSE(Q2, y), its gradient, one Adam step over both critics;
- actor: forward on obs, reparameterised sample, Q1 and Q2 of the sampled action with the
  critics' parameters held constant, loss mean(alpha log pi - min(Q1, Q2)), Adam step;
- temperature: loss mean(-log_alpha.exp() (log pi + target_entropy)) with log pi held constant,
  Adam step on log_alpha (one per task with several tasks, as `bench agent --disentangled-alpha`);
- Polyak update of both target critics (tau 0.005).

Networks: actor MLP obs -> (mean, raw log std) and two critic MLPs (obs, action) -> Q, each
`--layers` hidden layers of `--hidden` ReLU units; log std bounded to [-20, 2] by tanh;
PyTorch's default Linear initialisation; Adam (optax) lr 3e-4, betas (0.9, 0.999). The two
critics are one vmapped network over stacked parameters, the usual way to write twin critics in
JAX (manyworlds runs them as one batched product too). With `--tasks T > 1` (MT-SAC, the peer
of `bench agent --architecture mlp --tasks T --disentangled-alpha`) every row gets a task drawn
uniformly and the networks read the observation followed by a one-hot of its task.

Timing as `bench agent`: four random batches cycled, 3 warm-up updates (the first compiles),
then `--repeats` repeats of `--updates` updates, each repeat ending when the last update's
results are ready; prints JSON with updates_per_s (the median) and the samples.

Threads: the process is bound to `--threads` cores (os.sched_setaffinity, before jax loads) and
XLA's CPU flags ask for that many threads: jax 0.10's CPU backend ignores
`--xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1` and ran this update on both
cores of a 2-core machine (user time 1.4x wall time) until it was bound to one.

    python3 -m venv .venv-jax && .venv-jax/bin/pip install "jax[cpu]" optax
    .venv-jax/bin/python bench/peers/sac_update_jax.py --tasks 10 --batch 320 --updates 10
"""
import argparse
import json
import os
import statistics
import sys
import time


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--batch", type=int, default=128)
    p.add_argument("--hidden", type=int, default=400)
    p.add_argument("--layers", type=int, default=3)
    p.add_argument("--obs-dim", type=int, default=39)
    p.add_argument("--action-dim", type=int, default=4)
    p.add_argument("--tasks", type=int, default=1)
    p.add_argument("--updates", type=int, default=20, help="timed updates per repeat")
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--threads", type=int, default=1, help="XLA CPU threads")
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args()
    for name in ("batch", "hidden", "layers", "obs_dim", "action_dim", "tasks", "updates",
                 "repeats", "threads"):
        if getattr(args, name) < 1:
            p.error(f"--{name.replace('_', '-')} must be >= 1, got {getattr(args, name)}")
    return args


def main():
    args = parse_args()
    cores = sorted(os.sched_getaffinity(0))
    if args.threads > len(cores):
        sys.exit(f"--threads {args.threads}: this process may run on {len(cores)} cores")
    os.sched_setaffinity(0, cores[:args.threads])
    if args.threads == 1:
        os.environ["XLA_FLAGS"] = (os.environ.get("XLA_FLAGS", "") +
                                   " --xla_cpu_multi_thread_eigen=false"
                                   " intra_op_parallelism_threads=1")
    os.environ.setdefault("JAX_PLATFORMS", "cpu")
    import jax
    import jax.numpy as jnp
    import optax

    obs_dim, act_dim, tasks = args.obs_dim, args.action_dim, args.tasks
    net_in = obs_dim + (tasks if tasks > 1 else 0)
    discount, tau, log_std_min, log_std_max = 0.99, 0.005, -20.0, 2.0
    target_entropy = -float(act_dim)

    def linear_init(key, fan_in, fan_out):
        # PyTorch's Linear default: U(-1/sqrt(fan_in), 1/sqrt(fan_in)) for weight and bias
        bound = 1.0 / fan_in ** 0.5
        wk, bk = jax.random.split(key)
        return (jax.random.uniform(wk, (fan_in, fan_out), jnp.float32, -bound, bound),
                jax.random.uniform(bk, (fan_out,), jnp.float32, -bound, bound))

    def mlp_init(key, widths):
        keys = jax.random.split(key, len(widths) - 1)
        return [linear_init(k, i, o) for k, i, o in zip(keys, widths[:-1], widths[1:])]

    def mlp(params, x):
        for w, b in params[:-1]:
            x = jax.nn.relu(x @ w + b)
        w, b = params[-1]
        return x @ w + b

    hidden = [args.hidden] * args.layers
    key = jax.random.PRNGKey(args.seed)
    key, ka, kc = jax.random.split(key, 3)
    actor = mlp_init(ka, [net_in] + hidden + [2 * act_dim])
    critics = jax.vmap(lambda k: mlp_init(k, [net_in + act_dim] + hidden + [1]))(
        jax.random.split(kc, 2))
    target_critics = jax.tree_util.tree_map(lambda x: x, critics)
    log_alpha = jnp.zeros((tasks,), jnp.float32)
    adam = optax.adam(3e-4, b1=0.9, b2=0.999)
    state = dict(actor=actor, critics=critics, target=target_critics, log_alpha=log_alpha,
                 opt_actor=adam.init(actor), opt_critics=adam.init(critics),
                 opt_alpha=adam.init(log_alpha), key=key)

    def net_input(obs, task):
        if tasks == 1:
            return obs
        return jnp.concatenate([obs, jax.nn.one_hot(task, tasks, dtype=obs.dtype)], -1)

    def sample(actor_params, x, key):
        out = mlp(actor_params, x)
        mean, raw = out[:, :act_dim], out[:, act_dim:]
        log_std = log_std_min + 0.5 * (log_std_max - log_std_min) * (jnp.tanh(raw) + 1.0)
        eps = jax.random.normal(key, mean.shape, mean.dtype)
        u = mean + jnp.exp(log_std) * eps
        action = jnp.tanh(u)
        log_prob = (-0.5 * eps ** 2 - log_std - 0.5 * jnp.log(2.0 * jnp.pi)).sum(-1)
        log_prob = log_prob - jnp.log(1.0 - action ** 2 + 1e-6).sum(-1)
        return action, log_prob

    def q_values(critic_params, x, action):
        xa = jnp.concatenate([x, action], -1)
        return jax.vmap(lambda p: mlp(p, xa)[:, 0])(critic_params)  # (2, B)

    @jax.jit
    def update(state, obs, action, reward, next_obs, done, task):
        key, k_next, k_now = jax.random.split(state["key"], 3)
        x, next_x = net_input(obs, task), net_input(next_obs, task)
        alpha = jnp.exp(state["log_alpha"])[task if tasks > 1 else jnp.zeros_like(task)]
        next_action, next_log_prob = sample(state["actor"], next_x, k_next)
        next_q = q_values(state["target"], next_x, next_action).min(0)
        y = jax.lax.stop_gradient(
            reward + discount * (1.0 - done) * (next_q - alpha * next_log_prob))

        def critic_loss(critic_params):
            q = q_values(critic_params, x, action)
            return ((q - y) ** 2).mean(-1).sum()

        c_loss, c_grads = jax.value_and_grad(critic_loss)(state["critics"])
        c_updates, opt_critics = adam.update(c_grads, state["opt_critics"], state["critics"])
        critics = optax.apply_updates(state["critics"], c_updates)

        frozen = jax.lax.stop_gradient(critics)

        def actor_loss(actor_params):
            a, log_prob = sample(actor_params, x, k_now)
            q = q_values(frozen, x, a).min(0)
            return (alpha * log_prob - q).mean(), log_prob

        (a_loss, log_prob), a_grads = jax.value_and_grad(actor_loss, has_aux=True)(
            state["actor"])
        a_updates, opt_actor = adam.update(a_grads, state["opt_actor"], state["actor"])
        actor = optax.apply_updates(state["actor"], a_updates)

        entropy_term = jax.lax.stop_gradient(log_prob + target_entropy)

        def alpha_loss(log_alpha):
            per_row = jnp.exp(log_alpha)[task if tasks > 1 else jnp.zeros_like(task)]
            return (-per_row * entropy_term).mean()

        al_loss, al_grad = jax.value_and_grad(alpha_loss)(state["log_alpha"])
        al_updates, opt_alpha = adam.update(al_grad, state["opt_alpha"], state["log_alpha"])
        log_alpha = optax.apply_updates(state["log_alpha"], al_updates)
        target = optax.incremental_update(critics, state["target"], tau)
        new_state = dict(actor=actor, critics=critics, target=target, log_alpha=log_alpha,
                         opt_actor=opt_actor, opt_critics=opt_critics, opt_alpha=opt_alpha,
                         key=key)
        return new_state, (c_loss, a_loss, al_loss)

    data_key = jax.random.PRNGKey(args.seed + 1)
    batches = []
    for k in jax.random.split(data_key, 4):
        ks = jax.random.split(k, 6)
        b = args.batch
        batches.append((jax.random.normal(ks[0], (b, obs_dim)),
                        jax.random.uniform(ks[1], (b, act_dim), minval=-1.0, maxval=1.0),
                        jax.random.normal(ks[2], (b,)),
                        jax.random.normal(ks[3], (b, obs_dim)),
                        (jax.random.uniform(ks[4], (b,)) < 0.01).astype(jnp.float32),
                        jax.random.randint(ks[5], (b,), 0, tasks)))

    step = 0
    for _ in range(3):  # warm-up; the first call compiles
        state, losses = update(state, *batches[step % 4])
        step += 1
    jax.block_until_ready(losses)
    samples = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        for _ in range(args.updates):
            state, losses = update(state, *batches[step % 4])
            step += 1
        jax.block_until_ready((state, losses))
        samples.append(args.updates / (time.perf_counter() - t0))
    print(json.dumps({
        "peer": "jax-jit-sac", "python": sys.version.split()[0], "jax": jax.__version__,
        "optax": optax.__version__, "backend": jax.default_backend(), "threads": args.threads,
        "cores": sorted(os.sched_getaffinity(0)),
        "batch": args.batch, "hidden": args.hidden, "layers": args.layers,
        "obs_dim": obs_dim, "action_dim": act_dim, "tasks": tasks,
        "updates_per_repeat": args.updates, "repeats": args.repeats,
        "updates_per_s": statistics.median(samples), "samples": samples,
        "losses": [float(v) for v in losses]}))


if __name__ == "__main__":
    main()
