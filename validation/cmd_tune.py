"""``lusm tune``: plate length and width at which L1 and B2 coincide at a target frequency.

Parse, call :func:`fem.tuning.tune_plate`, print. No physics here.
"""

from __future__ import annotations

import argparse

from validation import limits
from validation.options import add_output_options, add_plate_options, print_json, real


def register(subparsers) -> None:
    """Add the ``tune`` sub-command to the ``lusm`` parser."""
    p = subparsers.add_parser(
        "tune",
        help="design for degeneracy: length and width with f_L1 = f_B2 = target",
        description="Find the plate length and width at which the L1 and B2 modes coincide "
        "(short circuit) at the target frequency, starting from the given plate (its "
        "thickness, gap, electrodes and material are kept).",
    )
    p.add_argument("--target-frequency", default=40e3, metavar="HZ",
                   type=real("--target-frequency", "Hz", *limits.TARGET_FREQUENCY_HZ),
                   help="common L1/B2 frequency wanted (Hz), default 40e3")
    p.add_argument("--fix", choices=("thickness", "thickness_ratio"), default="thickness",
                   help="keep the thickness (default) or the thickness/length ratio")
    p.add_argument("--model", choices=("2d", "3d"), default="2d", help="FE model")
    add_plate_options(p, note="; the length and width are starting values")
    from validation.cmd_modes import add_fe_options

    add_fe_options(p)
    add_output_options(p, folder=None)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> None:
    """Run ``lusm tune`` with parsed ``args``."""
    from validation.cmd_modes import check_refine_3d, fe_failure, is_fe_failure
    from validation.errors import LusmError
    from validation.options import check_fe_size, stator_from_args

    choice = stator_from_args(args)
    if choice.meshed:
        raise LusmError(f"--geometry {args.geometry} has its own mesh, which tune cannot "
                        "rescale; tune a stator file without [mesh] (a plain plate)",
                        "--geometry")
    if args.model == "3d":
        check_refine_3d(args.refine)
        check_fe_size(choice.stator, args.refine or 3, 3)
    else:
        check_fe_size(choice.stator, args.refine)

    from fem.modes import ModeSolverError
    from fem.tuning import tune_plate

    try:
        d = tune_plate(args.target_frequency, fix=args.fix, material=choice.material,
                       start=choice.stator, model=args.model, order=args.order,
                       refine=args.refine)
    except Exception as exc:
        if isinstance(exc, ModeSolverError) or is_fe_failure(exc):
            raise fe_failure(exc) from exc
        raise
    if args.json:
        print_json(d.to_dict())
        return
    st = d.stator
    print(f"target {d.target_frequency_Hz:g} Hz, material {d.material}, model {d.model}, "
          f"fixed {d.fix}")
    print(f"plate {st.length_m * 1e3:.4f} x {st.width_m * 1e3:.4f} x "
          f"{st.thickness_m * 1e3:.4g} mm (gap {st.electrode_gap_m * 1e3:g} mm)")
    print(f"{'mode':<5}{'f_short (Hz)':>14}{'f_open (Hz)':>14}{'k_eff':>9}")
    for name, m in (("L1", d.L1), ("B2", d.B2)):
        print(f"{name:<5}{m.f_short_Hz:>14.1f}{m.f_open_Hz:>14.1f}{m.k_eff:>9.4f}")
    print(f"|f_L1 - f_B2| / f = {d.relative_mismatch:.2e}, FE solves {d.fe_solves}, "
          f"outer iterations {d.outer_iterations}")
