"""``lusm characteristic``: speed-thrust, output power and efficiency from the steady engine."""

from __future__ import annotations

import argparse
import math

from validation import limits
from validation.options import (
    add_drive_options,
    add_motor_options,
    add_output_options,
    check_steady_work,
    coupling_of,
    figure_set,
    known_frequency,
    motor_params_of,
    moved,
    output_folder,
    parse_frequency,
    print_json,
    warn,
    warn_drive,
)


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``characteristic`` sub-command to the ``lusm`` parser."""
    p = subparsers.add_parser(
        "characteristic",
        help="speed-thrust, output power and efficiency curves (steady engine)",
        description="Steady slider velocity against load force, mechanical output power, "
        "electrical input power and efficiency, the no-load velocity and the stall force, "
        "from the steady engine, averaged (--accuracy fast) or on the finite-mass motor "
        "(--accuracy exact) (docs/steady.md).",
    )
    add_drive_options(p, time_steps=False, voltage_list=True)  # steady: no time step
    p.add_argument("--loads", default=None, metavar="START:STOP:STEP",
                   help="load forces (N), e.g. 0:2:0.1; default 21 loads from 0 to the stall "
                   "force")
    p.add_argument("--accuracy", choices=("fast", "exact"), default="fast",
                   help="fast: the averaged steady state, all loads from one set of orbits "
                   "(default); exact: the finite-mass motor from rest at every load "
                   "(docs/steady.md)")
    add_motor_options(p)
    add_output_options(p, folder="--plot", folder_help="write characteristic.png into DIR")
    p.set_defaults(func=run)


def parse_loads(text: str) -> list[float]:
    """``START:STOP:STEP`` (N) as a list of loads, STOP included when on the grid.

    At most :data:`validation.limits.MAX_GRID_POINTS` loads (times ``LUSM_MAX_WORK``), each
    within the load range of ``lusm simulate --load-N``.
    """
    from validation.ranges import parse_range

    loads = parse_range(text, "--loads", allow_list=False)
    top = limits.PRELOAD_N[1]
    if max(abs(float(x)) for x in loads) > top:
        raise ValueError(f"--loads must lie in [{-top:g}, {top:g}] N (the range of "
                         f"simulate --load-N), got {text!r}")
    return [float(x) for x in loads]


def run(args: argparse.Namespace) -> None:
    """Compute the characteristic(s) and print them."""
    loads = parse_loads(args.loads) if args.loads is not None else None
    plot = output_folder(args, "characteristic", "--plot")
    voltages = args.voltage  # a tuple: --voltage takes A,B,...
    warn_drive(max(voltages), args.preload)
    known_frequency(args.frequency)  # a bad number refused before any work
    params, damping_from = motor_params_of(args, args.source)
    coupling, coupling_from = coupling_of(args, params)
    freq = parse_frequency(args.frequency, params)
    check_steady_work(len(voltages) * (len(loads) if loads else 21), params, freq, coupling,
                      "loads x voltages", "--loads" if loads else "--frequency")

    from contact.characteristic import characteristic
    from validation.summaries import coupling_line, damping_line, damping_summary

    chars = [characteristic(params, v, args.preload, loads, frequency_Hz=freq,
                            coupling=coupling,
                            ultrasonic_friction=not args.no_ultrasonic_friction,
                            accuracy=args.accuracy, progress=True)
             for v in voltages]
    if args.accuracy == "fast":
        _warn_below_ripple(params, chars)
    docs = [c.to_dict() for c in chars]
    for d in docs:
        d["damping"] = damping_summary(params, damping_from)
        d["coupling"], d["coupling_from"] = coupling, coupling_from
    # one voltage: the characteristic itself; several: {"voltages_V", "characteristics"}
    doc = docs[0] if len(docs) == 1 else {"voltages_V": list(voltages),
                                          "characteristics": docs}
    if plot is not None:
        from validation.report_motor import characteristic_figure

        with figure_set(plot, "characteristic", "--plot", args.force) as stage:
            path = characteristic_figure(chars if len(chars) > 1 else chars[0],
                                         stage / "characteristic.png")
            doc["figures"] = moved([path], stage, plot)
    if args.json:
        print_json(doc, indent=2)
        return
    for v, char, d in zip(voltages, chars, docs, strict=True):
        if len(voltages) > 1:
            print(f"--- {v:g} V")
        print(f"{'no-load velocity (m/s)':<26} {char.no_load_velocity_m_s:.6g}")
        print(f"{'stall force (N)':<26} {char.stall_force_N:.6g}")
        print(f"{'accuracy':<26} {char.accuracy}")
        low, high = char.holding_range_N
        if math.isfinite(low) and math.isfinite(high):
            print(f"{'holds loads (N)':<26} {low:.4g} to {high:.4g}")
        print(f"{'load (N)':>10} {'v (m/s)':>12} {'P_in (W)':>11} {'P_out (W)':>11} "
              f"{'eff.':>8}")
        for row in d["curve"]:
            if math.isnan(row["velocity_m_s"]):  # no steady state from rest
                print(f"{row['load_N']:10.4g} {'runs away':>12}")
                continue
            print(f"{row['load_N']:10.4g} {row['velocity_m_s']:12.5g} "
                  f"{row['input_power_W']:11.4g} {row['output_power_W']:11.4g} "
                  f"{row['efficiency']:8.4f}")
    print(damping_line(params, damping_from))
    print(coupling_line(coupling, coupling_from))


def _warn_below_ripple(params, chars) -> None:
    """Warn where the averaged no-load velocity is below the slider's velocity ripple: there
    the slider is not slow against the drive period, the averaging behind ``--accuracy fast``
    does not hold, and the finite-mass motor can do something else (at 20 Hz the fast level
    gave 1.8e-6 m/s and a 1.18 N stall force where the exact one holds the slider)."""
    from contact.steady import ripple_scale

    for c in chars:
        ripple = ripple_scale(params, c.op, params.mu_d)
        v = abs(float(c.no_load_velocity_m_s))
        if 0.0 < v < ripple:
            warn(f"at {c.op.voltage_V:g} V and {c.op.frequency_Hz:g} Hz the averaged no-load "
                 f"velocity {v:.3g} m/s is below the slider's velocity ripple (about "
                 f"{ripple:.2g} m/s per drive period): the averaging behind --accuracy fast "
                 "does not hold; --accuracy exact runs the finite-mass motor")
