"""``lusm report``: the main job, the default motor end to end (:mod:`validation.report`), or
a designer's own stator with ``--geometry`` / plate options (:mod:`validation.report_design`)."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from lusm import limits
from lusm.options import MAX_VOLTAGES, add_plate_options, real, real_list

HELP = (
    "write the full report (parameter sets, paper reproduction, speed vs error, "
    "hard cases)"
)
DESCRIPTION = """\
Run the default motor end to end (or, with --geometry or a plate option, your stator: modes in
2D and 3D with pictures, reduced parameters, admittance, speed against voltage, motor
characteristics) and write index.md, index.html, report.json and PNG figures.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm report``."""
    p.add_argument("--out", default="report", metavar="DIR", help="output folder")
    p.add_argument("--quick", action="store_true",
                   help="coarser grids and shorter runs, same sections (~30 s)")
    p.add_argument("--force", action="store_true",
                   help="write into a non-empty folder that is not a report (files in the "
                   "way are kept as NAME.bak-N; nothing is deleted)")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bars")
    add_plate_options(p, note="; any of them reports on that stator instead")
    g = p.add_argument_group("drive", "operating points of a stator's report (--geometry or "
                             "a plate option)")
    g.add_argument("--voltages", default=None, metavar="V[,V...]",
                   type=real_list("--voltages", "V", *limits.VOLTAGE_V, MAX_VOLTAGES),
                   help="drive amplitudes of the speed-thrust curves (V), up to "
                   f"{MAX_VOLTAGES} comma-separated values in [0, {limits.VOLTAGE_V[1]:g}]; "
                   "default 200,300,400")
    g.add_argument("--preload", default=None, type=real("--preload", "N", *limits.PRELOAD_N),
                   help="preload of the speed table and the speed-thrust curves (N), in "
                   f"[0, {limits.PRELOAD_N[1]:g}]; default 14")
    g.add_argument("--frequency", default=None,
                   help="drive frequency (Hz), or 'auto' for the stator's own operating point "
                   "(default)")


DRIVE_OPTIONS = ("--voltages", "--preload", "--frequency")
"""The options of a stator's report only."""


def report_drive(args: argparse.Namespace, stator_given: bool):
    """The :class:`validation.report_design.ReportDrive` of ``args`` (None for the paper's
    report), checked before any work: a drive option without a stator is refused, naming
    it, as is a bad ``--frequency``."""
    from lusm.errors import LusmError
    from lusm.options import known_frequency, warn_drive

    given = [o for o in DRIVE_OPTIONS if getattr(args, o[2:]) is not None]
    if not stator_given:
        if given:
            raise LusmError(f"{given[0]} sets an operating point of a stator's report: give "
                            "--geometry FILE or a plate option (the paper's report keeps the "
                            "paper's)", given[0])
        return None
    from validation.report_design import ReportDrive

    known_frequency(args.frequency)  # a bad number refused now, 'auto' later
    drive = ReportDrive()
    voltages = args.voltages if args.voltages is not None else drive.voltages_V
    preload = args.preload if args.preload is not None else drive.preload_N
    for v in voltages:
        warn_drive(v, preload, voltage_option="--voltages")
    return ReportDrive(tuple(voltages), float(preload),
                       args.frequency.strip() if args.frequency is not None else "auto")


def run(args: argparse.Namespace) -> None:
    """Write the report and print where it is."""
    from lusm.errors import LusmError
    from lusm.options import output_folder, plate_given

    out = output_folder(args, "--out")  # refused before any work
    drive = report_drive(args, bool(args.geometry or plate_given(args)))
    try:
        doc = _write(args, out, drive)
    except OSError as exc:
        # a full disk or a file-size limit while the set is written: said naming --out and
        # the folder, not as the bare "File too large"
        where = Path(os.fsdecode(exc.filename)).absolute() if exc.filename else None
        if where is not None and out.absolute().parent not in (where, *where.parents):
            raise  # not the report's own files
        raise LusmError(f"--out {out}: cannot write ({exc.strerror or exc})", "--out") from None
    print(f"report written to {out / 'index.md'} (and index.html, report.json) "
          f"in {doc['wall_time_s']:.1f} s")


def _write(args: argparse.Namespace, out: Path, drive) -> dict:
    """The plate's design report (a stator named) or the paper's report, built aside and
    moved into ``out`` complete (a failure or Ctrl-C leaves ``out`` as it was)."""
    from lusm.options import (
        motor_params_of,
        stator_from_args,
        stator_options_text,
    )
    from lusm.output_set import output_set

    progress = not args.no_progress
    if drive is not None:
        from validation.report_design import write_design_report

        choice = stator_from_args(args)
        params, damping_from = motor_params_of(args, "fem")
        _check_frequency(drive, params)
        cal = _calibration(args.geometry)
        with output_set(out, "--out", args.force, "report") as stage:
            return write_design_report(stage, choice, params, stator_options_text(args),
                                       quick=args.quick, progress=progress,
                                       damping_from=damping_from, drive=drive,
                                       calibration=cal)
    from validation.report import write_report

    with output_set(out, "--out", args.force, "report") as stage:
        return write_report(stage, quick=args.quick, progress=progress)


def _calibration(geometry: str | None):
    """The fit a calibrated stator file carries (its ``[calibration]`` table), None for
    another stator; a table that cannot be read refused naming ``--geometry``."""
    if not geometry:
        return None
    from calibration.uncertainty import CalibrationFileError, read_calibration
    from lusm.errors import LusmError

    try:
        return read_calibration(geometry)
    except CalibrationFileError as exc:
        raise LusmError(f"--geometry {exc}", "--geometry") from None


def _check_frequency(drive, params) -> None:
    """Refuse, before the report's work, a ``--frequency`` the steady engine cannot drive
    this stator at (as ``lusm characteristic`` does), and an ``auto`` one the set has no
    operating point for."""
    from contact.model import default_coupling
    from lusm.options import check_steady_frequency, parse_frequency

    freq = parse_frequency(drive.frequency, params)
    check_steady_frequency(params, freq, default_coupling(params)[0])
