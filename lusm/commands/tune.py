"""``lusm tune``: plate dimensions at which L1 and B2 coincide.

``--fix thickness`` (default) or ``thickness_ratio``: length and width tuned to the target
frequency. ``--fix length`` (``width``): that dimension kept exactly, the other tuned until
L1 = B2, the common frequency printed (a ``--target-frequency`` is refused: the held dimension
sets it). Parse, call :func:`fem.tuning.tune_plate`, print. No physics here.
"""

from __future__ import annotations

import argparse
import math

from lusm import limits
from lusm.options import add_output_options, add_plate_options, print_json, real

FIX_CHOICES = ("length", "width", "thickness", "thickness_ratio")
"""``--fix`` entries (:data:`fem.tuning.FIX_OPTIONS`, repeated so the parser needs no numpy)."""


def fix_list(text: str) -> tuple[str, ...]:
    """``--fix``: one or more of :data:`FIX_CHOICES`, comma-separated."""
    items = tuple(t.strip() for t in text.split(","))
    if not all(items) or any(t not in FIX_CHOICES for t in items) or len(set(items)) < len(items):
        raise argparse.ArgumentTypeError(
            f"--fix must be one or more of {', '.join(FIX_CHOICES)} (comma-separated, each "
            f"once), got {text!r}")
    return items


HELP = "design for degeneracy: dimensions with f_L1 = f_B2 (= target)"
DESCRIPTION = """\
Find the plate dimensions at which the L1 and B2 modes coincide (short circuit), starting from
the given plate (its gap, electrodes and material are kept). By default the length and width are
tuned to the target frequency at the given thickness; --fix length (or width) keeps that
dimension exactly and tunes the other one, and the common frequency then follows from the held
dimension.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm tune``."""
    p.add_argument("--target-frequency", default=None, metavar="HZ",
                   type=real("--target-frequency", "Hz", *limits.TARGET_FREQUENCY_HZ),
                   help="common L1/B2 frequency wanted (Hz), default 40e3; not with --fix "
                   "length or width")
    p.add_argument("--fix", type=fix_list, default=("thickness",), metavar="WHAT",
                   help="what to hold, comma-separated: thickness (default; length and width "
                   "tuned to the target), thickness_ratio (h/l kept), length (width tuned, "
                   "frequency follows), width (length tuned, frequency follows); e.g. "
                   "'width,thickness_ratio'")
    p.add_argument("--model", choices=("2d", "3d"), default="2d", help="FE model")
    add_plate_options(p, note="; dimensions not held by --fix are starting values")
    from lusm.commands.modes import add_fe_options

    add_fe_options(p, three_d=True)
    add_output_options(p, folder=None)
    p.add_argument("--write", metavar="STATOR.toml", default=None,
                   help="write the tuned stator file: the --geometry file (or one of the plate "
                   "options) with the tuned dimensions, and a comment saying how they were "
                   "found; an existing file is not overwritten unless --force")
    p.add_argument("--force", action="store_true",
                   help="write --write over an existing file (the old one is kept as .bak-N)")


def run(args: argparse.Namespace) -> None:
    """Run ``lusm tune`` with parsed ``args``."""
    from lusm.commands.modes import warn_linear_elements

    warn_linear_elements(args)
    _check_fix(args)
    write = None
    if args.write is not None:  # refused before the tuning's solves, not after
        from lusm.options import file_target

        write = file_target(args.write, "--write", args.force, "tuned.toml")
    choice = _start_plate(args)
    if args.target_frequency is not None:  # length and width tuned (held ones refused)
        _check_target_reachable(args, choice)
    d = _tune(args, choice)
    _check_tuned_plate(d, args.target_frequency)
    if args.model == "2d":
        _warn_tuned_plate(d.stator)
    if write is not None:
        _write_stator(args, choice, d, write)
    if args.json:
        out = d.to_dict()
        if write is not None:
            out["written"] = str(write)
        print_json(out)
        return
    _print(d)
    if write is not None:
        print(f"wrote {write}")


