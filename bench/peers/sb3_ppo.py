#!/usr/bin/env python3
"""The peer of `manyworlds train configs/cartpole_ppo.yaml`: Stable-Baselines3's PPO trained
end to end on the same env through the manyworlds package, env steps per second from its own
wall time.

The run mirrors the config as far as SB3 allows: `cartpole` with 4 tasks x 2 envs (task states
sampled from the env's task sampler with the seed, each on two envs) on manyworlds' batched
executor (`manyworlds.sb3.SB3VecEnv`, 1 thread), 500-step rollouts per env (4,000 samples per
update), 10 epochs of minibatch 64, separate 2 x 64 tanh policy and value networks, lr 1e-3,
discount 0.99, GAE 0.95, clip 0.2, no entropy bonus, 20,000 steps per env (160,000 env steps,
40 updates). What differs: SB3 optimises policy and value with one Adam on the summed loss
(value coefficient 0.5) and clips the gradient norm at 0.5; its policy input is the flat
observation (4 env values + the task's 5 physics parameters = 9) where manyworlds' MT-PPO uses
the 4 env values and a one-hot of the 4 tasks (8); SB3 copies every observation (its
VecEnv keeps the previous one). Neither side evaluates during the timed run (manyworlds: one
evaluation of 4 episodes per task at the end, ~0.02 s).

Wall time is that of `model.learn(...)` (the C++ side's `wall_s` in summary.json likewise
covers its training loop); prints JSON with env_steps_per_s and, for a check that both sides
learn, the mean return of the last 8 finished training episodes.

    .venv-py/bin/python bench/peers/sb3_ppo.py --threads 1
"""
import argparse
import os


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--env", default="cartpole")
    p.add_argument("--num-tasks", type=int, default=4)
    p.add_argument("--envs-per-task", type=int, default=2)
    p.add_argument("--steps-per-env", type=int, default=20000)
    p.add_argument("--n-steps", type=int, default=500, help="rollout length per env")
    p.add_argument("--batch-size", type=int, default=64)
    p.add_argument("--epochs", type=int, default=10)
    p.add_argument("--hidden", type=int, default=64)
    p.add_argument("--layers", type=int, default=2)
    p.add_argument("--lr", type=float, default=1e-3)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--threads", type=int, default=1, help="torch intra-op threads")
    p.add_argument("--blas-threads", type=int, default=0, help="BLAS threads (0: as --threads)")
    return p.parse_args()


def main():
    args = parse_args()
    blas = str(args.blas_threads if args.blas_threads > 0 else args.threads)
    for var in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS"):
        os.environ[var] = blas
    import json
    import sys
    import time
    import warnings

    import numpy as np
    import stable_baselines3
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecMonitor

    import manyworlds
    from manyworlds.sb3 import SB3VecEnv

    # SB3 warns that 4,000 samples do not split into minibatches of 64 (the last one has 32).
    warnings.filterwarnings("ignore", message=".*mini-batch size.*")
    torch.set_num_threads(args.threads)
    probe = manyworlds.make(args.env)
    probe.seed_task(args.seed)
    tasks = [probe.sample_task_state() for _ in range(args.num_tasks)]
    probe.close()
    task_states = [t for t in tasks for _ in range(args.envs_per_task)]
    venv = VecMonitor(SB3VecEnv(args.env, num_envs=len(task_states), threads=1,
                                task_states=task_states))
    venv.seed(args.seed)
    total = args.steps_per_env * venv.num_envs
    model = PPO(
        "MlpPolicy", venv, n_steps=args.n_steps, batch_size=args.batch_size,
        n_epochs=args.epochs, learning_rate=args.lr, gamma=0.99, gae_lambda=0.95,
        clip_range=0.2, ent_coef=0.0, seed=args.seed, device="cpu", verbose=0,
        policy_kwargs=dict(net_arch=dict(pi=[args.hidden] * args.layers,
                                         vf=[args.hidden] * args.layers),
                           activation_fn=torch.nn.Tanh),
    )
    t0 = time.perf_counter()
    model.learn(total_timesteps=total)
    wall = time.perf_counter() - t0
    steps = model.num_timesteps
    returns = [ep["r"] for ep in list(model.ep_info_buffer)[-8:]]
    print(json.dumps({
        "peer": "stable-baselines3-ppo",
        "python": sys.version.split()[0],
        "sb3": stable_baselines3.__version__,
        "torch": torch.__version__,
        "threads": torch.get_num_threads(),
        "blas_threads": int(blas),
        "env": args.env, "num_envs": venv.num_envs, "n_steps": args.n_steps,
        "batch_size": args.batch_size, "epochs": args.epochs,
        "total_env_steps": steps, "wall_s": wall,
        "env_steps_per_s": steps / wall,
        "last_returns_mean": float(np.mean(returns)) if returns else None,
    }))


if __name__ == "__main__":
    main()
