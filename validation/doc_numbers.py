"""The numbers the README and ``docs/`` quote, computed in one place.

Every result quoted in the documentation is a *claim* here: a key, the function that computes
it, its unit, the command a reader runs to see it, and whether a test may recompute it
(``cheap``: well under a second or two). ``python -m validation.doc_numbers`` computes them
all and writes ``docs/numbers.json`` (with the machine and date); in the Markdown each quoted
number carries an invisible marker right after it::

    pure stick up to 139.1<!--n:dead_zone_14N_V--> V
    L1 ≈ 56.5<!--n:fe2d_L1_short_Hz*1e-3--> kHz

``*factor`` scales the stored value to the printed unit. ``tests/test_docs_numbers.py`` checks
that every marked number equals ``numbers.json`` to the precision it is printed with, that
every key exists, and recomputes the cheap claims against ``numbers.json``. To add a claim:
add a :class:`Claim` to :data:`CLAIMS`, run the generator, mark the number in the Markdown.

Timings are claims only as ratios measured in the same run (``*_ratio``), never as absolute
seconds; the machine they were measured on is stored beside them.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import re
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
NUMBERS_JSON = ROOT / "docs" / "numbers.json"
"""Where the generator writes (in a source checkout)."""

DOC_FILES = ("README.md", "docs/contact.md", "docs/fem.md", "docs/fem3d.md", "docs/beam.md",
             "docs/designer.md", "docs/limits.md", "docs/steady.md", "docs/distributed.md")
"""The Markdown files whose markers are checked and filled (those that exist)."""

MARKER = re.compile(
    r"(?P<num>[+\-−]?(?:\d{1,3}(?:[   ]\d{3})+|\d+)(?:\.\d+)?"
    r"(?:e[+\-−]?\d+)?)<!--n:(?P<key>\w+)(?:\*(?P<factor>[0-9.eE+\-]+))?-->")
"""A quoted number followed by its marker ``<!--n:key-->`` or ``<!--n:key*factor-->``."""


@dataclass(frozen=True)
class Quote:
    """One marked number in a Markdown file."""

    path: str
    line: int
    text: str
    key: str
    factor: float
    start: int
    end: int

    @property
    def printed(self) -> float:
        """The value as printed."""
        return float(re.sub(r"[   ]", "", self.text).replace("−", "-"))

    @property
    def half_ulp(self) -> float:
        """Half a unit in the last printed digit: the rounding the text allows."""
        mant, _, exp = self.text.lower().partition("e")
        decimals = len(mant.partition(".")[2])
        scale = 10.0 ** int(exp.replace("−", "-")) if exp else 1.0
        return 0.5 * 10.0 ** -decimals * scale

    def agrees(self, value: float) -> bool:
        """Whether ``value`` (stored unit) rounds to the printed number."""
        return abs(value * self.factor - self.printed) <= self.half_ulp * (1 + 1e-9) + 1e-300

    def formatted(self, value: float) -> str:
        """``value`` (stored unit) printed in the style of this quote."""
        v = value * self.factor
        mant, _, exp = self.text.lower().partition("e")
        decimals = len(mant.partition(".")[2])
        if exp:
            out = f"{v:.{decimals}e}"
            m, e = out.split("e")
            out = f"{m}e{int(e)}"
        else:
            out = f"{v:.{decimals}f}"
            sep = next((c for c in self.text if c in "   "), None)
            if sep:
                whole, dot, frac = out.lstrip("-").partition(".")
                groups = []
                while len(whole) > 3:
                    groups.insert(0, whole[-3:])
                    whole = whole[:-3]
                out = ("-" if out.startswith("-") else "") + sep.join([whole, *groups])
                out += dot + frac
        if self.text.startswith("+") and v >= 0:
            out = "+" + out
        return out


def quotes(root: Path = ROOT) -> list[Quote]:
    """Every marked number in :data:`DOC_FILES`."""
    found = []
    for rel in DOC_FILES:
        path = root / rel
        if not path.exists():
            continue
        text = path.read_text()
        for m in MARKER.finditer(text):
            found.append(Quote(rel, text.count("\n", 0, m.start()) + 1, m.group("num"),
                               m.group("key"), float(m.group("factor") or 1.0),
                               m.start("num"), m.end("num")))
    return found


def fill(doc: dict, root: Path = ROOT) -> int:
    """Rewrite every marked number from ``doc`` (a numbers.json document); returns changes."""
    changed = 0
    by_file: dict[str, list[Quote]] = {}
    for q in quotes(root):
        by_file.setdefault(q.path, []).append(q)
    for rel, qs in by_file.items():
        path = root / rel
        text = path.read_text()
        for q in sorted(qs, key=lambda q: -q.start):
            value = doc["numbers"][q.key]["value"]
            if value is None or q.agrees(value):
                continue
            text = text[:q.start] + q.formatted(value) + text[q.end:]
            changed += 1
        path.write_text(text)
    return changed


@dataclass(frozen=True)
class Claim:
    """One quoted result.

    Attributes
    ----------
    key : str
        Name used by the Markdown markers.
    unit : str
        Unit of the stored value (SI, or ``-`` for ratios and fractions).
    command : str
        The command that shows the number to a reader.
    compute : callable
        Returns the value (no arguments; shared work is cached).
    cheap : bool
        Whether the test suite recomputes it.
    rel_tol : float
        Relative tolerance of that recomputation (it may run on another machine/BLAS).
    """

    key: str
    unit: str
    command: str
    compute: Callable[[], float]
    cheap: bool = False
    rel_tol: float = 1e-6


_MODES = "lusm modes --json"
_SIM = "lusm simulate --voltage {v} --preload {f} --json"


# --- shared computations (each done once per process) ------------------------------------


@cache
def _table2():
    from rom import table2

    return table2()


@cache
def _sim(voltage_V: float, preload_N: float, duration_s: float = 0.05,
         coupling: str = "paper"):
    from contact.simulate import simulate

    return simulate(_table2(), voltage_V, preload_N, duration_s=duration_s, coupling=coupling,
                    energy=True)


def _excess(voltage_V: float, preload_N: float) -> float:
    e = _sim(voltage_V, preload_N).energy
    return e.non_conservative_J / e.input_J if e.input_J > 0 else 0.0


def _coupling_claims() -> tuple[Claim, ...]:
    """Velocity and stick fraction of both couplings, and the paper's excess work."""
    out = []
    for v, f in ((200, 10), (200, 14), (200, 18), (200, 25), (400, 14)):
        cmd = _SIM.format(v=v, f=f)
        for cp in ("paper", "consistent"):
            c = cmd + ("" if cp == "paper" else " --coupling consistent")
            out.append(Claim(f"v_{v}V_{f}N_{cp}_m_s", "m/s", c,
                             lambda v=v, f=f, cp=cp: _sim(v, f, 0.05, cp).steady.velocity_m_s,
                             cheap=True, rel_tol=1e-4))
            out.append(Claim(f"stick_{v}V_{f}N_{cp}", "-", c + " (stick_fraction)",
                             lambda v=v, f=f, cp=cp: _sim(v, f, 0.05, cp).steady.stick_fraction,
                             cheap=True, rel_tol=1e-4))
        out.append(Claim(f"excess_{v}V_{f}N", "-",
                         f"contact.simulate.simulate(table2(), {v}, {f}, energy=True).energy "
                         "(non_conservative_J / input_J)",
                         lambda v=v, f=f: _excess(v, f), cheap=True, rel_tol=1e-4))
    return tuple(out)


