"""``lusm characteristic``: speed-thrust, output power and efficiency from the steady engine."""

from __future__ import annotations

import argparse
import math

from lusm import limits
from lusm.messages import warn, warn_unused
from lusm.options import (
    add_contact_options,
    add_drive_options,
    check_steady_work,
    print_json,
    resolve_drive,
    write_figures,
)

HELP = "speed-thrust, output power and efficiency curves (steady engine)"
DESCRIPTION = """\
Steady slider velocity against load force, mechanical output power, electrical input power and
efficiency, the no-load velocity and the stall force, from the steady engine, averaged
(--accuracy fast) or on the finite-mass motor (--accuracy exact) (docs/steady.md).
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``lusm characteristic``."""
    add_drive_options(p, time_steps=False, voltage_list=True)  # steady: no time step
    p.add_argument("--loads", default=None, metavar="START:STOP:STEP",
                   help="load forces (N), e.g. 0:2:0.1 or 0,0.5,1 (as map's --voltages); "
                   "default 21 loads from 0 to the stall force")
    p.add_argument("--accuracy", choices=("fast", "exact"), default="exact",
                   help="exact: the finite-mass motor from rest at every load (default); "
                   "fast: the averaged steady state (slider mass -> infinity), all loads "
                   "from one set of orbits, about half the time, but blind to the creeps "
                   "and holds a start from rest can end in (docs/steady.md)")
    from lusm.uncertainty import add_uncertainty_option

    add_uncertainty_option(p, "the stall force and the speed at each load")
    add_contact_options(p, folder_help="write characteristic.png into DIR")


def parse_loads(text: str) -> list[float]:
    """``START:STOP:STEP`` (N, STOP included when on the grid) or a comma list, as a sorted
    list of loads (a list in any order draws one curve; ``map`` took lists where
    ``characteristic`` refused them).

    At most :data:`lusm.limits.MAX_GRID_POINTS` loads (times ``LUSM_MAX_WORK``), each
    within the load range of ``lusm simulate --load-N``.
    """
    from lusm.ranges import parse_range

    top = limits.PRELOAD_N[1]
    # repeats and values outside the range refused there
    loads = parse_range(text, "--loads", bounds=(-top, top), unit="N",
                        note="the range of simulate --load-N")
    return sorted(float(x) for x in loads)


def run(args: argparse.Namespace) -> None:
    """Compute the characteristic(s) and print them."""
    if args.accuracy == "fast":
        warn_unused(("--rest",), "it sets how --accuracy exact decides the start from rest")
    loads = parse_loads(args.loads) if args.loads is not None else None
    voltages = args.voltage  # a tuple: --voltage takes A,B,...
    plot, motor = resolve_drive(args, [max(voltages)], args.preload)
    frequency_from = ("auto" if motor.frequency_auto else
                      args.frequency if args.frequency is not None else "40e3")
    params, damping_from, freq = motor.params, motor.damping_from, motor.frequency_Hz
    coupling, coupling_from = motor.coupling, motor.coupling_from
    check_steady_work(len(voltages) * (len(loads) if loads else 21), params, freq, coupling,
                      "loads x voltages", "--loads" if loads else "--frequency")
    cal = None
    if args.uncertainty is not None:
        from lusm.uncertainty import calibration_of, check_work

        cal = calibration_of(args, motor)
        check_work(args, len(voltages) * (len(loads) if loads else 21), motor,
                   "loads x voltages")

    from contact.characteristic import characteristic
    from validation.summaries import coupling_line, damping_line, damping_summary

    chars = [characteristic(params, v, args.preload, loads, frequency_Hz=freq,
                            coupling=coupling,
                            ultrasonic_friction=not args.no_ultrasonic_friction,
                            accuracy=args.accuracy, progress=True, rest=args.rest)
             for v in voltages]
    if args.accuracy == "fast":
        _warn_fast_level(params, chars, coupling, not args.no_ultrasonic_friction)
    from lusm.physical_limits import warn_beyond

    for c in chars:  # before the results: the curve's load farthest beyond a limit
        warn_beyond(c.worst_limits(), f"at {c.op.voltage_V:g} V, {c.op.preload_N:g} N, "
                    f"{c.op.frequency_Hz:.6g} Hz (the curve's worst load)")
    docs = [c.to_dict() for c in chars]
    for c, d in zip(chars, docs, strict=True):  # the operating point, as simulate gives it
        d.update(voltage_V=c.op.voltage_V, preload_N=c.op.preload_N,
                 frequency_Hz=c.op.frequency_Hz, frequency_from=frequency_from)
        d["damping"] = damping_summary(params, damping_from)
        d["coupling"], d["coupling_from"] = coupling, coupling_from
        if args.accuracy == "exact":  # how the start from rest was decided (--rest)
            d["rest"] = args.rest
    if cal is not None:
        _add_bands(args, cal, motor, chars, docs)
    # one voltage: the characteristic itself; several: {"voltages_V", "characteristics"}
    doc = docs[0] if len(docs) == 1 else {"voltages_V": list(voltages),
                                          "characteristics": docs}
    if plot is not None:
        from validation.report_motor import characteristic_figure

        doc["figures"] = write_figures(args, "--plot", lambda stage: [
            characteristic_figure(chars if len(chars) > 1 else chars[0],
                                  stage / "characteristic.png")])
    if args.json:
        print_json(doc, indent=2)
        return
    for f in doc.get("figures", []):
        print(f"wrote {f}")
    for v, char, d in zip(voltages, chars, docs, strict=True):
        if len(voltages) > 1:
            print(f"--- {v:g} V")
        _print_one(args, v, char, d, frequency_from == "auto")
    print(damping_line(params, damping_from))
    print(coupling_line(coupling, coupling_from))
    if cal is not None:
        from lusm.uncertainty import drawn_line

        print(drawn_line(docs[0]["uncertainty"]))


