"""manyworlds-sweep: runs sweeps and searches of `manyworlds train` on Ray, and reports them.

    manyworlds-sweep run SWEEP.yaml [--out DIR] [--resume] [--address HOST:PORT]
    manyworlds-sweep report SWEEP_DIR [--metric success|return] [--reps N]
    manyworlds-sweep tune SEARCH.yaml [--out DIR] [--resume]
    manyworlds-sweep tensorboard DIR ...
    manyworlds-sweep archive SWEEP_DIR OUT_DIR
    manyworlds-sweep presets

Exit codes: 0 done; 1 a run failed (the others still ran); 2 bad input (one line saying what
was wrong, nothing started); 128 + N stopped by signal N.
"""

from __future__ import annotations

import argparse
import pathlib
import signal
import sys
import time

PRESETS = pathlib.Path(__file__).resolve().parent / "presets"


def _preset_path(name: str) -> pathlib.Path:
    """SWEEP.yaml as given, or preset:NAME for a shipped sweep file."""
    if name.startswith("preset:"):
        path = PRESETS / f"{name[len('preset:'):]}.yaml"
        if not path.is_file():
            known = ", ".join(sorted(p.stem for p in PRESETS.glob("*.yaml")))
            raise ValueError(f"no preset {name[len('preset:'):]!r}; shipped: {known}")
        return path
    return pathlib.Path(name)


