"""``lusm map``: stick-slip map over voltage x preload (paper Figs. 18-19)."""

from __future__ import annotations

import argparse

from lusm import limits
from lusm.errors import LusmError
from lusm.messages import warn, warn_unused
from lusm.options import (
    Motor,
    add_contact_options,
    add_drive_options,
    check_run_size,
    check_steady_work,
    check_steps,
    integer,
    print_json,
    resolve_drive,
    write_figures,
)

HELP = "stick-slip map over voltage x preload (Figs. 18-19)"
DESCRIPTION = "Classify the steady motion on a voltage x preload grid, in parallel."


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm map``."""
    p.add_argument("--voltages", default="50:450:50",
                   help=f"V0 grid (V), start:stop:step or a comma list, in "
                   f"[0, {limits.VOLTAGE_V[1]:g}]")
    p.add_argument("--preloads", default="10:26:2",
                   help=f"F_P grid (N), start:stop:step or a comma list, in "
                   f"[0, {limits.PRELOAD_N[1]:g}]")
    add_drive_options(p, required=False)
    p.add_argument("--method", choices=("steady", "transient"), default="steady",
                   help="steady: each point's steady states found directly, every stable "
                   "branch reported (docs/steady.md; --duration and --dt serve only the "
                   "transient of a point it cannot decide); transient: "
                   "a run from rest of --duration per point (the paper's way)")
    p.add_argument("--accuracy", choices=("fast", "exact"), default="exact",
                   help="steady engine level: fast (averaging, slider mass -> infinity) or "
                   "exact (finite slider mass, start from rest decided on the full model; the "
                   "default)")
    p.add_argument("--workers", type=integer("--workers", *limits.WORKERS), default=None,
                   help="threads (default: all cores)")
    from lusm.uncertainty import add_uncertainty_option

    add_uncertainty_option(p, "the speed at each point (with --method steady); the draws "
                           "times the points must stay within the steady map's bounds")
    add_contact_options(p, folder_help="write the map PNG into DIR", friction_note=" (Fig. 19)")


def _grid(text: str, option: str, bounds: tuple[float, float], unit: str):
    from lusm.ranges import parse_range

    return parse_range(text, option, bounds=bounds, unit=unit)


def _check_size(args: argparse.Namespace, volts, loads, frequency_Hz: float) -> None:
    from lusm.options import time_step_of

    # the steady engine takes its own step; --dt serves only the transient of an undecided
    # point. A typed one gets the transients' range all the same (--dt 1e-3 is refused, not
    # replaced by T/20 without a word); the default is within it
    why = (" (with --method steady it serves the transient of a point the steady engine "
           "cannot decide)" if args.method == "steady" else "")
    args.dt = time_step_of(args.dt, frequency_Hz, why)  # default: whole steps per period
    if args.method == "transient":
        check_run_size(args.duration, args.dt, frequency_Hz, runs=volts.size * loads.size)
    else:
        check_steps(args.duration, args.dt)


def run(args: argparse.Namespace) -> None:
    """Compute and print the map."""
    if args.method == "transient":
        warn_unused(("--accuracy", "--rest"), "--method transient runs every point from "
                    "rest, without the steady engine")
    elif args.accuracy == "fast":
        warn_unused(("--rest",), "it sets how --accuracy exact decides the start from rest")
    volts = _grid(args.voltages, "--voltages", limits.VOLTAGE_V, "V")
    loads = _grid(args.preloads, "--preloads", limits.PRELOAD_N, "N")
    if args.method == "steady" and volts.size * loads.size > limits.work_bound(
            limits.MAX_STEADY_POINTS):
        raise LusmError(
            f"--voltages x --preloads give {volts.size * loads.size} points; a steady map "
            f"takes at most {limits.work_bound(limits.MAX_STEADY_POINTS)} "
            f"({limits.more_work_hint()})", "--voltages")
    _check_uncertainty_size(args, volts.size * loads.size)
    # the 0 V / 0 N case only when the map is that single point
    plot, motor = resolve_drive(args, [float(volts.max())], float(loads.max()),
                                lambda f: _check_size(args, volts, loads, f),
                                voltage_option="--voltages", preload_option="--preloads")
    if args.method == "steady":  # a point's cost grows as the drive frequency falls
        check_steady_work(volts.size * loads.size, motor.params, motor.frequency_Hz,
                          motor.coupling, "points", "--voltages")
    cal = None
    if args.uncertainty is not None:
        from lusm.uncertainty import calibration_of, check_work

        cal = calibration_of(args, motor)
        check_work(args, volts.size * loads.size, motor, "points")
    m = _solve(args, motor, volts, loads)
    _warn_limits(m)
    summary = _summary(args, motor, m)
    if cal is not None:
        summary["uncertainty"] = _band(args, cal, motor, volts, loads)
    if plot is not None:
        summary["figures"] = _plot(args, motor, m)
        # "figure", the map's one path, kept for the scripts that read it
        summary["figure"] = summary["figures"][0]
    if args.json:
        print_json(summary, indent=2)
        return
    _print(args, motor, m)
    if cal is not None:
        _print_band(m, summary["uncertainty"])
    for f in summary.get("figures", []):
        print(f"wrote {f}")


def _check_uncertainty_size(args: argparse.Namespace, points: int) -> None:
    """Refuse, before any work, ``--uncertainty`` with a transient map or with more draws
    times points than a steady map may have (:data:`lusm.limits.MAX_STEADY_POINTS`)."""
    if args.uncertainty is None:
        return
    if args.method != "steady":
        raise LusmError("--uncertainty needs --method steady (a transient map per parameter "
                        "set drawn is too slow)", "--uncertainty")
    top = limits.work_bound(limits.MAX_STEADY_POINTS)
    fewer = (f"at most {top // points} draws here, or fewer points" if top // points >= 2
             else "fewer --voltages x --preloads points")
    if args.uncertainty * points > top:
        raise LusmError(f"--uncertainty {args.uncertainty} draws x {points} points = "
                        f"{args.uncertainty * points}, above a steady map's {top} points "
                        f"({fewer}; {limits.more_work_hint()})", "--uncertainty")


def _band(args: argparse.Namespace, cal, motor: Motor, volts, loads) -> dict:
    """The map's ``uncertainty``: the speed's band at every point over ``--uncertainty``
    parameter sets drawn from the calibration (:func:`calibration.bands.map_band`), with
    the relative standard deviation (std over |mean|)."""
    import numpy as np

    from calibration.bands import map_band
    from contact.options import SimulationOptions
    from lusm.uncertainty import band_json, run_band

    opts = SimulationOptions(duration_s=args.duration, dt_s=args.dt,
                             ultrasonic_friction=not args.no_ultrasonic_friction,
                             coupling=motor.coupling)
    band = run_band(args, lambda step: map_band(
        cal, motor.params, volts, loads, motor.frequency_Hz, opts, samples=args.uncertainty,
        workers=args.workers, progress=step, accuracy=args.accuracy, rest=args.rest))
    doc = band_json(band, velocity_m_s=band)
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = band.std / np.abs(band.mean)
    doc["velocity_relative_std"] = [[None if not np.isfinite(x) else float(x) for x in row]
                                    for row in rel]
    return doc


def _print_band(m, u: dict) -> None:
    """The speed's standard deviation at every point, as the speed table (mm/s)."""
    from lusm.uncertainty import drawn_line

    print("slider velocity standard deviation (mm/s), V0 (V) \\ F_P (N)")
    print(f"{'':>8}  " + " ".join(f"{f:>9g}" for f in m.preloads_N))
    for i, v in enumerate(m.voltages_V):
        print(f"{v:>8g}  " + " ".join(f"{'nan':>9}" if x is None else f"{x * 1e3:>9.4g}"
                                      for x in u["velocity_m_s"]["std"][i]))
    print(drawn_line(u) + " (JSON 'uncertainty': mean, std, 2.5/97.5 % quantiles, "
          "relative std per point)")


