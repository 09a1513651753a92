"""``lusm sweep``: L1 and B2 against the plate width or length (crossing diagram, PNG).

One of ``--width-mm`` / ``--length-mm`` is an ``a:b:step`` range (mm, :mod:`lusm.ranges`),
the other plate options are fixed values as on every stator command. Calls
:func:`fem.sweep.sweep_dimension` and :func:`validation.fem_figures.sweep_figure`, prints.
No physics here.
"""

from __future__ import annotations

import argparse
import math

from lusm import limits
from lusm.options import GAP_RULE, MATERIALS, add_output_options, print_json, real

HELP = "L1/B2 frequencies against the plate width or length (crossing diagram PNG)"
DESCRIPTION = """\
Sweep one plate dimension, identify L1 and B2 by shape at each point and plot their
short-circuit frequencies (the crossing/veering diagram). Give one of --width-mm / --length-mm
as a range A:B:STEP; the other is a fixed value.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm sweep``."""
    lo, hi = limits.PLATE_MM
    g = p.add_argument_group("stator", "the paper's 30 x 7.5 x 3 mm PZT-8 plate unless "
                             "--geometry or a plate option is given")
    g.add_argument("--geometry", metavar="STATOR.toml", default=None,
                   help="stator file to sweep: a plate, or one meshed by gmsh ([mesh] size_mm, "
                   "features kept as given); not one with its own mesh file")
    g.add_argument("--width-mm", metavar="MM|A:B:STEP", default=None,
                   help="plate width (mm): a value, or the range to sweep")
    g.add_argument("--length-mm", metavar="MM|A:B:STEP", default=None,
                   help="plate length (mm): a value, or the range to sweep")
    g.add_argument("--length", type=real("--length", "mm", lo, hi), default=None,
                   dest="fixed_length_mm", help=argparse.SUPPRESS)  # old spelling
    g.add_argument("--width", type=real("--width", "mm", lo, hi), default=None,
                   dest="fixed_width_mm", help=argparse.SUPPRESS)  # old spelling
    g.add_argument("--thickness-mm", type=real("--thickness-mm", "mm", lo, hi), default=None,
                   help="plate thickness (mm), default 3")
    g.add_argument("--gap-mm", type=real("--gap-mm", "mm", 0.0, hi, rule=GAP_RULE),
                   default=None, help="electrode gap (mm), default 0.5")
    g.add_argument("--material", choices=MATERIALS, default=None, help="default pzt8")
    from lusm.commands.modes import add_fe_options

    add_fe_options(p)
    add_output_options(p, folder="--out", folder_help="write the crossing diagram (PNG) "
                       "into DIR (default: no file)")


def _split(args: argparse.Namespace):
    """(parameter, option, range text, fixed values in mm) from the two dimension options."""
    from lusm.errors import LusmError

    ranges = [(o, getattr(args, o[2:].replace("-", "_"))) for o in ("--width-mm", "--length-mm")]
    ranged = [(o, t) for o, t in ranges if t is not None and ":" in t]
    if len(ranged) != 1:
        # as typed: a malformed 30:40 is not counted as a range
        given = [f"{o} {t}" for o, t in (ranged or ranges) if t is not None]
        got = " and ".join(given) + ("" if ranged else " (no range)") if given else "neither"
        raise LusmError("give exactly one of --width-mm / --length-mm as a range A:B:STEP (mm), "
                        f"the other a value or nothing; got {got}", "--width-mm")
    option, text = ranged[0]
    fixed = {}
    for o, t in ranges:
        if o == option or t is None:
            continue
        fixed[o] = real(o, "mm", *limits.PLATE_MM)(t) if t is not None else None
    return ("width" if option == "--width-mm" else "length"), option, text, fixed


