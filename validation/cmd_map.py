"""``lusm map``: stick-slip map over voltage x preload (paper Figs. 18-19)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from rom.sources import SOURCES
from validation.ranges import parse_range


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``map`` sub-command to the ``lusm`` parser."""
    p = subparsers.add_parser(
        "map",
        help="stick-slip map over voltage x preload (Figs. 18-19)",
        description="Classify the steady motion on a voltage x preload grid, in parallel.",
    )
    p.add_argument("--voltages", default="50:450:50", help="V0 grid (V), start:stop:step")
    p.add_argument("--preloads", default="10:26:2", help="F_P grid (N), start:stop:step")
    p.add_argument("--frequency", type=float, default=40e3, help="drive frequency (Hz)")
    p.add_argument("--duration", type=float, default=0.05, help="simulated time per point (s)")
    p.add_argument("--dt", type=float, default=1e-7, help="time step (s)")
    p.add_argument("--no-ultrasonic-friction", action="store_true",
                   help="use the constant mu_d instead of Eq. 11 (Fig. 19)")
    p.add_argument("--source", choices=SOURCES, default="table2", help="parameter set")
    p.add_argument("--workers", type=int, default=None, help="threads (default: all cores)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", type=Path, default=None, metavar="DIR", help="write the map PNG")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> None:
    """Compute and print the map."""
    from contact.maps import stick_slip_map
    from contact.simulate import SimulationOptions
    from rom.sources import get_params
    from validation.summaries import map_summary

    volts = parse_range(args.voltages, "--voltages")
    loads = parse_range(args.preloads, "--preloads")
    params = get_params(args.source)
    opts = SimulationOptions(duration_s=args.duration, dt_s=args.dt,
                             ultrasonic_friction=not args.no_ultrasonic_friction)
    m = stick_slip_map(params, volts, loads, args.frequency, opts, workers=args.workers)
    summary = map_summary(m)
    if args.plot is not None:
        from validation.figures import stick_slip_map as plot_map

        name = "fig19_map_constant_mu.png" if args.no_ultrasonic_friction else "fig18_map.png"
        from validation.figures import set_label

        summary["figure"] = str(plot_map(m, args.plot / name, set_label(params.source)))
    if args.json:
        print(json.dumps(summary, indent=2))
        return
    short = {"slip-separation": "o", "stick-slip": "*", "stick-slip-separation": "S",
             "pure-stick": "#", "pure-slip": "-"}
    print("V0 \\ F_P " + " ".join(f"{f:>5g}" for f in m.preloads_N))
    for i, v in enumerate(m.voltages_V):
        print(f"{v:>8g}  " + " ".join(f"{short[c]:>5}" for c in m.motion[i]))
    print("legend: " + ", ".join(f"{s} {c}" for c, s in short.items()))
    print(f"counts: {m.counts()}  wall time {m.wall_time_s:.2f} s")
