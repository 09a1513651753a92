"""``lusm simulate``: one stick-slip-separation run on any parameter set."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from rom.sources import SOURCES


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``simulate`` sub-command to the ``lusm`` parser."""
    p = subparsers.add_parser(
        "simulate",
        help="run the contact model (paper Eqs. 4-19) from rest",
        description="Simulate the slider driven by the stator tip: velocity, forces, "
        "stick/slip/separation phases, steady-state metrics.",
    )
    p.add_argument("--voltage", type=float, required=True, help="drive amplitude V0 (V), >= 0")
    p.add_argument("--preload", type=float, required=True, help="preload F_P (N), >= 0")
    p.add_argument("--frequency", default="40e3",
                   help="drive frequency (Hz), or 'auto' for the set's own operating point")
    p.add_argument("--duration", type=float, default=0.05, help="simulated time (s)")
    p.add_argument("--dt", type=float, default=1e-7, help="time step (s), <= 1/(20 f)")
    p.add_argument("--no-ultrasonic-friction", action="store_true",
                   help="use the constant mu_d instead of Eq. 11")
    p.add_argument("--coupling", choices=("paper", "consistent"), default="paper",
                   help="tangential force on B2: eta_T F_T (paper) or -phi_B(l) F_T")
    p.add_argument("--source", choices=SOURCES, default=None,
                   help="parameter set (default table2; fem with --geometry)")
    p.add_argument("--geometry", type=Path, default=None,
                   help="stator TOML file (implies --source fem)")
    p.add_argument("--energy", action="store_true", help="also compute the energy balance")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", type=Path, default=None, metavar="DIR",
                   help="write Figs. 9, 11, 12 and 14 as PNG files into DIR")
    p.set_defaults(func=run)


def load_params(source: str | None, geometry: Path | None):
    """The parameter set named on the command line."""
    if geometry is not None:
        if source not in (None, "fem"):
            raise ValueError(f"--geometry needs --source fem, got --source {source}")
        from rom.from_fem import fem_params_from_file

        return fem_params_from_file(geometry)
    from rom.sources import get_params

    return get_params(source or "table2")


def parse_frequency(text: str, params) -> float:
    """A frequency in Hz, or the set's operating point for 'auto'."""
    if text == "auto":
        from contact.drive import auto_frequency

        return auto_frequency(params)
    try:
        return float(text)
    except ValueError:
        raise ValueError(f"--frequency must be a number (Hz) or 'auto', got {text!r}") from None


def run(args: argparse.Namespace) -> None:
    """Run one simulation and print its summary."""
    from contact.simulate import simulate
    from validation.summaries import simulation_summary

    params = load_params(args.source, args.geometry)
    freq = parse_frequency(args.frequency, params)
    r = simulate(
        params, args.voltage, args.preload, freq,
        duration_s=args.duration, dt_s=args.dt,
        ultrasonic_friction=not args.no_ultrasonic_friction,
        coupling=args.coupling, energy=args.energy,
    )
    summary = simulation_summary(r)
    if args.plot is not None:
        from validation.figures import simulation_figures

        summary["figures"] = [str(p) for p in simulation_figures(r, args.plot)]
    if args.json:
        print(json.dumps(summary, indent=2))
        return
    for key, value in summary.items():
        if isinstance(value, dict):
            continue
        text = f"{value:.6g}" if isinstance(value, float) else str(value)
        print(f"{key:<30} {text}")
    if "energy" in summary:
        e = summary["energy"]
        print(f"{'energy residual (rel.)':<30} {e['relative_residual']:.3g}")
