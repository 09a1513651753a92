"""``lusm simulate``: one stick-slip-separation run on any parameter set."""

from __future__ import annotations

import argparse

from lusm import limits
from lusm.errors import LusmError
from lusm.messages import warn, warn_unused
from lusm.options import (
    PAPER_DURATION_S,
    Motor,
    add_contact_options,
    add_drive_options,
    check_run_size,
    check_steady_frequency,
    default_duration_s,
    print_json,
    real,
    resolve_drive,
    time_step_of,
    write_figures,
)

HELP = "run the contact model (paper Eqs. 4-19) from rest"
DESCRIPTION = """\
Simulate the slider driven by the stator tip: velocity, forces, stick/slip/separation phases,
steady-state metrics.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm simulate``."""
    add_drive_options(p, voltage_list=True, settling_duration=True)
    p.add_argument("--energy", action="store_true", help="also compute the energy balance")
    p.add_argument("--load-N", dest="load_N", default=0.0,
                   type=real("--load-N", "N", -limits.PRELOAD_N[1], limits.PRELOAD_N[1]),
                   help="external load on the slider (N), a constant force against the "
                   "forward (+x) direction: it opposes a forward motor and assists one "
                   "that drives backward; negative pushes forward")
    p.add_argument("--steady", action="store_true",
                   help="the steady state from rest found directly (docs/steady.md) instead "
                   "of a transient; no figures")
    from lusm.uncertainty import add_uncertainty_option

    add_uncertainty_option(p, "the steady speed (with --steady)")
    add_contact_options(p, folder_help="write Figs. 9, 11, 12 and 14 as PNG files into DIR")


def _refuse_combinations(args: argparse.Namespace) -> None:
    """Refuse the options that do not go together, before any work."""
    voltages = args.voltage
    if args.plot is not None and len(voltages) > 1:
        raise LusmError("--plot takes one --voltage (one set of figures per run); got "
                        f"{len(voltages)} voltages", "--plot")
    if args.plot is not None and args.steady:
        raise LusmError("--plot needs a transient (no time trace with --steady)", "--plot")
    if args.energy and args.steady:
        raise LusmError("--energy needs a transient (use lusm characteristic for the power "
                        "balance of the steady state)", "--energy")
    if args.uncertainty is not None and not args.steady:
        raise LusmError("--uncertainty needs --steady (a transient per parameter set drawn "
                        "is too slow)", "--uncertainty")
    if not args.steady:
        warn_unused(("--rest",), "it sets how --steady decides the start from rest")


def run(args: argparse.Namespace) -> None:
    """Run one simulation per ``--voltage`` (one parameter set for all) and print them."""
    voltages = args.voltage  # a tuple: --voltage takes A,B,...
    _refuse_combinations(args)
    typed_dt = args.dt  # the text typed, checked at the frequency in force

    def check_size(frequency_Hz: float) -> None:
        # --steady takes any positive step and uses neither --duration nor --dt
        args.dt = time_step_of(typed_dt, frequency_Hz, used=not args.steady)
        if not args.steady and args.duration is not None:  # a default waits for the set
            check_run_size(args.duration, args.dt, frequency_Hz)

    typed_duration = args.duration is not None
    plot, motor = resolve_drive(args, voltages, args.preload, check_size, load_N=args.load_N)
    params, damping_from, freq = motor.params, motor.damping_from, motor.frequency_Hz
    if args.steady and not typed_duration:
        args.duration = PAPER_DURATION_S  # unused: the steady engine takes its own run length
    elif not typed_duration:
        args.duration = default_duration_s(params, voltages, args.preload, freq, args.dt,
                                           args.load_N)
        check_run_size(args.duration, args.dt, freq)
    coupling, coupling_from = motor.coupling, motor.coupling_from
    if args.steady:
        # the range characteristic and map say (the engine's own refusal has no range)
        check_steady_frequency(params, freq, coupling)
        # said once --dt is known to be a number: a refusal is then the one line
        warn_unused(("--duration", "--dt"), "--steady takes its own step and run length")
    # how the not-settled warning names the run length
    args.duration_said = "--duration" if typed_duration else "the default duration"
    cal = None
    if args.uncertainty is not None:
        from lusm.uncertainty import calibration_of, check_work

        cal = calibration_of(args, motor)
        check_work(args, len(voltages), motor, "voltages")

    from contact.errors import RunawayError
    from validation.summaries import (
        damping_summary,
        runaway_summary,
    )

    summaries = []
    for v in voltages:
        try:
            summary = _simulate(args, v, params, freq, coupling, plot)
        except RunawayError as exc:
            if len(voltages) == 1:
                raise
            # a list is a sweep: the voltages the motor cannot hold the load at are answers
            # too (as the loads of lusm characteristic), not the end of the command; with
            # every key the other runs carry (null where no steady state has the value)
            summary = runaway_summary(params, v, args.preload, freq, args.load_N, coupling,
                                      not args.no_ultrasonic_friction, exc.reason)
            summary["limits"] = None  # no steady operating point, as the others' key says
        summary["damping"] = damping_summary(params, damping_from)
        summary["coupling"], summary["coupling_from"] = coupling, coupling_from
        summaries.append(summary)
    if cal is not None:
        _add_band(args, cal, motor, summaries)
    if args.json:
        doc = summaries[0] if len(summaries) == 1 else {"voltages_V": list(voltages),
                                                        "runs": summaries}
        print_json(doc, indent=2)
        return
    for v, summary in zip(voltages, summaries, strict=True):
        if len(voltages) > 1:
            print(f"--- {v:g} V")
        _print_one(summary, motor)
    if cal is not None:
        from lusm.uncertainty import drawn_line

        print(drawn_line(summaries[0]["uncertainty"]))