def _solve(args: argparse.Namespace, motor: Motor, volts, loads):
    """The map (:func:`contact.maps.stick_slip_map`), its unsettled points said."""
    from contact.maps import stick_slip_map
    from contact.options import SimulationOptions

    opts = SimulationOptions(duration_s=args.duration, dt_s=args.dt,
                             ultrasonic_friction=not args.no_ultrasonic_friction,
                             coupling=motor.coupling)
    m = stick_slip_map(motor.params, volts, loads, motor.frequency_Hz, opts,
                       workers=args.workers, progress=True, method=args.method,
                       accuracy=args.accuracy, rest=args.rest)
    if m.method == "transient" and not m.settled.all():  # as simulate warns of one run
        import numpy as np  # here: lusm map --help loads no NumPy

        pts = [f"{float(m.voltages_V[i]):g} V/{float(m.preloads_N[j]):g} N"
               for i, j in zip(*np.nonzero(~m.settled), strict=True)]
        warn(f"{len(pts)} point(s) not settled within --duration {args.duration:g} s ("
             + ", ".join(pts[:5]) + (", ..." if len(pts) > 5 else "") + "): their velocity "
             "is not the steady one (JSON 'settled'); give a longer --duration, or --method "
             "steady")
    return m


def _warn_limits(m) -> None:
    """One line, before the results, naming the points beyond a limit of the ceramic and the
    worst of them (each point's limits are in --json, the points marked on --plot)."""
    if m.limits is None:
        return
    over = [(float(m.voltages_V[i]), float(m.preloads_N[j]), m.limits[i, j])
            for i in range(m.voltages_V.size) for j in range(m.preloads_N.size)
            if m.limits[i, j] is not None and m.limits[i, j].exceeded()]
    if not over:
        return
    v, f, worst = max(over, key=lambda p: max(p[2].ratio(q) for q in p[2].exceeded()))
    line = worst.warning(f"at {len(over)} of {m.limits.size} points (JSON 'limits'); the "
                         f"worst, {v:g} V/{f:g} N")
    warn(line)


