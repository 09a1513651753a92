"""Reproduction of the paper's contact figures for one parameter set, with a verdict per claim.

Each claim of the paper is encoded once (``PAPER_CLAIMS``) with a number or a class read from
its text or figures, a tolerance and a reason template; the same runs feed the PNG figures and
the table "the paper says / we get / agrees?".
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from contact.maps import StickSlipMap, stick_slip_map
from contact.options import SimulationOptions
from contact.simulate import SimulationResult, simulate
from rom.params import MotorParams
from validation import figures


@dataclass(frozen=True)
class ReproSettings:
    """Grids and durations of a reproduction (the full report or ``--quick``).

    Attributes
    ----------
    duration_s : float
        Simulated time per run (s).
    map_voltages_V, map_preloads_N : tuple of float
        Grid of Figs. 18-19 (V, N).
    curve_voltages_V : tuple of float
        Voltages of Figs. 20 and 24 at 14 N (V).
    curve_preloads_N : tuple of float
        Preloads of Fig. 21 at 400 V (N).
    low_voltages_V : tuple of float
        Voltages of Fig. 25 (V).
    transient_s : float
        Start of the transient window A of Fig. 10 (s).
    method : {"steady", "transient"}
        Where the judged numbers (velocities, motion classes, mu_d, maps) come from: the
        steady engine (:func:`contact.steady.engine.steady_state`, the branch a start from rest
        reaches, settled by construction) or the runs of ``duration_s`` from rest. The
        figures of time traces and phase planes always come from those runs.
    """

    duration_s: float = 0.05
    map_voltages_V: tuple[float, ...] = tuple(np.arange(50.0, 451.0, 50.0))
    map_preloads_N: tuple[float, ...] = tuple(np.arange(10.0, 27.0, 2.0))
    curve_voltages_V: tuple[float, ...] = tuple(np.arange(0.0, 451.0, 25.0))
    curve_preloads_N: tuple[float, ...] = tuple(np.arange(10.0, 27.0, 2.0))
    low_voltages_V: tuple[float, ...] = (25.0, 50.0, 75.0, 100.0)
    transient_s: float = 0.002
    method: str = "steady"

    def __post_init__(self) -> None:
        if self.method not in ("steady", "transient"):
            raise ValueError(f"method must be 'steady' or 'transient', got {self.method!r}")

    @classmethod
    def quick(cls) -> ReproSettings:
        """Coarse grids and 10 ms runs judged as they are (not settled): same sections, a
        fraction of the time."""
        return cls(
            method="transient",
            duration_s=0.01,
            map_voltages_V=(100.0, 250.0, 400.0),
            map_preloads_N=(10.0, 18.0, 26.0),
            curve_voltages_V=(0.0, 100.0, 150.0, 250.0, 400.0),
            curve_preloads_N=(10.0, 18.0, 26.0),
            low_voltages_V=(50.0, 100.0),
        )


@dataclass(frozen=True)
class ClaimRow:
    """One line of the reproduction table."""

    figure: str
    paper_says: str
    we_get: str
    agrees: bool
    reason: str


@dataclass(frozen=True)
class Reproduction:
    """Everything reproduced for one parameter set."""

    source: str
    frequency_Hz: float
    rows: tuple[ClaimRow, ...]
    figures: dict[str, str]
    numbers: dict = field(default_factory=dict)


def _motion_row(fig: str, v: float, f: float, paper: str, r: SimulationResult,
                traced: SimulationResult) -> ClaimRow:
    """One motion-class claim judged on ``r``; ``traced`` (a run from rest with tip extrema)
    gives the lowest tip position quoted when the paper's separation is missing."""
    got = r.steady.motion
    ok = got == paper
    if ok:
        reason = ""
    elif "separation" in paper and r.steady.separation_fraction == 0.0:
        reason = (f"no separation: y_min = {traced.steady.y_tip_min_m * 1e6:.3f} um stays "
                  f"above y_c (the L1 amplitude is too small at this preload)")
    elif "stick" in paper and r.steady.stick_fraction == 0.0:
        reason = "the tip never sticks: the stick force exceeds mu_s F_N at every v_rel = 0"
    else:
        reason = "different phase mix (see the fractions)"
    we_get = (f"{got} (stick {r.steady.stick_fraction:.3f}, separation "
              f"{r.steady.separation_fraction:.3f})")
    return ClaimRow(fig, f"{v:g} V / {f:g} N: {paper}", we_get, ok, reason)


DEAD_ZONE_REL = 0.1
"""Fig. 24's dead-zone edge counts as reproduced within this share of the paper's simulated
120 V: half the gap between it and the ~100 V the paper measured."""


def _within(value: float, target: float, rel: float) -> bool:
    return abs(value - target) <= rel * abs(target)


