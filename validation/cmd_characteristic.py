"""``lusm characteristic``: speed-thrust, output power and efficiency from the steady engine."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

from rom.sources import SOURCES

MAX_LOADS = 1000
"""Largest number of loads one call evaluates (work is bounded before it starts)."""


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``characteristic`` sub-command to the ``lusm`` parser."""
    p = subparsers.add_parser(
        "characteristic",
        help="speed-thrust, output power and efficiency curves (steady engine)",
        description="Steady slider velocity against load force, mechanical output power, "
        "electrical input power and efficiency, the no-load velocity and the stall force, "
        "from the averaged steady state (docs/steady.md).",
    )
    p.add_argument("--voltage", type=float, required=True, help="drive amplitude V0 (V), >= 0")
    p.add_argument("--preload", type=float, required=True, help="preload F_P (N), >= 0")
    p.add_argument("--loads", default=None, metavar="START:STOP:STEP",
                   help="load forces (N), e.g. 0:2:0.1; default 21 loads from 0 to the stall "
                   "force")
    p.add_argument("--frequency", default="40e3",
                   help="drive frequency (Hz), or 'auto' for the set's own operating point")
    p.add_argument("--no-ultrasonic-friction", action="store_true",
                   help="use the constant mu_d instead of Eq. 11")
    p.add_argument("--coupling", choices=("paper", "consistent"), default="paper",
                   help="tangential force on B2: eta_T F_T (paper) or -phi_B(l) F_T")
    p.add_argument("--source", choices=SOURCES, default=None,
                   help="parameter set (default table2; fem with --geometry)")
    p.add_argument("--geometry", type=Path, default=None,
                   help="stator TOML file (implies --source fem)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", type=Path, default=None, metavar="DIR",
                   help="write characteristic.png into DIR")
    p.add_argument("--force", action="store_true",
                   help="write --plot into a non-empty folder lusm did not write")
    p.set_defaults(func=run)


def parse_loads(text: str) -> list[float]:
    """``START:STOP:STEP`` (N) as a list of loads, STOP included when on the grid."""
    parts = text.split(":")
    msg = (f"--loads must be START:STOP:STEP in N with finite START <= STOP, STEP > 0 and at "
           f"most {MAX_LOADS} loads, got {text!r}")
    if len(parts) != 3:
        raise ValueError(msg)
    try:
        start, stop, step = (float(x) for x in parts)
    except ValueError:
        raise ValueError(msg) from None
    if not all(math.isfinite(x) for x in (start, stop, step)) or step <= 0 or stop < start:
        raise ValueError(msg)
    n = int(math.floor((stop - start) / step + 1e-9)) + 1
    if n > MAX_LOADS:
        raise ValueError(msg)
    return [start + i * step for i in range(n)]


def _check(args: argparse.Namespace) -> None:
    for name, unit in (("voltage", "V"), ("preload", "N")):
        value = getattr(args, name)
        if not math.isfinite(value) or value < 0:
            raise ValueError(f"--{name} must be a finite number >= 0 {unit}, got {value!r}")


def run(args: argparse.Namespace) -> None:
    """Compute the characteristic and print it."""
    _check(args)
    loads = parse_loads(args.loads) if args.loads is not None else None
    if args.plot is not None:
        from validation.output_set import check_target

        check_target(args.plot, "figures", "--plot", args.force)
    from contact.characteristic import characteristic
    from validation.cmd_simulate import load_params, parse_frequency

    params = load_params(args.source, args.geometry)
    freq = parse_frequency(args.frequency, params)
    char = characteristic(params, args.voltage, args.preload, loads, frequency_Hz=freq,
                          coupling=args.coupling,
                          ultrasonic_friction=not args.no_ultrasonic_friction)
    doc = char.to_dict()
    if args.plot is not None:
        from validation.output_set import output_set
        from validation.report_motor import characteristic_figure

        with output_set(args.plot, "figures", "--plot", args.force) as stage:
            characteristic_figure(char, stage / "characteristic.png")
        doc["figures"] = [str(Path(args.plot) / "characteristic.png")]
    if args.json:
        print(json.dumps(doc, indent=2))
        return
    print(f"{'no-load velocity (m/s)':<26} {char.no_load_velocity_m_s:.6g}")
    print(f"{'stall force (N)':<26} {char.stall_force_N:.6g}")
    print(f"{'load (N)':>10} {'v (m/s)':>12} {'P_in (W)':>11} {'P_out (W)':>11} {'eff.':>8}")
    for row in doc["curve"]:
        print(f"{row['load_N']:10.4g} {row['velocity_m_s']:12.5g} {row['input_power_W']:11.4g} "
              f"{row['output_power_W']:11.4g} {row['efficiency']:8.4f}")
