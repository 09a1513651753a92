"""The report's "Motor characteristics" section and its figures (steady engine).

For each parameter set: speed-thrust, output power and efficiency at 200, 300 and 400 V, the
settled stick-slip map from the steady engine, and (Table 2) the branch diagram at 14 N.
Library code: matplotlib comes through :mod:`validation.plotting` (no backend chosen here).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from contact.characteristic import Characteristic
from rom.params import MotorParams
from validation.plotting import pyplot, save

CHARACTERISTIC_VOLTAGES_V = (200.0, 300.0, 400.0)
"""Drive amplitudes of the report's speed-thrust curves (V)."""

CHARACTERISTIC_PRELOAD_N = 14.0
"""Preload of the report's speed-thrust curves and branch diagram (N), the paper's Fig. 20."""


def characteristic_figure(char: Characteristic | Sequence[Characteristic], path: Path,
                          title: str = "") -> Path:
    """Speed against load and efficiency against load, one line per voltage (PNG).

    Each curve's stall force is marked on the zero-speed axis and its creep band (from
    :attr:`~contact.characteristic.Characteristic.creep_from_N` to the stall force, where
    the slider creeps slower than its creep speed) is shaded: the curve's knee, where it
    meets the axis on a linear scale, is not the stall force.
    """
    chars = [char] if isinstance(char, Characteristic) else list(char)
    plt = pyplot()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    speed_thrust_axes(ax1, chars, title)
    for i, c in enumerate(chars):
        ax2.plot(c.load_N, c.efficiency * 100, "s-", ms=3, color=f"C{i}",
                 label=f"{c.op.voltage_V:g} V")
    ax2.set_xlabel("load force (N)")
    ax2.set_ylabel("efficiency, output / electrical input (%)")
    ax2.set_title("efficiency")
    ax2.grid(True, alpha=0.3)
    ax2.legend(fontsize=8)
    return save(fig, path)


def speed_thrust_axes(ax, chars: Sequence[Characteristic], title: str = "") -> dict:
    """Draw the speed-thrust curves of ``chars`` on ``ax`` with their stall forces and creep
    bands.

    Returns
    -------
    dict
        The drawn artists by kind: ``"curves"`` (one line per voltage), ``"stall"`` (one
        marker per finite stall force, its x data the stall force in N), ``"creep"`` (one
        shaded span per creep band, from ``creep_from_N`` to the stall force) and
        ``"creep_speed"`` (one dotted line per finite creep speed, in mm/s, on the side of
        the motor's own direction).
    """
    drawn: dict[str, list] = {"curves": [], "stall": [], "creep": [], "creep_speed": []}
    for i, c in enumerate(chars):
        colour = f"C{i}"
        drawn["curves"] += ax.plot(c.load_N, c.velocity_m_s * 1e3, "o-", ms=3, color=colour,
                                   label=f"{c.op.voltage_V:g} V")
        stall = float(c.stall_force_N)
        if np.isfinite(stall):
            drawn["stall"] += ax.plot([stall], [0.0], "X", ms=10, color=colour, mec="k",
                                      label=f"stall {stall:.3g} N", zorder=5)
        lo = float(c.creep_from_N)
        if np.isfinite(lo) and np.isfinite(stall):
            drawn["creep"].append(ax.axvspan(
                min(lo, stall), max(lo, stall), color=colour, alpha=0.15,
                label=f"creep band {min(lo, stall):.3g} to {max(lo, stall):.3g} N"))
        creep = float(c.creep_speed_m_s)
        if np.isfinite(creep) and np.isfinite(lo):
            sign = -1.0 if c.no_load_velocity_m_s < 0 else 1.0  # a motor driving backward
            drawn["creep_speed"].append(ax.axhline(
                sign * creep * 1e3, color=colour, ls=":", lw=1,
                label=f"creep speed {creep * 1e3:.2g} mm/s"))
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_xlabel("load force (N)")
    ax.set_ylabel("steady slider velocity (mm/s)")
    level = {"exact": "exact level", "fast": "averaged level"}.get(chars[0].accuracy, "")
    ax.set_title("speed-thrust" + (f", {title}" if title else "")
                 + f", F_P = {chars[0].op.preload_N:g} N, {level}", fontsize=10)
    note = ("shaded: the slider creeps, slower than\nthe creep speed, up to the stall (X)"
            if drawn["creep"] else None)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, title=note, title_fontsize=7)
    return drawn