@dataclass
class _Cases:
    """The runs of one parameter set and what :func:`reproduce` collects from them."""

    params: MotorParams
    frequency_Hz: float
    settings: ReproSettings
    out: Path
    prefix: str
    figs: dict[str, str] = field(default_factory=dict)
    rows: list[ClaimRow] = field(default_factory=list)
    numbers: dict = field(default_factory=dict)

    @property
    def options(self) -> SimulationOptions:
        # the paper's coupling for every set, as the section says (the library's default is
        # "auto", the consistent one for the FE and beam sets)
        return SimulationOptions(duration_s=self.settings.duration_s, coupling="paper")

    def run(self, v: float, f: float, **kw) -> SimulationResult:
        """The traced transient at ``v`` (V), ``f`` (N)."""
        return simulate(self.params, v, f, self.frequency_Hz, self.options, **kw)

    def settled(self, v: float, f: float, traced: SimulationResult | None = None
                ) -> SimulationResult:
        """The judged result at (v, f): steady engine, or the traced run itself."""
        if self.settings.method == "transient":
            return traced if traced is not None else self.run(v, f)
        return simulate(self.params, v, f, self.frequency_Hz, self.options, method="steady")


def reproduce(
    params: MotorParams,
    frequency_Hz: float,
    out_dir: Path,
    prefix: str,
    settings: ReproSettings,
    progress: Callable[[str], None] | None = None,
) -> Reproduction:
    """Run the paper's cases on one parameter set, draw its figures, judge its claims."""
    say = progress or (lambda _msg: None)
    c = _Cases(params, frequency_Hz, settings, Path(out_dir), prefix)
    c.numbers["method"] = settings.method
    for name, section in (("Figs. 9-17", _figs_9_to_17), ("Figs. 18-19 (maps)", _maps),
                          ("Figs. 20, 24, 25 (voltage sweep)", _voltage_sweep),
                          ("Fig. 21 (preload sweep)", _preload_sweep)):
        say(name)
        section(c)
    return Reproduction(params.source, frequency_Hz, tuple(c.rows), c.figs, c.numbers)


def _figs_9_to_17(c: _Cases) -> None:
    """Figs. 9-17: the 200 V / 14 N run, its transient, and the four motion classes."""
    base = c.run(200.0, 14.0)
    base_settled = c.settled(200.0, 14.0, base)
    c.figs["fig09"] = str(figures.slider_velocity(base, c.out / f"{c.prefix}fig09_velocity.png"))
    transient = c.run(200.0, 14.0, duration_s=c.settings.transient_s + 5 / c.frequency_Hz,
                    full_periods=5, steady_periods=5)
    c.figs["fig10"] = str(figures.forces_and_relative_velocity(
        transient, c.out / f"{c.prefix}fig10_forces_transient.png"))
    c.figs["fig11"] = str(figures.forces_and_relative_velocity(
        base, c.out / f"{c.prefix}fig11_forces_steady.png"))
    c.figs["fig12"] = str(figures.hysteresis_loop(base, c.out / f"{c.prefix}fig12_hysteresis.png"))
    v9 = base_settled.steady.velocity_m_s
    how = ("steady engine" if c.settings.method == "steady" else
           "settled" if base.steady.settled else "not settled")
    # a held slider's window mean is its ring about rest, roundoff once settled (1.661e-19
    # m/s on the beam set): the row says it is held instead
    held = base_settled.steady.motion == "pure-stick"
    c.rows.append(ClaimRow(
        "Fig. 9", "200 V / 14 N: steady slider velocity about 0.03 m/s, reached after ~20 ms",
        f"0 m/s, held in pure stick ({how})" if held else f"{v9:.4g} m/s ({how})",
        _within(v9, 0.03, 0.3),
        "" if _within(v9, 0.03, 0.3) else
        "the slider has not settled within this run" if not base_settled.steady.settled else
        "the equations with these parameters give this velocity; see docs/contact.md",
    ))
    a_stick, b_stick = transient.steady.stick_fraction, base_settled.steady.stick_fraction
    ok_ab = a_stick > b_stick
    c.rows.append(ClaimRow(
        "Figs. 10-11", "the tip sticks longer per cycle in the transient (span A) than in the "
        "steady state (span B)",
        f"stick fraction A {a_stick:.3f} (t = {c.settings.transient_s * 1e3:g} ms), "
        f"B {b_stick:.3f}",
        ok_ab,
        "" if ok_ab else "no stick in span A" if a_stick == 0 else
        "pure stick throughout" if a_stick == b_stick == 1.0 else
        "the tip does not stick longer in span A",
    ))
    cases = (("Fig. 14", 200.0, 14.0, "stick-slip-separation", base),
             ("Fig. 15", 200.0, 10.0, "slip-separation", None),
             ("Fig. 16", 200.0, 18.0, "stick-slip", None),
             ("Fig. 17", 200.0, 25.0, "pure-stick", None))
    c.numbers["cases"] = {}
    for fig, v, f, paper, traced in cases:
        traced = traced or c.run(v, f)
        r = base_settled if traced is base else c.settled(v, f, traced)
        c.rows.append(_motion_row(fig, v, f, paper, r, traced))
        key = fig.split()[-1].replace(".", "")
        c.figs[f"fig{key}"] = str(figures.transformed_phase_plane(
            traced, c.out / f"{c.prefix}fig{key}_phase_plane.png"))
        c.numbers["cases"][f"{v:g}V_{f:g}N"] = {
            "motion": r.steady.motion, "velocity_m_s": r.steady.velocity_m_s,
            "stick_fraction": r.steady.stick_fraction,
            "separation_fraction": r.steady.separation_fraction,
        }