def _progress(line: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {line}", file=sys.stderr, flush=True)


def _cmd_run(args: argparse.Namespace) -> int:
    from manyworlds.sweep import runner, spec

    sweep = spec.load(_preset_path(args.sweep), config_root=args.config_root,
                      steps_per_task=args.steps_per_task)
    out = pathlib.Path(args.out) if args.out else pathlib.Path("runs/sweeps") / sweep.name
    result = runner.run_sweep(sweep, out, resume=args.resume, address=args.address, cli=args.cli,
                              num_cpus=args.num_cpus, max_retries=args.max_retries,
                              progress=_progress)
    for run_id, message in result["failed"].items():
        print(f"failed: {run_id}: {message}", file=sys.stderr)
    failed = f", {len(result['failed'])} failed" if result["failed"] else ""
    print(f"{out}: {len(result['finished'])} of {len(sweep.runs)} runs finished{failed}; "
          f"report: manyworlds-sweep report {out}")
    return 1 if result["failed"] else 0


def _cmd_report(args: argparse.Namespace) -> int:
    from manyworlds.sweep import report

    report.write_report(args.sweep_dir, out_dir=args.out, metric=args.metric, source=args.source,
                        reps=args.reps, seed=args.seed, target=args.target,
                        curve_reps=args.curve_reps, improvement_reps=args.improvement_reps,
                        plots=not args.no_plots)
    out = pathlib.Path(args.out) if args.out else pathlib.Path(args.sweep_dir) / "report"
    print((out / "summary.md").read_text())
    print(f"{out}: report.json, scores.csv, aggregates.csv, summary.md"
          f"{'' if args.no_plots else ' and plots'}", file=sys.stderr)
    return 0


def _cmd_tune(args: argparse.Namespace) -> int:
    from manyworlds.sweep import tune

    settings = tune.load_search(_preset_path(args.search), config_root=args.config_root,
                                steps_per_task=args.steps_per_task)
    out = pathlib.Path(args.out) if args.out else pathlib.Path("runs/searches")
    trials = tune.run_search(settings, out, cli=args.cli, address=args.address,
                             num_cpus=args.num_cpus, resume=args.resume)
    metric = settings["metric"]
    print(f"{'trial':<28} {'best ' + metric:>18} {'evals':>5}  values")
    for t in trials:
        best = "-" if t["best"] is None else f"{t['best']:.4g}"
        values = " ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                          for k, v in t["values"].items())
        print(f"{t['trial'][:28]:<28} {best:>18} {t['evaluations']:>5}  {values}"
              f"{'  error: ' + t['error'] if t['error'] else ''}")
    print(f"{out / settings['name']}: search_results.json, search_results.csv", file=sys.stderr)
    return 1 if any(t["error"] for t in trials) else 0


def _cmd_tensorboard(args: argparse.Namespace) -> int:
    from manyworlds.sweep import tensorboard

    for path in args.dirs:
        path = pathlib.Path(path)
        if (path / "sweep.json").is_file():
            written = tensorboard.export_sweep(path)
            print(f"{path}: event files for {len(written)} runs; tensorboard --logdir {path}/runs")
        elif (path / "config.yaml").is_file():
            print(f"{tensorboard.export_run(path)}")
        else:
            raise ValueError(f"{path} is neither a sweep directory (sweep.json) nor a run "
                             f"directory (config.yaml)")
    return 0


def _cmd_archive(args: argparse.Namespace) -> int:
    from manyworlds.sweep import archive

    result = archive.archive_sweep(args.sweep_dir, args.out_dir)
    waiting = f"; {len(result['unfinished'])} not finished, left out" if result["unfinished"] else ""
    print(f"{args.out_dir}: {len(result['archived'])} finished runs without checkpoints{waiting}; "
          f"report: manyworlds-sweep report {args.out_dir}")
    return 0


def _cmd_presets(args: argparse.Namespace) -> int:
    for path in sorted(PRESETS.glob("*.yaml")):
        first = path.read_text().splitlines()[0].lstrip("# ").strip()
        print(f"preset:{path.stem:<24} {first}")
    return 0


def parser() -> argparse.ArgumentParser:
    main = argparse.ArgumentParser(
        prog="manyworlds-sweep", description=__doc__.split("\n\n")[0],
        epilog="docs/sweeps.md: sweep and search files, clusters, statistics")
    commands = main.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def ray_options(p: argparse.ArgumentParser) -> None:
        p.add_argument("--address", help="join a running Ray cluster (auto, or HOST:PORT of "
                                         "`ray start --head`); default: a local instance")
        p.add_argument("--num-cpus", type=int, help="CPUs of the local instance (default: all)")
        p.add_argument("--cli", help="the manyworlds program (default: $MANYWORLDS_CLI, PATH, "
                                     "build/manyworlds)")
        p.add_argument("--config-root", help="another folder to find the configs in")
        p.add_argument("--steps-per-task", type=int,
                       help="the budget of every run (overrides the file's budget)")
        p.add_argument("--resume", action="store_true",
                       help="continue the sweep in --out: finished runs stay, the others resume")

    run = commands.add_parser("run", help="run every run of a sweep file",
                              description="Runs every run of a sweep file as a Ray task "
                                          "(`manyworlds train` in SWEEP_DIR/runs/...).")
    run.add_argument("sweep", help="the sweep file, or preset:NAME (manyworlds-sweep presets)")
    run.add_argument("--out", help="the sweep directory (default runs/sweeps/NAME)")
    run.add_argument("--max-retries", type=int, default=3,
                     help="reschedules of a run whose worker or node died (default 3)")
    ray_options(run)
    run.set_defaults(handler=_cmd_run)

    rep = commands.add_parser("report", help="statistics of a sweep with rliable",
                              description="IQM, mean, median and optimality gap with stratified-"
                                          "bootstrap 95 % intervals, performance profiles, "
                                          "probability of improvement, curves; JSON, CSV, "
                                          "Markdown and plots in SWEEP_DIR/report/.")
    rep.add_argument("sweep_dir")
    rep.add_argument("--out", help="the report folder (default SWEEP_DIR/report)")
    rep.add_argument("--metric", default="success", choices=["success", "return"])
    rep.add_argument("--source", default="auto", choices=["auto", "eval", "meta_test",
                                                          "meta_train"],
                     help="which final evaluation is scored (auto: meta_test where a run has one)")
    rep.add_argument("--reps", type=int, default=10000,
                     help="bootstrap resamples of the aggregates and profiles (default 10000)")
    rep.add_argument("--curve-reps", type=int, default=2000,
                     help="bootstrap resamples per point of the curves (default 2000)")
    rep.add_argument("--improvement-reps", type=int, default=2000,
                     help="bootstrap resamples of each probability of improvement (default 2000)")
    rep.add_argument("--target", type=float,
                     help="with --metric return: the return that counts as optimal (for the "
                          "optimality gap)")
    rep.add_argument("--seed", type=int, default=0, help="the bootstrap's seed")
    rep.add_argument("--no-plots", action="store_true", help="tables only")
    rep.set_defaults(handler=_cmd_report)

    tun = commands.add_parser("tune", help="hyperparameter search with Ray Tune (ASHA)",
                              description="Searches a config's keys with Ray Tune; each trial is "
                                          "`manyworlds train`, its evaluations reported as "
                                          "they are written.")
    tun.add_argument("search", help="the search file, or preset:NAME")
    tun.add_argument("--out", help="the folder of searches (default runs/searches)")
    ray_options(tun)
    tun.set_defaults(handler=_cmd_tune)

    tb = commands.add_parser("tensorboard", help="TensorBoard event files of runs or sweeps")
    tb.add_argument("dirs", nargs="+", help="run directories or sweep directories")
    tb.set_defaults(handler=_cmd_tensorboard)

    arc = commands.add_parser(
        "archive", help="a sweep's finished runs without checkpoints, to keep or share",
        description="Copies SWEEP_DIR's sweep.json and, of every finished run, its config, "
                    "summary, .jsonl logs and run log into OUT_DIR: what `report` scores and "
                    "`run --resume` leaves finished, without checkpoints and task states. "
                    "Run again as the sweep goes on, it adds the newly finished runs.")
    arc.add_argument("sweep_dir")
    arc.add_argument("out_dir")
    arc.set_defaults(handler=_cmd_archive)

    pre = commands.add_parser("presets", help="list the shipped sweep and search files")
    pre.set_defaults(handler=_cmd_presets)
    return main


def main(argv: list[str] | None = None) -> int:
    from manyworlds.sweep.runner import SweepError

    args = parser().parse_args(argv)
    # SIGTERM ends the driver as Ctrl-C does: Ray's workers stop, each run checkpoints
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit(128 + signum))
    try:
        return args.handler(args)
    except (ValueError, SweepError) as error:
        print(f"manyworlds-sweep: {error}", file=sys.stderr)
        return 2
    except ImportError as error:
        print(f"manyworlds-sweep: {error.name or error} is missing: install the sweep extra "
              f"(pip install 'manyworlds[sweep]')", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("manyworlds-sweep: interrupted; continue with --resume", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
