"""``lusm optimize``: the best stator for a motor objective, searched on dask (parse, call,
print)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from lusm.commands.explore import add_cluster_options, add_worker_timeout_option
from lusm.errors import LusmError
from lusm.messages import warn, warnings_said
from lusm.options import figure_set, file_target, integer, moved, output_folder, print_json

MAX_EVALUATIONS = 100_000
"""Largest ``--budget`` (:data:`studies.optimize.problem.MAX_EVALUATIONS`, written out so that
building the parser imports no numpy)."""

HELP = "search a study's design space for the best stator (optuna on dask.distributed)"
DESCRIPTION = """\
Search the design variables of a study file's [optimize] table (explore's axes with bounds)
for the best design by its objectives (an output or a ratio of two, at the study's operating
points) under its constraints (split, or split = "tuned": each design's width tuned to
L1 = B2 first; drive frequency band, volume, bounds on any output):
optuna's TPE sampler, asked in batches of the cluster's workers, each design evaluated as
lusm explore evaluates a plate. Writes one dataset row per evaluation. See docs/optimize.md.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm optimize``."""
    p.add_argument("study", metavar="STUDY.toml", help="the study file with an [optimize] table")
    p.add_argument("--out", required=True, metavar="FILE.nc", help="netCDF file to write")
    p.add_argument("--budget", default=None,
                   type=integer("--budget", 1, MAX_EVALUATIONS, work=True),
                   help="designs to evaluate (default: the study's optimize.evaluations)")
    p.add_argument("--seed", default=None, type=integer("--seed", 0, 2**31 - 1),
                   help="the sampler's seed (default: the study's optimize.seed, else 0)")
    p.add_argument("--resume", action="store_true",
                   help="continue an interrupted run from FILE.nc.parts/ (the same designs)")
    add_cluster_options(p, "; the cluster's workers are the designs asked at once")
    add_worker_timeout_option(p)
    p.add_argument("--plot", metavar="DIR",
                   help="write the convergence figure (best feasible objective against the "
                   "evaluations) and, for several objectives, the Pareto front into DIR")
    p.add_argument("--write", metavar="STATOR.toml", default=None,
                   help="write the best design as a stator file (the study's stator file "
                   "with the design's values)")
    p.add_argument("--check-3d", action="store_true",
                   help="compute the best design's L1 and B2 with the 3D model too (minutes)")
    p.add_argument("--json", action="store_true", help="print one JSON summary")
    p.add_argument("--force", action="store_true",
                   help="replace an existing FILE.nc (kept as FILE.nc.bak-N), --write file or "
                   "non-empty --plot folder")


def run(args: argparse.Namespace) -> None:
    """Check the study and the outputs, run the search, print the best design."""
    with warnings_said() as said:
        _run(args, said)


def _run(args: argparse.Namespace, said: list[str]) -> None:
    problem, plot, write = _checked(args)
    result = _search(args, problem)
    from studies.dataset import open_result

    ds = open_result(result.path)
    summary = _summary(problem, result, ds)
    if plot is not None:
        summary["figures"] = _plot(problem, ds, plot, args.force, result.path)
    if write is not None:
        summary["written"] = _write(args, problem, ds, write)
    if args.check_3d and result.best:
        summary["check_3d"] = _check_3d(problem, ds)
    summary["warnings"] = list(said)
    if args.json:
        print_json(summary, indent=2)
        return
    _print(summary)


def _checked(args: argparse.Namespace):
    """The problem of ``args`` (with ``--seed``), and the ``--plot`` and ``--write`` targets,
    checked before any work."""
    from dataclasses import replace

    from lusm.commands.explore import check_cluster_options, warn_study
    from studies.dataset import check_out
    from studies.optimize.problem import load_problem, with_seed
    from studies.optimize.result import is_complete_file

    check_cluster_options(args)
    problem = load_problem(args.study)
    warn_study(problem.study)
    if args.seed is not None:
        problem = with_seed(problem, args.seed)
    if args.budget is not None:
        problem = replace(problem, evaluations=args.budget)
    if not (args.resume and is_complete_file(Path(args.out), problem.fingerprint)):
        check_out(Path(args.out), args.force)
    plot = output_folder(args, "--plot")
    if plot is not None and Path(plot).resolve() == Path(args.out).resolve():
        raise LusmError(f"--plot {plot} names the --out file; give the figures a folder of "
                        "their own", "--plot")
    write = None
    if args.write is not None:
        write = file_target(args.write, "--write", args.force, "best.toml")
        if write.resolve() == Path(args.out).resolve():
            raise LusmError(f"--write {write} names the --out file", "--write")
    return problem, plot, write


def _search(args: argparse.Namespace, problem):
    """Run the search; on an interrupt or an error, say what is kept for ``--resume``."""
    from lusm.commands.explore import cluster_lost_line, worker_timeout_s
    from lusm.interrupts import Terminated
    from studies.cluster import DEFAULT_WORKERS, ClusterLostError
    from studies.optimize import optimize
    from studies.parts import parts_folder

    parts = parts_folder(Path(args.out))
    try:
        return optimize(problem, args.out, scheduler=args.scheduler,
                        scheduler_file=args.scheduler_file,
                        workers=DEFAULT_WORKERS if args.workers is None else args.workers,
                        resume=args.resume, force=args.force, progress=not args.json,
                        worker_timeout_s=worker_timeout_s(args))
    except ClusterLostError as exc:  # the environment, not a bug: one line, exit 2
        options = [o for name, value in (("--budget", args.budget), ("--seed", args.seed))
                   if value is not None for o in (name, str(value))]
        raise LusmError(cluster_lost_line(exc, args, parts, "optimize", tuple(options), (
            "evaluated design is", "evaluated designs are", "no design had been evaluated")),
            exc.where.split()[0]) from None
    except (KeyboardInterrupt, Terminated):
        n = len(list(parts.glob("g*.npz"))) if parts.is_dir() else 0
        if n:
            print(f"lusm optimize: {n} evaluated design{'s are' if n != 1 else ' is'} kept "
                  f"in {parts}; run the same command with --resume to continue",
                  file=sys.stderr)
        raise


def _design_text(problem, ds, row: int) -> str:
    """A design's values as a reader reads them (``length 36.21 mm, material pzt8``)."""
    items = []
    for v in problem.variables:
        value = ds[v.name].values[row]
        if v.name == "material":
            items.append(f"material {value}")
        elif v.name == "frequency":
            items.append(f"frequency {float(value) / 1e3:.4f} kHz")
        else:
            items.append(f"{v.name} {float(value) * 1e3:.4g} mm")
    if problem.tune is not None:
        from studies.optimize.tuned import tuned_key

        value = float(ds[tuned_key(problem.tune.variable)].values[row])
        items.append(f"{problem.tune.variable} {value * 1e3:.5g} mm (tuned)")
    return ", ".join(items)