def _maps(c: _Cases) -> None:
    """Figs. 18-19: the stick-slip maps with Eq. 11's friction and with a constant one."""
    maps: dict[bool, StickSlipMap] = {}
    for us in (True, False):
        maps[us] = stick_slip_map(
            c.params, c.settings.map_voltages_V, c.settings.map_preloads_N, c.frequency_Hz,
            SimulationOptions(duration_s=c.settings.duration_s, ultrasonic_friction=us,
                              coupling="paper"),
            progress=False, method=c.settings.method,
        )
        name = "fig18" if us else "fig19"
        c.figs[name] = str(figures.stick_slip_map(
            maps[us], c.out / f"{c.prefix}{name}_map.png",
            f"{figures.set_label(c.params.source)}: mu_d {'Eq. 11' if us else 'constant'}"))
    m18, m19 = maps[True], maps[False]
    corner_ok = m18.motion[0, -1] == "pure-stick" and "separation" in m18.motion[-1, 0]
    more_ss = m19.counts()["stick-slip"] >= m18.counts()["stick-slip"]
    c.rows.append(ClaimRow(
        "Figs. 18-19", "pure stick at low V / high F_P, slip-separation at high V / low F_P, "
        "stick-slip in between; constant mu_d gives more stick-slip than Eq. 11",
        f"corners {m18.motion[0, -1]} / {m18.motion[-1, 0]}; stick-slip points "
        f"{m18.counts()['stick-slip']} (Eq. 11) vs {m19.counts()['stick-slip']} (constant)",
        bool(corner_ok and more_ss),
        "" if corner_ok and more_ss else "map corners or counts differ (see the figures)",
    ))
    c.numbers["map_counts_eq11"] = m18.counts()
    c.numbers["map_counts_constant_mu"] = m19.counts()


