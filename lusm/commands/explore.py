"""``lusm explore``: a design-space study on dask.distributed (parse, call, print)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from lusm import limits
from lusm.errors import LusmError
from lusm.messages import warn, warnings_said
from lusm.options import (
    figure_set,
    integer,
    moved,
    output_folder,
    print_json,
    real,
    warn_drive,
    warn_thin_plate,
)

WORKER_TIMEOUT_DEFAULT_S = 300.0
"""Default of ``--worker-timeout-s`` (s): :data:`studies.cluster.WORKER_TIMEOUT_S` (not
imported here: building the parser imports no dask)."""

HELP = "design-space study (geometry x drive) on dask.distributed"
DESCRIPTION = """\
Run the study of a TOML file (axes, outputs, solver; [study] stator = FILE.toml starts every
plate from a designer's stator file, whose plate and features the axes vary): one task per
geometry (FE solve, reduction, all its drive points) on a LocalCluster or an existing dask
scheduler; write a labelled netCDF dataset. See docs/distributed.md.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm explore``."""
    p.add_argument("study", metavar="STUDY.toml", help="the study file")
    p.add_argument("--out", required=True, metavar="FILE.nc", help="netCDF file to write")
    p.add_argument("--resume", action="store_true",
                   help="continue an interrupted run from FILE.nc.parts/")
    add_cluster_options(p)
    add_worker_timeout_option(p)
    p.add_argument("--plot", metavar="DIR",
                   help="write figures (PNG) of the no-load velocity, stall force, L1-B2 split "
                   "(diverging scale, zero contour), peak efficiency and auto drive frequency "
                   "where the dataset has them into DIR: maps over length x width (or the "
                   "first two axes that vary), curves over a single varying axis; a panel or "
                   "line per material")
    p.add_argument("--json", action="store_true", help="print one JSON summary")
    p.add_argument("--force", action="store_true",
                   help="replace an existing FILE.nc (kept as FILE.nc.bak-N) and write into a "
                   "non-empty --plot folder")


def add_cluster_options(p: argparse.ArgumentParser, workers_note: str = "") -> None:
    """``--scheduler``, ``--scheduler-file`` and ``--workers`` (explore's and optimize's)."""
    where = p.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="tcp://HOST:8786",
                       help="run on this dask scheduler instead of a LocalCluster")
    where.add_argument("--scheduler-file", metavar="FILE",
                       help="run on the dask scheduler described by this file")
    p.add_argument("--workers", default=None, type=integer("--workers", *limits.WORKERS),
                   help=f"processes of the LocalCluster (default 2), in "
                   f"[{limits.WORKERS[0]}, {limits.WORKERS[1]}]; not with --scheduler or "
                   f"--scheduler-file (that cluster has its own workers){workers_note}")


def add_worker_timeout_option(p: argparse.ArgumentParser) -> None:
    """``--worker-timeout-s`` (explore's and optimize's): the bound of
    :class:`studies.cluster.ClusterWatch` on a cluster without workers."""
    p.add_argument("--worker-timeout-s", default=None, metavar="S",
                   type=real("--worker-timeout-s", "s", *limits.WORKER_TIMEOUT_S),
                   help="how long to wait when the cluster has no worker left (an external "
                   "scheduler whose workers died) before stopping with the finished parts "
                   f"kept for --resume (default {WORKER_TIMEOUT_DEFAULT_S:g} s), in "
                   f"[{limits.WORKER_TIMEOUT_S[0]:g}, {limits.WORKER_TIMEOUT_S[1]:g}] s")


def worker_timeout_s(args: argparse.Namespace) -> float:
    """``--worker-timeout-s``, or its default (s)."""
    return WORKER_TIMEOUT_DEFAULT_S if args.worker_timeout_s is None else args.worker_timeout_s


def run(args: argparse.Namespace) -> None:
    """Check the study and the outputs, run the study, print its summary; ``--json``'s
    ``"warnings"`` lists every warning the run says (those of reading the study, of its
    plates and drive points, of the workers, of the figures)."""
    with warnings_said() as said:
        _run(args, said)


def _run(args: argparse.Namespace, said: list[str]) -> None:
    """:func:`run`, with ``said`` the record of the warnings said so far (filled as they
    are said)."""
    study, plot = _checked_study(args)
    result = _run_study(args, study, plot)
    if plot is not None:
        _write_maps(result, plot, args.force)
    summary = result.to_dict()
    # what stderr said, as it said it (the warnings of the study, its plates and drive
    # points, the workers and the figures)
    summary["warnings"] = list(said)
    if study.needs_motor:  # every velocity and force depends on it (as characteristic says)
        from studies.dataset import damping_text

        summary["damping"] = damping_text(study)
    if study.stator is not None:
        summary["stator_file"] = json.loads(study.text)["stator"]["file"]  # absolute
    if args.json:
        print_json(summary, indent=2)
        return
    _print_summary(result, study, summary)


def _checked_study(args: argparse.Namespace):
    """The study of ``args`` and its ``--plot`` folder (or None), with the options checked
    and the study's warnings said, before any work."""
    from studies.dataset import check_out, is_complete
    from studies.study import load_study

    check_cluster_options(args)
    study = load_study(args.study)
    warn_study(study)
    if not (args.resume and is_complete(study, args.out)):
        check_out(args.out, args.force)
    plot = output_folder(args, "--plot")
    if plot is not None and Path(plot).resolve() == Path(args.out).resolve():
        # refused before the study runs, not after its dataset is written
        raise LusmError(f"--plot {plot} names the --out file; give the maps a folder of "
                        "their own", "--plot")
    _refuse_plot_in_parts(plot, args.out)
    return study, plot


def check_cluster_options(args: argparse.Namespace) -> None:
    """Refuse, before any work, an empty or impossible ``--scheduler`` /
    ``--scheduler-file``, ``--workers`` beside them, and an empty STUDY.toml (explore's and
    optimize's)."""
    from studies.cluster import check_port, check_scheduler_names

    try:  # before anything else: '' would pass the --workers check below
        check_scheduler_names(args.scheduler, args.scheduler_file)
        if args.scheduler:  # a port no connection can have: at once, not after 10 s
            check_port(args.scheduler)
    except ValueError as exc:
        raise LusmError(str(exc), str(exc).split()[0]) from None
    if args.workers is not None and (args.scheduler or args.scheduler_file):
        # the existing cluster's workers run the study: --workers would be ignored
        option = "--scheduler" if args.scheduler else "--scheduler-file"
        raise LusmError(f"--workers sets the processes of the LocalCluster; with {option} the "
                        "study runs on that cluster's own workers: drop --workers", "--workers")
    if not args.study.strip():
        raise LusmError(f"STUDY.toml must name a study file, got {args.study!r}")


def warn_study(study) -> None:
    """The single-point commands' warnings for the study's plates and drive (a thick plate,
    a through hole, a high voltage or preload), said once before any work."""
    _warn_thick(study)
    _warn_holes(study)
    _warn_drive(study)


def _refuse_plot_in_parts(plot: str | None, out: str) -> None:
    """Refuse a ``--plot`` folder that is the run's own parts folder (or inside it): the
    run would make it as a figure folder, and every later run at that ``--out``, even with
    --force, would refuse a parts folder without its study file."""
    from studies.parts import parts_folder

    if plot is None:
        return
    parts = parts_folder(Path(out)).resolve()
    target = Path(plot).resolve()
    if target == parts or parts in target.parents:
        raise LusmError(f"--plot {plot} is inside {parts_folder(Path(out))}, the parts folder "
                        "this run keeps its finished geometries in; give the maps a folder of "
                        "their own", "--plot")


def _run_study(args: argparse.Namespace, study, plot: str | None):
    """Run the study (:func:`studies.explore.explore`) and say its workers' warnings and
    failed geometries; on an interrupt or an error, say what is kept and where."""
    from lusm.interrupts import Terminated
    from studies.cluster import DEFAULT_WORKERS, ClusterLostError
    from studies.dataset import open_result
    from studies.explore import NothingComputedError, explore
    from studies.parts import PartsBusyError, parts_folder

    before = _file_stamp(Path(args.out))
    parts = parts_folder(Path(args.out))
    parts_before = _count_parts(parts)
    try:
        result = explore(study, args.out, scheduler=args.scheduler,
                         scheduler_file=args.scheduler_file,
                         workers=DEFAULT_WORKERS if args.workers is None else args.workers,
                         resume=args.resume, force=args.force, progress=not args.json,
                         worker_timeout_s=worker_timeout_s(args))
        for text in result.warnings:  # said once each, as every command says a warning
            warn(text)
        _report_failures(open_result(result.path), result.path)
    except NothingComputedError:
        raise  # its message says where the parts are kept
    except PartsBusyError:
        raise  # the parts there are the running one's, not this run's to offer
    except ClusterLostError as exc:  # the environment, not a bug: one line, exit 2
        raise LusmError(cluster_lost_line(exc, args, parts), exc.where.split()[0]) from None
    except (KeyboardInterrupt, Terminated):
        if parts.exists():
            print(f"lusm explore: {_geometries(_count_parts(parts))} kept in {parts}; run the "
                  "same command with --resume to continue", file=sys.stderr)
        elif _file_stamp(Path(args.out)) not in (None, before):
            # the dataset and the parts' removal are one step: this run finished it
            print(f"lusm explore: {args.out} is complete"
                  + ("; the --plot maps were not written" if plot is not None else ""),
                  file=sys.stderr)
        raise
    except Exception:
        # an error after this run finished geometries (a worker of other code, workers
        # lost beyond dask's allowed failures): they are kept, as after an interrupt
        done = _count_parts(parts)
        if done and done != parts_before:
            print(f"lusm explore: {_geometries(done)} kept in {parts}; run the same command "
                  "with --resume to continue once the cause is fixed", file=sys.stderr)
        raise
    return result


def cluster_lost_line(exc, args: argparse.Namespace, parts: Path, command: str = "explore",
                      options: tuple[str, ...] = (), what: tuple[str, str, str] = (
                          "finished geometry is", "finished geometries are",
                          "no geometry had finished")) -> str:
    """The one line of a cluster lost mid-study (explore's and optimize's): what went, what
    is kept, and the command that resumes (``lusm COMMAND``, with ``options`` after the
    cluster's); ``what`` says one part kept, several, and none."""
    import shlex

    done = _count_parts(parts)
    kept = (f"{done} {what[0] if done == 1 else what[1]} kept in {parts}" if done
            else what[2])
    where = (["--scheduler", args.scheduler] if args.scheduler else
             ["--scheduler-file", args.scheduler_file] if args.scheduler_file else [])
    again = ["lusm", command, args.study, "--out", args.out, *where, *options]
    if args.worker_timeout_s is not None:
        again += ["--worker-timeout-s", f"{args.worker_timeout_s:g}"]
    if done:
        return (f"{exc}; {kept}; once the cluster is back, resume with: "
                f"{shlex.join([*again, '--resume'])}")
    return f"{exc}; {kept}; once the cluster is back, run: {shlex.join(again)}"


def _write_maps(result, plot: str, force: bool) -> None:
    """Write the ``--plot`` figures of the study's dataset into ``plot`` (their paths into
    ``result.figures``); if they cannot be, say that the dataset is complete all the same."""
    from lusm.interrupts import Terminated
    from studies.dataset import open_result
    from studies.maps import design_maps, drawable_maps

    try:
        ds = open_result(result.path)
        if not drawable_maps(ds):  # nothing to draw: no folder made either
            warn(f"--plot {plot}: nothing to draw (a figure needs a plate or drive axis "
                 "with at least two values and a finite answer along it); nothing written")
        else:
            with figure_set(plot, "--plot", force, "explore") as stage:
                result.figures = moved(design_maps(ds, stage), stage, plot)
    except (KeyboardInterrupt, Terminated, LusmError, ValueError, OSError):
        # the study's result is not lost with its maps
        print(f"lusm explore: {result.path} is complete; the --plot maps were not written",
              file=sys.stderr)
        raise


def _print_summary(result, study, summary: dict) -> None:
    """The study's summary for a reader: its size, where it computed, what it wrote."""
    def plural(n: int, word: str, many: str) -> str:
        return f"{n} {word if n == 1 else many}"

    # the axes behind the count: a study's drive points include its loads, where the work
    # bounds' "drive points" (docs/limits.md) are voltage x preload (x frequency)
    axes = [plural(len(study.axes[a]), a, "frequencies" if a == "frequency" else a + "s")
            for a in study.drive_dims]
    drive = (f" x {plural(result.drive_points, 'drive point', 'drive points')}"
             + (f" ({' x '.join(axes)})" if len(axes) > 1 else "")
             if study.needs_motor else " (FE outputs only)")
    if result.already_complete:
        print(f"{result.path} is complete (study {study.name!r}, "
              f"{plural(result.geometries, 'geometry', 'geometries')}); nothing to resume")
    else:
        print(f"study {study.name!r}: {plural(result.geometries, 'geometry', 'geometries')}"
              f"{drive}; {result.computed} "
              f"computed on {result.workers} worker{'' if result.workers == 1 else 's'}, "
              f"{result.reused} from an earlier run; {result.wall_time_s:.3g} s")
        if "damping" in summary:
            print(f"damping: {summary['damping']}")
        print(f"wrote {result.path}")
    for f in result.figures:
        print(f"wrote {f}")


def _count_parts(folder: Path) -> int:
    """Finished geometries in a parts folder (0 when there is none)."""
    return len(list(folder.glob("g*.npz"))) if folder.is_dir() else 0


def _geometries(n: int) -> str:
    """``"1 finished geometry is"`` / ``"3 finished geometries are"``."""
    return f"{n} finished geometry is" if n == 1 else f"{n} finished geometries are"


def _file_stamp(path: Path) -> tuple[int, int] | None:
    """``(inode, mtime_ns)`` of a file, None when there is none: whether a run wrote it."""
    try:
        st = path.stat()
    except OSError:
        return None
    return st.st_ino, st.st_mtime_ns


def _warn_drive(study) -> None:
    """The drive warnings of the single-point commands (:func:`lusm.options.warn_drive`),
    once per study, for the axis values that trigger them: the largest voltage above 600 V,
    the largest preload above 100 N, and 0 V with 0 N. A study that drives nothing (FE
    outputs only) gets none."""
    if not study.needs_motor:
        return
    ax = study.axes
    names = {"voltage_option": "axes.voltage", "preload_option": "axes.preload"}
    v, p = max(ax["voltage"]), max(ax["preload"])
    warn_drive(v, p, **names)
    if 0.0 in ax["voltage"] and 0.0 in ax["preload"] and (v, p) != (0.0, 0.0):
        warn_drive(0.0, 0.0, **names)  # the unloaded 0 V / 0 N point (said above if alone)


def _warn_thick(study) -> None:
    """The thin-plate warning modes gives, for the study's thickest plate against its
    narrowest (a 0.6 mm wide, 3 mm thick plate is outside the 2D model's range)."""
    ax = study.axes
    thick = max(ax["thickness"]) * 1e3
    warn_thin_plate(f"{study.source}: thickness up to {thick:g} mm", thick,
                    min(min(ax["length"]), min(ax["width"])) * 1e3,
                    "the study's smallest in-plane size",
                    "check such plates with lusm modes --model 3d")


def _warn_holes(study) -> None:
    """The single-point commands' warning for a through hole of the study's stator file
    (:func:`lusm.options.warn_holes`), said for its smallest, thickest plate, where the
    hole weighs most."""
    holes = () if study.stator is None else getattr(study.stator.stator, "holes_m", ())
    if not holes:
        return
    from types import SimpleNamespace

    from lusm.options import warn_holes

    ax = study.axes  # the sizes the warning weighs, not a plate to build (it may not exist)
    plate = SimpleNamespace(holes_m=holes, length_m=min(ax["length"]),
                            width_m=min(ax["width"]), thickness_m=max(ax["thickness"]))
    warn_holes(plate, f"study.stator {study.stator.path}")


def _report_failures(ds, path) -> list[str]:
    """Say which geometries did not compute fully (their reasons are in the dataset's
    ``status``), and return what was said. A study where none did has no dataset:
    :func:`studies.explore.explore` refuses to write one of NaN."""
    from studies.task import computed_fully

    said = []
    status = [str(x) for x in ds["status"].values.ravel()]
    slow = [x for x in status if " not settled within " in x]
    if slow:  # computed, but a transient's end is not a steady state: said, not refused
        said.append(f"{len(slow)} of {len(status)} geometries have drive points that did not "
                    f"settle (in {path}, variable 'status'); first: {slow[0]}")
    bad = [x for x in status if not computed_fully(x)]
    if bad:
        from lusm.errors import short_reason

        first = short_reason(bad[0]).replace("dt_s", "solver.dt").replace("frequency_Hz",
                                                                           "frequency")
        said.append(f"{len(bad)} of {len(status)} geometries did not compute fully (each "
                    f"one's reason is in {path}, variable 'status'); first: {first}")
    for text in said:
        warn(text)
    return said
