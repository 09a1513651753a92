"""``lusm render``: offscreen PNGs (and GIF animations) of the mode shapes.

The 2D plate's L1 and B2, or with ``--model 3d`` any mode of the 3D band table (``lusm modes
--model 3d --band``: by name or by its row), coloured by displacement or electric potential.
Parse, call :mod:`fem.render` or :mod:`fem.render3d`, print the files written. No physics
here; ``fem`` and pyvista are imported when the command runs. The pictures are built aside
and moved into ``--out`` complete (:mod:`lusm.output_set`).
"""

from __future__ import annotations

import argparse
import re

from lusm import limits
from lusm.commands.modes import add_fe_options, band_option
from lusm.fe_errors import fe_failure, is_fe_failure
from lusm.options import add_output_options, add_plate_options, integer

HELP = "PNG pictures (and GIF animations) of the mode shapes (2D L1/B2, any 3D mode), offscreen"
DESCRIPTION = """\
Render the FE mode shapes offscreen with pyvista: 2D, the deformed planform coloured by
displacement magnitude over the undeformed outline, electrodes outlined (driven in red); 3D
(--model 3d), the deformed solid coloured by displacement magnitude or electric potential,
any mode of the band table of 'lusm modes --model 3d --band'. Mode name and frequency in the
title.
"""

MODE_NAME = re.compile(r"^(L|B|OB|T)[1-9][0-9]*$")
"""Names a mode of the band may have (:data:`fem.band.FAMILIES`): L1, B2, OB3, T2, ..."""