def _summary(problem, result, ds) -> dict:
    """The run's summary: its counts and the best designs with their objectives and 2D
    split (JSON-ready, SI units)."""
    from studies.optimize.result import objective_variable, row_design

    best = []
    trials = [int(t) for t in ds["trial"].values]
    for t in result.best:
        row = trials.index(t)
        entry = {"trial": t, "design": row_design(problem, ds, row),
                 "objectives": {o.label: float(ds[objective_variable(o.label)].values[row])
                                for o in problem.objectives},
                 "split_Hz": float(ds["split"].values[row]),
                 "f_L1_short_Hz": float(ds["f_L1_short"].values[row]),
                 "text": _design_text(problem, ds, row)}
        best.append(entry)
    return {"out": str(result.path), "study": problem.study.name,
            "evaluations": result.evaluations, "computed": result.computed,
            "reused": result.reused, "feasible": result.feasible,
            "infeasible_everywhere": result.infeasible_everywhere,
            "workers": result.workers, "batch": result.batch,
            "wall_time_s": result.wall_time_s,
            "designs_per_s": result.computed / result.wall_time_s if result.wall_time_s else None,
            "stopped_by": result.stopped_by,
            "already_complete": result.already_complete,
            "objectives": {o.label: {"goal": "maximize" if o.maximize else "minimize",
                                     "unit": o.unit} for o in problem.objectives},
            "best": best}