@cache
def _fe2d():
    from fem.geometry import PlateStator
    from fem.material import get_material
    from fem.modes import DEFAULT_REFINE, plate_modes

    return plate_modes(PlateStator(), get_material("pzt8"), 2, DEFAULT_REFINE)


@cache
def _fe_vs_3d():
    from fem.plane_stress_error import plane_stress_error

    return plane_stress_error()


@cache
def _beam():
    from rom.sources import get_params

    return get_params("beam")


@cache
def _fe_precision():
    from fem.modes import DEFAULT_REFINE
    from validation.work_precision import fe_work_precision

    points, ref = fe_work_precision({2: (DEFAULT_REFINE, 16)})
    default, fine = points
    return max(default.error_L1, default.error_B2), fine.wall_time_s / default.wall_time_s


@cache
def _render_measures() -> dict[str, float]:
    """Mirror difference and centre-line offset of the L1/B2 pictures (tests' 480 x 200 px)."""
    from fem.render import centre_line_offset_px, mirror_difference, mode_image

    model = _fe2d_model()
    out = {}
    for m in (_fe2d().L1, _fe2d().B2):
        img = mode_image(model, m, decorations=False, window_size=(480, 200))
        out[f"{m.name}_mirror"] = mirror_difference(img)
        out[f"{m.name}_offset"] = centre_line_offset_px(img)
    return out


