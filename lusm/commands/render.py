"""``lusm render``: offscreen PNGs (and GIF animations) of the L1/B2 mode shapes.

Parse, call :mod:`fem.render`, print the files written. No physics here; ``fem`` and
pyvista are imported when the command runs. The pictures are built aside and moved into
``--out`` complete (:mod:`lusm.output_set`).
"""

from __future__ import annotations

import argparse

from lusm.commands.modes import add_fe_options
from lusm.fe_errors import fe_failure, is_fe_failure
from lusm.options import add_output_options, add_plate_options

HELP = "PNG pictures (and GIF animations) of the L1/B2 mode shapes, offscreen"
DESCRIPTION = """\
Render the FE mode shapes offscreen with pyvista: deformed planform coloured by displacement
magnitude over the undeformed outline, electrodes outlined (driven in red), mode name and
frequency in the title.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm render``."""
    p.add_argument("--mode", choices=("L1", "B2", "all"), default="all", help="which mode")
    p.add_argument("--animate", action="store_true", help="also write one period as a GIF")
    add_plate_options(p)
    add_fe_options(p)
    add_output_options(p, folder="--out", default="renders", json_flag=False,
                       folder_help="output folder (default renders)")


def run(args: argparse.Namespace) -> None:
    """Run ``lusm render`` with parsed ``args``."""
    from lusm.commands.modes import warn_linear_elements
    from lusm.options import check_fe_size, output_folder, stator_from_args, write_figures

    warn_linear_elements(args)
    output_folder(args, "--out")  # refused before any work
    choice = stator_from_args(args)

    from fem.meshing.mesh import DEFAULT_REFINE
    from fem.model import plate_model
    from fem.modes import ModeSolverError, plate_modes
    from fem.render import render_modes

    refine = DEFAULT_REFINE if args.refine is None else args.refine
    check_fe_size(choice.stator, refine)
    try:
        modes = plate_modes(choice.stator, choice.material, args.order, refine)
    except Exception as exc:
        if isinstance(exc, ModeSolverError) or is_fe_failure(exc):
            raise fe_failure(exc, choice.stator) from exc
        raise
    model = plate_model(choice.stator, choice.material, args.order, refine)
    which = ("L1", "B2") if args.mode == "all" else (args.mode,)
    from contact.deferred_signals import deferred_signals

    with deferred_signals():  # not interrupted half-way: a signal there crashes VTK
        import pyvista  # noqa: F401

    def draw(stage):
        # a signal inside VTK's rendering prints VTK errors or crashes it (as the design
        # report's pictures, exit 139): drawn with SIGINT/SIGTERM held, delivered once they
        # are done (about a second, three with --animate), when the staging is discarded
        with deferred_signals():
            return render_modes(model, modes, stage, which, args.animate)

    written = write_figures(args, "--out", draw)
    for path in written:
        print(path)