def run(args: argparse.Namespace) -> None:
    """Run ``lusm sweep`` with parsed ``args``."""
    import numpy as np

    from fem.units import to_si
    from lusm.commands.modes import warn_linear_elements
    from lusm.options import output_folder, write_figures

    warn_linear_elements(args)
    out = output_folder(args, "--out")
    parameter, option, text, fixed, typed_as, values_mm = _swept_values(args)
    if args.geometry:
        base, material = _base_of_file(args, fixed, typed_as, parameter, values_mm)
    else:
        base, material = _base_of_options(args, fixed, parameter, option, text, values_mm)
    # metres as every command takes a length in mm (fem.units: 6.5 mm is 0.0065, one plate
    # with modes' and explore's)
    values_m = np.array([to_si(float(v), 1e-3) for v in values_mm])
    _check_sweep(args, base, parameter, option, text, values_m)
    res = _solve(args, parameter, values_m, base, material)
    _report_failures(res, parameter)
    png = None
    if out is not None:
        from validation.fem_figures import sweep_figure

        png = write_figures(args, "--out", lambda stage: [
            sweep_figure(res, stage / f"sweep_{parameter}.png")])[0]
    if args.json:
        d = res.to_dict()
        d["values_mm"] = [float(v) for v in values_mm]  # as typed: no 26.000000000000004
        d["png"] = png
        print_json(d)
        return
    _print_table(res, parameter, values_mm)
    if png is not None:
        print(f"wrote {png}")


def _swept_values(args: argparse.Namespace):
    """The swept dimension, its option and text, the fixed dimensions by option (and the
    old spelling each was typed in), and the values (mm), bounded before any work."""
    import argparse as _ap

    from lusm.errors import LusmError
    from lusm.ranges import parse_range

    try:
        parameter, option, text, fixed = _split(args)
    except _ap.ArgumentTypeError as exc:
        raise LusmError(str(exc)) from None
    try:  # the plate range (above 0) said with the form, as every grid says it
        values_mm = parse_range(text, option, allow_list=False, bounds=limits.PLATE_MM,
                                unit="mm")
    except ValueError as exc:
        raise LusmError(str(exc), option) from None
    top = limits.work_bound(limits.MAX_SWEEP_POINTS)
    if values_mm.size > top:
        raise LusmError(f"{option} has {values_mm.size} points, above the limit {top} FE "
                        f"solves ({limits.more_work_hint()})", option)
    typed_as = _take_old_spellings(args, fixed, option, text)
    return parameter, option, text, fixed, typed_as, values_mm


def _take_old_spellings(args: argparse.Namespace, fixed: dict, option: str,
                        text: str) -> dict[str, str]:
    """Add ``--length`` / ``--width`` (the old spellings of the fixed dimensions) to
    ``fixed``, refusing one that fixes the swept dimension or repeats its new spelling;
    returns the old spelling typed of each new option."""
    from lusm.errors import LusmError

    typed_as = {}

    for old, new, value in (("--length", "--length-mm", args.fixed_length_mm),
                            ("--width", "--width-mm", args.fixed_width_mm)):
        if value is None:
            continue
        if new == option:
            raise LusmError(f"{old} fixes the {new[2:-3]}, which {option} {text} sweeps; give "
                            "one", old)
        if fixed.get(new) is not None:
            raise LusmError(f"{old} and {new} both give the fixed {new[2:-3]}; give one ({old} "
                            f"is the old spelling of {new})", old)
        fixed[new], typed_as[new] = value, old
    return typed_as


def _base_of_file(args: argparse.Namespace, fixed: dict, typed_as: dict[str, str],
                  parameter: str, values_mm):
    """The stator file's plate and material, warned of at the sweep's smallest plate."""
    from lusm.errors import LusmError
    from lusm.options import (
        StatorChoice,
        load_design,
        warn_holes,
        warn_refine_unused,
        warn_thin_plate,
    )

    given = [typed_as.get(o, o) for o, v in fixed.items() if v is not None]
    given += [o for o in ("--thickness-mm", "--gap-mm", "--material")
              if getattr(args, o[2:].replace("-", "_")) is not None]
    if given:
        raise LusmError(f"{', '.join(given)} cannot be combined with --geometry: the "
                        "stator file sets the plate", given[0])
    design = load_design(args.geometry)
    if design.mesh_path is not None:
        raise LusmError(f"--geometry {args.geometry} has its own mesh, which sweep cannot "
                        "rescale; sweep a stator file without a [mesh] file", "--geometry")
    base, material = design.stator, design.material
    warn_refine_unused(StatorChoice(base, material, design), args.geometry)
    warn_holes(base, f"--geometry {args.geometry}")
    # at the sweep's smallest plate, as the plain-plate branch checks it
    inplane = {"length": base.length_m, "width": base.width_m}
    inplane[parameter] = float(values_mm.min()) * 1e-3
    least = min(inplane, key=inplane.get)  # the dimension that gives the ratio
    warn_thin_plate(f"--geometry {args.geometry}: thickness {base.thickness_m * 1e3:g} mm",
                    base.thickness_m * 1e3, inplane[least] * 1e3,
                    f"the sweep's smallest in-plane dimension ({least} "
                    f"{inplane[least] * 1e3:g} mm)")
    return base, material