def _write_stator(args: argparse.Namespace, choice, d, path) -> None:
    """Write the tuned stator file (:func:`fem.stator_file.tuned_stator_text`): the
    ``--geometry`` file, or one of the plate options, with the tuned dimensions."""
    from fem.stator_file import tuned_stator_text
    from lusm.messages import command_line
    from lusm.options import write_text_file

    st = d.stator
    dims = {"length_mm": st.length_m * 1e3, "width_mm": st.width_m * 1e3,
            "thickness_mm": st.thickness_m * 1e3}
    held = d.fix.replace("+", ", ")
    reached = (f"common frequency {d.frequency_Hz:.1f} Hz" if d.target_frequency_Hz is None
               else f"target {d.target_frequency_Hz:g} Hz")
    import textwrap

    how = (f"{', '.join(d.tuned)} tuned until L1 = B2 (short circuit), {held} held; "
               f"{reached}; |f_L1 - f_B2| / f = {d.relative_mismatch:.2e} "
               f"(L1 {d.L1.f_short_Hz:.1f} Hz, B2 {d.B2.f_short_Hz:.1f} Hz), {d.model} model, "
               f"order {args.order}, {d.fe_solves} FE solves")
    comment = f"Tuned by: {command_line()}\n" + textwrap.fill(how, 88)
    if choice.design is not None:
        source = choice.design.path.read_text(encoding="utf-8")
        text = tuned_stator_text(dims, comment, source_text=source)
    else:
        tables = {"electrodes": {"gap_mm": float(f"{st.electrode_gap_m * 1e3:.12g}"),
                                 "drive": list(st.drive_electrodes)},
                  "material": {"name": choice.material.name}}
        text = tuned_stator_text(dims, comment, plate_tables=tables)
    write_text_file(path, "--write", text)


def _check_fix(args: argparse.Namespace) -> None:
    """Refuse ``--fix`` combinations that leave nothing to tune or contradict the target."""
    from lusm.errors import LusmError

    fix = args.fix
    held = [f for f in ("length", "width") if f in fix]
    if len(held) == 2:
        raise LusmError("--fix cannot hold both length and width: only the thickness would be "
                        "left, and it moves L1 and B2 too little to make them meet; hold one "
                        "of them", "--fix")
    if "thickness" in fix and "thickness_ratio" in fix:
        raise LusmError("--fix cannot hold both thickness and thickness_ratio; choose one",
                        "--fix")
    if held and args.target_frequency is not None:
        other = "width" if held[0] == "length" else "length"
        raise LusmError(f"--target-frequency cannot be combined with --fix {held[0]}: the "
                        f"{other} is tuned until L1 = B2 and their common frequency follows "
                        f"from the {held[0]}; leave out --target-frequency, or use --fix "
                        "thickness to tune length and width to a target", "--target-frequency")


def _start_plate(args: argparse.Namespace):
    """The start plate, bounded with the tuning's solves before any of them."""
    from lusm.commands.modes import check_refine_3d
    from lusm.errors import LusmError
    from lusm.options import check_fe_size, check_fe_work, stator_from_args

    # the start plate's thickness ratio is not the tuned plate's: that one is checked after
    choice = stator_from_args(args, warn_thin=False)
    if choice.meshed:
        raise LusmError(f"--geometry {args.geometry} has its own mesh, which tune cannot "
                        "rescale; describe its features with [tip], [chamfers], [[holes]] "
                        "(meshed by gmsh, rescaled by tune) or tune its plate with "
                        "--length-mm, --width-mm, --thickness-mm "
                        f"{choice.stator.thickness_m * 1e3:g} (add --fix length to keep the "
                        "length), or a stator file without [mesh]", "--geometry")
    if args.model == "3d":
        check_refine_3d(args.refine)
        from fem.tuning import MAX_3D_SOLVES

        cells = _check_3d_size(args, choice.stator)
        solves = MAX_3D_SOLVES
    else:
        cells = check_fe_size(choice.stator, args.refine, needs_b2=False)
        solves = limits.TUNE_SOLVES
    # a tuning's solves are its own: the message names only the mesh
    check_fe_work(cells, solves, args.model == "3d", "--refine", choice.stator, fewer="")
    return choice


def _check_3d_size(args: argparse.Namespace, stator) -> int:
    """The bricks of one 3D solve of the tuning (the fine mesh of ``lusm modes --model 3d``'s
    default, on the quarter plate where it applies; with ``--refine`` its uniform mesh of
    three layers), refused above the bound."""
    from fem.solid3d.estimate import default_meshes
    from fem.solid3d.symmetric import quarter_model_applies
    from lusm.options import check_fe_size

    if args.refine is not None:
        return check_fe_size(stator, args.refine, 3, layers_option=False)
    fine = default_meshes(stator)[1]
    return check_fe_size(stator, fine.refine, fine.layers, layers_option=False,
                         edge_grading=fine.edge_grading,
                         quarter=quarter_model_applies(stator, fine.edge_grading))


