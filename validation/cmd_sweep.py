"""``lusm sweep``: L1 and B2 against the plate width or length (crossing diagram, PNG).

Parse the ``a:b:step`` range (mm, :mod:`validation.ranges`), call
:func:`fem.sweep.sweep_dimension` and :func:`fem.sweep.plot_sweep`, print. No physics here.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from validation.ranges import parse_range


def register(subparsers) -> None:
    """Add the ``sweep`` sub-command to the ``lusm`` parser."""
    p = subparsers.add_parser(
        "sweep",
        help="L1/B2 frequencies against the plate width or length (crossing diagram PNG)",
        description="Sweep one plate dimension, identify L1 and B2 by shape at each point and "
        "plot their short-circuit frequencies (the crossing/veering diagram).",
    )
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--width-mm", metavar="A:B:STEP", help="sweep the width (mm)")
    g.add_argument("--length-mm", metavar="A:B:STEP", help="sweep the length (mm)")
    p.add_argument("--length", type=float, default=30.0, dest="fixed_length_mm",
                   help="length when sweeping the width (mm)")
    p.add_argument("--width", type=float, default=7.5, dest="fixed_width_mm",
                   help="width when sweeping the length (mm)")
    p.add_argument("--thickness-mm", type=float, default=3.0, help="thickness (mm)")
    p.add_argument("--gap-mm", type=float, default=0.5, help="electrode gap (mm)")
    p.add_argument("--material", choices=("pzt8", "paper"), default="pzt8")
    p.add_argument("--out", default=".", metavar="DIR", help="output directory (PNG)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> None:
    """Run ``lusm sweep`` with parsed ``args``."""
    from fem.geometry import PlateStator
    from fem.sweep import plot_sweep, sweep_dimension

    parameter = "width" if args.width_mm is not None else "length"
    option = "--width-mm" if parameter == "width" else "--length-mm"
    values = 1e-3 * parse_range(args.width_mm if parameter == "width" else args.length_mm,
                                option, allow_list=False, positive=True)
    base = PlateStator(
        length_m=args.fixed_length_mm * 1e-3,
        width_m=args.fixed_width_mm * 1e-3,
        thickness_m=args.thickness_mm * 1e-3,
        electrode_gap_m=args.gap_mm * 1e-3,
    )
    res = sweep_dimension(parameter, values, base, args.material, progress=not args.json)
    png = plot_sweep(res, Path(args.out) / f"sweep_{parameter}.png")
    if args.json:
        out = res.to_dict()
        out["png"] = str(png)
        print(json.dumps(out))
        return
    print(f"{parameter} (mm){'L1 short (Hz)':>16}{'B2 short (Hz)':>16}")
    for v, fl, fb in zip(res.values_m, res.f_L1_short_Hz, res.f_B2_short_Hz, strict=True):
        print(f"{v * 1e3:>10.4g}{fl:>16.1f}{fb:>16.1f}")
    for xc in res.crossings_m():
        print(f"L1/B2 crossing at {parameter} {xc * 1e3:.4f} mm")
    print(f"wrote {png}")