@cache
def _fe2d_model():
    from fem.geometry import PlateStator
    from fem.material import get_material
    from fem.model import plate_model
    from fem.modes import DEFAULT_REFINE

    return plate_model(PlateStator(), get_material("pzt8"), 2, DEFAULT_REFINE)


@cache
def _order1_refine_for_target(target: float = 5e-4) -> float:
    """Smallest order-1 refine whose L1 and B2 are both within ``target`` of the reference."""
    from validation.work_precision import fe_work_precision

    points, _ = fe_work_precision({1: tuple(range(28, 41))})
    ok = [p.refine for p in points if max(p.error_L1, p.error_B2) <= target]
    return float(min(ok)) if ok else float("nan")


@cache
def _tuned():
    from fem.tuning import tune_plate

    return tune_plate(40e3)


@cache
def _gap_keff(model: str, gap_mm: float, refine: int | None = None,
              layers: int | None = None) -> float:
    """B2 k_eff of the paper plate with another electrode gap, 2D or 3D."""
    from fem.geometry import PlateStator
    from fem.material import get_material

    stator = PlateStator(electrode_gap_m=gap_mm * 1e-3)
    if model == "2d":
        from fem.modes import DEFAULT_REFINE, plate_modes

        return plate_modes(stator, get_material("pzt8"), 2, DEFAULT_REFINE).B2.k_eff
    from fem.solid3d import DEFAULT_LAYERS, DEFAULT_REFINE_3D, solid_modes

    return solid_modes(stator, get_material("pzt8"), 2, refine or DEFAULT_REFINE_3D,
                       layers or DEFAULT_LAYERS).B2.k_eff


@cache
def _isolated_pairs() -> dict[str, object]:
    """Resonance pairs of the admittance with all four electrodes in phase (L1) and with the
    B2 polarity (+ - - +), as in tests/test_admittance.py."""
    import numpy as np

    from fem.admittance import modal_port, resonance_pairs

    f = np.linspace(50e3, 62e3, 2401)
    out = {}
    for name, pol in (("L1", (1, 1, 1, 1)), ("B2", (1, -1, -1, 1))):
        port = modal_port(_fe2d_model(), 62e3, (1, 2, 3, 4), pol, 1e-4, 1e-4, 1e-4)
        (out[name],) = [p for p in resonance_pairs(port, f) if p.mode == name]
    return out


@cache
def _map_counts(ultrasonic_friction: bool = True, coupling: str = "paper") -> dict[str, int]:
    """Motion-class counts of the 9 x 9 map of ``lusm map`` (50-450 V x 10-26 N)."""
    import numpy as np

    from contact.maps import stick_slip_map
    from contact.simulate import SimulationOptions

    m = stick_slip_map(_table2(), np.arange(50.0, 451.0, 50.0), np.arange(10.0, 27.0, 2.0),
                       options=SimulationOptions(ultrasonic_friction=ultrasonic_friction,
                                                 coupling=coupling), progress=False)
    return m.counts()