def _add_bands(args: argparse.Namespace, cal, motor, chars, docs: list[dict]) -> None:
    """Each curve's ``uncertainty``: the bands of its stall force and of the speed at each
    of its loads over ``--uncertainty`` parameter sets drawn from the calibration
    (:func:`calibration.bands.characteristic_band`)."""
    from calibration.bands import characteristic_band
    from lusm.uncertainty import band_json, run_band

    for c, d in zip(chars, docs, strict=True):
        stall, speeds = run_band(args, lambda step, c=c: characteristic_band(
            cal, motor.params, c.op.voltage_V, args.preload, c.load_N, motor.frequency_Hz,
            samples=args.uncertainty, progress=step, coupling=motor.coupling,
            ultrasonic_friction=not args.no_ultrasonic_friction, accuracy=args.accuracy,
            rest=args.rest))
        d["uncertainty"] = band_json(stall, stall_force_N=stall, velocity_m_s=speeds)


def _print_band(d: dict) -> None:
    """The stall force's band and the speed's band at each load."""
    from lusm.uncertainty import band_text

    u = d["uncertainty"]
    print(f"{'stall force band (N)':<26} {band_text(u['stall_force_N'])}")
    print(f"{'load (N)':>10} {'v mean (m/s)':>13} {'v std (m/s)':>12} {'v 2.5 %':>11} "
          f"{'v 97.5 %':>11} {'no speed':>8}")
    v = u["velocity_m_s"]
    for k, row in enumerate(d["curve"]):
        cells = [v[q][k] for q in ("mean", "std", "q2.5", "q97.5")]
        text = " ".join(f"{'nan':>11}" if x is None else f"{x:11.5g}" for x in cells[1:])
        mean = "nan" if cells[0] is None else f"{cells[0]:.5g}"
        print(f"{row['load_N']:10.4g} {mean:>13} {text} {v['missing'][k]:>8}")