def _plot(problem, ds, plot: Path, force: bool, out: Path) -> list[str]:
    from studies.optimize.figures import optimize_figures

    labels = [o.label for o in problem.objectives]
    goals = [o.maximize for o in problem.objectives]
    try:
        with figure_set(plot, "--plot", force, "optimize") as stage:
            return moved(optimize_figures(ds, stage, labels, goals), stage, plot)
    except BaseException:
        print(f"lusm optimize: {out} is complete; the --plot figures were not written",
              file=sys.stderr)
        raise


def _write(args: argparse.Namespace, problem, ds, path: Path) -> str | None:
    """Write the best design's stator file; refused when no design is feasible."""
    from lusm.messages import command_line
    from lusm.options import write_text_file
    from studies.optimize.export import best_stator_text
    from studies.optimize.result import best_row, row_design

    row = best_row(ds)
    if row is None:
        raise LusmError(f"--write {path}: no design met the constraints, so there is no best "
                        f"design to write ({args.out} holds every evaluation)", "--write")
    design = row_design(problem, ds, row)
    split = float(ds["split"].values[row])
    comment = (f"Optimised by: {command_line()}\nbest design, trial {int(ds['trial'][row])}: "
               f"{_design_text(problem, ds, row)}; 2D split f_B2 - f_L1 = {split:.1f} Hz")
    write_text_file(path, "--write", best_stator_text(problem, design, comment))
    return str(path)


def _check_3d(problem, ds) -> dict:
    """The best design's L1 and B2 from the 3D model beside the 2D ones."""
    from studies.optimize.check3d import check_3d
    from studies.optimize.result import best_row

    return check_3d(problem, ds, best_row(ds))


def _print(summary: dict) -> None:
    """The run's summary for a reader."""
    if summary["already_complete"]:
        print(f"{summary['out']} is complete ({summary['evaluations']} designs); nothing to "
              "resume")
    else:
        rate = summary["designs_per_s"] or 0.0
        print(f"study {summary['study']!r}: {summary['evaluations']} designs evaluated "
              f"({summary['computed']} this run, {summary['reused']} from an earlier run) on "
              f"{summary['workers']} worker{'s' if summary['workers'] != 1 else ''}, batches "
              f"of {summary['batch']}; {summary['wall_time_s']:.3g} s ({rate:.3g} designs/s)"
              + ("; stopped by optimize.wall_time" if summary["stopped_by"] == "wall_time"
                 else ""))
    if summary["infeasible_everywhere"]:
        warn(f"no design met the constraints (0 of {summary['evaluations']} feasible): there "
             f"is no optimum; {summary['out']} holds each design's constraint values")
    units = {k: v["unit"] for k, v in summary["objectives"].items()}
    several = len(summary["best"]) > 1
    if several:
        print(f"Pareto front: {len(summary['best'])} designs")
    for b in summary["best"]:
        values = ", ".join(f"{k} = {v:.4g}{'' if units[k] == '1' else ' ' + units[k]}"
                           for k, v in b["objectives"].items())
        rel = b["split_Hz"] / b["f_L1_short_Hz"] * 100
        print(f"{'' if several else 'best design: '}trial {b['trial']}: {b['text']}; {values}; "
              f"2D split {b['split_Hz']:.1f} Hz ({rel:+.3g} % of f_L1)")
    check = summary.get("check_3d")
    if check:
        print(f"3D check: L1 {check['f_L1_3d_Hz']:.1f} Hz, B2 {check['f_B2_3d_Hz']:.1f} Hz, "
              f"split {check['split_3d_Hz']:.1f} Hz (2D: L1 {check['f_L1_2d_Hz']:.1f} Hz, B2 "
              f"{check['f_B2_2d_Hz']:.1f} Hz, split {check['split_2d_Hz']:.1f} Hz)")
    for f in summary.get("figures", []):
        print(f"wrote {f}")
    if summary.get("written"):
        print(f"wrote {summary['written']}")
    if not summary["already_complete"]:
        print(f"wrote {summary['out']}")