def branch_diagram(params: MotorParams, voltages_V, preload_N: float, path: Path, *,
                   accuracy: str = "exact", frequency_Hz: float | None = None) -> Path:
    """Every steady branch's velocity against voltage at one preload (PNG at ``path``).

    Stable branches are filled, unstable ones open; the branch a start from rest reaches is
    ringed; the period multiplicity k labels multi-period orbits.
    """
    from contact.steady.engine import steady_state

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    # one colour per class of orbit, in the legend only where drawn; k = 0 (averaged) means
    # are a class of their own, not period-1 orbits
    classes = {1: ("C0", "period-1 orbit"), 2: ("C1", "period-2 orbit"),
               3: ("C2", "period-3 orbit"), 4: ("C3", "period-4 or longer orbit"),
               0: ("C4", "no period up to 16 (long mean)")}
    drawn, held = set(), False
    for v0 in np.asarray(voltages_V, dtype=float):
        r = steady_state(params, v0, preload_N, accuracy=accuracy, frequency_Hz=frequency_Hz)
        for b in r.branches:
            if b.motion == "dead-zone":
                ax.plot(v0, 0.0, "ks", ms=6)
                held = True
                if b.from_rest:
                    ax.plot(v0, 0.0, "o", mfc="none", mec="k", ms=11)
                continue
            k = min(b.k, 4)
            drawn.add(k)
            colour = classes[k][0]
            ax.plot(v0, b.velocity_m_s * 1e3, "o", color=colour,
                    mfc=colour if b.stable else "none", ms=6)
            if b.from_rest:
                ax.plot(v0, b.velocity_m_s * 1e3, "o", mfc="none", mec="k", ms=11)
    for k in sorted(drawn, key=lambda k: (k == 0, k)):
        ax.plot([], [], "o", color=classes[k][0], label=classes[k][1])
    if held:
        ax.plot([], [], "ks", label="dead zone (slider held)")
    ax.plot([], [], "o", mfc="none", mec="k", ms=11, label="reached from rest")
    ax.set_xlabel("drive voltage V0 (V)")
    ax.set_ylabel("steady slider velocity (mm/s)")
    ax.set_yscale("symlog", linthresh=1e-2)
    ax.set_title(f"steady branches at F_P = {preload_N:g} N (open: unstable)")
    ax.grid(True)
    ax.legend(fontsize=8)
    return save(fig, path)


def _row(name: str, c: Characteristic) -> list:
    eff = c.efficiency[np.isfinite(c.efficiency)]
    best = float(eff.max()) if eff.size else float("nan")
    at = float(c.load_N[np.nanargmax(c.efficiency)]) if eff.size else float("nan")
    return [name, c.op.voltage_V, c.no_load_velocity_m_s * 1e3, c.stall_force_N,
            c.creep_from_N, c.input_power_W[0], best * 100, at]


def _grid(values: np.ndarray) -> str:
    """An evenly spaced grid as ``lusm map`` takes it: ``start:stop:step``."""
    step = float(values[1] - values[0]) if values.size > 1 else 1.0
    return f"{values[0]:g}:{values[-1]:g}:{step:g}"


def motor_section(params: dict[str, MotorParams], frequencies_Hz: dict[str, float],
                  out: Path, quick: bool, say: Callable[[str], None] = lambda _m: None,
                  table: Callable[[list, list], list[str]] | None = None,
                  damping_from: dict[str, str] | None = None,
                  cites: dict[str, str] | None = None,
                  voltages_V: Sequence[float] = CHARACTERISTIC_VOLTAGES_V,
                  preload_N: float = CHARACTERISTIC_PRELOAD_N):
    """Markdown lines and JSON data of "Motor characteristics" for each parameter set.

    Parameters
    ----------
    params : dict
        Parameter sets by name.
    frequencies_Hz : dict
        Drive frequency of each set (Hz).
    out : Path
        Report folder; figures go to ``out / "figures"``.
    quick : bool
        3 x 3 maps and a 50 V branch grid instead of 9 x 9 and 25 V.
    say : callable
        Progress callback, one call per finished item.
    table : callable
        The report's Markdown table builder ``table(header, rows)``.
    damping_from : dict, optional
        Where each set's damping ratios came from (default: Table 2 for ``table2``, Table 2's
        ratios borrowed for the others); named beside each set's speeds.
    cites : dict, optional
        The ``lusm`` options that name each set and its drive frequency (``"--source fem
        --frequency auto"``, ``"--geometry FILE --frequency auto"``; ``""`` for Table 2 at
        40 kHz); each set's subsection cites the ``lusm characteristic`` and ``lusm map``
        commands that reproduce its numbers with them (one ``lusm characteristic --frequency
        F`` for every set would run Table 2's). A set without an entry is cited with no
        command.
    voltages_V : sequence of float
        Drive amplitudes of the speed-thrust curves (V), one curve each.
    preload_N : float
        Preload of the speed-thrust curves (N) and of the branch diagram.
    """
    from validation.summaries import borrowed_damping, table2_damping

    volts = np.arange(50.0, 451.0, 200.0 if quick else 50.0)
    loads = np.arange(10.0, 27.0, 8.0 if quick else 2.0)
    curves = tuple(float(v) for v in voltages_V)
    md = _intro(volts, loads, curves, preload_N, "table2" in params)
    origins = {name: (damping_from or {}).get(name) or (
        table2_damping() if name == "table2" else borrowed_damping(name)) for name in params}
    data: dict = {}
    rows = []
    for name, p in params.items():
        data[name], set_rows = _set_data(name, p, frequencies_Hz[name], volts, loads, out, say,
                                         origins[name], curves, preload_N)
        rows += set_rows
    md += (table or (lambda h, r: []))(
        ["set", "V0 (V)", "no-load velocity (mm/s)", "stall force (N)",
         "creeps from (N)", "input power at no load (W)", "peak efficiency (%)", "at load (N)"],
        rows)
    md.append("")
    for name, d in data.items():
        cite = cites.get(name) if cites is not None else None
        md += _set_markdown(name, d, params[name], origins[name], cite, volts, loads, curves,
                            preload_N)
    if "table2" in params:
        grid = np.arange(50.0, 451.0, 50.0 if quick else 25.0)
        fig_b = branch_diagram(params["table2"], grid, preload_N,
                               out / "figures" / "table2_branches.png",
                               frequency_Hz=frequencies_Hz["table2"])
        say("branch diagram")
        md += [f"### Coexisting steady states (Table 2, {preload_N:g} N)", "",
               "Every steady state against voltage (exact level): where two stable branches "
               "coexist the motor's speed depends on its history (hysteresis); the ringed one "
               "is reached from rest.", "", f"![branches](figures/{fig_b.name})", ""]
        data["branch_diagram"] = {"voltages_V": grid.tolist(),
                                  "figure": f"figures/{fig_b.name}"}
    return md, data