def _add_band(args: argparse.Namespace, cal, motor: Motor, summaries: list[dict]) -> None:
    """Each run's ``uncertainty``: the band of its steady speed over ``--uncertainty``
    parameter sets drawn from the calibration (:func:`calibration.bands.speed_band`)."""
    from calibration.bands import speed_band
    from lusm.uncertainty import band_json, run_band

    band = run_band(args, lambda step: speed_band(
        cal, motor.params, args.voltage, args.preload, motor.frequency_Hz,
        samples=args.uncertainty, progress=step, load_N=args.load_N, coupling=motor.coupling,
        ultrasonic_friction=not args.no_ultrasonic_friction, rest=args.rest))
    for k, summary in enumerate(summaries):
        summary["uncertainty"] = band_json(band, velocity_m_s=band.part(k))


def _print_one(summary: dict, motor: Motor) -> None:
    """One run's summary as ``key value`` lines, its branches, damping, coupling, energy
    balance and figures."""
    from lusm.physical_limits import print_limits
    from validation.summaries import coupling_line, damping_line

    for key, value in summary.items():
        if isinstance(value, dict | list) or value is None:
            continue  # nested tables, and what the steady engine has not (run length, ...)
        text = f"{value:.6g}" if isinstance(value, float) else str(value)
        print(f"{key:<30} {text}")
    for b in summary.get("branches") or ():
        # every stable steady state, as the JSON has them, also the ones a start from rest
        # does not reach
        print(f"{'branch (from rest)' if b['from_rest'] else 'branch':<30} "
              + branch_text(b))
    print_limits(summary.get("limits"))
    print(damping_line(motor.params, motor.damping_from))
    print(coupling_line(motor.coupling, motor.coupling_from))
    if "energy" in summary:
        # every term of the balance, as --json gives them, not the residual alone
        e = summary["energy"]
        for key, value in e.items():
            if key != "relative_residual":
                print(f"{'energy ' + key:<30} {value:.6g}")
        print(f"{'energy residual (rel.)':<30} {e['relative_residual']:.3g}")
    for f in summary.get("figures", []):
        print(f"wrote {f}")
    if "uncertainty" in summary:
        from lusm.uncertainty import band_text

        print(f"{'velocity band (m/s)':<30} "
              + band_text(summary["uncertainty"]["velocity_m_s"], fmt=".6g"))


def branch_text(b: dict) -> str:
    """One stable steady state of ``--steady`` (a :func:`validation.summaries.branch_summary`)
    in words: ``'0.00146359 m/s, stick-slip, period 1'``."""
    period = f"period {b['k']}" if b["k"] else "no short period (a long mean)"
    return (f"{b['velocity_m_s']:.6g} m/s, {b['motion']}, {period}"
            + (", slider held" if b["held"] else ""))


def _simulate(args: argparse.Namespace, voltage_V: float, params, freq: float, coupling: str,
              plot) -> dict:
    """One run at ``voltage_V``: its summary (and its figures when ``plot`` is a folder)."""
    import warnings

    from contact.simulate import simulate
    from contact.steady.runaway import RunawayWarning
    from validation.summaries import simulation_summary

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RunawayWarning)
        r = simulate(
            params, voltage_V, args.preload, freq,
            duration_s=args.duration, dt_s=args.dt,
            ultrasonic_friction=not args.no_ultrasonic_friction,
            coupling=coupling, energy=args.energy, load_N=args.load_N,
            method="steady" if args.steady else "event", rest=args.rest,
        )
    for w in caught:  # said as every warning is (the one-line form names --load-N)
        warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    # a runaway is why the run did not settle: its warning replaces the "not settled" one,
    # and its reason is the run's runs_away, as a --steady list's runaway says it
    runaway = next((str(w.message) for w in caught if issubclass(w.category, RunawayWarning)),
                   None)
    summary = simulation_summary(r, runs_away=runaway)
    from contact.operating_limits import simulation_limits
    from lusm.physical_limits import limits_json, warn_beyond

    # a slider that runs away is at no steady operating point: no limits to say
    lims = None if runaway is not None else simulation_limits(r)
    warn_beyond(lims, f"at {voltage_V:g} V, {args.preload:g} N, {freq:.6g} Hz")
    summary["limits"] = limits_json(lims)
    if not args.steady and not r.steady.settled:
        if runaway is None:
            st = r.steady
            warn(f"at {voltage_V:g} V the slider has not settled within {args.duration_said} "
                 f"{args.duration:g} s (the last window's mean velocity {st.velocity_m_s:.4g} "
                 f"m/s, an earlier one's {st.previous_velocity_m_s:.4g} m/s): the printed "
                 "velocity is not the steady one; give a longer --duration, or --steady")
    if plot is not None:
        from validation.figures import simulation_figures

        summary["figures"] = write_figures(args, "--plot",
                                           lambda stage: simulation_figures(r, stage))
    return summary