@cache
def _work_precision() -> dict[str, float]:
    """Velocity errors of the 200 V / 14 N case against solve_ivp at rtol 1e-11."""
    from validation.work_precision import contact_work_precision

    points, _ = contact_work_precision(_table2(), cases=((200.0, 14.0),))
    out: dict[str, float] = {}
    for p in points:
        out[f"{p.method} {p.setting}"] = p.velocity_error
    return out


def _wp(prefix: str, setting: str | None = None, agg=max) -> float:
    wp = _work_precision()
    vals = [v for k, v in wp.items() if k.startswith(prefix) and (setting is None
                                                                  or k.endswith(setting))]
    return agg(vals)


@cache
def _dead_zone_edge(preload_N: float, coupling: str = "paper") -> float:
    from validation.hard_cases import dead_zone_edge

    return dead_zone_edge(_table2(), preload_N, coupling=coupling)


@cache
def _speed_stick_slip() -> tuple[float, float]:
    """(reference time / kernel time, |dv|/v) at 200 V / 14 N, 50 ms, dt = 1e-7 s."""
    from contact.simulate import simulate

    _sim(200.0, 14.0, 0.001)  # JIT / cache load
    times = [simulate(_table2(), 200.0, 14.0).wall_time_s for _ in range(5)]
    r = simulate(_table2(), 200.0, 14.0)
    ref = simulate(_table2(), 200.0, 14.0, method="reference")
    v_ref = ref.steady.velocity_m_s
    dv = abs(r.steady.velocity_m_s - v_ref) / abs(v_ref)
    return ref.wall_time_s / statistics.median(times), dv


# --- the claims --------------------------------------------------------------------------