def _summary(args: argparse.Namespace, motor: Motor, m) -> dict:
    """The map's JSON: the points, the damping, coupling and frequency, the engine's level."""
    from validation.summaries import damping_summary, map_summary

    summary = map_summary(m)
    summary["damping"] = damping_summary(motor.params, motor.damping_from)
    summary["coupling"], summary["coupling_from"] = motor.coupling, motor.coupling_from
    summary["frequency_Hz"] = motor.frequency_Hz
    if m.method == "steady":  # the engine's level, and how the start from rest was decided
        summary["accuracy"] = args.accuracy
        if args.accuracy == "exact":
            summary["rest"] = args.rest
    return summary


def _plot(args: argparse.Namespace, motor: Motor, m) -> list[str]:
    """Draw the map into the ``--plot`` folder; returns the figures' paths."""
    from validation.figures import set_label
    from validation.figures import stick_slip_map as plot_map

    name = "fig19_map_constant_mu.png" if args.no_ultrasonic_friction else "fig18_map.png"
    # the method in the title: a transient map with unsettled points is not the settled
    # steady one
    how = (f"steady engine ({args.accuracy} level)" if m.method == "steady" else
           f"transients of {args.duration:g} s from rest"
           + ("" if m.settled.all() else f", {int((~m.settled).sum())} not settled"))
    title = f"{set_label(motor.params.source)}, {motor.frequency_Hz / 1e3:.4g} kHz, {how}"
    return write_figures(args, "--plot",
                         lambda stage: [plot_map(m, stage / name, title)])


def _print(args: argparse.Namespace, motor: Motor, m) -> None:
    """The motion classes and the speeds as tables, and what the map rests on."""
    from validation.summaries import coupling_line, damping_line

    params, damping_from, freq = motor.params, motor.damping_from, motor.frequency_Hz
    coupling, coupling_from = motor.coupling, motor.coupling_from
    short = {"slip-separation": "o", "stick-slip": "*", "stick-slip-separation": "S",
             "pure-stick": "#", "pure-slip": "-", "separated": "."}
    print("V0 (V) \\ F_P (N)")
    print(f"{'':>8}  " + " ".join(f"{f:>5g}" for f in m.preloads_N))
    for i, v in enumerate(m.voltages_V):
        print(f"{v:>8g}  " + " ".join(f"{short.get(c, '?'):>5}" for c in m.motion[i]))
    print("legend: " + ", ".join(f"{s} {c}" for c, s in short.items()))
    # the speeds too, as --json gives them: mm/s, 4 significant digits
    print("slider velocity (mm/s), V0 (V) \\ F_P (N)")
    print(f"{'':>8}  " + " ".join(f"{f:>9g}" for f in m.preloads_N))
    for i, v in enumerate(m.voltages_V):
        print(f"{v:>8g}  " + " ".join(f"{x * 1e3:>9.4g}" for x in m.velocity_m_s[i]))
    print(damping_line(params, damping_from))
    print(coupling_line(coupling, coupling_from))
    auto_note = " (auto: the set's own operating point)" if motor.frequency_auto else ""
    print(f"frequency {freq:.6g} Hz{auto_note}")
    counts = ", ".join(f"{c} {n}" for c, n in m.counts().items() if n)
    print(f"points: {counts}; wall time {m.wall_time_s:.2f} s ({m.method}"
          + (f", {args.accuracy})" if m.method == "steady" else f", {args.duration:g} s runs)"))
    _print_non_monotone(m)
    if m.method == "steady":
        multi = [(float(m.voltages_V[i]), float(m.preloads_N[j])) for i, j in m.several_branches()]
        if multi:
            print("several stable steady states (the table shows the one reached from rest): "
                  + ", ".join(f"{v:g} V/{f:g} N" for v, f in multi))
        undecided = int(m.fallback.sum())
        if undecided:
            from contact.maps import fallback_duration_s

            # the duration the fallback transients ran, --duration's where longer than 0.3 s
            print(f"undecided by the steady engine (creep, no periodic tip orbit): {undecided} "
                  f"point(s), taken from {fallback_duration_s(args.duration, freq):g} s "
                  "transients (see --json)")


def _print_non_monotone(m) -> None:
    """Say the neighbours whose speeds run against the trend (a higher voltage slower, a
    higher preload faster, by more than :data:`contact.maps.NON_MONOTONE_FACTOR` times): creep
    level or another branch, not a trend (``--plot`` joins them with red dashes)."""
    from contact.maps import NON_MONOTONE_FACTOR

    def point(ij) -> str:
        i, j = ij
        return (f"{m.voltages_V[i]:g} V/{m.preloads_N[j]:g} N "
                f"{abs(m.velocity_m_s[i, j]) * 1e3:.3g} mm/s")

    pairs = m.non_monotone_pairs()
    if pairs:
        print(f"speeds against the trend (x{NON_MONOTONE_FACTOR:g} or more between "
              "neighbours; creep level or another branch): "
              + "; ".join(f"{point(a)} vs {point(b)}" for a, b in pairs))