def _intro(volts: np.ndarray, loads: np.ndarray, curves: Sequence[float], preload_N: float,
           table2: bool) -> list[str]:
    """The section's heading and its paragraph on what is computed and how (``table2``: the
    report has Table 2's set, whose coupling is the paper's)."""
    coupling = ("Table 2's set runs with the paper's coupling (eta_T F_T), every other set "
                "with the work-consistent one (-phi_B(l) F_T; `docs/contact.md` 2.3)"
                if table2 else "The stator's set runs with the work-consistent tangential "
                "coupling (-phi_B(l) F_T; `docs/contact.md` 2.3)")
    return ["## 5. Motor characteristics", "",
            ("What each parameter set does as a motor" if table2 else
             "What this stator does as a motor")
            + ", from the steady-state engine "
            "(`docs/steady.md`): no transient is run except where the engine cannot decide. "
            "Speed-thrust and efficiency at "
            + ", ".join(f"{v:g}" for v in curves)
            + f" V and {preload_N:g} N (`lusm characteristic`, with the options "
            "each set's subsection cites: the exact level, the finite-mass motor from rest. "
            "The averaged level, `--accuracy fast`, puts the stall force where the averaged "
            "slider stops, while the full model's still creeps forward: up to several times "
            "lower on these sets, and a held slider where the full model creeps; the column "
            "'creeps from' gives it, where the creep begins: between it and the stall force "
            "the slider moves at a small fraction of its no-load speed, its velocity ripple "
            "breaking the guide's ideal stiction; docs/steady.md); settled stick-slip maps "
            f"over {volts[0]:g}-{volts[-1]:g} V x {loads[0]:g}-{loads[-1]:g} N (`lusm map`: "
            "exact level, the branch reached from rest). Efficiency is the mechanical output "
            "power over the electrical input power (motional current times voltage). "
            + coupling + "; each set's damping "
            "and coupling are named below (the damping sets the scale of every speed).", ""]