def _base_of_options(args: argparse.Namespace, fixed: dict, parameter: str, option: str,
                     text: str, values_mm):
    """The plate the options give, checked at the sweep's smallest plate (the thin-plate
    check is the sweep's worst plate)."""
    import argparse as _ap

    from fem.geometry import PlateStator
    from lusm.errors import LusmError
    from lusm.options import stator_from_args

    gap_mm = PlateStator().electrode_gap_m * 1e3 if args.gap_mm is None else args.gap_mm
    if gap_mm >= values_mm.min():  # said of the sweep, not of one plate
        raise LusmError(f"{option} {text}: the electrode gap {gap_mm:g} mm must stay "
                        "below every swept length and width", option)
    dims = {**fixed, f"--{parameter}-mm": float(values_mm.min())}
    ns = _ap.Namespace(geometry=None, thickness_mm=args.thickness_mm, gap_mm=args.gap_mm,
                       material=args.material, length_mm=dims.get("--length-mm"),
                       width_mm=dims.get("--width-mm"))
    choice = stator_from_args(ns)
    return choice.stator, choice.material


def _check_sweep(args: argparse.Namespace, base, parameter: str, option: str, text: str,
                 values_m) -> None:
    """Refuse, before any solve, a sweep whose gap, slenderness, features or FE work no
    plate of it can take."""
    from dataclasses import replace

    from fem.errors import FeatureError
    from lusm.errors import LusmError, feature_reason
    from lusm.options import check_fe_size, check_fe_work

    smallest = min(base.length_m, base.width_m, float(values_m.min()))
    if base.electrode_gap_m >= smallest:
        raise LusmError(f"{option} {text}: the electrode gap {base.electrode_gap_m * 1e3:g} mm "
                        "must stay below every swept length and width", option)
    try:  # the sweep's two extremes, which also hold the features if any plate does
        ends = [replace(base, **{f"{parameter}_m": float(v)})
                for v in (values_m.min(), values_m.max())]
        # the slenderness is monotone in the swept dimension: when the less slender end is
        # too slender for the solver to reach B2, every plate is
        _check_some_b2_in_reach(sorted(ends, key=lambda st: st.length_m / st.width_m),
                                option, text)
        cells = [check_fe_size(st, args.refine, needs_b2=False) for st in ends]
    except ValueError as exc:
        if not isinstance(exc, FeatureError):
            raise
        # a plate of the sweep no longer holds the file's features: the range is to blame
        raise LusmError(f"{option} {text}: a plate of the sweep no longer holds the features "
                        f"of --geometry {args.geometry} ({feature_reason(exc)}); the sweep "
                        "keeps the tip, chamfers and holes as given: sweep a range whose "
                        "plates keep them", option) from None
    check_fe_work(max(cells), values_m.size, False, "--refine", base,
                  fewer=f"sweep fewer values ({option})")


def _solve(args: argparse.Namespace, parameter: str, values_m, base, material):
    """:func:`fem.sweep.sweep_dimension`, a solver failure said as bad input."""
    from fem.mesh_settings import MeshSettings
    from fem.sweep import sweep_dimension
    from lusm.fe_errors import fe_failure, is_fe_failure

    try:
        return sweep_dimension(parameter, values_m, base, material,
                               MeshSettings(args.order, args.refine), progress=not args.json)
    except Exception as exc:
        if is_fe_failure(exc):
            raise fe_failure(exc, base) from exc
        raise