def _print_one(args: argparse.Namespace, v: float, char, d: dict, auto: bool) -> None:
    """One voltage's characteristic: its drive, no-load speed, stall force, creep band,
    runaway bounds and the speed-thrust table with powers and efficiency."""
    print(f"{'drive':<26} {v:g} V, {args.preload:g} N, {char.op.frequency_Hz:.6g} Hz"
          + (" (auto)" if auto else ""))
    backward = (" (backward: the slider runs toward -y; the stall force and the default "
                "loads are negative, braking that motion)" if char.direction == "backward"
                else "")
    print(f"{'no-load velocity (m/s)':<26} {char.no_load_velocity_m_s:.6g}{backward}")
    print(f"{'stall force (N)':<26} {char.stall_force_N:.6g}")
    creep = _creep_line(char)
    if creep:
        print(f"{'creeps from (N)':<26} {creep}")
    print(f"{'accuracy':<26} {char.accuracy}" + (
        " (averaged, slider mass -> infinity: which steady state a start from rest "
        "reaches on the real slider, --accuracy exact decides)"
        if char.accuracy == "fast" else ""))
    low, high = char.holding_range_N
    # loads the slider is not run away under (beyond them it is back-driven without
    # bound): not "holds loads", which would read as a holding force beside a smaller
    # stall force
    if math.isfinite(low) and math.isfinite(high):
        print(f"{'no runaway within (N)':<26} {low:.4g} to {high:.4g}")
    else:  # undriven or weakly driven: the line says why there is no bound
        print(f"{'no runaway within (N)':<26} no full-slip bound (the tip sticks at the "
              "scan's ends): each load's start from rest decides")
    print(f"{'load (N)':>10} {'v (m/s)':>12} {'P_in (W)':>11} {'P_out (W)':>11} "
          f"{'eff.':>8}")
    for row in d["curve"]:
        if math.isnan(row["velocity_m_s"]):  # no steady state from rest
            print(f"{row['load_N']:10.4g} {'runs away':>12}")
            continue
        print(f"{row['load_N']:10.4g} {row['velocity_m_s']:12.5g} "
              f"{row['input_power_W']:11.4g} {row['output_power_W']:11.4g} "
              f"{row['efficiency']:8.4g}")
    undefined = [r for r in d["curve"]
                 if math.isnan(r["efficiency"]) and not math.isnan(r["velocity_m_s"])]
    why = []  # one reason per kind of row (at 0 V it is the input, not the output)
    if any(r["output_power_W"] < 0 for r in undefined):
        why.append("negative mechanical output (P_out < 0: the load assists the "
                   "motion, or the slider runs backward against it)")
    if any(not r["input_power_W"] > 0 for r in undefined):
        why.append("no electrical input (P_in <= 0: an undriven motor)")
    if why:
        print("eff. nan: " + "; or ".join(why))
    from lusm.physical_limits import print_limits

    print_limits(d.get("limits"))  # the curve's worst load (each load's: --json)
    if "uncertainty" in d:
        _print_band(d)


def _creep_line(char) -> str | None:
    """The creep band of an exact-level curve (:attr:`contact.characteristic.Characteristic.
    creep_from_N`), or None: said so that the curve's knee is not read as the stall force
    (it can be half the stall force: 0.76 N against 1.38 N)."""
    from contact.characteristic import CREEP_RIPPLES

    lo, hi = char.creep_from_N, char.stall_force_N
    if not math.isfinite(lo):
        return None
    inside = [abs(float(v)) for f, v in zip(char.load_N, char.velocity_m_s, strict=True)
              if min(lo, hi) <= f <= max(lo, hi) and math.isfinite(v)]  # ends included:
    # at an averaged stall of 0 the no-load point is the band's fastest creep
    speed = (f", at most {max(inside):.3g} m/s on this curve" if inside else "")
    if char.creep_rule == "whole curve":
        where = "the whole curve: up to the stall force"
    elif char.creep_rule == "averaged stall":
        where = "the averaged stall: up to the stall force"
    else:  # the averaging followed another sheet: the band is found on the full model's
        where = (f"where the velocity falls below {CREEP_RIPPLES:g} ripple scales, the "
                 f"averaged stall {char.averaged_stall_force_N:.4g} N being another "
                 "branch's: from it on")
    return (f"{lo:.6g} ({where} the slider creeps{speed}, "
            "its velocity ripple breaking the guide's ideal stiction; docs/steady.md)")


def _warn_fast_level(params, chars, coupling: str, ultrasonic_friction: bool) -> None:
    """Say :func:`contact.characteristic.averaging_doubt` of each curve in the options'
    terms."""
    from contact.characteristic import averaging_doubt

    for c in chars:
        doubt = averaging_doubt(params, c, coupling=coupling,
                                ultrasonic_friction=ultrasonic_friction)
        if doubt is not None:
            warn(doubt.replace("the averaging does not hold there; the exact level runs",
                               "the averaging behind --accuracy fast does not hold; "
                               "--accuracy exact runs")
                 .replace("the exact level): several",
                          "--accuracy exact, the default): several"))