CLAIMS: tuple[Claim, ...] = (
    Claim("table2_f_L1_Hz", "Hz", "lusm params --source table2",
          lambda: _table2().f_L1_Hz, cheap=True, rel_tol=1e-12),
    Claim("table2_f_B2_Hz", "Hz", "lusm params --source table2",
          lambda: _table2().f_B2_Hz, cheap=True, rel_tol=1e-12),
    Claim("beam_f_L1_Hz", "Hz", "lusm params --source beam",
          lambda: _beam().f_L1_Hz, cheap=True, rel_tol=1e-9),
    Claim("beam_f_B2_Hz", "Hz", "lusm params --source beam",
          lambda: _beam().f_B2_Hz, cheap=True, rel_tol=1e-9),
    Claim("fe2d_L1_short_Hz", "Hz", _MODES, lambda: _fe2d().L1.f_short_Hz, cheap=True,
          rel_tol=1e-8),
    Claim("fe2d_L1_open_Hz", "Hz", _MODES, lambda: _fe2d().L1.f_open_Hz, cheap=True,
          rel_tol=1e-8),
    Claim("fe2d_B2_short_Hz", "Hz", _MODES, lambda: _fe2d().B2.f_short_Hz, cheap=True,
          rel_tol=1e-8),
    Claim("fe2d_B2_open_Hz", "Hz", _MODES, lambda: _fe2d().B2.f_open_Hz, cheap=True,
          rel_tol=1e-8),
    Claim("fe2d_vs_3d_L1_short", "-", "lusm report (section 1, 2D vs 3D)",
          lambda: _fe_vs_3d().relative_error["L1_short"]),
    Claim("fe2d_vs_3d_L1_open", "-", "lusm report (section 1, 2D vs 3D)",
          lambda: _fe_vs_3d().relative_error["L1_open"]),
    Claim("fe2d_vs_3d_B2_short", "-", "lusm report (section 1, 2D vs 3D)",
          lambda: _fe_vs_3d().relative_error["B2_short"]),
    Claim("fe2d_vs_3d_B2_open", "-", "lusm report (section 1, 2D vs 3D)",
          lambda: _fe_vs_3d().relative_error["B2_open"]),
    Claim("fe2d_default_error", "-", "lusm report (section 3b, order 2 at the default refine)",
          lambda: _fe_precision()[0]),
    Claim("fe2d_default_time_ratio", "-",
          "lusm report (section 3b, wall time of refine 16 over the default refine)",
          lambda: _fe_precision()[1]),
    Claim("dead_zone_14N_V", "V", "lusm report (section 4, dead-zone edge); "
          "python -m validation.doc_numbers --show dead_zone_14N_V",
          lambda: _dead_zone_edge(14.0), cheap=True, rel_tol=1e-3),
    Claim("dead_zone_14N_vs_paper", "-", "dead_zone_14N_V / 120 V - 1 (paper, Fig. 24)",
          lambda: _dead_zone_edge(14.0) / 120.0 - 1.0, cheap=True, rel_tol=1e-2),
    Claim("dead_zone_14N_consistent_V", "V",
          "python -m validation.doc_numbers --show dead_zone_14N_consistent_V",
          lambda: _dead_zone_edge(14.0, "consistent"), cheap=True, rel_tol=1e-3),
    Claim("v_200V_14N_m_s", "m/s", _SIM.format(v=200, f=14),
          lambda: _sim(200.0, 14.0).steady.velocity_m_s, cheap=True, rel_tol=1e-5),
    Claim("v_400V_14N_m_s", "m/s", _SIM.format(v=400, f=14),
          lambda: _sim(400.0, 14.0).steady.velocity_m_s, cheap=True, rel_tol=1e-5),
    Claim("v_400V_14N_settled_m_s", "m/s", _SIM.format(v=400, f=14) + " --duration 0.2",
          lambda: _sim(400.0, 14.0, 0.2).steady.velocity_m_s, cheap=True, rel_tol=1e-5),
    Claim("v_150V_14N_m_s", "m/s", _SIM.format(v=150, f=14),
          lambda: _sim(150.0, 14.0).steady.velocity_m_s, cheap=True, rel_tol=1e-4),
    Claim("stick_200V_14N", "-", _SIM.format(v=200, f=14) + " (stick_fraction)",
          lambda: _sim(200.0, 14.0).steady.stick_fraction, cheap=True, rel_tol=1e-4),
    Claim("stick_200V_18N", "-", _SIM.format(v=200, f=18) + " (stick_fraction)",
          lambda: _sim(200.0, 18.0).steady.stick_fraction, cheap=True, rel_tol=1e-4),
    Claim("A_N_200V_14N_m", "m", _SIM.format(v=200, f=14) + " (normal_amplitude_m)",
          lambda: _sim(200.0, 14.0).normal_amplitude_m, cheap=True, rel_tol=1e-6),
    Claim("A_N_450V_14N_m", "m", _SIM.format(v=450, f=14) + " (normal_amplitude_m)",
          lambda: _sim(450.0, 14.0).normal_amplitude_m, cheap=True, rel_tol=1e-6),
    Claim("normal_swing_200V_14N_N", "N", "2 k A_N at 200 V / 14 N (lusm params; A_N above)",
          lambda: 2 * _table2().k_contact * _sim(200.0, 14.0).normal_amplitude_m,
          cheap=True, rel_tol=1e-6),
    Claim("events_200V_14N", "-", _SIM.format(v=200, f=14) + " (events)",
          lambda: float(_sim(200.0, 14.0).events), cheap=True, rel_tol=1e-3),
    Claim("map_slip_separation", "-", "lusm map --json (counts)",
          lambda: _map_counts().get("slip-separation", 0)),
    Claim("map_stick_slip", "-", "lusm map --json (counts)",
          lambda: _map_counts().get("stick-slip", 0)),
    Claim("map_pure_stick", "-", "lusm map --json (counts)",
          lambda: _map_counts().get("pure-stick", 0)),
    Claim("map_pure_slip", "-", "lusm map --json (counts)",
          lambda: _map_counts().get("pure-slip", 0)),
    Claim("map_const_mu_stick_slip", "-", "lusm map --no-ultrasonic-friction --json (counts)",
          lambda: _map_counts(False).get("stick-slip", 0)),
    Claim("map_const_mu_pure_slip", "-", "lusm map --no-ultrasonic-friction --json (counts)",
          lambda: _map_counts(False).get("pure-slip", 0)),
    Claim("map_consistent_stick_slip", "-", "lusm map --coupling consistent --json (counts)",
          lambda: _map_counts(True, "consistent").get("stick-slip", 0)),
    Claim("map_consistent_pure_stick", "-", "lusm map --coupling consistent --json (counts)",
          lambda: _map_counts(True, "consistent").get("pure-stick", 0)),
    Claim("wp_event_dt_1250ns", "-", "lusm report (section 3a, event-located, dt = 1.25e-06 s)",
          lambda: _wp("event", "dt = 1.25e-06 s")),
    Claim("wp_event_dt_100ns", "-", "lusm report (section 3a, event-located, dt = 1e-07 s)",
          lambda: _wp("event", "dt = 1e-07 s")),
    Claim("wp_event_dt_25ns", "-", "lusm report (section 3a, event-located, dt = 2.5e-08 s)",
          lambda: _wp("event", "dt = 2.5e-08 s")),
    Claim("wp_literal_eps_paper_min", "-", "lusm report (section 3a, literal RK4, eps = 1e-10)",
          lambda: _wp("literal RK4, eps = 1e-10", agg=min)),
    Claim("wp_literal_eps_paper_max", "-", "lusm report (section 3a, literal RK4, eps = 1e-10)",
          lambda: _wp("literal RK4, eps = 1e-10", agg=max)),
    Claim("wp_literal_eps_wide_min", "-", "lusm report (section 3a, literal RK4, eps = 0.0001)",
          lambda: _wp("literal RK4, eps = 0.0001", agg=min)),
    Claim("wp_literal_eps_wide_max", "-", "lusm report (section 3a, literal RK4, eps = 0.0001)",
          lambda: _wp("literal RK4, eps = 0.0001", agg=max)),
    Claim("render_mirror_L1", "-", "python -m validation.doc_numbers --show render_mirror_L1",
          lambda: _render_measures()["L1_mirror"]),
    Claim("render_mirror_B2", "-", "python -m validation.doc_numbers --show render_mirror_B2",
          lambda: _render_measures()["B2_mirror"]),
    Claim("render_offset_L1_px", "px", "python -m validation.doc_numbers --show "
          "render_offset_L1_px", lambda: _render_measures()["L1_offset"]),
    Claim("render_offset_B2_px", "px", "python -m validation.doc_numbers --show "
          "render_offset_B2_px", lambda: _render_measures()["B2_offset"]),
    Claim("fe_order1_refine_target", "-",
          "python -m validation.doc_numbers --show fe_order1_refine_target (order-1 refines "
          "28-40 against the Richardson reference)", _order1_refine_for_target),
    Claim("tune_length_m", "m", "lusm tune --target-frequency 40e3 --json",
          lambda: _tuned().stator.length_m),
    Claim("tune_width_m", "m", "lusm tune --target-frequency 40e3 --json",
          lambda: _tuned().stator.width_m),
    Claim("tune_fe_solves", "-", "lusm tune --target-frequency 40e3 --json (fe_solves)",
          lambda: _tuned().fe_solves),
    Claim("tune_outer_iterations", "-",
          "lusm tune --target-frequency 40e3 --json (outer_iterations)",
          lambda: _tuned().outer_iterations),
    Claim("fe2d_B2_keff_gap002", "-", "lusm modes --gap-mm 0.02 --json",
          lambda: _gap_keff("2d", 0.02), cheap=True, rel_tol=1e-6),
    Claim("fe3d_B2_keff_gap002_default", "-", "lusm modes --model 3d --gap-mm 0.02 --json",
          lambda: _gap_keff("3d", 0.02)),
    Claim("fe3d_B2_keff_gap002_r4l4", "-",
          "lusm modes --model 3d --gap-mm 0.02 --refine 4 --layers 4 --json",
          lambda: _gap_keff("3d", 0.02, 4, 4)),
    Claim("fe3d_B2_keff_gap002_r6l6", "-",
          "lusm modes --model 3d --gap-mm 0.02 --refine 6 --layers 6 --json",
          lambda: _gap_keff("3d", 0.02, 6, 6)),
    Claim("adm_L1_isolated_fr_Hz", "Hz", "pytest tests/test_admittance.py (isolated L1)",
          lambda: _isolated_pairs()["L1"].f_resonance_Hz, cheap=True, rel_tol=1e-6),
    Claim("adm_L1_isolated_fa_Hz", "Hz", "pytest tests/test_admittance.py (isolated L1)",
          lambda: _isolated_pairs()["L1"].f_antiresonance_Hz, cheap=True, rel_tol=1e-6),
    Claim("adm_L1_isolated_keff", "-", "pytest tests/test_admittance.py (isolated L1)",
          lambda: _isolated_pairs()["L1"].k_eff, cheap=True, rel_tol=1e-5),
    Claim("adm_B2_isolated_keff", "-", "pytest tests/test_admittance.py (isolated B2)",
          lambda: _isolated_pairs()["B2"].k_eff, cheap=True, rel_tol=1e-5),
    Claim("fe2d_L1_keff", "-", _MODES, lambda: _fe2d().L1.k_eff, cheap=True, rel_tol=1e-6),
    Claim("fe2d_B2_keff", "-", _MODES, lambda: _fe2d().B2.k_eff, cheap=True, rel_tol=1e-6),
    Claim("contact_speed_ratio", "-", "python benchmarks/contact_speed.py (200 V / 14 N row)",
          lambda: _speed_stick_slip()[0]),
    Claim("contact_vs_reference_dv", "-", "python benchmarks/contact_speed.py (dv/v column)",
          lambda: _speed_stick_slip()[1]),
    *_coupling_claims(),
)
"""Every quoted result, in the order the generator computes them."""


