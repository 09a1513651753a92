"""``lusm render``: offscreen PNGs (and GIF animations) of the L1/B2 mode shapes.

Parse, call :mod:`fem.render`, print the files written. No physics here; ``fem`` and
pyvista are imported when the command runs.
"""

from __future__ import annotations

import argparse


def register(subparsers) -> None:
    """Add the ``render`` sub-command to the ``lusm`` parser."""
    p = subparsers.add_parser(
        "render",
        help="PNG pictures (and GIF animations) of the L1/B2 mode shapes, offscreen",
        description="Render the FE mode shapes offscreen with pyvista: deformed planform "
        "coloured by displacement magnitude over the undeformed outline, electrodes "
        "outlined (driven in red), mode name and frequency in the title.",
    )
    p.add_argument("--mode", choices=("L1", "B2", "all"), default="all", help="which mode")
    p.add_argument("--out", default="renders", metavar="DIR", help="output directory")
    p.add_argument("--animate", action="store_true", help="also write one period as a GIF")
    p.add_argument(
        "--geometry", metavar="STATOR.toml", default=None,
        help="stator file (default: the paper's 30 x 7.5 x 3 mm PZT-8 plate)",
    )
    p.add_argument("--order", type=int, choices=(1, 2), default=2, help="element order")
    p.add_argument("--refine", type=int, default=None, help="elements per plate width")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> None:
    """Run ``lusm render`` with parsed ``args``."""
    from fem.geometry import PlateStator
    from fem.material import get_material
    from fem.model import plate_model
    from fem.modes import DEFAULT_REFINE, ModeSolverError, plate_modes
    from fem.render import render_modes

    if args.geometry:
        from fem.stator_file import load_stator

        design = load_stator(args.geometry)
        stator, material = design.stator, design.material
    else:
        stator, material = PlateStator(), get_material("pzt8")
    refine = DEFAULT_REFINE if args.refine is None else args.refine
    try:
        modes = plate_modes(stator, material, args.order, refine)
    except ModeSolverError as exc:
        raise ValueError(str(exc)) from exc
    model = plate_model(stator, material, args.order, refine)
    which = ("L1", "B2") if args.mode == "all" else (args.mode,)
    for path in render_modes(model, modes, args.out, which, args.animate):
        print(path)
