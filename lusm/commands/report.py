"""``lusm report``: the main job, the default motor end to end (:mod:`validation.report`), or
a designer's own stator with ``--geometry`` / plate options (:mod:`validation.report_design`)."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from lusm.options import add_plate_options

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


def run(args: argparse.Namespace) -> None:
    """Write the report and print where it is."""
    from lusm.errors import LusmError
    from lusm.options import output_folder

    out = output_folder(args, "--out")  # refused before any work
    try:
        doc = _write(args, out)
    except OSError as exc:
        # a full disk or a file-size limit while the set is written: said naming --out and
        # the folder, not as the bare "File too large"
        where = Path(os.fsdecode(exc.filename)).absolute() if exc.filename else None
        if where is not None and out.absolute().parent not in (where, *where.parents):
            raise  # not the report's own files
        raise LusmError(f"--out {out}: cannot write ({exc.strerror or exc})", "--out") from None
    print(f"report written to {out / 'index.md'} (and index.html, report.json) "
          f"in {doc['wall_time_s']:.1f} s")


def _write(args: argparse.Namespace, out: Path) -> dict:
    """The plate's design report (a stator named) or the paper's report, built aside and
    moved into ``out`` complete (a failure or Ctrl-C leaves ``out`` as it was)."""
    from lusm.options import (
        motor_params_of,
        plate_given,
        stator_from_args,
        stator_options_text,
    )
    from lusm.output_set import output_set

    progress = not args.no_progress
    if args.geometry or plate_given(args):
        from validation.report_design import write_design_report

        choice = stator_from_args(args)
        params, damping_from = motor_params_of(args, "fem")
        with output_set(out, "--out", args.force, "report") as stage:
            return write_design_report(stage, choice, params, stator_options_text(args),
                                       quick=args.quick, progress=progress,
                                       damping_from=damping_from)
    from validation.report import write_report

    with output_set(out, "--out", args.force, "report") as stage:
        return write_report(stage, quick=args.quick, progress=progress)