def mode_choice(text: str) -> str | int:
    """``--mode``: ``all``, a mode's name (L1, B2, OB3, T2, ...) or its row of the 3D band
    table (an integer from 1)."""
    t = text.strip()
    if t == "all" or MODE_NAME.match(t):
        return t
    if t.isdigit() and int(t) >= 1:
        return int(t)
    raise argparse.ArgumentTypeError(
        f"--mode must be all, L1, B2, another mode's name of the 3D band table (OB3, T2, ...) "
        f"or its row there (an integer from 1, with --model 3d), got {text!r}")


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm render``."""
    p.add_argument("--mode", type=mode_choice, default="all", metavar="L1|B2|NAME|INDEX|all",
                   help="which mode (default all: L1 and B2); with --model 3d any mode of the "
                   "band table of 'lusm modes --model 3d --band' by its name or its row INDEX "
                   "(from 1)")
    p.add_argument("--animate", action="store_true", help="also write one period as a GIF")
    p.add_argument("--model", choices=("2d", "3d"), default="2d",
                   help="2d: the plane-stress planform (default); 3d: the piezoelastic solid")
    p.add_argument("--color", choices=("displacement", "potential"), default="displacement",
                   help="3d: colour by the displacement magnitude (default) or by the signed "
                   "electric potential of the mode (diverging colours, white at 0 V)")
    p.add_argument("--band", nargs="?", const="auto", default=None, type=band_option,
                   metavar="F1:F2",
                   help="3d: the band whose table INDEX counts in (kHz or with a unit, as "
                   "'lusm modes --band'; default the L1/B2 pair +- 20 %%)")
    p.add_argument("--layers", type=integer("--layers", 1, limits.MAX_LAYERS, work=True),
                   default=None, help="3d: element layers through h (default 3)")
    add_plate_options(p)
    add_fe_options(p, three_d=True)
    add_output_options(p, folder="--out", default="renders", json_flag=False,
                       folder_help="output folder (default renders)")


def run(args: argparse.Namespace) -> None:
    """Run ``lusm render`` with parsed ``args``."""
    from fem.mesh_settings import MeshSettings
    from lusm.commands.modes import warn_linear_elements
    from lusm.options import check_fe_size, output_folder, stator_from_args

    warn_linear_elements(args)
    _check_model_options(args)
    output_folder(args, "--out")  # refused before any work
    choice = stator_from_args(args)
    if args.model == "3d":
        _run_3d(args, choice)
        return

    from fem.meshing.mesh import DEFAULT_REFINE
    from fem.model import plate_model
    from fem.modes import ModeSolverError, plate_modes
    from fem.render import render_modes

    refine = DEFAULT_REFINE if args.refine is None else args.refine
    check_fe_size(choice.stator, refine)
    mesh = MeshSettings(args.order, refine)
    try:
        modes = plate_modes(choice.stator, choice.material, mesh)
    except Exception as exc:
        if isinstance(exc, ModeSolverError) or is_fe_failure(exc):
            raise fe_failure(exc, choice.stator) from exc
        raise
    model = plate_model(choice.stator, choice.material, mesh)
    which = ("L1", "B2") if args.mode == "all" else (args.mode,)
    _draw(args, lambda stage: render_modes(model, modes, stage, which,
                                                     args.animate))


def _draw(args: argparse.Namespace, render) -> None:
    """Run ``render(stage)`` with the signals held, move the set into ``--out``, print it."""
    from contact.deferred_signals import deferred_signals
    from lusm.options import write_figures

    with deferred_signals():  # not interrupted half-way: a signal there crashes VTK
        import pyvista  # noqa: F401

    def draw(stage):
        # a signal inside VTK's rendering prints VTK errors or crashes it (as the design
        # report's pictures, exit 139): drawn with SIGINT/SIGTERM held, delivered once they
        # are done (about a second, three with --animate), when the staging is discarded
        with deferred_signals():
            return render(stage)

    for path in write_figures(args, "--out", draw):
        print(path)


def _check_model_options(args: argparse.Namespace) -> None:
    """Refuse the 3D options without ``--model 3d``, before any work."""
    from lusm.errors import LusmError

    if args.model == "3d":
        return
    for option, given in (("--color", args.color != "displacement"),
                          ("--band", args.band is not None),
                          ("--layers", args.layers is not None)):
        if given:
            raise LusmError(f"{option} applies to --model 3d only (the 2D pictures show the "
                            "displacement of L1 and B2)", option)
    if args.mode not in ("all", "L1", "B2"):
        raise LusmError(f"--mode {args.mode}: the 2D model draws L1 and B2 only; other modes "
                        "and rows of the band table need --model 3d", "--mode")


def _run_3d(args: argparse.Namespace, choice) -> None:
    """``--model 3d``: the chosen modes of the 3D band, drawn by :mod:`fem.render3d`."""
    from fem.band import BandTooWideError, band_shapes, default_band_Hz
    from fem.mesh_settings import MeshSettings
    from fem.solid3d.model import DEFAULT_LAYERS, DEFAULT_REFINE_3D, solid_model
    from lusm.commands.modes import check_refine_3d
    from lusm.errors import LusmError
    from lusm.fe_errors import fe_failures_as_input
    from lusm.options import check_fe_size

    check_refine_3d(args.refine)
    refine = DEFAULT_REFINE_3D if args.refine is None else args.refine
    layers = DEFAULT_LAYERS if args.layers is None else args.layers
    check_fe_size(choice.stator, refine, layers, "--refine")
    with fe_failures_as_input(choice.stator):
        model = solid_model(choice.stator, choice.material,
                            MeshSettings(args.order, refine, layers))
        if args.band in (None, "auto"):
            from fem.solid3d.model import modes_of_solid_model

            pair = modes_of_solid_model(model)
            ops = {"L1": pair.L1.f_short_Hz, "B2": pair.B2.f_short_Hz}
            lo, hi = default_band_Hz(ops)
        else:
            lo, hi = args.band
        try:
            band = band_shapes(model, lo, hi)
        except BandTooWideError as exc:
            raise LusmError(f"--band {lo:g}:{hi:g} Hz: {exc}", "--band") from None
    chosen = _chosen(args.mode, band, lo, hi)
    from fem.render3d import render_modes3d

    _draw(args, lambda stage: render_modes3d(model, chosen, stage, args.animate,
                                                         color=args.color))


def _chosen(mode: str | int, band, lo: float, hi: float) -> list:
    """The band's modes ``--mode`` names (all: L1 and B2), refused with what the band holds."""
    from lusm.errors import LusmError

    held = ", ".join(f"{m.index} {m.name} ({m.f_short_Hz:.0f} Hz)" for m in band) or "no mode"
    if isinstance(mode, int):
        if mode > len(band):
            raise LusmError(f"--mode {mode}: the band {lo:.0f}-{hi:.0f} Hz holds {len(band)} "
                            f"modes ({held}); give a row from 1 to {len(band)}", "--mode")
        return [band[mode - 1]]
    names = ("L1", "B2") if mode == "all" else (mode,)
    chosen = [m for n in names for m in band if m.name == n]
    if len(chosen) < len(names):
        missing = [n for n in names if all(m.name != n for m in band)]
        raise LusmError(f"--mode {mode}: no {' or '.join(missing)} in the band "
                        f"{lo:.0f}-{hi:.0f} Hz (it holds {held}); widen it with --band or "
                        "give a row", "--mode")
    return chosen
