"""``lusm admittance``: electrical admittance of the driven electrodes (modal superposition).

Parse, call :func:`fem.admittance.plate_admittance` and
:func:`fem.admittance.plot_admittance`, print. No physics here.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def register(subparsers) -> None:
    """Add the ``admittance`` sub-command to the ``lusm`` parser."""
    p = subparsers.add_parser(
        "admittance",
        help="admittance Y(f) of the driven electrodes: resonance/antiresonance, k_eff, PNG",
        description="Admittance of the driven electrodes (others grounded) of the 2D FE plate "
        "by modal superposition with a residual mode; resonance/antiresonance pairs and the "
        "k_eff they imply; |Y| and phase plot.",
    )
    p.add_argument("--f-min", type=float, default=45e3, metavar="HZ", help="band start (Hz)")
    p.add_argument("--f-max", type=float, default=65e3, metavar="HZ", help="band end (Hz)")
    p.add_argument("--points", type=int, default=2001, help="frequency points")
    p.add_argument("--zeta", type=float, default=None,
                   help="one damping ratio for all modes (default: the paper's zeta_L1, "
                   "zeta_B2; 0.01 for other modes)")
    p.add_argument("--electrodes", default=None, metavar="E[,E...]",
                   help="driven electrodes, e.g. 1,4 (default: the stator's drive)")
    p.add_argument("--length-mm", type=float, default=30.0, help="plate length (mm)")
    p.add_argument("--width-mm", type=float, default=7.5, help="plate width (mm)")
    p.add_argument("--thickness-mm", type=float, default=3.0, help="plate thickness (mm)")
    p.add_argument("--gap-mm", type=float, default=0.5, help="electrode gap (mm)")
    p.add_argument("--material", choices=("pzt8", "paper"), default="pzt8")
    p.add_argument("--out", default=".", metavar="DIR", help="output directory (PNG)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def _electrodes(text: str | None) -> tuple[int, ...] | None:
    if text is None:
        return None
    try:
        return tuple(int(t) for t in text.split(","))
    except ValueError as exc:
        raise ValueError(f"--electrodes must be comma-separated numbers, got {text!r}") from exc


def run(args: argparse.Namespace) -> None:
    """Run ``lusm admittance`` with parsed ``args``."""
    from fem.admittance import plate_admittance, plot_admittance
    from fem.geometry import PlateStator

    stator = PlateStator(
        length_m=args.length_mm * 1e-3,
        width_m=args.width_mm * 1e-3,
        thickness_m=args.thickness_mm * 1e-3,
        electrode_gap_m=args.gap_mm * 1e-3,
    )
    res = plate_admittance(stator, args.material, args.f_min, args.f_max, args.points,
                           electrodes=_electrodes(args.electrodes), zeta=args.zeta)
    png = plot_admittance(res, Path(args.out) / "admittance.png")
    if args.json:
        out = res.to_dict()
        out["png"] = str(png)
        print(json.dumps(out))
        return
    p = res.port
    print(f"electrodes {p.electrodes} driven, others grounded; band {args.f_min:g}-"
          f"{args.f_max:g} Hz; {p.frequencies_Hz.size} modes + residual mode at "
          f"{p.f_res_Hz:.0f} Hz")
    print(f"C0 (clamped) {p.C0_F:.4e} F, C_free (static) {p.C_free_F:.4e} F")
    if not res.pairs:
        print("no resonance/antiresonance pair resolved in the band (heavy damping?)")
    print(f"{'mode':<5}{'f_r (Hz)':>12}{'f_a (Hz)':>12}{'k_eff':>9}")
    for q in res.pairs:
        print(f"{q.mode or '-':<5}{q.f_resonance_Hz:>12.1f}{q.f_antiresonance_Hz:>12.1f}"
              f"{q.k_eff:>9.4f}")
    print(f"wrote {png}")