def _check_target_reachable(args: argparse.Namespace, choice) -> None:
    """Refuse, before any FE solve, a target whose plate is far outside the accepted sizes
    (the bar estimate is within a few % of the tuned length; the margin leaves the edge
    cases to the check after tuning)."""
    from fem.tuning import bar_length_m
    from lusm.errors import LusmError

    est_mm = bar_length_m(choice.material, args.target_frequency) * 1e3
    near_top_mm = est_mm * TUNED_LENGTH_OVER_BAR  # the estimate where the rule binds
    lo, hi = limits.PLATE_MM
    # the shortest plate: within the range, and wide enough for electrodes of at least
    # ELECTRODE_GAP_RATIO gaps beside the gap (a tuned plate is about 0.27 times as wide
    # as long: 11.4 x 42.1 mm at 40 kHz). Narrower electrodes: the 2D model leaves the
    # 3D one (6e5 Hz gives a 0.63 mm wide plate, electrodes 0.13 gaps wide, L1 5 % off
    # 3D; 7e5 Hz and above fail after 10-50 FE solves)
    shortest = max(lo, _least_width_mm(choice.stator.electrode_gap_m) / TUNED_ASPECT)
    if not (shortest <= near_top_mm and est_mm <= hi):
        asked_mm = near_top_mm if near_top_mm < shortest else est_mm
        raise LusmError(
            f"--target-frequency {args.target_frequency:g} Hz: asks for a plate about "
            f"{asked_mm:.4g} mm long, outside the [{shortest:.3g}, {hi:g}] mm that the "
            f"plate range and the electrode-width rule (electrodes at least "
            f"{ELECTRODE_GAP_RATIO:g} gaps wide) allow; targets from about "
            f"{_inward(args.target_frequency * est_mm / hi, up=True):.4g} to "
            f"{_inward(args.target_frequency * near_top_mm / shortest):.4g} Hz fit (the "
            f"upper end set by the {choice.stator.electrode_gap_m * 1e3:g} mm electrode "
            f"gap)",
            "--target-frequency")


def _tune(args: argparse.Namespace, choice):
    """:func:`fem.tuning.tune_plate`, its solver failures said as bad input."""
    import warnings

    from fem.errors import FeatureError
    from fem.mesh_settings import MeshSettings
    from fem.model import GapValidityWarning
    from fem.modes import ModeSolverError
    from fem.tuning import tune_plate
    from lusm.errors import LusmError, feature_reason
    from lusm.fe_errors import fe_failure, is_fe_failure

    try:
        with warnings.catch_warnings():  # said once, of the tuned plate, not per iteration
            warnings.simplefilter("ignore", GapValidityWarning)
            return tune_plate(args.target_frequency, fix=args.fix, material=choice.material,
                              start=choice.stator, model=args.model,
                              mesh=MeshSettings(args.order, args.refine), progress=True)
    except Exception as exc:
        if isinstance(exc, ModeSolverError) or is_fe_failure(exc):
            raise fe_failure(exc, choice.stator) from exc
        if choice.parametric and isinstance(exc, FeatureError):
            raise LusmError(f"--geometry {args.geometry}: a plate tried while tuning no longer "
                            f"holds the file's features ({feature_reason(exc)}); tune "
                            "rescales the plate but keeps the tip, chamfers and holes as "
                            "given: move them inwards or hold a dimension with --fix length",
                            "--geometry") from None
        raise


def _warn_tuned_plate(st) -> None:
    """What ``lusm modes`` says of the tuned plate: its holes, the gap's validity, its
    thickness."""
    from fem.model import stator_gap_validity
    from lusm.messages import warn
    from lusm.options import warn_holes, warn_thin_plate

    warn_holes(st, "the tuned plate")  # 2D tunes holes softer than 3D
    validity = stator_gap_validity(st)
    if validity is not None:
        warn(f"the tuned plate: {validity}")
    warn_thin_plate(f"the tuned plate: thickness {st.thickness_m * 1e3:g} mm",
                    st.thickness_m * 1e3, min(st.length_m, st.width_m) * 1e3,
                    "its smaller in-plane dimension")


def _print(d) -> None:
    """The tuned plate, its L1 and B2, and how close they came."""
    from validation.summaries import plate_text

    st = d.stator
    if d.target_frequency_Hz is None:
        print(f"no target: the {d.tuned[0]} is tuned until L1 = B2, the frequency follows; "
              f"material {d.material}, model {d.model}, fixed {d.fix.replace('+', ', ')}")
    else:
        print(f"target {d.target_frequency_Hz:g} Hz, material {d.material}, model {d.model}, "
              f"fixed {d.fix.replace('+', ', ')}")
    print(f"{plate_text(st, '.4f')} (gap {st.electrode_gap_m * 1e3:g} mm)")
    print(f"{'mode':<5}{'f_short (Hz)':>14}{'f_open (Hz)':>14}{'k_eff':>9}")
    for name, m in (("L1", d.L1), ("B2", d.B2)):
        print(f"{name:<5}{m.f_short_Hz:>14.1f}{m.f_open_Hz:>14.1f}{m.k_eff:>9.4f}")
    solves = (f"FE solves {d.fe_solves}" if not d.solves_3d else
              f"FE solves {d.fe_solves} ({d.fe_solves - d.solves_3d} 2D, {d.solves_3d} 3D)")
    if d.target_frequency_Hz is None:
        print(f"common frequency {d.frequency_Hz:.1f} Hz, |f_L1 - f_B2| / f = "
              f"{d.relative_mismatch:.2e}, {solves}")
    else:
        print(f"|f_L1 - f_B2| / f = {d.relative_mismatch:.2e}, {solves}, "
              f"outer iterations {d.outer_iterations}")