def _voltage_sweep(c: _Cases) -> None:
    """Figs. 20, 24, 25: friction, velocity and the dead zone against voltage at 14 N."""
    volts = np.asarray(c.settings.curve_voltages_V)
    sweep = [c.settled(float(v), 14.0) for v in volts]
    mu = np.array([r.mu_d_eff for r in sweep])
    vel = np.array([r.steady.velocity_m_s for r in sweep])
    c.figs["fig20"] = str(figures.curve(volts, {"mu_d (Eq. 11)": mu}, "voltage amplitude V0 (V)",
                                      "dynamic friction coefficient mu_d", c.out /
                                      f"{c.prefix}fig20_mu_vs_voltage.png", "F_P = 14 N"))
    c.figs["fig24"] = str(figures.curve(volts, {"simulation": vel}, "voltage amplitude V0 (V)",
                                      "steady slider velocity (m/s)", c.out /
                                      f"{c.prefix}fig24_velocity_vs_voltage.png", "F_P = 14 N"))
    sel = volts >= 50
    mono = bool(np.all(np.diff(mu[sel]) < 0)) if np.sum(sel) > 1 else False
    c.rows.append(ClaimRow(
        "Fig. 20", "mu_d falls with voltage, about 0.36 -> 0.22 over 50-450 V (14 N)",
        f"{mu[sel][0]:.3f} -> {mu[sel][-1]:.3f} over {volts[sel][0]:g}-{volts[sel][-1]:g} V",
        mono and abs(mu[sel][-1] - 0.22) < 0.03,
        "" if mono and abs(mu[sel][-1] - 0.22) < 0.03 else
        "trend as published, but a smaller normal amplitude A_N gives a narrower range",
    ))
    moving = volts[np.abs(vel) > 1e-6]
    edge = float(moving.min()) if moving.size else float("nan")
    stuck_below = volts[volts < edge] if moving.size else volts
    # judged on the edge itself, bisected to 0.5 V (section 4 bisects it to 0.05 V): on the
    # 25 V grid "no motion up to 125 V, moving from 150 V" would pass for the paper's 120 V
    # while the edge lies at 139 V
    from validation.hard_cases import dead_zone_edge

    bisected = dead_zone_edge(c.params, 14.0, c.frequency_Hz, 0.01, tol_V=0.5, coupling="paper")
    dz_ok = bool(np.isfinite(bisected)) and _within(bisected, 120.0, DEAD_ZONE_REL)
    c.rows.append(ClaimRow(
        "Fig. 24", "dead zone: no motion up to about 120 V (simulation; ~100 V measured), 14 N",
        f"no motion up to {float(stuck_below.max()) if stuck_below.size else 0:g} V, moving "
        f"from {edge:g} V on the grid; "
        + (f"edge {bisected:.1f} V by bisection to 0.5 V ({bisected / 120.0 - 1.0:+.0%})"
           if np.isfinite(bisected) else "pure stick up to 1000 V"),
        dz_ok, "" if dz_ok else "the dead-zone edge lies elsewhere on this set",
    ))
    if 400.0 in volts:
        r400 = sweep[list(volts).index(400.0)]
        v400 = float(r400.steady.velocity_m_s)
        how = ("steady engine" if c.settings.method == "steady" else
               "settled" if r400.steady.settled else "not settled")
        c.rows.append(ClaimRow(
            "Fig. 24", "about 0.2 m/s at 400 V, 14 N", f"{v400:.4g} m/s ({how})",
            _within(v400, 0.2, 0.3), "" if _within(v400, 0.2, 0.3) else
            # as for Fig. 9: an unsettled run's velocity is not the model's answer (the quick
            # report's 10 ms run gives 0.072 m/s where the steady state is 0.217 m/s)
            "the slider has not settled within this run" if not r400.steady.settled else
            "the equations with these parameters give this velocity",
        ))
    c.numbers["voltage_sweep"] = {"voltage_V": volts.tolist(), "velocity_m_s": vel.tolist(),
                                "mu_d": mu.tolist(), "motion": [r.steady.motion for r in sweep]}
    low_traced = [c.run(float(v), 14.0) for v in c.settings.low_voltages_V]
    c.figs["fig25"] = str(_low_voltage_figure(low_traced,
                                            c.out / f"{c.prefix}fig25_low_voltage_vrel.png"))
    low = [c.settled(r.op.voltage_V, 14.0, r) for r in low_traced]
    all_stuck = all(r.steady.motion == "pure-stick" for r in low)
    c.rows.append(ClaimRow(
        "Fig. 25", "v_rel stays in the stick band at 25-100 V (14 N): pure stick, dead zone",
        ", ".join(f"{r.op.voltage_V:g} V {r.steady.motion}" for r in low), all_stuck,
        "" if all_stuck else "the tip slips at some of these voltages on this set",
    ))


def _preload_sweep(c: _Cases) -> None:
    """Fig. 21: the dynamic friction against preload at 400 V."""
    loads = np.asarray(c.settings.curve_preloads_N)
    mu21 = np.array([c.settled(400.0, float(f)).mu_d_eff for f in loads])
    c.figs["fig21"] = str(figures.curve(loads, {"mu_d (Eq. 11)": mu21}, "preload F_P (N)",
                                      "dynamic friction coefficient mu_d",
                                      c.out / f"{c.prefix}fig21_mu_vs_preload.png", "V0 = 400 V"))
    spread = float(mu21.max() - mu21.min())
    c.rows.append(ClaimRow(
        "Fig. 21", "preload has little influence on mu_d (400 V)",
        f"mu_d {mu21.min():.3f}-{mu21.max():.3f} over {loads[0]:g}-{loads[-1]:g} N",
        spread < 0.05, "" if spread < 0.05 else "mu_d varies strongly with preload here",
    ))
    c.numbers["preload_sweep"] = {"preload_N": loads.tolist(), "mu_d": mu21.tolist()}


def _low_voltage_figure(runs: list[SimulationResult], path: Path) -> Path:
    """Relative velocity in time at low voltages (paper Fig. 25)."""
    plt = figures.pyplot()
    fig, ax = plt.subplots(figsize=(7, 4))
    for r in runs:
        ax.plot(r.trace.t_s * 1e3, r.trace.v_rel_m_s, lw=0.6, label=f"V0 = {r.op.voltage_V:g} V")
    ax.set_xlabel("time t (ms)")
    ax.set_ylabel("relative velocity v_rel (m/s)")
    ax.set_title("F_P = 14 N", fontsize=9)
    ax.legend(fontsize=8)
    return figures.save(fig, path)
