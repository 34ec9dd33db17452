#!/usr/bin/env python3
"""The learner peer table: manyworlds' SAC update, PPO epoch and PPO training run against
plain PyTorch in Python (Debian's python3-torch and PyPI's torch) and Stable-Baselines3,
interleaved on one machine, medians and ratios.

Groups (each method is one process; every round runs every method of every group once, the
order within a group rotated from round to round; the table holds the medians over rounds of
each run's own median, and the median over rounds of the per-round ratios):

- sac: `manyworlds bench agent --json` (3 x 400 ReLU actor and twin critics, obs 39, action 4,
  batch 128; one update = critic target, critic loss and Adam step, actor loss through the
  critics and Adam step, temperature Adam step, Polyak update) against bench/peers/sac_update.py
  (the same update in plain PyTorch); updates/s. Thread settings: manyworlds' default (libtorch
  1 thread, OpenBLAS 2) and OpenBLAS 1; each torch with 1 and 2 threads, and Debian's torch
  also with 1 torch thread and OpenBLAS 2 (the layout manyworlds uses).
- ppo: `manyworlds bench agent --algo ppo --batch 10000 --minibatch 1000 --hidden 256 --layers 2`
  (one PPO epoch: 2 x 256 tanh Gaussian policy and value, minibatch forward, clipped
  surrogate / MSE, backward, Adam) against bench/peers/ppo_epoch.py; samples/s. Threads:
  manyworlds with OpenBLAS 2 and 1, each torch with 1 and 2 (torch and BLAS alike).
- sb3: `manyworlds train configs/cartpole_ppo.yaml` (evaluation and checkpoint only at the
  end; env steps/s = total env steps / wall_s of its summary.json) against
  bench/peers/sb3_ppo.py (Stable-Baselines3 PPO on the same env through the manyworlds
  package, same rollout, epochs, minibatch and network sizes; steps / wall time of learn()),
  160,000 env steps each. SB3 is timed with 1 torch thread; `--sb3-thread-probe` first runs
  a short probe (4,000 steps) with 1 and 2 threads to show which is faster.

The best thread setting of each side is the one with the highest median; ratios are
manyworlds' best over each peer's best, per round.

    python3 bench/peers/learner_peers.py --rounds 3 --json bench/logs/learner_peers.json
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))


def run_json(cmd, env=None):
    """Runs cmd, returns the JSON object on the last line of its stdout (None on failure)."""
    full_env = dict(os.environ)
    if env:
        full_env.update(env)
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, env=full_env, cwd=REPO)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        print(f"  FAILED ({proc.returncode}): {' '.join(cmd)}\n{proc.stderr[-2000:]}",
              file=sys.stderr, flush=True)
        return None
    lines = [l for l in proc.stdout.strip().splitlines() if l.strip()]
    # The C++ program prints one pretty-printed JSON object; the peers one line.
    text = proc.stdout[proc.stdout.index("{"):] if lines and lines[0].startswith("{") \
        else lines[-1]
    out = json.loads(text)
    out["_process_wall_s"] = wall
    return out


def mw_train(cli, steps_per_env):
    """manyworlds train on the cartpole PPO config; env steps/s from its own summary."""
    run_dir = tempfile.mkdtemp(prefix="mw_ppo_peer_")
    cmd = [cli, "train", "configs/cartpole_ppo.yaml", f"experiment.run_dir={run_dir}/run",
           f"experiment.steps_per_task={steps_per_env}", f"experiment.eval_every={steps_per_env}",
           f"experiment.checkpoint_every={steps_per_env}"]
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=REPO)
    if proc.returncode != 0:
        print(f"  FAILED: {' '.join(cmd)}\n{proc.stderr[-2000:]}", file=sys.stderr, flush=True)
        return None
    with open(os.path.join(run_dir, "run", "summary.json")) as f:
        summary = json.load(f)
    subprocess.run(["rm", "-rf", run_dir])
    return {"env_steps_per_s": summary["env_steps_per_s"], "wall_s": summary["wall_s"],
            "total_env_steps": summary["total_env_steps"],
            "final_mean_return": summary["final_eval"]["mean_return"]}


def methods(args):
    """{group: [(name, side, metric, thunk)]}; side is 'manyworlds' or a peer label."""
    cli = args.cli
    sac_peer = os.path.join(HERE, "sac_update.py")
    ppo_peer = os.path.join(HERE, "ppo_epoch.py")
    sb3_peer = os.path.join(HERE, "sb3_ppo.py")
    sac_size = ["--updates", str(args.sac_updates), "--repeats", str(args.sac_repeats)]
    ppo_size = ["--batch", "10000", "--minibatch", "1000", "--hidden", "256", "--layers", "2",
                "--updates", str(args.ppo_epochs), "--repeats", str(args.ppo_repeats)]
    g = {"sac": [], "ppo": [], "sb3": []}
    g["sac"].append(("manyworlds (torch 1, BLAS 2)", "manyworlds", "updates_per_s",
                     lambda: run_json([cli, "bench", "agent", "--json"] + sac_size)))
    g["sac"].append(("manyworlds (torch 1, BLAS 1)", "manyworlds", "updates_per_s",
                     lambda: run_json([cli, "bench", "agent", "--json", "--blas-threads", "1"]
                                      + sac_size)))
    g["ppo"].append(("manyworlds (torch 1, BLAS 2)", "manyworlds", "samples_per_s",
                     lambda: run_json([cli, "bench", "agent", "--algo", "ppo", "--json"]
                                      + ppo_size)))
    g["ppo"].append(("manyworlds (torch 1, BLAS 1)", "manyworlds", "samples_per_s",
                     lambda: run_json([cli, "bench", "agent", "--algo", "ppo", "--json",
                                       "--blas-threads", "1"] + ppo_size)))
    g["sb3"].append(("manyworlds train", "manyworlds", "env_steps_per_s",
                     lambda: mw_train(cli, args.sb3_steps_per_env)))
    torches = []
    if args.debian_python:
        torches.append(("Debian torch", args.debian_python))
    if args.pypi_python and os.path.exists(args.pypi_python):
        torches.append(("PyPI torch", args.pypi_python))
    for label, py in torches:
        settings = [("1", "1"), ("2", "2")]
        if label.startswith("Debian"):
            settings.append(("1", "2"))
        for t, b in settings:
            name = f"{label} (torch {t}, BLAS {b})"
            g["sac"].append((name, label, "updates_per_s",
                             lambda py=py, t=t, b=b: run_json(
                                 [py, sac_peer, "--threads", t, "--blas-threads", b] + sac_size)))
        for t in ("1", "2"):
            g["ppo"].append((f"{label} (threads {t})", label, "samples_per_s",
                             lambda py=py, t=t: run_json(
                                 [py, ppo_peer, "--threads", t] + ppo_size,
                                 env={"OPENBLAS_NUM_THREADS": t, "OMP_NUM_THREADS": t,
                                      "MKL_NUM_THREADS": t})))
    sb3 = []
    if args.sb3_debian_python and os.path.exists(args.sb3_debian_python):
        sb3.append(("SB3 2.4, Debian torch", args.sb3_debian_python))
    if args.sb3_pypi_python and os.path.exists(args.sb3_pypi_python):
        sb3.append(("SB3, PyPI torch", args.sb3_pypi_python))
    for label, py in sb3:
        g["sb3"].append((f"{label} (threads 1)", label, "env_steps_per_s",
                         lambda py=py: run_json([py, sb3_peer, "--threads", "1",
                                                 "--steps-per-env",
                                                 str(args.sb3_steps_per_env)])))
    return g, sb3


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--groups", default="sac,ppo,sb3")
    p.add_argument("--cli", default=os.path.join(REPO, "build", "manyworlds"))
    p.add_argument("--debian-python", default="/usr/bin/python3",
                   help="a Python with Debian's python3-torch ('' to skip)")
    p.add_argument("--pypi-python", default=os.path.join(REPO, ".venv-torch", "bin", "python"),
                   help="a Python with PyPI's torch (skipped if missing)")
    p.add_argument("--sb3-debian-python", default=os.path.join(REPO, ".venv-py", "bin", "python"))
    p.add_argument("--sb3-pypi-python", default=os.path.join(REPO, ".venv-torch", "bin", "python"))
    p.add_argument("--sac-updates", type=int, default=10)
    p.add_argument("--sac-repeats", type=int, default=3)
    p.add_argument("--ppo-epochs", type=int, default=2)
    p.add_argument("--ppo-repeats", type=int, default=3)
    p.add_argument("--sb3-steps-per-env", type=int, default=20000)
    p.add_argument("--sb3-thread-probe", action="store_true",
                   help="first time SB3 briefly with 1 and 2 torch threads")
    p.add_argument("--json", help="write every sample and the summary here")
    args = p.parse_args()
    groups = [s for s in args.groups.split(",") if s]
    # A private copy of the program: a relink of build/ during the run cannot change it.
    cli_stat = os.stat(args.cli)
    private = os.path.join(tempfile.mkdtemp(prefix="mw_peers_cli_"), "manyworlds")
    shutil.copy2(args.cli, private)
    record = {"date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
              "rounds": args.rounds, "runs": {}, "probe": {},
              "cli": {"path": args.cli, "mtime_utc": time.strftime(
                  "%Y-%m-%dT%H:%M:%SZ", time.gmtime(cli_stat.st_mtime))},
              "git_head": subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=REPO,
                                         capture_output=True, text=True).stdout.strip()}
    args.cli = private
    table, sb3 = methods(args)

    if args.sb3_thread_probe and "sb3" in groups:
        for label, py in sb3:
            for t in ("1", "2"):
                out = run_json([py, os.path.join(HERE, "sb3_ppo.py"), "--threads", t,
                                "--steps-per-env", "500"])
                rate = out["env_steps_per_s"] if out else None
                record["probe"][f"{label} (threads {t})"] = rate
                print(f"probe {label} threads {t}: {rate}", flush=True)

    for r in range(args.rounds):
        for group in groups:
            ms = table[group]
            k = r % len(ms)
            for name, side, metric, thunk in ms[k:] + ms[:k]:
                out = thunk()
                rate = out.get(metric) if out else None
                record["runs"].setdefault(group, {}).setdefault(name, {
                    "side": side, "metric": metric, "rates": [None] * args.rounds,
                    "details": []})
                entry = record["runs"][group][name]
                entry["rates"][r] = rate
                entry["details"].append(out)
                print(f"round {r + 1} {group:4s} {name:34s} {metric} "
                      f"{'FAILED' if rate is None else f'{rate:.1f}'}", flush=True)

    summary = {}
    for group in groups:
        runs = record["runs"].get(group, {})
        med = {n: statistics.median([x for x in e["rates"] if x is not None])
               for n, e in runs.items() if any(x is not None for x in e["rates"])}
        best = {}
        for n, e in runs.items():
            if n in med and (e["side"] not in best or med[n] > med[best[e["side"]]]):
                best[e["side"]] = n
        mw = best.get("manyworlds")
        rows = []
        for side, n in best.items():
            if side == "manyworlds" or mw is None:
                continue
            ratios = [a / b for a, b in zip(runs[mw]["rates"], runs[n]["rates"])
                      if a is not None and b is not None]
            rows.append({"peer": n, "peer_median": med[n], "manyworlds": mw,
                         "manyworlds_median": med[mw],
                         "ratio_median": statistics.median(ratios) if ratios else None,
                         "ratios": ratios})
        summary[group] = {"medians": med, "best": best, "ratios": rows}
        print(f"\n## {group}: medians over {args.rounds} rounds")
        for n, v in sorted(med.items(), key=lambda kv: -kv[1]):
            print(f"  {n:38s} {v:12.1f}")
        for row in rows:
            print(f"  ratio {row['manyworlds']} / {row['peer']}: median {row['ratio_median']:.2f}"
                  f" (rounds: {', '.join(f'{x:.2f}' for x in row['ratios'])})")
    record["summary"] = summary
    if args.json:
        with open(args.json, "w") as f:
            json.dump(record, f, indent=1)
    shutil.rmtree(os.path.dirname(private), ignore_errors=True)


if __name__ == "__main__":
    main()