TUNED_ASPECT = 0.2696
"""Width over length of a plate tuned to L1 = B2 where the electrode rule binds (2.000 x
7.418 mm at 2.2465e5 Hz, PZT-8, 3 mm; 11.43 / 42.13 = 0.2713 at 40 kHz): with 0.27 the check
before the solves quoted targets up to 2.248e5 Hz, which the tuned plate then refused."""
TUNED_LENGTH_OVER_BAR = 0.985
"""Tuned length over the bar estimate (:func:`fem.tuning.bar_length_m`) near the electrode
rule's upper end: 7.4403 mm against 7.5503 mm at 2.24e5 Hz (3 mm PZT-8 plate; 0.996 at
40 kHz). With the bar estimate alone the check before the solves let targets up to 2.283e5 Hz
through, which the same rule on the tuned plate then refused above 2.246e5 Hz."""
ELECTRODE_GAP_RATIO = 1.5
"""Least electrode width, ``(width - gap) / 2``, over the gap of a tuned plate (docs/limits.md):
checked on the estimate before any FE solve and on the tuned plate. Against the 3D model, the
3 mm plate tuned to 2e5 Hz (electrodes 1.76 gaps wide) is 0.06 % off in L1 and 0.6 % in B2;
to 3e5 Hz (0.97 gaps) 0.46 % and 0.44 %, its B2 k_eff 15 % high; to 4e5 Hz (0.57 gaps) B2 is
8.8 % off. The former check asked the plate, not its electrodes, to be 1.5 gaps wide."""


def _inward(value: float, up: bool = False) -> float:
    """``value`` rounded to 4 significant digits towards the inside of a quoted range (``up``
    for its lower end), so that both ends quoted are accepted ('.4g' rounds outwards)."""
    q = 10.0 ** (math.floor(math.log10(abs(value))) - 3)
    return (math.ceil if up else math.floor)(value / q * (1 - 1e-12 if up else 1 + 1e-12)) * q


def _least_width_mm(gap_m: float) -> float:
    """Narrowest plate (mm) whose two electrodes are :data:`ELECTRODE_GAP_RATIO` gaps wide."""
    return (2.0 * ELECTRODE_GAP_RATIO + 1.0) * gap_m * 1e3


def _check_tuned_plate(d, target_Hz: float | None) -> None:
    """Refuse a tuned plate that the other commands would refuse (outside ``PLATE_MM``).

    A plate's frequencies scale as 1 / (its size) at a held thickness, so the message
    estimates the targets whose plate fits from the one found.
    """
    from lusm.errors import LusmError

    st = d.stator
    dims = {"length": st.length_m * 1e3, "width": st.width_m * 1e3,
            "thickness": st.thickness_m * 1e3}
    lo, hi = limits.PLATE_MM
    bad = {k: v for k, v in dims.items() if not lo <= v <= hi}
    least = _least_width_mm(st.electrode_gap_m)
    if not bad and target_Hz is not None and dims["width"] < least * (1 - 1e-9):
        # the estimate before the solves let it through (the tuned aspect is a little
        # narrower at high frequency); the same rule on the plate found
        electrode = 0.5 * (dims["width"] - st.electrode_gap_m * 1e3)
        raise LusmError(
            f"--target-frequency {target_Hz:g} Hz: the tuned plate is {dims['width']:.4g} mm "
            f"wide, its electrodes {electrode:.3g} mm beside the "
            f"{st.electrode_gap_m * 1e3:g} mm gap, less than the {ELECTRODE_GAP_RATIO:g} x "
            f"the gap the 2D model needs (docs/limits.md); targets up to about "
            f"{_inward(target_Hz * dims['width'] / least):.4g} Hz fit", "--target-frequency")
    if not bad:
        return
    name, value = next(iter(bad.items()))
    option = "--target-frequency" if target_Hz is not None else "--fix"
    where = ""
    if target_Hz is not None:
        size = max(dims["length"], dims["width"])
        where = (f"; targets from about {_inward(target_Hz * size / hi, up=True):.4g} Hz give "
                 f"a plate within "
                 f"{hi:g} mm")
    raise LusmError(f"{option}: the tuned plate's {name} is {value:.4g} mm, outside the "
                    f"[{lo:g}, {hi:g}] mm the other commands accept{where}", option)