def _print_table(res, parameter: str, values_mm) -> None:
    """The sweep's table and its L1/B2 crossings, with their uncertainty."""
    print(f"{parameter} (mm){'L1 short (Hz)':>16}{'B2 short (Hz)':>16}")
    # the values as typed (as --json's values_mm): as many digits as give each value back,
    # and tell the rows apart
    digits = 4
    while digits < 15 and (  # to the range's rounding (lusm.ranges: 12 digits)
            any(not math.isclose(float(f"{v:.{digits}g}"), v, rel_tol=1e-12) for v in values_mm)
            or len({f"{v:.{digits}g}" for v in values_mm}) < values_mm.size):
        digits += 1
    for v, fl, fb in zip(values_mm, res.f_L1_short_Hz, res.f_B2_short_Hz, strict=True):
        cells = [f"{x:>16.1f}" if math.isfinite(x) else f"{'-':>16}" for x in (fl, fb)]
        print(f"{float(v):>10.{digits}g}{''.join(cells)}")
    for xc, err in res.crossing_estimates_m():
        if not math.isfinite(err):  # two grid points: one line, no error estimate
            print(f"L1/B2 crossing at {parameter} {xc * 1e3:.4g} mm (linear between two "
                  f"grid points, error unknown: sweep more points around it, or lusm tune "
                  f"solves for it)")
            continue
        # to the decimal of the uncertainty's leading digit (cubic against linear)
        digits = min(4, max(1, -math.floor(math.log10(err * 1e3)))) if err > 0 else 4
        print(f"L1/B2 crossing at {parameter} {xc * 1e3:.{digits}f} mm (+- "
              f"{err * 1e3:.1g} mm between the grid points: cubic against linear "
              f"interpolation; lusm tune solves for it)")


def _check_some_b2_in_reach(ends, option: str, text: str) -> None:
    """Refuse a sweep whose least slender plate (``ends[0]``; ``ends[1]`` the most slender)
    is too slender for the solver to reach B2 from L1, or whose most slender one is wider
    than long: then no plate of it has a pair (:func:`fem.modes.check_b2_in_reach`). A sweep
    only partly too wide keeps its other plates (the wide ones fail alone, before a solve)."""
    from fem.modes import SlenderPlateError, WidePlateError, check_b2_in_reach
    from lusm.errors import LusmError
    from lusm.fe_errors import slender_reason

    try:
        check_b2_in_reach(ends[1])
    except WidePlateError as exc:  # a 30 x 40 mm end: refused in the option's terms
        raise LusmError(f"{option} {text}: no plate of the sweep can have an L1/B2 pair: even "
                        f"{exc}; sweep plates narrower than long", option) from None
    except SlenderPlateError:
        pass  # the least slender end decides that
    try:
        check_b2_in_reach(ends[0])
    except WidePlateError:
        return  # the sweep's wide plates fail alone; the others are solved
    except SlenderPlateError as exc:
        raise LusmError(f"{option} {text}: no plate of the sweep can have an L1/B2 pair: even "
                        f"{slender_reason(exc)}; sweep plates at most about "
                        f"{exc.max_slenderness:.0f} times longer than wide", option) from None


def _report_failures(res, parameter: str) -> None:
    """Refuse a sweep where no point gave L1 and B2; warn about the points that did not."""
    from lusm.errors import LusmError, short_reason
    from lusm.messages import warn

    bad = [i for i, f in enumerate(res.failures) if f]
    if not bad:
        return
    where = ", ".join(f"{res.values_m[i] * 1e3:g}" for i in bad[:6]) + \
        (", ..." if len(bad) > 6 else "")
    option = f"--{parameter}-mm"
    reason = short_reason(res.failures[bad[0]])
    if len(bad) == len(res.failures):
        raise LusmError(f"{option}: L1 and B2 were identified at no point of the sweep "
                        f"({where} mm); at {res.values_m[0] * 1e3:g} mm: {reason}", option)
    warn(f"{option}: L1 and B2 were not identified at {len(bad)} of {len(res.failures)} "
         f"points ({where} mm; '-' in the table, a gap in the figure); at "
         f"{res.values_m[bad[0]] * 1e3:g} mm: {reason}")
