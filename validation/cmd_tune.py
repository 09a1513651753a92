"""``lusm tune``: plate length and width at which L1 and B2 coincide at a target frequency.

Parse, call :func:`fem.tuning.tune_plate`, print. No physics here.
"""

from __future__ import annotations

import argparse
import json


def register(subparsers) -> None:
    """Add the ``tune`` sub-command to the ``lusm`` parser."""
    p = subparsers.add_parser(
        "tune",
        help="design for degeneracy: length and width with f_L1 = f_B2 = target",
        description="Find the plate length and width at which the L1 and B2 modes coincide "
        "(short circuit) at the target frequency, starting from the given plate.",
    )
    p.add_argument("--target-frequency", type=float, default=40e3, metavar="HZ",
                   help="common L1/B2 frequency wanted (Hz), default 40e3")
    p.add_argument("--fix", choices=("thickness", "thickness_ratio"), default="thickness",
                   help="keep the thickness (default) or the thickness/length ratio")
    p.add_argument("--material", choices=("pzt8", "paper"), default="pzt8")
    p.add_argument("--model", choices=("2d", "3d"), default="2d", help="FE model")
    p.add_argument("--length-mm", type=float, default=30.0, help="starting length (mm)")
    p.add_argument("--width-mm", type=float, default=7.5, help="starting width (mm)")
    p.add_argument("--thickness-mm", type=float, default=3.0, help="thickness (mm)")
    p.add_argument("--gap-mm", type=float, default=0.5, help="electrode gap (mm), kept")
    p.add_argument("--refine", type=int, default=None, help="mesh refinement")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> None:
    """Run ``lusm tune`` with parsed ``args``."""
    from fem.geometry import PlateStator
    from fem.modes import ModeSolverError
    from fem.tuning import tune_plate

    start = PlateStator(
        length_m=args.length_mm * 1e-3,
        width_m=args.width_mm * 1e-3,
        thickness_m=args.thickness_mm * 1e-3,
        electrode_gap_m=args.gap_mm * 1e-3,
    )
    try:
        d = tune_plate(args.target_frequency, fix=args.fix, material=args.material,
                       start=start, model=args.model, refine=args.refine)
    except ModeSolverError as exc:
        raise ValueError(str(exc)) from exc
    if args.json:
        print(json.dumps(d.to_dict()))
        return
    st = d.stator
    print(f"target {d.target_frequency_Hz:g} Hz, material {d.material}, model {d.model}, "
          f"fixed {d.fix}")
    print(f"plate {st.length_m * 1e3:.4f} x {st.width_m * 1e3:.4f} x "
          f"{st.thickness_m * 1e3:.4g} mm (gap {st.electrode_gap_m * 1e3:g} mm)")
    print(f"{'mode':<5}{'f_short (Hz)':>14}{'f_open (Hz)':>14}{'k_eff':>9}")
    for name, m in (("L1", d.L1), ("B2", d.B2)):
        print(f"{name:<5}{m.f_short_Hz:>14.1f}{m.f_open_Hz:>14.1f}{m.k_eff:>9.4f}")
    print(f"|f_L1 - f_B2| / f = {d.relative_mismatch:.2e}, FE solves {d.fe_solves}")