def claims_by_key() -> dict[str, Claim]:
    """The claims indexed by key."""
    return {c.key: c for c in CLAIMS}


def machine() -> str:
    """One line naming the machine the numbers were measured on."""
    return (f"{os.cpu_count()} CPUs, {platform.machine()}, Python {platform.python_version()}, "
            f"{platform.system()}")


def compute(keys: list[str] | None = None) -> dict:
    """Compute the claims (all, or ``keys``) into the ``numbers.json`` document."""
    table = claims_by_key()
    unknown = [k for k in keys or [] if k not in table]
    if unknown:
        raise ValueError(f"--show: unknown key {unknown[0]!r}; known: {', '.join(table)}")
    numbers = {}
    for key in keys or list(table):
        c = table[key]
        value = float(c.compute())
        numbers[key] = {"value": value if math.isfinite(value) else None, "unit": c.unit,
                        "command": c.command}
    return {"generated_by": "python -m validation.doc_numbers",
            "date": time.strftime("%Y-%m-%d", time.gmtime()), "machine": machine(),
            "numbers": numbers}


def main(argv: list[str] | None = None) -> int:
    """``python -m validation.doc_numbers [--out docs/numbers.json] [--show KEY ...]``."""
    ap = argparse.ArgumentParser(prog="python -m validation.doc_numbers",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=NUMBERS_JSON, help="where to write the JSON")
    ap.add_argument("--show", nargs="+", metavar="KEY",
                    help="compute and print these claims only (nothing written)")
    ap.add_argument("--fill", action="store_true",
                    help="rewrite the marked numbers in the docs from --out (no computing)")
    args = ap.parse_args(argv)
    if args.fill:
        n = fill(json.loads(args.out.read_text()))
        print(f"{n} quoted numbers updated from {args.out}")
        return 0
    try:
        doc = compute(args.show)
    except ValueError as exc:
        print(f"doc_numbers: error: {exc}")
        return 2
    if args.show:
        for key, entry in doc["numbers"].items():
            print(f"{key} = {entry['value']:.6g} {entry['unit']}   ({entry['command']})")
        return 0
    tmp = args.out.with_name(args.out.name + ".partial")
    tmp.write_text(json.dumps(doc, indent=1) + "\n")
    os.replace(tmp, args.out)
    print(f"{len(doc['numbers'])} numbers written to {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