def _set_data(name: str, p: MotorParams, f: float, volts: np.ndarray, loads: np.ndarray,
              out: Path, say: Callable[[str], None], origin: str, curves: Sequence[float],
              preload_N: float) -> tuple[dict, list]:
    """One set's characteristics (exact level) and steady map, their figures, its JSON data
    and its rows of the section's table."""
    from contact.characteristic import characteristic
    from contact.maps import stick_slip_map
    from contact.model import default_coupling
    from contact.options import SimulationOptions
    from validation.figures import stick_slip_map as map_figure
    from validation.summaries import damping_summary

    t0 = time.perf_counter()
    coupling, coupling_why = default_coupling(p)
    # the exact level, as the command's default: the averaged one puts the stall force where
    # the averaged slider stops, well below the finite-mass motor's
    chars = [characteristic(p, v, preload_N, frequency_Hz=f, coupling=coupling,
                            accuracy="exact") for v in curves]
    say(f"{name} characteristics")
    fig_c = characteristic_figure(chars, out / "figures" / f"{name}_characteristic.png",
                                  title=name)
    m = stick_slip_map(p, volts, loads, f, SimulationOptions(coupling=coupling),
                       progress=False, method="steady")
    say(f"{name} map")
    fig_m = map_figure(m, out / "figures" / f"{name}_steady_map.png",
                       f"{name}, steady engine, {f / 1e3:.4g} kHz")
    data = {
        "frequency_Hz": f,
        "characteristics": {f"{c.op.voltage_V:g}": c.to_dict() for c in chars},
        "map": {"voltages_V": volts.tolist(), "preloads_N": loads.tolist(),
                "motion": m.motion.tolist(), "velocity_m_s": m.velocity_m_s.tolist(),
                "counts": m.counts(), "undecided": int(m.fallback.sum()),
                "several_branches": int(sum(len(b) > 1 for b in m.branches.flat)),
                "wall_time_s": m.wall_time_s},
        "figures": {"characteristic": f"figures/{fig_c.name}",
                    "map": f"figures/{fig_m.name}"},
        "wall_time_s": time.perf_counter() - t0,
        "damping": damping_summary(p, origin),
        "coupling": coupling, "coupling_from": coupling_why,
        "limits": {f"{c.op.voltage_V:g}": (None if not c.limits or c.limits[0] is None
                                          else c.limits[0].to_dict()) for c in chars},
    }
    return data, [_row(name, c) for c in chars]


def limits_table(limits_by_voltage: dict) -> list[str]:
    """Markdown table of the no-load operating points' limits
    (:mod:`contact.operating_limits`): each quantity's value and its ratio to the limit,
    bold beyond it; empty without shape data."""
    from contact.operating_limits import QUANTITIES

    rows = {v: d for v, d in limits_by_voltage.items() if d is not None}
    if not rows:
        return []
    head = ["V0 (V)"] + [f"{q.replace('_', ' ')} ({unit})"
                         for q, (_, _, _, unit) in QUANTITIES.items()]
    md = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for v, d in rows.items():
        cells = [v]
        for q, (_, _, factor, _) in QUANTITIES.items():
            r = d[q]["ratio"]
            if not r == r:  # NaN: no limit of its own (the dampers' total power)
                cells.append(f"{d[q]['value'] * factor:.3g}")
                continue
            text = f"{d[q]['value'] * factor:.3g} ({r:.2g} of {d[q]['limit'] * factor:.3g})"
            cells.append(f"**{text}**" if r > 1 else text)
        md.append("| " + " | ".join(cells) + " |")
    first = next(iter(rows.values()))["stress"]
    if "basis" in first:  # what the stress column is, and the bound beside it
        sums = ", ".join(f"{d['stress']['sum_of_peaks'] * 1e-6:.3g}" for d in rows.values())
        md += ["", f"Stress: {first['basis']}; the L1 and B2 peaks added give {sums} MPa."]
    return md + [""]


def _set_markdown(name: str, d: dict, p: MotorParams, origin: str, cite: str | None,
                  volts: np.ndarray, loads: np.ndarray, curves: Sequence[float],
                  preload_N: float) -> list[str]:
    """One set's subsection: its damping and coupling, the commands that reproduce it
    (``cite``: the options naming the set, None for no command), its map and figures."""
    from validation.summaries import coupling_line, damping_line

    mp = d["map"]
    md = [f"### {name} at {d['frequency_Hz'] / 1e3:.4g} kHz", "",
          f"The {damping_line(p, origin)}; the "
          f"{coupling_line(d['coupling'], d['coupling_from'])}.", ""]
    if cite is not None:
        opts = f" {cite}" if cite else ""
        md += [f"Reproduce: `lusm characteristic{opts} --voltage V0 --preload "
               f"{preload_N:g}` (V0 = "
               + ", ".join(f"{v:g}" for v in curves)
               + f"), `lusm map{opts} --voltages {_grid(volts)} --preloads "
               f"{_grid(loads)}`.", ""]
    lim = limits_table(d.get("limits") or {})
    if lim:
        md += [f"Physical limits at no load, {preload_N:g} N (value, and its "
               "share of the ceramic's limit; bold beyond it; `lusm simulate --steady` gives "
               "them with `limits`; docs/designer.md, 'Physical limits'):", ""] + lim
    return md + ["Map: " + ", ".join(f"{n} {c}" for c, n in mp["counts"].items() if n)
                 + f" point(s); {mp['several_branches']} point(s) with several stable "
                 f"steady states (the map shows the one reached from rest); {mp['undecided']} "
                 "point(s) the engine could not decide (creep), taken from 0.3 s transients; "
                 f"computed in {mp['wall_time_s']:.1f} s.", "",
                 f"![{name} characteristic]({d['figures']['characteristic']})",
                 f"![{name} steady map]({d['figures']['map']})", ""]
