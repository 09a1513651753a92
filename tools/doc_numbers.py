"""The numbers the README and ``docs/`` quote, computed in one place.

Every result quoted in the documentation is a *claim* here: a key, the function that computes
it, its unit, the command a reader runs to see it, and whether a test may recompute it
(``cheap``: well under a second or two). ``python -m tools.doc_numbers`` computes them
all and writes ``docs/numbers.json`` (with the machine and date); in the Markdown each quoted
number carries an invisible marker right after it::

    pure stick up to 139.1<!--n:dead_zone_14N_V--> V
    L1 ≈ 56.5<!--n:fe2d_L1_short_Hz*1e-3--> kHz

``*factor`` scales the stored value to the printed unit. ``tests/test_docs_numbers.py`` checks
that every marked number equals ``numbers.json`` to the precision it is printed with, that
every key exists, and recomputes the cheap claims against ``numbers.json``. To add a claim:
add a :class:`Claim` to :data:`CLAIMS`, mark the number in the Markdown, run
``python -m tools.doc_numbers --update KEY`` (only that claim; or no option for all of
them) and then ``--fill``. A document joins the check by being listed in :data:`DOC_FILES`.
Numbers that are not results (the plate's
``30 × 7.5 × 3 mm``, the paper's published values, test tolerances) end with
``<!--input-->`` or ``<!--paper-->``, which covers every number since the previous marker
within its paragraph, table row or list item; ``LINTED`` in the test lists the documents in
which every number with a unit must be covered (every file of :data:`DOC_FILES`). Whole
tables printed by a benchmark are not claims but generated blocks
(:mod:`tools.doc_tables`), which the lint skips. A marker never goes inside backticks
(it would show on GitHub).

Timings are claims only as ratios measured in the same run (``*_ratio``, or the ratios of one
benchmark run), never as absolute seconds, with one exception: the wall times of a fresh
``lusm`` process (``startup_*_s``), because the start-up target is itself absolute; the
machine they were measured on is stored beside them. Expensive claims (benchmarks of minutes:
``steady_map_*``, ``explore_*``) are not ``cheap``, so the tests only check that the Markdown
quotes ``numbers.json``; the claims of one benchmark share a ``batch`` and are computed
together in one fresh process, so that ``--update 'explore_*'`` runs the benchmark once.
"""

from __future__ import annotations

import argparse
import fnmatch
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

from fem.mesh_settings import MeshSettings

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
    batch : str
        Claims sharing one expensive run (a benchmark): the generator computes all the claims
        of a batch in one fresh process, so the run is made once and its timings are not
        disturbed by the claims computed before it. Empty: no batch.
    """

    key: str
    unit: str
    command: str
    compute: Callable[[], float]
    cheap: bool = False
    rel_tol: float = 1e-6
    batch: str = ""

    @property
    def timing(self) -> bool:
        """Whether this is a speed ratio: measured in a fresh process by :func:`compute`
        (the start-up ratios spawn their own processes).

        In the generator's own process the FE and map claims before it leave BLAS threads and
        caches behind that changed measured ratios up to tenfold.
        """
        return self.key.endswith("_ratio") and not self.key.startswith("startup_")


def _mean_normal_force(voltage_V: float, preload_N: float) -> float:
    """The period mean of F_N (N) on the orbit a start from rest reaches (Table 2's set)."""
    from contact.steady.engine import steady_state

    return steady_state(_table2(), voltage_V, preload_N, energy=False).from_rest.mean_FN_N


def _in_fresh_process(keys: list[str]) -> list[float]:
    """The values of the claims ``keys`` computed, in order, by one new interpreter."""
    import subprocess
    import sys

    code = ("from tools.doc_numbers import claims_by_key; t = claims_by_key(); "
            f"[print(repr(float(t[k].compute()))) for k in {keys!r}]")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)})
    if out.returncode:  # the child's own last line (an ImportError of a missing install, ...)
        last = (out.stderr.strip().splitlines() or ["no output"])[-1]
        raise SystemExit(f"doc_numbers: the fresh process for {', '.join(keys)} failed "
                         f"(exit {out.returncode}): {last}")
    return [float(v) for v in out.stdout.split()[-len(keys):]]


_ISOLATED = ("python -m tools.doc_numbers --show 'adm_*_isolated_*' (isolated {}; "
             "tests/test_admittance.py)")
_MODES = "lusm modes --json"
_SIM = "lusm simulate --voltage {v} --preload {f} --json"


# --- shared computations (each done once per process) ------------------------------------


@cache
def _table2():
    from rom import table2

    return table2()


@cache
def _free_tip_amplitudes(voltage_V: float) -> tuple[float, float]:
    """Table 2's free (no preload) L1 and B2 tip amplitudes (m) at 40 kHz."""
    from rom.damping import free_tip_amplitudes

    a_l, a_b = free_tip_amplitudes(_table2(), 40e3, voltage_V)
    return float(a_l), float(a_b)


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
    from fem.meshing.mesh import DEFAULT_REFINE
    from fem.modes import plate_modes

    return plate_modes(PlateStator(), get_material("pzt8"), MeshSettings(2, DEFAULT_REFINE))


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
    from fem.meshing.mesh import DEFAULT_REFINE
    from validation.work_precision import fe_work_precision

    # best of 5: one timing of the default mesh (tens of ms) moved the ratio from 4 to 10
    points, ref = fe_work_precision({2: (DEFAULT_REFINE, 16)}, repeat=5)
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
    from fem.meshing.mesh import DEFAULT_REFINE
    from fem.model import plate_model

    return plate_model(PlateStator(), get_material("pzt8"), MeshSettings(2, DEFAULT_REFINE))


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
def _tuned_fixed_length(model: str = "2d"):
    """``lusm tune --fix length --length-mm 35 [--model 3d]``: the width tuned until L1 = B2."""
    from fem.geometry import PlateStator
    from fem.tuning import tune_plate

    return tune_plate(fix="length", start=PlateStator(length_m=35e-3), model=model)


@cache
def _fixed_length_checks() -> dict[str, float]:
    """The 2D fixed-length design re-solved on a finer 2D mesh and on the default 3D mesh."""
    from fem.modes import plate_modes
    from fem.solid3d.model import solid_modes

    st = _tuned_fixed_length("2d").stator
    fine, solid = plate_modes(st, mesh=MeshSettings(refine=8)), solid_modes(st)
    return {"split_refine8": (fine.B2.f_short_Hz - fine.L1.f_short_Hz) / fine.L1.f_short_Hz,
            "split_3d": (solid.B2.f_short_Hz - solid.L1.f_short_Hz) / solid.L1.f_short_Hz}


@cache
def _fixed_length_thickness_spans() -> dict[str, dict[str, float]]:
    """``python benchmarks/tune_fixed_length_3d.py --json`` (h = 1..5 mm at l = 35 mm)."""
    import subprocess
    import sys

    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    run = subprocess.run([sys.executable, "benchmarks/tune_fixed_length_3d.py", "--json"],
                         capture_output=True, text=True, check=True, cwd=ROOT, env=env)
    return json.loads(run.stdout.strip().splitlines()[-1])


@cache
def _gap_keff(model: str, gap_mm: float, refine: int | None = None,
              layers: int | None = None) -> float:
    """B2 k_eff of the paper plate with another electrode gap, 2D or 3D."""
    from fem.geometry import PlateStator
    from fem.material import get_material

    stator = PlateStator(electrode_gap_m=gap_mm * 1e-3)
    if model == "2d":
        from fem.meshing.mesh import DEFAULT_REFINE
        from fem.modes import plate_modes

        return plate_modes(stator, get_material("pzt8"), MeshSettings(2, DEFAULT_REFINE)).B2.k_eff
    from fem.solid3d.model import DEFAULT_LAYERS, DEFAULT_REFINE_3D, solid_modes

    mesh = MeshSettings(2, refine or DEFAULT_REFINE_3D, layers or DEFAULT_LAYERS)
    return solid_modes(stator, get_material("pzt8"), mesh).B2.k_eff


@cache
@cache
def _fe2d_no_inertia():
    """The default 2D plate without the thickness inertia of docs/fem.md 1.3."""
    from fem.geometry import PlateStator
    from fem.meshing.mesh import DEFAULT_REFINE
    from fem.modes import plate_modes

    return plate_modes(PlateStator(), "pzt8",
                       MeshSettings(2, DEFAULT_REFINE, thickness_inertia=False))


def _isolated_b2_damping_drift() -> float:
    """Relative change of the isolated B2 port's k_eff (polarity + - - +) from zeta = 1e-4
    to 0.01 (docs/fem3d.md 4: the 0.5 % of the 1 + 4 drive is not this port's)."""
    from fem.admittance import plate_admittance

    k = [plate_admittance(f_min_Hz=50e3, f_max_Hz=60e3, n_points=3001, electrodes=(1, 2, 3, 4),
                          polarity=(1, -1, -1, 1), zeta=z).pairs[0].k_eff for z in (1e-4, 1e-2)]
    return k[1] / k[0] - 1


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
    from contact.options import SimulationOptions

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


# --- docs/beam.md: Appendix A beam theory against Table 2 and the paper's ANSYS -----------


@cache
def _beam_numbers() -> dict[str, float]:
    """Every figure of docs/beam.md, from rom.beam at its defaults (well under a second)."""
    import numpy as np

    from fem.beam_shapes import phi_B
    from fem.material import get_material
    from rom.beam import beam_constants, beam_frequencies, euler_bernoulli_b2_frequency
    from rom.table2 import PAPER_ANSYS_HZ, TABLE1

    c, f, b, t = beam_constants(), beam_frequencies(), _beam(), _table2()
    rho, length = TABLE1["rho_kg_m3"], TABLE1["length_m"]
    area = TABLE1["width_m"] * TABLE1["thickness_m"]

    def hz(k: float) -> float:
        return math.sqrt(k / c.M_b) / (2 * math.pi)

    out = {"I_m4": c.inertia_m4, "phi_B_end": abs(c.phi_Bl), "eta_T": c.phi_B0 - c.phi_Bl,
           "dphi_B_0_per_m": float(phi_B(0.0, length, 1)),
           "dphi_B_mid_per_m": float(phi_B(length / 2, length, 1)),
           "zeta_L1": t.C_l / (2 * math.sqrt(t.K_l * t.M_l)),
           "zeta_B2": t.C_b / (2 * math.sqrt(t.K_b * t.M_b))}
    out["Q_L1"], out["Q_B2"] = 1 / (2 * out["zeta_L1"]), 1 / (2 * out["zeta_B2"])
    for name in ("M_l", "K_l", "C_l", "A_l", "M_b", "K_b", "C_b", "A_b"):
        out[name] = getattr(b, name)
        out[f"{name}_vs_t2"] = getattr(b, name) / getattr(t, name) - 1  # as lusm compare
    rows = {"L1": f.f_L1_Hz, "B2_eb": f.f_B2_euler_bernoulli_Hz, "B2_printed": hz(c.K_b_printed),
            "B2_shear": hz(c.K_b_shear), "B2_condensed": f.f_B2_condensed_Hz,
            "B2_timoshenko": f.f_B2_timoshenko_Hz}
    for name, value in rows.items():
        mode = name[:2]
        out[f"f_{name}_Hz"] = value
        out[f"f_{name}_vs_t2"] = value / getattr(t, f"f_{mode}_Hz") - 1
        out[f"f_{name}_vs_ansys"] = value / PAPER_ANSYS_HZ[mode] - 1
    for name in ("printed", "shear", "timoshenko"):
        k = getattr(c, f"K_b_{name}")
        out[f"K_b_{name}"] = k
        out[f"K_b_{name}_vs_t2"] = k / t.K_b - 1
    out["A_b_timoshenko"] = c.A_b_timoshenko
    out["EI_factor_to_t2"] = c.K_b_bending / t.K_b
    out["c11_for_ansys_L1_Pa"] = rho * (2 * length * PAPER_ANSYS_HZ["L1"]) ** 2
    out["c11_implied_by_t2_Pa"] = 2 * length * t.K_l / (area * math.pi**2)
    out["M_l_t2_over_rhoAl"] = t.M_l / (rho * area * length)
    s11 = float(np.linalg.inv(np.asarray(get_material("pzt8").cE_Pa))[0, 0])
    out["pzt8_inv_sE11_Pa"] = 1 / s11
    out["f_L1_free_sE11_Hz"] = math.sqrt(1 / s11 / rho) / (2 * length)
    out["timoshenko_lowering"] = 1 - f.f_B2_timoshenko_Hz / f.f_B2_euler_bernoulli_Hz
    out["A_l_t2_over_beam"] = t.A_l / b.A_l
    out["A_l_full_electrode"] = 2 * b.A_l
    out["A_l_t2_over_full"] = t.A_l / (2 * b.A_l)
    out["rayleigh_vs_closed"] = abs(f.f_B2_euler_bernoulli_Hz / euler_bernoulli_b2_frequency() - 1)
    return out


_BEAM_UNITS = {"I_m4": "m^4", "dphi_B_0_per_m": "1/m", "dphi_B_mid_per_m": "1/m",
               "M_l": "kg", "K_l": "N/m", "C_l": "N s/m", "A_l": "N/V", "M_b": "kg",
               "K_b": "N/m", "C_b": "N s/m", "A_b": "N/V", "K_b_printed": "N/m",
               "K_b_shear": "N/m", "K_b_timoshenko": "N/m", "A_b_timoshenko": "N/V",
               "c11_for_ansys_L1_Pa": "Pa", "c11_implied_by_t2_Pa": "Pa", "pzt8_inv_sE11_Pa": "Pa",
               "f_L1_free_sE11_Hz": "Hz", "A_l_full_electrode": "N/V"}
_BEAM_KEYS = ("I_m4", "phi_B_end", "eta_T", "dphi_B_0_per_m", "dphi_B_mid_per_m", "zeta_L1",
              "zeta_B2", "Q_L1", "Q_B2",
              *(f"{n}{s}" for n in ("M_l", "K_l", "C_l", "A_l", "M_b", "K_b", "C_b", "A_b")
                for s in ("", "_vs_t2")),
              *(f"f_{n}{s}" for n in ("L1", "B2_eb", "B2_printed", "B2_shear", "B2_condensed",
                                      "B2_timoshenko") for s in ("_Hz", "_vs_t2", "_vs_ansys")),
              *(f"K_b_{n}{s}" for n in ("printed", "shear", "timoshenko") for s in ("", "_vs_t2")),
              "A_b_timoshenko", "EI_factor_to_t2", "c11_for_ansys_L1_Pa", "c11_implied_by_t2_Pa",
              "M_l_t2_over_rhoAl", "pzt8_inv_sE11_Pa", "f_L1_free_sE11_Hz", "timoshenko_lowering",
              "A_l_t2_over_beam", "A_l_full_electrode", "A_l_t2_over_full", "rayleigh_vs_closed")
"""Keys of :func:`_beam_numbers` (listed so that importing this module computes nothing)."""


def _beam_claims() -> tuple[Claim, ...]:
    """The docs/beam.md claims: cheap, recomputed by the tests to 1e-9."""
    return tuple(Claim(f"beam_{k}", _BEAM_UNITS.get(k, "Hz" if k.endswith("_Hz") else "-"),
                       f"python -m tools.doc_numbers --show beam_{k} "
                       "(rom.beam with Table 2's ratios; lusm compare)",
                       lambda k=k: _beam_numbers()[k], cheap=True, rel_tol=1e-9)
                 for k in _BEAM_KEYS)


# --- docs/designer.md: the example stators and their perturbation estimates --------------


@cache
def _designer_numbers() -> dict[str, float]:
    """The table and estimates of docs/designer.md (examples/*, order 2; a few seconds).

    The perturbation estimate is the one of tests/test_examples_stators.py: mass-only,
    ``df/f = -+ 1/2 dm <|phi|^2>`` with the plain plate's mass-normalized shapes (refine 8).
    """
    import importlib.util
    import tempfile

    import numpy as np

    from fem.geometry import PlateStator
    from fem.meshing.mesh_io import read_stator_mesh, write_stator_msh
    from fem.meshing.meshed_stator import MeshedStator
    from fem.model import build_model, plate_model
    from fem.modes import modes_of_model, plate_modes
    from fem.stator_file import load_stator

    examples = ROOT / "examples"
    rho_h = 7600.0 * 3e-3  # PZT-8 density x thickness (kg/m^2)
    plain = plate_modes(PlateStator(), "pzt8", MeshSettings(2, 8))
    model = plate_model(PlateStator(), "pzt8", MeshSettings(2, 8))
    sets = {"plain": plain}
    for name in ("tip_protrusion", "chamfered"):
        sets[name] = load_stator(examples / name / "stator.toml").modes()
    out: dict[str, float] = {}
    for name, res in sets.items():
        out[f"{name}_dofs"] = res.dofs
        for mode in ("L1", "B2"):
            m = getattr(res, mode)
            out[f"{name}_{mode}_short_Hz"] = m.f_short_Hz
            out[f"{name}_{mode}_open_Hz"] = m.f_open_Hz
            out[f"{name}_{mode}_mac"] = m.mac
            if name != "plain":
                out[f"{name}_{mode}_shift"] = m.f_short_Hz / getattr(plain, mode).f_short_Hz - 1

    def mean_sq(shape, points):
        u = (model.probe(points) @ shape).reshape(2, -1)
        return float(np.mean(np.sum(u * u, axis=0)))

    xs = np.linspace(-1e-3, 1e-3, 21)
    tip_end = np.vstack((xs, np.full_like(xs, 30e-3)))
    c, w2, length = 1.5e-3, 3.75e-3, 30e-3
    g = np.linspace(0.0, 1.0, 41)[1:-1]
    u, v = np.meshgrid(g, g)
    keep = u + v > 1.0
    pts = [np.vstack((sx * (w2 - c + u[keep] * c), length - (c - v[keep] * c) if far
                      else c - v[keep] * c)) for sx in (1.0, -1.0) for far in (False, True)]
    corners = np.hstack(pts) * (1.0 - 1e-9)
    for name, dm, where, sign in (("tip_protrusion", rho_h * 2e-3 * 1e-3, tip_end, -1.0),
                                  ("chamfered", rho_h * 2 * c * c, corners, 1.0)):
        for mode in ("L1", "B2"):
            est = sign * 0.5 * dm * mean_sq(getattr(plain, mode).shape, where)
            out[f"{name}_{mode}_estimate"] = est
            out[f"{name}_{mode}_fe_over_estimate"] = out[f"{name}_{mode}_shift"] / est - 1

    path = examples / "chamfered" / "make_mesh.py"
    spec = importlib.util.spec_from_file_location("make_mesh_chamfered", path)
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    with tempfile.TemporaryDirectory() as tmp:
        msh = write_stator_msh(Path(tmp) / "t.msh", *script.chamfered_mesh(chamfer_m=0.0),
                               file_format="gmsh22")
        imp = read_stator_mesh(msh)
    st = MeshedStator(length_m=30e-3, width_m=7.5e-3, thickness_m=3e-3, electrode_gap_m=0.0,
                      mesh=imp.mesh, tip_m=imp.points_m["tip"], preload_m=(0.0, 0.0))
    tri = modes_of_model(build_model(imp.mesh, st, "pzt8", 2))
    out["triangulated_dofs"] = tri.dofs
    for mode in ("L1", "B2"):
        out[f"triangulated_{mode}_rel"] = abs(getattr(tri, mode).f_short_Hz
                                              / getattr(plain, mode).f_short_Hz - 1)
    return out


_DESIGNER_KEYS = (
    *(f"{n}_{k}" for n in ("plain", "tip_protrusion", "chamfered") for k in (
        "dofs", *(f"{m}_{q}" for m in ("L1", "B2") for q in ("short_Hz", "open_Hz", "mac")))),
    *(f"{n}_{m}_{q}" for n in ("tip_protrusion", "chamfered") for m in ("L1", "B2")
      for q in ("shift", "estimate", "fe_over_estimate")),
    "triangulated_dofs", "triangulated_L1_rel", "triangulated_B2_rel")
"""Keys of :func:`_designer_numbers` (listed so that importing this module computes nothing)."""


def _designer_claims() -> tuple[Claim, ...]:
    """The docs/designer.md claims (FE runs of the examples: not recomputed by the tests;
    tests/test_examples_stators.py checks the same physics against bounds)."""
    def cmd(k: str) -> str:
        if k.startswith("plain"):
            return "lusm modes --refine 8 --json"
        for name in ("tip_protrusion", "chamfered"):
            if k.startswith(name) and k.endswith(("Hz", "mac", "dofs")):
                return f"lusm modes --geometry examples/{name}/stator.toml --json"
            if k.startswith(name) and k.endswith("shift"):  # against the refine-8 plain plate
                return (f"python -m tools.doc_numbers --show designer_{k} (f_short of "
                        f"lusm modes --geometry examples/{name}/stator.toml over that of "
                        f"lusm modes --refine 8, minus 1)")
        return f"python -m tools.doc_numbers --show designer_{k}"

    return tuple(Claim(f"designer_{k}", "Hz" if k.endswith("Hz") else "-", cmd(k),
                       lambda k=k: _designer_numbers()[k]) for k in _DESIGNER_KEYS)


# --- docs/designer.md: parametric stators (fem.meshing.parametric, gmsh) -------------------


@cache
def _parametric_numbers() -> dict[str, float]:
    """examples/tip_parametric against examples/tip_protrusion, [chamfers] against
    examples/chamfered, the mesh cost, and fixed-length tuning of the tip stator (2D; the
    tuned plate re-solved on a mesh twice as fine and in 3D)."""
    from dataclasses import replace

    from fem.meshing.parametric import parametric_mesh
    from fem.model import build_model
    from fem.modes import modes_of_model, plate_modes
    from fem.solid3d.model import solid_modes
    from fem.stator_file import load_stator, parse_stator
    from fem.tuning import tune_plate

    ex = ROOT / "examples"
    par = load_stator(ex / "tip_parametric" / "stator.toml")
    msh = load_stator(ex / "tip_protrusion" / "stator.toml")
    cham = parse_stator({"plate": {"length_mm": 30, "width_mm": 7.5, "thickness_mm": 3},
                         "chamfers": {"size_mm": 1.5}}, src="chamfers")
    cham_msh = load_stator(ex / "chamfered" / "stator.toml")
    out: dict[str, float] = {}
    rp, rm = par.modes(), msh.modes()
    fine = plate_modes(replace(par.stator, mesh_size_m=par.stator.element_size_m / 4), par.material,
                       MeshSettings(2))
    rc, rcm = cham.modes(), cham_msh.modes()
    out["tip_dofs"], out["tip_fine_dofs"], out["chamfer_dofs"] = rp.dofs, fine.dofs, rc.dofs
    for mode in ("L1", "B2"):
        f = getattr(rp, mode).f_short_Hz
        out[f"tip_{mode}_short_Hz"] = f
        out[f"tip_{mode}_rel_msh"] = abs(f / getattr(rm, mode).f_short_Hz - 1)
        out[f"tip_{mode}_rel_fine"] = abs(f / getattr(fine, mode).f_short_Hz - 1)
        out[f"chamfer_{mode}_short_Hz"] = getattr(rc, mode).f_short_Hz
        out[f"chamfer_{mode}_rel_msh"] = abs(getattr(rc, mode).f_short_Hz
                                             / getattr(rcm, mode).f_short_Hz - 1)
    t0 = time.perf_counter()
    for _ in range(5):
        parametric_mesh(par.stator, cached=False)
    t_mesh = (time.perf_counter() - t0) / 5
    # against warm, uncached analyses on the same mesh (assembly and both eigensolutions):
    # the first solve of the process also paid its imports, and the ratio moved 1.3-4 %
    mesh = parametric_mesh(par.stator)
    t_fe = []
    for _ in range(3):
        t0 = time.perf_counter()
        modes_of_model(build_model(mesh, par.stator, par.material, 2))
        t_fe.append(time.perf_counter() - t0)
    out["mesh_time_ratio"] = t_mesh / min(t_fe)
    d = tune_plate(None, fix="length", material=par.material, start=par.stator)
    out["fixlen_width_m"] = d.stator.width_m
    out["fixlen_frequency_Hz"] = d.frequency_Hz
    out["fixlen_split"] = d.relative_mismatch
    out["fixlen_fe_solves"] = d.fe_solves
    f2 = plate_modes(replace(d.stator, mesh_size_m=d.stator.element_size_m / 2), par.material,
                     MeshSettings(2))
    out["fixlen_split_fine"] = f2.B2.f_short_Hz / f2.L1.f_short_Hz - 1
    f3 = solid_modes(d.stator, par.material, MeshSettings(2))
    out["fixlen_split_3d"] = f3.B2.f_short_Hz / f3.L1.f_short_Hz - 1
    return out


_PARAMETRIC_KEYS = (
    "tip_dofs", "tip_fine_dofs", "chamfer_dofs",
    *(f"{n}_{m}_{q}" for n, qs in (("tip", ("short_Hz", "rel_msh", "rel_fine")),
                                   ("chamfer", ("short_Hz", "rel_msh")))
      for m in ("L1", "B2") for q in qs),
    "mesh_time_ratio", "fixlen_width_m", "fixlen_frequency_Hz", "fixlen_split",
    "fixlen_fe_solves", "fixlen_split_fine", "fixlen_split_3d")
"""Keys of :func:`_parametric_numbers`."""


def _parametric_claims() -> tuple[Claim, ...]:
    """The docs/designer.md claims on parametric stators (gmsh; about a minute with the 3D
    solve, not recomputed by the tests; tests/test_parametric.py checks the same agreements
    against bounds)."""
    def cmd(k: str) -> str:
        if k.startswith("tip_") and k.endswith(("short_Hz", "tip_dofs")):
            return "lusm modes --geometry examples/tip_parametric/stator.toml --json"
        if k.startswith("fixlen_") and k != "fixlen_split_fine" and k != "fixlen_split_3d":
            return "lusm tune --geometry examples/tip_parametric/stator.toml --fix length --json"
        return f"python -m tools.doc_numbers --show param_{k}"

    def unit(k: str) -> str:
        return "Hz" if k.endswith("Hz") else "m" if k.endswith("_m") else "-"

    return tuple(Claim(f"param_{k}", unit(k), cmd(k), lambda k=k: _parametric_numbers()[k],
                       batch="parametric") for k in _PARAMETRIC_KEYS)


# --- docs/designer.md: the motor tables of a stator file (examples/light_damping) ---------


_LIGHT = "examples/light_damping/stator.toml"
_T2_FEM = "examples/table2_damping/stator.toml"
"""The paper's plate with Table 2's ratios: the FE set (``get_params('fem')``, Table 2's
ratios) that the docs compare with the paper, as a command gives it (``--source fem`` and
the plate options get the material's damping)."""
_MOTOR_CASES = (("paper", 14.0), ("consistent", 14.0), ("paper", 5.0))
"""(coupling, preload N) of the light-damping comparison, all at 300 V."""


@cache
def _motor_tables() -> dict[str, float]:
    """Steady speed from rest at 300 V, ``--frequency auto``, of the paper plate's FE set with
    the light-damping example's ``[damping]`` (zeta = 0.01) and with Table 2's ratios, as
    ``lusm simulate --steady --frequency auto`` prints them."""
    from contact.drive import auto_frequency
    from contact.simulate import simulate
    from rom.from_fem import fem_params, fem_params_from_file

    sets = {"light": fem_params_from_file(ROOT / _LIGHT), "t2": fem_params()}
    out: dict[str, float] = {}
    for coupling, preload in _MOTOR_CASES:
        tag = f"{coupling}_{preload:g}N"
        for name, p in sets.items():
            r = simulate(p, 300.0, preload, auto_frequency(p), coupling=coupling,
                         method="steady")
            out[f"{name}_v_{tag}"] = r.steady.velocity_m_s
        out[f"ratio_{tag}"] = out[f"light_v_{tag}"] / out[f"t2_v_{tag}"]
    return out


def _motor_claims() -> tuple[Claim, ...]:
    """The docs/designer.md speeds of the light-damping example against Table 2's damping."""
    out = []
    for coupling, preload in _MOTOR_CASES:
        tag = f"{coupling}_{preload:g}N"
        opts = f"--voltage 300 --preload {preload:g} --coupling {coupling} --steady " \
               "--frequency auto"
        for name, unit, cmd in (
                ("light_v", "m/s", f"lusm simulate --geometry {_LIGHT} {opts}"),
                ("t2_v", "m/s", f"lusm simulate --geometry {_T2_FEM} {opts}"),
                ("ratio", "-", "the two velocities above")):
            key = f"{name}_{tag}"
            out.append(Claim(f"motor_{key}", unit, cmd, lambda k=key: _motor_tables()[k]))
    return tuple(out)


_TUNED = "examples/tuned_40k/stator.toml"
_FITTED = "examples/tuned_40k/identified.toml"


@cache
def _fitted_damping() -> dict[str, float]:
    """The tuned 40 kHz plate with Table 2's damping ratios and with its damping fitted to
    the paper's free tip amplitudes (docs/designer.md): ratios and the 400 V / 14 N
    characteristic of each."""
    from contact.characteristic import characteristic
    from contact.drive import auto_frequency
    from contact.model import default_coupling
    from rom.from_fem import fem_params_from_file

    out = {}
    for tag, path in (("t2", _TUNED), ("fitted", _FITTED)):
        p = fem_params_from_file(ROOT / path)
        c = characteristic(p, 400.0, 14.0, frequency_Hz=auto_frequency(p),
                           coupling=default_coupling(p)[0])  # the CLI's: auto, exact
        out |= {f"{tag}_zeta_L1": p.zeta_L1, f"{tag}_zeta_B2": p.zeta_B2,
                f"{tag}_v0": c.no_load_velocity_m_s, f"{tag}_stall": c.stall_force_N}
    return out


@cache
def _paper_operating_limits(voltage_V: float = 400.0):
    """The operating limits of Table 2's set at ``voltage_V`` / 14 N / 40 kHz (the paper's
    400 V by default), steady state from rest (:mod:`contact.operating_limits`)."""
    from contact.operating_limits import operating_limits
    from contact.steady.engine import steady_state

    p = _table2()
    r = steady_state(p, voltage_V, 14.0, frequency_Hz=40e3)
    return operating_limits(p, voltage_V, 40e3, r.from_rest)


def _default_q() -> float:
    """The default damping's Q of a PZT-8 stator file: 1/Q = 1/Q_m + 1/Q_mount."""
    from fem.material import combined_quality_factor, pzt8
    from fem.stator_file import DEFAULT_Q_MOUNT

    return combined_quality_factor(pzt8().mechanical_Q, DEFAULT_Q_MOUNT)


def _operating_limit_claims() -> tuple[Claim, ...]:
    """docs/designer.md, 'Physical limits' and 'The default damping'."""
    cmd = "lusm simulate --voltage 400 --preload 14 --steady --json (limits.{q}.value)"
    out = [Claim("default_damping_Q", "-", "lusm params --geometry examples/tip_parametric/"
                 "stator.toml (the damping line)", _default_q, cheap=True, rel_tol=1e-12),
           Claim("default_damping_zeta", "-", "lusm params --geometry examples/tip_parametric/"
                 "stator.toml (zeta_L1)", lambda: 0.5 / _default_q(), cheap=True,
                 rel_tol=1e-12)]
    for q, unit in (("vibration_velocity", "m/s"), ("stress", "Pa"),
                    ("dissipated_power", "W"), ("power_density", "W/m^3")):
        out.append(Claim(f"oplim_paper_400V_{q}", unit, cmd.format(q=q),
                         lambda q=q: _paper_operating_limits().values[q], cheap=True,
                         rel_tol=1e-4))
    out.append(Claim("oplim_paper_400V_stress_B2", "Pa", "python -m tools.doc_numbers --show "
                     "oplim_paper_400V_stress_B2 (B2's share: stress_B2_Pa_m x W)",
                     lambda: (_paper_operating_limits().amplitudes_m[1]
                              * _table2().shape.stress_B2_Pa_m), cheap=True, rel_tol=1e-4))
    for v in (400.0, 300.0):
        out.append(Claim(f"oplim_paper_{v:g}V_stress_bound", "Pa",
                         f"lusm simulate --voltage {v:g} --preload 14 --steady --json "
                         "(limits.stress.sum_of_peaks: the L1 and B2 peaks added)",
                         lambda v=v: _paper_operating_limits(v).stress_bound_Pa, cheap=True,
                         rel_tol=1e-4))
    out.append(Claim("oplim_paper_300V_stress", "Pa", "lusm simulate --voltage 300 --preload 14 "
                     "--steady --json (limits.stress.value)",
                     lambda: _paper_operating_limits(300.0).values["stress"], cheap=True,
                     rel_tol=1e-4))
    return tuple(out)


def _fitted_damping_claims() -> tuple[Claim, ...]:
    """docs/designer.md: what fitting the damping to the paper's amplitudes changes."""
    cmd = ("lusm characteristic --voltage 400 --preload 14 --frequency auto --geometry {f} "
           "(the damping line and the no-load velocity, stall force)")
    out = []
    for tag, path in (("t2", _TUNED), ("fitted", _FITTED)):
        for key, unit in (("zeta_L1", "-"), ("zeta_B2", "-"), ("v0", "m/s"), ("stall", "N")):
            out.append(Claim(f"tuned40k_{tag}_{key}", unit, cmd.format(f=path),
                             lambda k=f"{tag}_{key}": _fitted_damping()[k]))
    return tuple(out)


_COUPLING_VOLTS = (300, 350, 400)


@cache
def _coupling_speeds() -> dict[str, float]:
    """Steady speeds from rest of the FE set (``--frequency auto``, 14 N) under both
    couplings: the evidence of docs/contact.md 2.3 for the default of non-Table-2 sets."""
    from contact.drive import auto_frequency
    from contact.simulate import simulate
    from rom.sources import get_params

    p = get_params("fem")
    f = auto_frequency(p)
    return {f"{c}_{v}": simulate(p, float(v), 14.0, f, coupling=c,
                                 method="steady").steady.velocity_m_s
            for c in ("paper", "consistent") for v in _COUPLING_VOLTS}


def _default_coupling_claims() -> tuple[Claim, ...]:
    return tuple(
        Claim(f"coupling_fem_{c}_{v}V", "m/s",
              f"lusm simulate --geometry {_T2_FEM} --voltage {v} --preload 14 --steady "
              f"--frequency auto --coupling {c}", lambda k=f"{c}_{v}": _coupling_speeds()[k])
        for c in ("paper", "consistent") for v in _COUPLING_VOLTS)


_PROXY_SETS = (
    ("table2", "", "lusm simulate --voltage 300 --preload 14 --steady --frequency {f}"),
    ("fem", "", "lusm simulate --geometry " + _T2_FEM
     + " --voltage 300 --preload 14 --steady --frequency {f}"),
    ("t40", _TUNED, "lusm characteristic --geometry " + _TUNED
     + " --voltage 400 --preload 14 --frequency {f}"),
    ("t40fit", _FITTED, "lusm characteristic --geometry " + _FITTED
     + " --voltage 400 --preload 14 --frequency {f}"),
)
"""(tag, stator file or "", command) of docs/contact.md section 6's comparison of the
operating point's proxy (the amplitudes' product, ``auto``) with the largest free ellipse."""


def _largest_ellipse_Hz(p) -> float:
    """Where the free tip ellipse's true area is largest, searched as ``auto_frequency``
    searches the amplitudes' product (grid between the widened resonances, then bounded)."""
    import numpy as np
    from scipy.optimize import minimize_scalar

    from contact.drive import GRID_POINTS, tip_ellipse_area

    f1, f2 = sorted((p.f_L1_Hz, p.f_B2_Hz))
    grid = np.linspace(0.8 * f1, 1.2 * f2, GRID_POINTS)
    best = grid[int(np.argmax([tip_ellipse_area(p, f) for f in grid]))]
    step = grid[1] - grid[0]
    res = minimize_scalar(lambda f: -tip_ellipse_area(p, f), bounds=(best - step, best + step),
                          method="bounded", options={"xatol": 1e-3})
    return float(res.x)


@cache
def _drive_proxies() -> dict[str, float]:
    """Frequencies and motor answers at the product's point and at the largest ellipse's."""
    from contact.characteristic import characteristic
    from contact.drive import auto_frequency
    from contact.model import default_coupling
    from contact.simulate import simulate
    from rom.from_fem import fem_params_from_file
    from rom.sources import get_params

    out: dict[str, float] = {}
    for tag, path, _ in _PROXY_SETS:
        p = (_table2() if tag == "table2" else get_params("fem") if tag == "fem"
             else fem_params_from_file(ROOT / path))
        coupling = default_coupling(p)[0]
        for which, f in (("product", auto_frequency(p)), ("ellipse", _largest_ellipse_Hz(p))):
            out[f"{tag}_{which}_Hz"] = f
            if path:
                c = characteristic(p, 400.0, 14.0, frequency_Hz=f, coupling=coupling)
                out[f"{tag}_{which}_v0"] = c.no_load_velocity_m_s
                out[f"{tag}_{which}_stall"] = c.stall_force_N
            else:
                r = simulate(p, 300.0, 14.0, f, coupling=coupling, method="steady")
                out[f"{tag}_{which}_v"] = r.steady.velocity_m_s
    return out


def _drive_proxy_claims() -> tuple[Claim, ...]:
    """docs/contact.md section 6: the operating point's proxy against the largest ellipse."""
    out = []
    for tag, path, cmd in _PROXY_SETS:
        quantities = (("v0", "m/s"), ("stall", "N")) if path else (("v", "m/s"),)
        for which in ("product", "ellipse"):
            f_cmd = cmd.format(f=f"F (F: drive_proxy_{tag}_{which}_Hz)")
            out.append(Claim(f"drive_proxy_{tag}_{which}_Hz", "Hz",
                             "python -m tools.doc_numbers --show "
                             f"drive_proxy_{tag}_{which}_Hz (auto_frequency for the product; "
                             "the same search of contact.drive.tip_ellipse_area for the "
                             "ellipse)",
                             lambda k=f"{tag}_{which}_Hz": _drive_proxies()[k]))
            for q, unit in quantities:
                out.append(Claim(f"drive_proxy_{tag}_{which}_{q}", unit, f_cmd,
                                 lambda k=f"{tag}_{which}_{q}": _drive_proxies()[k]))
    return tuple(out)


# --- docs/contact.md: the remaining figures of sections 3-6 ------------------------------


def _separation_voltage(preload_N: float) -> float:
    """Voltage at which the tip first separates (V), from the 200 V run.

    In contact Eqs. 4 + 7 are linear, so the tip's excursion from its static position scales
    with the voltage: ``V_sep = 200 V (y_c - y_0)/(y_min - y_0)``.
    """
    from contact.model import normal_force_zero_tip_displacement

    p = _table2()
    r = _sim(200.0, preload_N)
    y0 = p.phi_Ll * (p.phi_L0 - p.phi_Ll) * preload_N / p.K_l
    y_c = normal_force_zero_tip_displacement(p, preload_N)
    return 200.0 * (y_c - y0) / (float(r.window.y_tip_m.min()) - y0)


@cache
def _fine_map_counts(ultrasonic_friction: bool = True) -> dict[str, int]:
    """Motion-class counts of ``lusm map --voltages 50:650:25 --preloads 2:30:1`` (725 points)."""
    import numpy as np

    from contact.maps import stick_slip_map
    from contact.options import SimulationOptions

    m = stick_slip_map(_table2(), np.arange(50.0, 651.0, 25.0), np.arange(2.0, 31.0, 1.0),
                       options=SimulationOptions(ultrasonic_friction=ultrasonic_friction),
                       progress=False)
    return m.counts()


_STARTUP_KEYS = ("python", "numba", "arraymath", "contact", "run_1ms", "lusm_simulate",
                 "lusm_help")
"""Names of the rows of benchmarks/startup.py's ``CASES``, in order."""


def _bench(name: str):
    """The benchmark script ``benchmarks/<name>.py`` as a module."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(f"bench_{name}",
                                                  ROOT / "benchmarks" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@cache
def _startup_seconds() -> dict[str, float]:
    """Fresh-process wall times (s) of benchmarks/startup.py's cases, fastest of 3, and the
    denominator of :func:`_startup_ratios` under the key ``"integration"``."""
    import subprocess
    import sys

    bench = _bench("startup")
    code = ("from threadpoolctl import threadpool_limits; threadpool_limits(1); "
            "from contact.simulate import simulate; from rom import table2; "
            "simulate(table2(), 200.0, 14.0, duration_s=0.001); "
            "print(min(simulate(table2(), 200.0, 14.0).wall_time_s for _ in range(7)))")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=ROOT, env=env)
    out = {k: min(bench.wall(cmd, 1) for _ in range(3))
           for k, (_, cmd) in zip(_STARTUP_KEYS, bench.CASES, strict=True)}
    out["integration"] = float(run.stdout.split()[-1])
    return out


def _startup_ratios() -> dict[str, float]:
    """Fresh-process wall times over one 50 ms integration (benchmarks/startup.py's cases).

    All rows share one denominator, the fastest of 7 integrations in a fresh process with BLAS
    held to one thread; each row is the fastest of 3 fresh processes (minima, not medians: on
    a shared machine a run can lose a time slice ten times its length).
    """
    sec = _startup_seconds()
    return {k: sec[k] / sec["integration"] for k in _STARTUP_KEYS}


def _contact_claims() -> tuple[Claim, ...]:
    """Figures of docs/contact.md beyond the coupling table."""
    sim = _SIM.format(v=200, f=14)
    out = [
        Claim("v_200V_14N_10ms_m_s", "m/s", sim + " --duration 0.01",
              lambda: _sim(200.0, 14.0, 0.01).steady.velocity_m_s, cheap=True, rel_tol=1e-4),
        Claim("v_200V_14N_20ms_m_s", "m/s", sim + " --duration 0.02",
              lambda: _sim(200.0, 14.0, 0.02).steady.velocity_m_s, cheap=True, rel_tol=1e-4),
        Claim("fig9_paper_over_v", "-", "0.03 m/s (paper, Fig. 9) / v_200V_14N_m_s",
              lambda: 0.03 / _sim(200.0, 14.0).steady.velocity_m_s, cheap=True, rel_tol=1e-4),
        Claim("v_175V_14N_m_s", "m/s", _SIM.format(v=175, f=14),
              lambda: _sim(175.0, 14.0).steady.velocity_m_s, cheap=True, rel_tol=1e-4),
        Claim("y_min_200V_14N_m", "m", "python -m tools.doc_numbers --show y_min_200V_14N_m "
              "(lowest tip normal displacement of the steady window)",
              lambda: float(_sim(200.0, 14.0).window.y_tip_m.min()), cheap=True, rel_tol=1e-5),
        Claim("y_c_14N_m", "m", "contact.model.normal_force_zero_tip_displacement(table2(), 14)",
              lambda: __import__("contact.model", fromlist=["x"])
              .normal_force_zero_tip_displacement(_table2(), 14.0), cheap=True, rel_tol=1e-9),
        Claim("separation_voltage_14N_V", "V",
              "python -m tools.doc_numbers --show separation_voltage_14N_V",
              lambda: _separation_voltage(14.0), cheap=True, rel_tol=1e-4),
        Claim("dead_zone_14N_vs_experiment", "-", "dead_zone_14N_V / 100 V - 1 (paper, Fig. 24)",
              lambda: _dead_zone_edge(14.0) / 100.0 - 1.0, cheap=True, rel_tol=1e-2),
        Claim("steps_200V_14N", "-", sim + " (steps)",
              lambda: float(_sim(200.0, 14.0).steps), cheap=True, rel_tol=1e-12),
        Claim("energy_residual_200V_14N", "-",
              "contact.simulate.simulate(table2(), 200, 14, energy=True).energy"
              ".relative_residual", lambda: abs(_sim(200.0, 14.0).energy.relative_residual)),
        Claim("auto_frequency_table2_Hz", "Hz",
              "lusm simulate --voltage 200 --preload 14 --frequency auto --json",
              lambda: __import__("contact.drive", fromlist=["x"]).auto_frequency(_table2()),
              cheap=True, rel_tol=1e-6),
        Claim("wp_event_stick_max", "-", "lusm report (section 3a, stick-fraction error)",
              lambda: max(p.stick_error for p in __import__(
                  "validation.work_precision", fromlist=["x"]).contact_work_precision(
                  _table2(), cases=((200.0, 14.0),))[0] if p.method.startswith("event"))),
    ]
    out.append(Claim("settle_400V_14N_s", "s", _SIM.format(v=400, f=14) + " --duration D "
                     "(settled), D on a 25 ms grid",
                     lambda: next(d * 1e-3 for d in range(50, 301, 25)
                                  if _sim(400.0, 14.0, d * 1e-3).steady.settled),
                     cheap=True, rel_tol=1e-9))
    for v, f in ((50, 14), (450, 14), (400, 10), (400, 26)):
        out.append(Claim(f"mu_d_{v}V_{f}N", "-", _SIM.format(v=v, f=f) + " (mu_d_effective)",
                         lambda v=v, f=f: _sim(float(v), float(f)).mu_d_eff, cheap=True,
                         rel_tol=1e-5))
    for ultrasonic, tag in ((True, ""), (False, "const_mu_")):
        flag = "" if ultrasonic else " --no-ultrasonic-friction"
        for cls in ("slip-separation", "stick-slip", "pure-stick", "pure-slip"):
            out.append(Claim(
                f"fine_map_{tag}{cls.replace('-', '_')}", "-",
                f"lusm map --voltages 50:650:25 --preloads 2:30:1{flag} --json (counts)",
                lambda u=ultrasonic, c=cls: _fine_map_counts(u).get(c, 0)))
    for k in _STARTUP_KEYS:
        out.append(Claim(f"startup_{k}_ratio", "-",
                         "python benchmarks/startup.py (x one 50 ms integration; here the "
                         "fastest of 3 processes over the fastest of 7 runs)",
                         lambda k=k: _startup_ratios()[k]))
    for k in ("lusm_simulate", "lusm_help"):
        out.append(Claim(f"startup_{k}_s", "s",
                         "python benchmarks/startup.py (wall s; here the fastest of 3 fresh "
                         "processes)", lambda k=k: _startup_seconds()[k]))
    return tuple(out)


# --- docs/steady.md: the steady engine against settled transients -----------------------


@cache
def _steady_point() -> dict[str, float]:
    """The 200 V / 14 N row of ``python benchmarks/steady_speed.py``: velocities and the
    transient's wall time over each steady level's (median of 3, numba warmed first)."""
    from contact.steady.engine import steady_state
    from contact.steady.settled import transient_reference

    p = _table2()
    steady_state(p, 200, 14, accuracy="exact")
    transient_reference(p, 200, 14, duration_s=0.01, steady_periods=20)
    out: dict[str, float] = {}
    times: dict[str, list[float]] = {"transient": [], "coarse": [], "fast": [], "exact": []}
    bench = _bench("steady_speed")
    for _ in range(3):
        t = time.perf_counter()
        out["transient"] = transient_reference(p, 200, 14, duration_s=0.3)[0]
        times["transient"].append(time.perf_counter() - t)
        t = time.perf_counter()
        out["coarse"] = transient_reference(p, 200, 14, duration_s=0.3,
                                             dt_s=bench.COARSE_DT_S)[0]
        times["coarse"].append(time.perf_counter() - t)
        for acc in ("fast", "exact"):
            t = time.perf_counter()
            r = steady_state(p, 200, 14, accuracy=acc)
            times[acc].append(time.perf_counter() - t)
            out[acc] = r.velocity_m_s
            out[f"{acc}_periods"] = r.periods
    for acc in ("fast", "exact"):
        out[f"{acc}_rel_error"] = abs(out[acc] - out["transient"]) / abs(out["transient"])
        out[f"{acc}_speed_ratio"] = (statistics.median(times["transient"])
                                     / statistics.median(times[acc]))
    t_ref = statistics.median(times["transient"])
    out["coarse_rel_error"] = abs(out["coarse"] - out["transient"]) / abs(out["transient"])
    out["coarse_speed_ratio"] = t_ref / statistics.median(times["coarse"])
    out["exact_vs_coarse_ratio"] = (statistics.median(times["coarse"])
                                    / statistics.median(times["exact"]))
    per_period = bench.kernel_seconds_per_period(p, 200.0, 14.0)
    out["period_floor_ratio"] = t_ref / (out["exact_periods"] * per_period)
    # the full model's run from rest that decides the branch reached, alone
    rest = steady_state(p, 200, 14, accuracy="exact").rest_periods
    out["rest_floor_ratio"] = t_ref / (rest * per_period)
    t_setup = bench.setup_seconds(p, 200.0, 14.0)
    out["setup_floor_ratio"] = t_ref / t_setup
    out["joint_floor_ratio"] = t_ref / (t_setup + out["exact_periods"] * per_period)
    return out


@cache
def _mu_at_twice_an(voltage_V: float, preload_N: float) -> float:
    """Eq. 11's mu_d,eff with A_N doubled (the tip's peak-to-peak normal displacement, the
    other reading of "normal vibration amplitude" that docs/contact.md section 4 weighs)."""
    p = _table2()
    a_n = _sim(voltage_V, preload_N).normal_amplitude_m
    return p.a_mu + (p.mu_d - p.a_mu) * math.exp(-p.b_mu * 2.0 * a_n)


def _gain_at_twice_an(voltage_V: float, duration_s: float | None) -> float:
    """Relative change of the speed at ``voltage_V`` / 14 N when Eq. 11 takes twice A_N
    (``b_mu`` doubled: the same law), Table 2's coupling kept."""
    from contact.simulate import simulate

    p = _table2()
    kw = {} if duration_s is None else {"duration_s": duration_s}
    base = simulate(p, voltage_V, 14.0, coupling="paper", **kw).steady.velocity_m_s
    twice = simulate(p.with_(b_mu=2.0 * p.b_mu), voltage_V, 14.0, coupling="paper",
                     **kw).steady.velocity_m_s
    return twice / base - 1.0


@cache
def _no_preload():
    """The branch from rest at 200 V without preload (exact level)."""
    from contact.steady.engine import steady_state
    from rom import table2

    return steady_state(table2(), 200, 0, accuracy="exact").from_rest


def _max_slenderness() -> float:
    from fem.modes import N_MODES, SEARCH_GROWTH, max_slenderness

    return max_slenderness(SEARCH_GROWTH[-1] * N_MODES)


@cache
def _steady_400_loaded():
    """The branch from rest at 400 V / 14 N under a 1 N load (exact level): its mean forces."""
    from contact.steady.engine import steady_state
    from rom import table2

    return steady_state(table2(), 400, 14, load_N=1.0, accuracy="exact").from_rest


def _steady_mass_error(voltage_V: float, mass_kg: float) -> float:
    """|fast - exact| / exact at 14 N with slider mass ``mass_kg`` and mu_sd = 0."""
    from contact.steady.engine import steady_state

    p = _table2().with_(M_slider=mass_kg, mu_sd=0.0)
    kw = {"coupling": "paper"}  # Table 2's, which "auto" gives only the unedited set
    fast = steady_state(p, voltage_V, 14, accuracy="fast", **kw).velocity_m_s
    exact = steady_state(p, voltage_V, 14, accuracy="exact", **kw).velocity_m_s
    return abs(fast - exact) / abs(exact)


@cache
def _steady_150() -> dict[str, float]:
    """The coexisting branches at 150 V / 14 N (tests/test_steady_exact.py)."""
    from contact.steady.engine import steady_state
    from contact.steady.settled import transient_reference

    r = steady_state(_table2(), 150, 14, accuracy="exact")
    stable = [b for b in r.branches if b.stable]
    return {"rest": r.from_rest.velocity_m_s, "rest_k": r.from_rest.k,
            "k1": next(b.velocity_m_s for b in stable if b.k == 1),
            "transient": transient_reference(_table2(), 150, 14, duration_s=0.2)[0],
            "fast": steady_state(_table2(), 150, 14, accuracy="fast").velocity_m_s}


@cache
@cache
def _char_30khz(accuracy: str) -> float:
    """No-load velocity (m/s) of ``lusm characteristic`` at 200 V / 14 N / 30 kHz."""
    from contact.characteristic import characteristic

    return characteristic(_table2(), 200, 14, [0.0], frequency_Hz=30e3,
                          accuracy=accuracy).no_load_velocity_m_s


def _steady_characteristic() -> dict[str, float]:
    """``lusm characteristic --voltage 400 --preload 14 --loads 0:2:0.5 --accuracy fast``."""
    import numpy as np

    from contact.characteristic import characteristic
    from lusm.commands.characteristic import parse_loads

    c = characteristic(_table2(), 400, 14, parse_loads("0:2:0.5"), accuracy="fast")
    i = int(np.nanargmax(c.efficiency))
    return {"no_load": c.no_load_velocity_m_s, "stall": c.stall_force_N,
            "peak_efficiency": float(c.efficiency[i]), "peak_load": float(c.load_N[i]),
            "peak_input": float(c.input_power_W[i]), "peak_output": float(c.output_power_W[i])}


@cache
def _steady_load_edge() -> dict[str, float]:
    """Just past the averaged holding range at 100 V / 14 N: the finite-mass motor settles."""
    from contact.model import OperatingPoint
    from contact.simulate import simulate
    from contact.steady.runaway import holding_range_N
    from contact.steady.slow import slow_problem

    high = holding_range_N(slow_problem(_table2(), OperatingPoint(100.0, 14.0, 40e3)))[1]
    r = simulate(_table2(), 100.0, 14.0, load_N=5.22, duration_s=2.0)
    return {"high": high, "beyond": r.steady.velocity_m_s if r.steady.settled else math.nan}


@cache
def _steady_load_limits() -> dict[str, float]:
    """Loads at 400 V / 14 N (docs/steady.md "Loads the motor cannot carry")."""
    from contact.characteristic import characteristic
    from contact.model import OperatingPoint
    from contact.steady.engine import steady_state
    from contact.steady.settled import transient_reference
    from contact.steady.slow import slow_problem

    c = characteristic(_table2(), 400, 14, [3.5], accuracy="fast")
    r = steady_state(_table2(), 400, 14, load_N=3.5, accuracy="exact", energy=False)
    sp = slow_problem(_table2(), OperatingPoint(400.0, 14.0, 40e3))
    return {"holding_low": c.holding_range_N[0], "holding_high": c.holding_range_N[1],
            "guide_hold": sp.thrust_at_rest()[1],
            "back_m_s": r.velocity_m_s,
            "back_transient_m_s": transient_reference(_table2(), 400, 14, load_N=3.5,
                                                      duration_s=1.2)[0]}


@cache
def _steady_load_hard() -> dict[str, float]:
    """Close stable orbits, an irregular creep and a slow orbit far from the averaged root,
    under a load (docs/steady.md)."""
    from contact.steady.engine import steady_state
    from contact.steady.settled import transient_reference

    p = _table2()
    multi = steady_state(p, 75, 15, load_N=5.0, accuracy="exact", energy=False)
    creep = steady_state(p, 75.3, 14.73, load_N=4.74, accuracy="exact", energy=False)
    out = {"multi_exact": multi.velocity_m_s, "multi_k": multi.from_rest.k,
           "multi_transient": transient_reference(p, 75, 15, load_N=5.0, duration_s=0.3)[0],
           "creep_exact": creep.velocity_m_s,
           "creep_error": creep.from_rest.velocity_error_m_s / abs(creep.velocity_m_s),
           "creep_transient": transient_reference(p, 75.3, 14.73, load_N=4.74,
                                                  duration_s=1.2)[0]}
    out["multi_gap"] = abs(out["multi_exact"] / out["multi_transient"] - 1)
    p2 = steady_state(p, 61.6, 6.78, load_N=2.2, accuracy="exact", energy=False)
    out["p2_rest_m_s"] = p2.velocity_m_s
    out["p2_k1_m_s"] = next(b.velocity_m_s for b in p2.branches if b.k == 1 and b.stable)
    from rom.sources import get_params

    fe = get_params("fem")
    kw = {"load_N": -1.15, "coupling": "consistent", "frequency_Hz": 40e3}  # below its modes
    q = steady_state(fe, 293.6, 24.12, accuracy="exact", energy=False, **kw)
    ref = transient_reference(fe, 293.6, 24.12, duration_s=0.6, steady_periods=1200, **kw)[0]
    out["quasi_k"] = q.from_rest.k
    out["quasi_avg_m_s"] = steady_state(fe, 293.6, 24.12, energy=False, accuracy="fast",
                                        **kw).velocity_m_s
    out["quasi_slower"] = 1 - ref / out["quasi_avg_m_s"]
    out["quasi_error"] = abs(q.velocity_m_s / ref - 1)
    return out


@cache
def _steady_hidden_creep() -> dict[str, float]:
    """Beam and FE sets on the 9 x 9 grid at 40 kHz (consistent coupling): points the
    averages hold (fast level, velocity 0) where the exact level's full model creeps."""
    import numpy as np

    from contact.steady.engine import steady_state
    from rom.sources import get_params

    speeds = []
    for src in ("beam", "fem"):
        p = get_params(src)
        for v in np.linspace(50, 450, 9):
            for f in np.linspace(10, 26, 9):
                kw = {"coupling": "consistent", "energy": False, "frequency_Hz": 40e3}
                if steady_state(p, float(v), float(f), accuracy="fast", **kw).velocity_m_s != 0.0:
                    continue
                ex = steady_state(p, float(v), float(f), accuracy="exact", **kw)
                if ex.velocity_m_s != 0.0:
                    speeds.append(abs(ex.velocity_m_s))
    return {"points": len(speeds), "min_m_s": min(speeds), "max_m_s": max(speeds)}


@cache
def _steady_branch_diagram() -> dict[str, float]:
    """From-rest branch of the exact level at 14 N, 50-450 V in steps of 25 V; the last
    held voltage, the first voltage of each moving class and a few velocities."""
    from contact.steady.engine import steady_state
    from contact.steady.settled import transient_reference

    rows = {v: steady_state(_table2(), v, 14, accuracy="exact") for v in range(50, 451, 25)}
    motion = {v: r.from_rest.motion if r.velocity_m_s else "dead-zone" for v, r in rows.items()}
    out = {"dead_zone_last_V": max(v for v, m in motion.items() if m == "dead-zone")}
    for cls in ("stick-slip", "pure-slip", "slip-separation"):
        vs = [v for v, m in motion.items() if m == cls]
        out[f"{cls}_first_V"] = min(vs) if vs else math.nan
        out[f"{cls}_last_V"] = max(vs) if vs else math.nan
    for v in (175, 200, 400, 450):
        out[f"v_{v}V"] = rows[v].velocity_m_s
    out["transient_175V"] = transient_reference(_table2(), 175, 14, duration_s=0.3)[0]
    return out


CREEP_M_S = 1e-4
"""Reference speed (m/s) below which a moving map point is a creep point (docs/steady.md's
guarantee there is only "creeping")."""


@cache
def _steady_scan() -> dict[str, float]:
    """``python benchmarks/steady_scan_budget.py``: the former scan against the present one."""
    m = _bench("steady_scan_budget").measure()
    out = {"time_ratio": m["time_ratio"], "differ": len(m["differ"]),
           "k0_samples": m["k0_samples"], "g_change_max": m["g_change_max"],
           "sign_changes": m["sign_changes"]}
    for name in ("former", "now"):
        s = m[name]
        out.update({f"{name}_orbits": s["orbits"], f"{name}_k0": s["k0"],
                    f"{name}_periods": s["periods"],
                    f"{name}_k0_share": s["k0_periods"] / s["periods"]})
    return out


@cache
def _steady_from_rest() -> dict[str, float]:
    """``python benchmarks/steady_from_rest.py``: the start from rest decided by the run out
    of the ripple zone against the transient from rest, on 617 points of five parameter sets."""
    t = _bench("steady_from_rest").measure(progress=False)["total"]
    return {"points": t["points"], "probe_decided": t["probe_decided"], "differ": t["differ"],
            "track_max_accepted": t["track_max_accepted"],
            "track_min_rejected": t["track_min_rejected"],
            "periods_ratio": t["periods_transient"] / t["periods_probe"]}


def _rest_periods_200V_14N() -> float:
    """Periods of the full model from rest that decide the branch reached at 200 V / 14 N."""
    from contact.steady.engine import steady_state

    return float(steady_state(_table2(), 200, 14, energy=False).rest_periods)


@cache
def _ripple_scale_14N() -> float:
    """``contact.steady.slow.ripple_scale`` of Table 2's set at 200 V / 14 N (m/s)."""
    from contact.model import OperatingPoint
    from contact.steady.slow import ripple_scale, slow_problem

    op = OperatingPoint(200.0, 14.0, 40e3)
    return ripple_scale(_table2(), op, slow_problem(_table2(), op).mu_d_eff)


@cache
def _steady_map() -> dict[str, float]:
    """``python benchmarks/steady_speed.py --map``: the 9 x 9 map (50-450 V x 10-26 N) of the
    steady levels against a settled transient per point (the benchmark's rows), wall times
    summed over the map."""
    import numpy as np

    from contact.steady.engine import steady_state
    from contact.steady.settled import transient_reference

    bench = _bench("steady_speed")
    p = _table2()
    steady_state(p, 200, 14, accuracy="exact")
    transient_reference(p, 200, 14, duration_s=0.01, steady_periods=20)
    rows = [bench.point(p, float(v), float(f), 0.3) for v in np.linspace(50, 450, 9)
            for f in np.linspace(10, 26, 9)]
    moving = [r for r in rows if abs(r["transient_m_s"]) > 1e-6]
    held = [r for r in rows if abs(r["transient_m_s"]) <= 1e-6]
    out: dict[str, float] = {"moving": len(moving), "held": len(held),
                             "creep": sum(abs(r["transient_m_s"]) < CREEP_M_S for r in moving),
                             "ref_longer": sum(r["transient_duration_s"] > 0.3 for r in rows),
                             "ref_unsettled": sum(not r["settled"] for r in rows)}
    t_ref = sum(r["transient_s"] for r in rows)
    for acc in ("fast", "exact"):
        err = np.array([r[f"{acc}_rel_error"] for r in moving])
        out[f"{acc}_median"] = float(np.median(err))
        out[f"{acc}_p90"] = float(np.percentile(err, 90))
        out[f"{acc}_max"] = float(err.max())
        out[f"{acc}_max_noncreep"] = max(r[f"{acc}_rel_error"] for r in moving
                                         if abs(r["transient_m_s"]) >= CREEP_M_S)
        out[f"{acc}_held_max_m_s"] = max(abs(r[f"{acc}_m_s"]) for r in held)
        out[f"{acc}_speed_ratio"] = t_ref / sum(r[f"{acc}_s"] for r in rows)
    out["exact_within_1e-5"] = int(sum(r["exact_rel_error"] <= 1e-5 for r in moving))
    t_coarse = sum(r["coarse_s"] for r in rows)
    out["coarse_speed_ratio"] = t_ref / t_coarse
    out["exact_vs_coarse_ratio"] = t_coarse / sum(r["exact_s"] for r in rows)
    out["coarse_max"] = max(r["coarse_rel_error"] for r in moving)
    # what ``lusm map`` runs: stick_slip_map(method="steady"), exact level with the transient
    # fallback on undecided points, one worker like the serial references above
    from contact.maps import stick_slip_map

    m = stick_slip_map(p, np.linspace(50, 450, 9), np.linspace(10, 26, 9), workers=1,
                       progress=False, method="steady")
    ref = {(r["voltage_V"], r["preload_N"]): r["transient_m_s"] for r in rows}
    worst = 0.0
    for i, v in enumerate(m.voltages_V):
        for j, f in enumerate(m.preloads_N):
            r0 = ref[(float(v), float(f))]
            if abs(r0) > 1e-6:
                worst = max(worst, abs(m.velocity_m_s[i, j] - r0) / abs(r0))
    out["cli_speed_ratio"] = t_ref / m.wall_time_s
    out["cli_worst_moving"] = worst
    out["cli_undecided"] = int(m.fallback.sum())
    out["cli_held_max_m_s"] = max(abs(float(m.velocity_m_s[i, j]))
                                  for i, v in enumerate(m.voltages_V)
                                  for j, f in enumerate(m.preloads_N)
                                  if abs(ref[(float(v), float(f))]) <= 1e-6)
    return out


@cache
def _steady_creep(voltage_V: float, preload_N: float) -> dict[str, float]:
    """A creep point of the map: 0.3 s transient and exact level."""
    from contact.steady.engine import steady_state
    from contact.steady.settled import transient_reference

    return {"transient": transient_reference(_table2(), voltage_V, preload_N,
                                             duration_s=0.3)[0],
            "exact": steady_state(_table2(), voltage_V, preload_N,
                                  accuracy="exact").velocity_m_s}


def _steady_claims() -> tuple[Claim, ...]:
    """Figures of docs/steady.md."""
    return (*_steady_200V_claims(), *_steady_point_claims(), *_steady_sweep_claims(),
            *_steady_benchmark_claims())


def _steady_200V_claims() -> list[Claim]:
    """docs/steady.md's figures of 200 V / 14 N: its velocity at each level and their costs
    (benchmarks/steady_speed.py)."""
    bench = "python benchmarks/steady_speed.py"
    return [
        Claim("steady_200V_14N_transient_m_s", "m/s", bench + " (transient_m_s)",
              lambda: _steady_point()["transient"], cheap=True, rel_tol=1e-6),
        Claim("steady_200V_14N_fast_m_s", "m/s", bench + " (fast_m_s)",
              lambda: _steady_point()["fast"], cheap=True, rel_tol=1e-6),
        Claim("steady_200V_14N_exact_m_s", "m/s", bench + " (exact_m_s)",
              lambda: _steady_point()["exact"], cheap=True, rel_tol=1e-6),
        Claim("steady_200V_14N_fast_rel_error", "-", bench + " (fast_rel_error)",
              lambda: _steady_point()["fast_rel_error"], cheap=True, rel_tol=1e-3),
        Claim("steady_200V_14N_exact_rel_error", "-", bench + " (exact_rel_error)",
              lambda: _steady_point()["exact_rel_error"]),
        Claim("steady_200V_14N_fast_periods", "-",
              'steady_state(table2(), 200, 14, accuracy="fast").periods',
              lambda: _steady_point()["fast_periods"],
              cheap=True, rel_tol=1e-9),
        Claim("steady_200V_14N_exact_periods", "-",
              'steady_state(table2(), 200, 14, accuracy="exact").periods',
              lambda: _steady_point()["exact_periods"], cheap=True, rel_tol=1e-9),
        Claim("steady_200V_14N_period_floor_ratio", "-", bench + " (last line: the settled "
              "transient over the exact level's periods at the kernel's cost per period)",
              lambda: _steady_point()["period_floor_ratio"], batch="steady_point"),
        Claim("steady_200V_14N_rest_floor_ratio", "-", "python -m tools.doc_numbers "
              "--show steady_200V_14N_rest_floor_ratio (the settled transient of " + bench
              + " over the exact level's run from rest alone, steady_200V_14N_rest_periods "
              "periods, at the kernel's cost per period)",
              lambda: _steady_point()["rest_floor_ratio"], batch="steady_point"),
        Claim("steady_200V_14N_setup_floor_ratio", "-", bench + " (the line 'fixed costs': "
              "the settled transient over the fast and full systems with their exponentials)",
              lambda: _steady_point()["setup_floor_ratio"], batch="steady_point"),
        Claim("steady_200V_14N_joint_floor_ratio", "-", bench + " (the settled transient over "
              "the systems plus the exact level's periods at the kernel's cost per period)",
              lambda: _steady_point()["joint_floor_ratio"], batch="steady_point"),
        Claim("steady_200V_14N_fast_speed_ratio", "-", bench + " (transient_s / fast_s; here "
              "medians of 3)", lambda: _steady_point()["fast_speed_ratio"], batch="steady_point"),
        Claim("steady_200V_14N_exact_speed_ratio", "-", bench + " (transient_s / exact_s; here "
              "medians of 3)", lambda: _steady_point()["exact_speed_ratio"],
              batch="steady_point"),
        Claim("steady_200V_14N_coarse_rel_error", "-", bench + " (the line 'coarse "
              "transient': the settled transient at 20 steps per period against 250)",
              lambda: _steady_point()["coarse_rel_error"], batch="steady_point"),
        Claim("steady_200V_14N_coarse_speed_ratio", "-", bench + " (transient_s / coarse_s; "
              "here medians of 3)", lambda: _steady_point()["coarse_speed_ratio"],
              batch="steady_point"),
        Claim("steady_200V_14N_exact_vs_coarse_ratio", "-", bench + " (coarse_s / exact_s; "
              "here medians of 3)", lambda: _steady_point()["exact_vs_coarse_ratio"],
              batch="steady_point"),
    ]


def _steady_point_claims() -> list[Claim]:
    """docs/steady.md's figures of single drive points: 150 V / 14 N, the characteristic at
    30 kHz, loaded, no preload."""
    ex = 'steady_state(table2(), {v}, {f}, accuracy="exact")'
    return [
        Claim("steady_150V_14N_rest_m_s", "m/s", ex.format(v=150, f=14) + ".velocity_m_s",
              lambda: _steady_150()["rest"]),
        Claim("steady_150V_14N_rest_k", "-", ex.format(v=150, f=14) + ".from_rest.k",
              lambda: _steady_150()["rest_k"]),
        Claim("steady_150V_14N_k1_m_s", "m/s", ex.format(v=150, f=14) + ".branches (k = 1)",
              lambda: _steady_150()["k1"]),
        Claim("steady_150V_14N_transient_m_s", "m/s",
              "transient_reference(table2(), 150, 14, duration_s=0.2)",
              lambda: _steady_150()["transient"]),
        Claim("steady_150V_14N_fast_m_s", "m/s",
              'steady_state(table2(), 150, 14, accuracy="fast").velocity_m_s',
              lambda: _steady_150()["fast"]),
        Claim("char_30kHz_fast_no_load_m_s", "m/s",
              "lusm characteristic --voltage 200 --preload 14 --frequency 30000 --accuracy fast",
              lambda: _char_30khz("fast")),
        Claim("char_30kHz_exact_no_load_m_s", "m/s",
              "lusm characteristic --voltage 200 --preload 14 --frequency 30000",
              lambda: _char_30khz("exact")),
        *(Claim(f"steady_400V_14N_1N_{k}", "N",
                'steady_state(table2(), 400, 14, load_N=1, accuracy="exact").from_rest.' + k,
                lambda k=k: getattr(_steady_400_loaded(), k), cheap=True, rel_tol=1e-7)
          for k in ("mean_FN_N", "mean_FT_N")),
        *(Claim(f"steady_char_450V_40N_{k}_N", "N",
                f"lusm characteristic --voltage 450 --preload 40 --json ({k}_force_N)",
                lambda k=k: getattr(_char_exact(450.0, 40.0), f"{k}_force_N"))
          for k in ("stall", "averaged_stall")),
        Claim("contact_no_preload_200V_m_s", "m/s",
              "lusm simulate --voltage 200 --preload 0 --steady --json (steady_velocity_m_s)",
              lambda: _no_preload().velocity_m_s, cheap=True, rel_tol=1e-7),
        Claim("contact_no_preload_200V_mean_FN_N", "N",
              'steady_state(table2(), 200, 0, accuracy="exact").from_rest.mean_FN_N',
              lambda: _no_preload().mean_FN_N, cheap=True, rel_tol=1e-7),
        Claim("contact_no_preload_200V_separation", "-",
              "lusm simulate --voltage 200 --preload 0 --steady --json "
              "(separation_fraction)", lambda: _no_preload().phase_fraction[3], cheap=True,
              rel_tol=1e-6),
        Claim("contact_no_preload_200V_stall_N", "N",
              "lusm characteristic --voltage 200 --preload 0 --json (stall_force_N)",
              lambda: _char_exact(200.0, 0.0).stall_force_N),
        Claim("fem_max_slenderness", "-",
              "python -c 'from fem.modes import max_slenderness; print(max_slenderness(32))' "
              "(length / width whose B2 beam theory puts within the 32 modes searched)",
              lambda: _max_slenderness(), cheap=True, rel_tol=1e-9),
        Claim("steady_150V_14N_fast_vs_exact", "-", "steady_150V_14N_fast_m_s / "
              "steady_150V_14N_rest_m_s - 1",
              lambda: _steady_150()["fast"] / _steady_150()["rest"] - 1),
    ]


def _steady_sweep_claims() -> list[Claim]:
    """docs/steady.md's figures over masses, loads and voltages."""
    ex = 'steady_state(table2(), {v}, {f}, accuracy="exact")'
    out = []
    for v, mass in ((200, 0.2), (200, 0.4), (200, 0.8), (400, 0.2), (400, 0.4), (400, 0.8)):
        out.append(Claim(
            f"steady_mass_error_{v}V_{int(mass * 10)}", "-",
            f"python -m tools.doc_numbers --show steady_mass_error_{v}V_{int(mass * 10)} "
            f"(|fast - exact| / exact, {v} V / 14 N, M_slider = {mass} kg, mu_sd = 0)",
            lambda v=v, mass=mass: _steady_mass_error(float(v), mass)))
    char = "lusm characteristic --voltage 400 --preload 14 --loads 0:2:0.5 --accuracy fast --json"
    for k, unit in (("no_load", "m/s"), ("stall", "N"), ("peak_efficiency", "-"),
                    ("peak_load", "N"), ("peak_input", "W"), ("peak_output", "W")):
        out.append(Claim(f"steady_char_400V_14N_{k}", unit, char,
                         lambda k=k: _steady_characteristic()[k]))
    limits = "lusm characteristic --voltage 400 --preload 14 --loads 3:6:1 --json"
    for k, unit, cmd in (
            ("holding_low", "N", limits + " (holding_range_N)"),
            ("holding_high", "N", limits + " (holding_range_N)"),
            ("guide_hold", "N", "python -m tools.doc_numbers --show steady_load_400V_14N_"
             "guide_hold (F_T(0+) + mu_sd (F_N + M g), the load a held slider resists)"),
            ("back_m_s", "m/s", 'steady_state(table2(), 400, 14, load_N=3.5, accuracy="exact")'
             ".velocity_m_s"),
            ("back_transient_m_s", "m/s",
             "transient_reference(table2(), 400, 14, load_N=3.5, duration_s=1.2)")):
        out.append(Claim(f"steady_load_400V_14N_{k}", unit, cmd,
                         lambda k=k: _steady_load_limits()[k]))
    edge = "lusm characteristic --voltage 100 --preload 14 --loads 5:5.2:0.1 (no runaway within)"
    out += [Claim("steady_load_100V_14N_holding_high", "N", edge,
                  lambda: _steady_load_edge()["high"]),
            Claim("steady_load_100V_14N_beyond_m_s", "m/s",
                  "lusm simulate --voltage 100 --preload 14 --load-N 5.22 --duration 2 --json",
                  lambda: _steady_load_edge()["beyond"])]
    creep = ("python -m tools.doc_numbers --show 'steady_hidden_creep_*' (beam and FE "
             "sets, 9 x 9 grid 50-450 V x 10-26 N at 40 kHz, consistent coupling: held by the "
             "fast level, moving at the exact level)")
    for k, unit in (("points", "-"), ("min_m_s", "m/s"), ("max_m_s", "m/s")):
        out.append(Claim(f"steady_hidden_creep_{k}", unit, creep,
                         lambda k=k: _steady_hidden_creep()[k]))
    hard = "python -m tools.doc_numbers --show 'steady_load_hard_*'"
    for k, unit in (("multi_exact", "m/s"), ("multi_k", "-"), ("multi_transient", "m/s"),
                    ("multi_gap", "-"), ("creep_exact", "m/s"), ("creep_error", "-"),
                    ("creep_transient", "m/s"),
                    ("p2_rest_m_s", "m/s"), ("p2_k1_m_s", "m/s"), ("quasi_avg_m_s", "m/s"),
                    ("quasi_slower", "-"), ("quasi_error", "-"), ("quasi_k", "-")):
        out.append(Claim(f"steady_load_hard_{k}", unit, hard + " (75 V / 15 N / 5 N, "
                         "75.3 V / 14.73 N / 4.74 N, 61.6 V / 6.78 N / 2.2 N and the FE set at "
                         "293.6 V / 24.12 N / -1.15 N, exact level and transients)",
                         lambda k=k: _steady_load_hard()[k]))
    diag = ("python -m tools.doc_numbers --show steady_branch_* (" + ex.format(v="V", f=14)
            + " for V = 50, 75, ..., 450)")
    for k, unit in (("dead_zone_last_V", "V"), ("stick-slip_first_V", "V"),
                    ("stick-slip_last_V", "V"), ("pure-slip_first_V", "V"),
                    ("pure-slip_last_V", "V"), ("slip-separation_first_V", "V"),
                    ("v_175V", "m/s"), ("v_200V", "m/s"), ("v_400V", "m/s"), ("v_450V", "m/s"),
                    ("transient_175V", "m/s")):
        out.append(Claim(f"steady_branch_{k.replace('-', '_')}", unit, diag,
                         lambda k=k: _steady_branch_diagram()[k]))
    return out


def _steady_benchmark_claims() -> list[Claim]:
    """docs/steady.md's figures of the map, scan and from-rest benchmarks and of creep."""
    mapc = "python benchmarks/steady_speed.py --map"
    ex = 'steady_state(table2(), {v}, {f}, accuracy="exact")'
    out = []
    for k, unit in (("moving", "-"), ("held", "-"), ("fast_median", "-"), ("fast_p90", "-"),
                    ("fast_max", "-"), ("fast_held_max_m_s", "m/s"), ("exact_median", "-"),
                    ("exact_p90", "-"), ("exact_max", "-"), ("exact_held_max_m_s", "m/s"),
                    ("exact_within_1e-5", "-"), ("creep", "-"), ("ref_longer", "-"),
                    ("ref_unsettled", "-"), ("fast_max_noncreep", "-"),
                    ("fast_speed_ratio", "-"), ("exact_speed_ratio", "-"),
                    ("cli_speed_ratio", "-"), ("cli_worst_moving", "-"),
                    ("cli_undecided", "-"), ("cli_held_max_m_s", "m/s"),
                    ("coarse_speed_ratio", "-"), ("exact_vs_coarse_ratio", "-"),
                    ("coarse_max", "-")):
        out.append(Claim(f"steady_map_{k.replace('-', '_')}", unit,
                         mapc + " (benchmark, minutes; not run by the tests)",
                         lambda k=k: _steady_map()[k], batch="steady_map"))
    scan = "python benchmarks/steady_scan_budget.py"
    for k in ("differ", "k0_samples", "g_change_max", "sign_changes", "former_orbits",
              "former_k0", "former_periods", "former_k0_share", "now_orbits", "now_k0",
              "now_periods", "now_k0_share"):
        out.append(Claim(f"steady_scan_{k}", "-", scan, lambda k=k: _steady_scan()[k],
                         batch="steady_scan"))
    out.append(Claim("steady_scan_time_ratio", "-", scan + " (time former / now)",
                     lambda: _steady_scan()["time_ratio"], batch="steady_scan"))
    rest = "python benchmarks/steady_from_rest.py (benchmark, minutes; not run by the tests)"
    for k in ("points", "probe_decided", "differ", "track_max_accepted", "track_min_rejected",
              "periods_ratio"):
        out.append(Claim(f"steady_from_rest_{k}", "-", rest,
                         lambda k=k: _steady_from_rest()[k], batch="steady_from_rest"))
    out.append(Claim("steady_200V_14N_rest_periods", "-",
                     "steady_state(table2(), 200, 14).rest_periods",
                     _rest_periods_200V_14N, cheap=True, rel_tol=0.0))
    out.append(Claim("steady_ripple_scale_200V_14N_m_s", "m/s",
                     "contact.steady.slow.ripple_scale(table2(), OperatingPoint(200, 14, 40e3), "
                     "mu_d_eff of slow_problem)", _ripple_scale_14N, cheap=True,
                     rel_tol=1e-9))
    for v, f in ((100, 10), (200, 20)):
        for k in ("transient", "exact"):
            cmd = (f"transient_reference(table2(), {v}, {f}, duration_s=0.3)"
                   if k == "transient" else ex.format(v=v, f=f))
            out.append(Claim(f"steady_creep_{v}V_{f}N_{k}_m_s", "m/s", cmd,
                             lambda v=v, f=f, k=k: _steady_creep(float(v), float(f))[k]))
    return out


# --- docs/steady.md: computed figures that had been marked input -------------------------


@cache
def _char_exact(voltage_V: float, preload_N: float):
    """``lusm characteristic --voltage V --preload F`` (exact level, default loads)."""
    from contact.characteristic import characteristic

    return characteristic(_table2(), voltage_V, preload_N)


def _creep_max_m_s() -> float:
    """The largest creep speed (m/s) on the exact curve at 200 V / 14 N: its loads strictly
    between the averaged and the exact stall force (``creeps from`` of the command)."""
    c = _char_exact(200.0, 14.0)
    lo, hi = c.averaged_stall_force_N, c.stall_force_N
    return max(abs(float(v)) for f, v in zip(c.load_N, c.velocity_m_s, strict=True)
               if lo < f < hi)


@cache
def _char_designer(name: str, voltage_V: float):
    """``lusm characteristic --geometry examples/<name>/stator.toml --voltage V --preload 14
    --frequency auto`` (exact level, default loads)."""
    from contact.characteristic import characteristic
    from contact.drive import auto_frequency
    from rom.from_fem import fem_params_from_file

    p = fem_params_from_file(ROOT / "examples" / name / "stator.toml")
    return characteristic(p, voltage_V, 14.0, frequency_Hz=auto_frequency(p))


def _char_30khz_constant_to_N() -> float:
    """The largest load (N) up to which the fast level's default curve at 200 V / 14 N /
    30 kHz keeps its no-load velocity (to 1e-6 relative) at every load."""
    from contact.characteristic import characteristic

    c = characteristic(_table2(), 200, 14, frequency_Hz=30e3, accuracy="fast")
    top = 0.0
    for f, v in zip(c.load_N, c.velocity_m_s, strict=True):
        if abs(v / c.no_load_velocity_m_s - 1.0) > 1e-6:
            break
        top = float(f)
    return top


def _threshold_load_N(voltage_V: float, lo: float, hi: float, duration_s: float,
                      moves: Callable[[object], bool]) -> float:
    """Smallest load (N, to 1e-4 N) in (lo, hi] at which ``moves`` holds for a transient
    from rest of Table 2's set at ``voltage_V`` / 14 N (``lo`` does not, ``hi`` does)."""
    import warnings

    from contact.simulate import simulate

    def run(load: float) -> bool:
        with warnings.catch_warnings():  # the run-away warning is the point here
            warnings.simplefilter("ignore")
            return moves(simulate(_table2(), voltage_V, 14.0, load_N=load,
                                  duration_s=duration_s).steady)

    assert not run(lo) and run(hi)
    while hi - lo > 1e-4:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if run(mid) else (mid, hi)
    return hi


@cache
def _probe_point(params, voltage_V: float, preload_N: float, load_N: float):
    """``contact.steady.from_rest.probe_from_rest`` at 40 kHz, the coupling steady_state's
    default."""
    from contact.model import OperatingPoint, resolve_coupling
    from contact.steady.from_rest import probe_from_rest
    from contact.steady.full_orbit import full_system
    from contact.steady.slow import slow_problem

    coupling = resolve_coupling(params, "auto")
    op = OperatingPoint(voltage_V, preload_N, 40e3, load_N)
    sp = slow_problem(params, op, coupling=coupling, accuracy="exact")
    return probe_from_rest(sp, full_system(params, op, sp.mu_d_eff, coupling))


@cache
def _wrong_sheet() -> dict[str, float]:
    """126.9 V / 14.72 N under -1.57 N (tests/test_from_rest.py): the slider leaves the
    ripple zone beside a period-1 sheet it does not follow and settles on a period-2 orbit."""
    from contact.steady.engine import steady_state

    r = steady_state(_table2(), 126.9, 14.72, load_N=-1.57, energy=False)
    return {"rest_m_s": r.velocity_m_s, "rest_k": r.from_rest.k,
            "root_m_s": next(b.velocity_m_s for b in r.branches
                             if b.k == 1 and b.stable and not b.from_rest),
            "track": _probe_point(_table2(), 126.9, 14.72, -1.57).track_error}


@cache
def _beam_miss() -> dict[str, float]:
    """The beam set at 1000 V / 10 N under -1 N, 40 kHz: the probe's known miss."""
    from contact.steady.engine import steady_state
    from rom.sources import get_params

    p = get_params("beam")
    kw = {"load_N": -1.0, "frequency_Hz": 40e3, "energy": False}
    rest = steady_state(p, 1000, 10, rest="transient", **kw).velocity_m_s
    root = _probe_point(p, 1000.0, 10.0, -1.0).orbit.velocity_m_s
    return {"rest_m_s": rest, "probe_m_s": steady_state(p, 1000, 10, **kw).velocity_m_s,
            "below": 1.0 - rest / root}


@cache
def _stiff_contact(load_N: float) -> float:
    """Table 2's set with a ten times stiffer contact (k_contact = 1.7378e8 N/m) at
    492.28 V / 13.91 N: how much slower (relative) the period-2 orbit a transient from rest
    settles on is than the stable period-1 orbit the exact level answers with."""
    import warnings

    from contact.steady.engine import steady_state

    p = _table2()
    stiff = p.with_(k_contact=10.0 * p.k_contact)
    kw = {"load_N": load_N, "energy": False}
    with warnings.catch_warnings():  # an edited copy of Table 2's: consistent coupling
        warnings.simplefilter("ignore")
        probe = steady_state(stiff, 492.28, 13.91, **kw)
        rest = steady_state(stiff, 492.28, 13.91, rest="transient", **kw)
    assert probe.from_rest.k == 1 and rest.from_rest.k == 2
    return 1.0 - rest.velocity_m_s / probe.velocity_m_s


@cache
def _creep_252V() -> dict[str, float]:
    """252 V / 25.64 N / 40 414 Hz (tests/test_steady_exact.py): the 15-period creep from
    rest, the held orbit shot from the 2 000-period transient's end, and a 400-period window
    of the 0.6 s transient against the creep."""
    from contact.model import OperatingPoint
    from contact.steady.engine import steady_state
    from contact.steady.exact import REST_TRANSIENT_PERIODS
    from contact.steady.full_orbit import full_system, run_periods, shoot
    from contact.steady.settled import transient_reference
    from contact.steady.slow import slow_problem

    f = 40414.0
    creep = steady_state(_table2(), 252, 25.64, frequency_Hz=f, accuracy="exact").from_rest
    op = OperatingPoint(252, 25.64, f)
    fs = full_system(_table2(), op, slow_problem(_table2(), op, accuracy="exact").mu_d_eff,
                     "paper")
    z, m, _, _, _ = run_periods(fs, fs.system.z0, fs.system.mode0, REST_TRANSIENT_PERIODS)
    window = transient_reference(_table2(), 252, 25.64, frequency_Hz=f, duration_s=0.6)[0]
    return {"creep_m_s": creep.velocity_m_s, "creep_k": creep.k,
            "held_multiplier": shoot(fs, z, m, 1, energy=False).multiplier,
            "window_error": abs(window / creep.velocity_m_s - 1.0)}


def _guide_share_139V() -> float:
    """Guide power over input power of the held slider at 139 V / 14 N (exact level)."""
    from contact.steady.engine import steady_state

    b = steady_state(_table2(), 139, 14, accuracy="exact").from_rest
    return b.guide_power_W / b.input_power_W


def _input_1kHz_W() -> float:
    """A 0.3 s transient's own input power (W) at 200 V / 14 N / 1 kHz under 1.5 N (held)."""
    from contact.simulate import simulate

    r = simulate(_table2(), 200, 14, 1e3, duration_s=0.3, energy=True, load_N=1.5)
    return r.energy.input_J / r.steady.window_s


def _hold_check_m_s() -> float:
    """The hold check's bound at 200 V / 14 N: HOLD_CHECK_FACTOR times the ripple scale."""
    from contact.steady.exact import HOLD_CHECK_FACTOR

    return HOLD_CHECK_FACTOR * _ripple_scale_14N()


def _multi_cli_m_s() -> float:
    """``lusm simulate --voltage 75 --preload 15 --load-N 5 --duration 0.3`` (its last 20
    periods)."""
    from contact.simulate import simulate

    return simulate(_table2(), 75, 15, load_N=5.0, duration_s=0.3).steady.velocity_m_s


def _steady_input_claims() -> tuple[Claim, ...]:
    """Figures of docs/steady.md the tests check: the characteristics' stall forces and
    creep, and the steady engine's hard cases."""
    return (*_characteristic_input_claims(), *_steady_case_input_claims())


def _characteristic_input_claims() -> tuple[Claim, ...]:
    """docs/steady.md's stall forces and creep of speed-thrust characteristics."""
    c400 = "lusm characteristic --voltage 400 --preload 14 --json"
    c200 = "lusm characteristic --voltage 200 --preload 14 --json"
    return (
        Claim("steady_char_400V_14N_exact_stall_N", "N", c400 + " (stall_force_N)",
              lambda: _char_exact(400.0, 14.0).stall_force_N, cheap=True, rel_tol=1e-6),
        Claim("steady_char_200V_14N_exact_stall_N", "N", c200 + " (stall_force_N)",
              lambda: _char_exact(200.0, 14.0).stall_force_N, cheap=True, rel_tol=1e-6),
        Claim("steady_char_200V_14N_averaged_stall_N", "N", c200 + " (averaged_stall_force_N)",
              lambda: _char_exact(200.0, 14.0).averaged_stall_force_N, cheap=True,
              rel_tol=1e-6),
        Claim("steady_char_200V_14N_creep_max_m_s", "m/s",
              "lusm characteristic --voltage 200 --preload 14 (the line 'creeps from': at "
              "most ... m/s on this curve)", _creep_max_m_s, cheap=True, rel_tol=1e-5),
        Claim("steady_char_200V_14N_creep_max_share", "-",
              "steady_char_200V_14N_creep_max_m_s / no_load_velocity_m_s of " + c200,
              lambda: _creep_max_m_s() / _char_exact(200.0, 14.0).no_load_velocity_m_s,
              cheap=True, rel_tol=1e-5),
        Claim("char_30kHz_fast_constant_to_N", "N",
              "lusm characteristic --voltage 200 --preload 14 --frequency 30000 --accuracy "
              "fast (the largest load up to which every row keeps the no-load velocity)",
              _char_30khz_constant_to_N, cheap=True, rel_tol=1e-6),
        Claim("char_tuned60k_140V_14N_creep_from_N", "N", _CHAR_T60 + " (creep_from_N)",
              lambda: _char_designer("tuned_60k", 140.0).creep_from_N, cheap=True,
              rel_tol=1e-6),
        Claim("char_tuned60k_140V_14N_averaged_stall_N", "N",
              _CHAR_T60 + " (averaged_stall_force_N)",
              lambda: _char_designer("tuned_60k", 140.0).averaged_stall_force_N, cheap=True,
              rel_tol=1e-6),
        Claim("char_tuned60k_140V_14N_stall_N", "N", _CHAR_T60 + " (stall_force_N)",
              lambda: _char_designer("tuned_60k", 140.0).stall_force_N, cheap=True,
              rel_tol=1e-6),
        Claim("char_tuned40k_100V_14N_stall_N", "N",
              _CHAR_T60.replace("tuned_60k", "tuned_40k").replace("140", "100")
              + " (stall_force_N)",
              lambda: _char_designer("tuned_40k", 100.0).stall_force_N, cheap=True,
              rel_tol=1e-6),
        Claim("steady_undriven_14N_break_free_N", "N",
              _SHOW.format("steady_undriven_14N_break_free_N") + " (the smallest load, to "
              "1e-4 N, at which lusm simulate --voltage 0 --preload 14 --load-N L --duration "
              "0.2 ends with the slider moving)",
              lambda: _threshold_load_N(0.0, 5.7, 5.75, 0.2,
                                        lambda s: s.velocity_m_s != 0.0)),
        Claim("steady_load_100V_14N_runaway_N", "N",
              _SHOW.format("steady_load_100V_14N_runaway_N") + " (the smallest load, to "
              "1e-4 N, at which lusm simulate --voltage 100 --preload 14 --load-N L "
              "--duration 2 does not settle)",
              lambda: _threshold_load_N(100.0, 5.22, 5.24, 2.0, lambda s: not s.settled)),
    )


def _steady_case_input_claims() -> tuple[Claim, ...]:
    """docs/steady.md's hard cases of the steady engine: thresholds, the wrong sheet, the
    beam set's miss, a stiff contact, creep at 252 V."""
    wrong = ("python -m tools.doc_numbers --show 'steady_wrong_sheet_*' (126.9 V / "
             "14.72 N under -1.57 N: steady_state(table2(), 126.9, 14.72, load_N=-1.57), ")
    beam = ("steady_state(get_params('beam'), 1000, 10, load_N=-1, frequency_Hz=40e3{})"
            ".velocity_m_s")
    stiff = ("python -m tools.doc_numbers --show {} (p = table2().with_(k_contact="
             "1.7378e8): 1 - steady_state(p, 492.28, 13.91, load_N={}, rest='transient') over "
             "steady_state(p, 492.28, 13.91, load_N={}), velocity_m_s)")
    s252 = ("python -m tools.doc_numbers --show 'steady_252V_*' (steady_state(table2(), "
            "252, 25.64, frequency_Hz=40414, accuracy='exact'), ")
    return (
        Claim("steady_hold_check_200V_14N_m_s", "m/s",
              "contact.steady.exact.HOLD_CHECK_FACTOR x steady_ripple_scale_200V_14N_m_s",
              _hold_check_m_s, cheap=True, rel_tol=1e-9),
        Claim("steady_wrong_sheet_root_m_s", "m/s", wrong + "the stable period-1 branch)",
              lambda: _wrong_sheet()["root_m_s"], cheap=True, rel_tol=1e-6),
        Claim("steady_wrong_sheet_track", "-", wrong + "contact.steady.from_rest.probe_from_rest's "
              "track_error)", lambda: _wrong_sheet()["track"], cheap=True, rel_tol=1e-6),
        Claim("steady_wrong_sheet_rest_m_s", "m/s", wrong + "velocity_m_s)",
              lambda: _wrong_sheet()["rest_m_s"], cheap=True, rel_tol=1e-6),
        Claim("steady_beam_miss_rest_m_s", "m/s", beam.format(", rest='transient'"),
              lambda: _beam_miss()["rest_m_s"], cheap=True, rel_tol=1e-6),
        Claim("steady_beam_miss_probe_m_s", "m/s", beam.format(""),
              lambda: _beam_miss()["probe_m_s"], cheap=True, rel_tol=1e-6),
        Claim("steady_beam_miss_below", "-",
              "1 - steady_beam_miss_rest_m_s / the sheet's root (contact.steady.from_rest."
              "probe_from_rest(...).orbit.velocity_m_s)",
              lambda: _beam_miss()["below"], cheap=True, rel_tol=1e-5),
        Claim("steady_stiff_slower", "-", stiff.format("steady_stiff_slower", 0, 0),
              lambda: _stiff_contact(0.0), cheap=True, rel_tol=1e-5),
        Claim("steady_stiff_loaded_slower", "-", stiff.format("steady_stiff_loaded_slower",
                                                              0.732, 0.732),
              lambda: _stiff_contact(0.732), cheap=True, rel_tol=1e-5),
        Claim("steady_139V_14N_guide_share", "-",
              'steady_state(table2(), 139, 14, accuracy="exact").from_rest: guide_power_W / '
              "input_power_W", _guide_share_139V, cheap=True, rel_tol=1e-6),
        Claim("steady_1kHz_200V_14N_transient_input_W", "W",
              "simulate(table2(), 200, 14, 1e3, duration_s=0.3, energy=True, load_N=1.5): "
              "energy.input_J / steady.window_s", _input_1kHz_W, cheap=True, rel_tol=1e-6),
        Claim("steady_252V_creep_m_s", "m/s", s252 + "velocity_m_s)",
              lambda: _creep_252V()["creep_m_s"], cheap=True, rel_tol=1e-7),
        Claim("steady_252V_creep_k", "-", s252 + "from_rest.k)",
              lambda: _creep_252V()["creep_k"], cheap=True, rel_tol=0.0),
        Claim("steady_252V_held_multiplier", "-", s252 + "and contact.steady.full_orbit.shoot "
              "of one period from the end of its 2 000-period transient: multiplier)",
              lambda: _creep_252V()["held_multiplier"], cheap=True, rel_tol=1e-5),
        Claim("steady_252V_window_error", "-", s252 + "against transient_reference(table2(), "
              "252, 25.64, frequency_Hz=40414, duration_s=0.6), its last 400 periods)",
              lambda: _creep_252V()["window_error"], cheap=True, rel_tol=1e-4),
        Claim("steady_load_hard_multi_cli_m_s", "m/s",
              "lusm simulate --voltage 75 --preload 15 --load-N 5 --duration 0.3 "
              "(steady_velocity_m_s)", _multi_cli_m_s, cheap=True, rel_tol=1e-6),
    )


# --- docs/limits.md: the cost of the work bounds ------------------------------------------


def _peak_MB(*args: str) -> float:
    """Peak resident memory (MB) of ``python -m lusm.cli ARGS`` (``/usr/bin/time -f %M``)."""
    import subprocess
    import sys

    run = subprocess.run(["/usr/bin/time", "-f", "%M", sys.executable, "-m", "lusm.cli",
                          *args], capture_output=True, text=True, check=True, cwd=ROOT,
                         env={**os.environ, "PYTHONPATH": str(ROOT)})
    return int(run.stderr.split()[-1]) / 1024.0


def _dt_bound_time_ratio() -> float:
    """Wall time of the 2e7-step run (dt = 2.5e-9 s, the bound) over the default 5e5-step run
    (200 V / 14 N, 50 ms), the integrations' own ``wall_time_s``, each the fastest of 3."""
    from contact.simulate import simulate

    _sim(200.0, 14.0, 0.001)
    default = min(simulate(_table2(), 200.0, 14.0).wall_time_s for _ in range(3))
    bound = min(simulate(_table2(), 200.0, 14.0, dt_s=2.5e-9).wall_time_s for _ in range(3))
    return bound / default


@cache
def _refine48() -> dict[str, float]:
    """Dofs and wall time of ``lusm modes --refine 48`` over the default refine's (fastest
    of 3 at the default, one run at 48)."""
    from fem.geometry import PlateStator
    from fem.mesh_settings import DEFAULT_REFINE
    from fem.modes import plate_modes

    default = min(plate_modes(PlateStator(), "pzt8", MeshSettings(2, DEFAULT_REFINE)).wall_time_s
                  for _ in range(3))
    r = plate_modes(PlateStator(), "pzt8", MeshSettings(2, 48))
    return {"dofs": r.dofs, "time_ratio": r.wall_time_s / default}


def _limits_claims() -> tuple[Claim, ...]:
    """Figures of docs/limits.md (the step bound and the largest 2D refine)."""
    sim = "lusm simulate --voltage 200 --preload 14 --json"
    return (
        Claim("limits_bad_input_rows", "-", "sum(len(t) for t in tests.test_bad_input.TABLES"
              ".values()) (the rows of python -m pytest tests/test_bad_input.py)",
              lambda: sum(len(t) for t in __import__(
                  "tests.test_bad_input", fromlist=["x"]).TABLES.values()),
              cheap=True, rel_tol=1e-12),
        Claim("limits_dt_bound_time_ratio", "-", sim + " --dt 2.5e-9 (wall_time_s) over " + sim
              + " (wall_time_s), each the fastest of 3 runs in one process",
              _dt_bound_time_ratio),
        Claim("limits_dt_bound_peak_MB", "MB", "/usr/bin/time -f %M " + sim + " --dt 2.5e-9",
              lambda: _peak_MB("simulate", "--voltage", "200", "--preload", "14", "--dt",
                               "2.5e-9", "--json")),
        Claim("limits_refine48_dofs", "-", "lusm modes --refine 48 --json (dofs)",
              lambda: _refine48()["dofs"], batch="refine48"),
        Claim("limits_refine48_time_ratio", "-", "lusm modes --refine 48 --json (wall_time_s) "
              "over lusm modes --json (wall_time_s)", lambda: _refine48()["time_ratio"],
              batch="refine48"),
        Claim("limits_refine48_peak_MB", "MB", "/usr/bin/time -f %M lusm modes --refine 48 "
              "--json", lambda: _peak_MB("modes", "--refine", "48", "--json")),
    )


# --- docs/distributed.md: the scaling benchmark of lusm explore ---------------------------


_WORKER_START = """
import time
t = time.perf_counter()
import sys
sys.path.insert(0, "benchmarks")
from explore_scaling import STUDY, _warm
from studies.study import study_from_dict
_warm(study_from_dict(STUDY))
print(time.perf_counter() - t)
"""
"""A worker's start in a fresh process: imports, numba kernels (compiled or loaded from the
cache) and one task on a plate outside the study."""


@cache
def _explore_scaling() -> dict[str, float]:
    """``python benchmarks/explore_scaling.py --json`` (one run) as ratios, and a worker's
    start with a cold and a warm numba cache (a fresh ``NUMBA_CACHE_DIR``)."""
    import subprocess
    import sys
    import tempfile

    load = os.getloadavg()[0]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    run = subprocess.run([sys.executable, "benchmarks/explore_scaling.py", "--json"],
                         capture_output=True, text=True, check=True, cwd=ROOT, env=env)
    f = json.loads(run.stdout[run.stdout.index("{"):])
    with tempfile.TemporaryDirectory() as tmp:
        starts = [float(subprocess.run(
            [sys.executable, "-c", _WORKER_START], capture_output=True, text=True, check=True,
            cwd=ROOT, env={**env, "NUMBA_CACHE_DIR": tmp}).stdout.split()[-1])
            for _ in range(2)]
    result_100 = _explore_result_bytes_100()
    task, fe = f["task_time_in_process_s"], f["fe_part_of_task_s"]
    p5, p50 = f["drive_point_5ms_s"], f["drive_point_50ms_s"]
    w1, w2 = f["workers_1"], f["workers_2"]
    # a task's cost besides its drive points: the FE solve, the reduction and the auto drive
    # frequency (the estimate had taken the FE solve alone, and the rest as drive points)
    geo = task - f["drive_points_per_task"] * p5
    t100_5, t100_50 = geo + 100 * p5, geo + 100 * p50
    return {
        "fe_over_task": fe / task, "point5_over_task": p5 / task,
        "geometry_over_task": geo / task,
        "point50_over_point5": p50 / p5,
        "point50_worst_over_best": f["drive_point_50ms_worst_of_5_s"] / p50,
        "w1_rate_over_in_process": w1["tasks_per_s"] * task,
        "speedup_2_over_1": f["speedup_2_over_1"],
        "w1_task_over_in_process": w1["task_time_mean_s"] / task,
        "w2_task_over_in_process": w2["task_time_mean_s"] / task,
        "noop_w1_over_task": w1["noop_round_trip_per_task_s"] / task,
        "noop_w2_over_task": w2["noop_round_trip_per_task_s"] / task,
        "part_write_over_task": w1["part_write_per_task_s"] / task,
        "overhead_w1_over_task": w1["overhead_per_task_s"] / task,
        "overhead_w2_over_task": w2["overhead_per_task_s"] / task,
        "final_write_over_task": w1["final_write_s"] / task,
        "task_over_noop": task / w1["noop_round_trip_per_task_s"],
        "study_bytes": f["study_argument_bytes"],
        "result_bytes": w1["result_bytes_per_task"],
        "bit_identical": float(f["bit_identical_1_vs_2_workers"]),
        "t100_5_over_fe": t100_5 / fe, "t100_50_over_fe": t100_50 / fe,
        "t100_50_worst_over_fe": (geo + 100 * f["drive_point_50ms_worst_of_5_s"]) / fe,
        "contact_share_100_5": 100 * p5 / t100_5,
        "scheduler_share_100_5": max(w1["noop_round_trip_per_task_s"],
                                     w2["noop_round_trip_per_task_s"]) / t100_5,
        "result_kB_100": result_100 / 1e3,
        "results_GB_1e4": result_100 * 1e4 / 1e9,
        "load_average": load,
        "cold_start_over_warm": starts[0] / starts[1],
        "cold_start_share_5": starts[0] / (100 * t100_5),
        "cold_start_share_50": starts[0] / (100 * t100_50),
        "warm_start_share_5": starts[1] / (100 * t100_5),
        "results_over_part_writes_50": 100 * w1["part_write_per_task_s"] / t100_50,
        "results_over_part_writes_fe": 100 * w1["part_write_per_task_s"] / fe,
    }


def _explore_result_bytes_100() -> int:
    """Pickled bytes of one task's result with 100 drive points (10 voltages x 10 preloads,
    the benchmark's plate and solver), as ``lusm explore`` counts them."""
    import pickle
    import sys

    sys.path.insert(0, str(ROOT / "benchmarks"))
    from explore_scaling import STUDY

    from studies.study import study_from_dict
    from studies.task import compute_geometry

    axes = {**STUDY["axes"], "length": "30 mm", "width": "7.5 mm",
            "voltage": {"start": "100 V", "stop": "400 V", "num": 10},
            "preload": {"start": "6 N", "stop": "15 N", "num": 10}}
    return len(pickle.dumps(compute_geometry(study_from_dict({**STUDY, "axes": axes}), 0),
                            protocol=5))


_EXPLORE_UNITS = {"study_bytes": "B", "result_bytes": "B", "result_kB_100": "kB",
                  "results_GB_1e4": "GB"}


def _explore_claims() -> tuple[Claim, ...]:
    """Figures of docs/distributed.md: one run of the scaling benchmark, in one process."""
    cmd = ("python benchmarks/explore_scaling.py --json (benchmark, minutes; not run by the "
           "tests), as ratios; python -m tools.doc_numbers --update 'explore_*'")
    keys = ("fe_over_task", "point5_over_task", "geometry_over_task", "point50_over_point5",
            "point50_worst_over_best",
            "w1_rate_over_in_process", "speedup_2_over_1", "w1_task_over_in_process",
            "w2_task_over_in_process", "noop_w1_over_task", "noop_w2_over_task",
            "part_write_over_task", "overhead_w1_over_task", "overhead_w2_over_task",
            "final_write_over_task", "task_over_noop", "study_bytes", "result_bytes",
            "bit_identical", "t100_5_over_fe", "t100_50_over_fe", "t100_50_worst_over_fe",
            "contact_share_100_5", "scheduler_share_100_5", "result_kB_100", "results_GB_1e4",
            "load_average",
            "cold_start_over_warm", "cold_start_share_5", "cold_start_share_50",
            "warm_start_share_5", "results_over_part_writes_50", "results_over_part_writes_fe")
    return tuple(Claim(f"explore_{k}", _EXPLORE_UNITS.get(k, "-"), cmd,
                       lambda k=k: _explore_scaling()[k], batch="explore_scaling")
                 for k in keys)


@cache
def _tuned_length_study() -> dict[str, float]:
    """``lusm explore examples/studies/tuned_60k_length.toml``'s answers, each geometry computed
    in this process (``compute_geometry``, as a worker computes it): the L1-B2 split and the
    stall force at the shortest and the longest plate."""
    from studies.study import load_study
    from studies.task import compute_geometry

    study = load_study(ROOT / "examples" / "studies" / "tuned_60k_length.toml")
    parts = [compute_geometry(study, i) for i in range(study.n_geometries)]
    out = {}
    for end, part in (("short", parts[0]), ("long", parts[-1])):
        out[f"split_{end}_Hz"] = float(part["split"])
        out[f"stall_{end}_N"] = float(part["stall_force"].ravel()[0])
    return out


def _tuned_length_claims() -> tuple[Claim, ...]:
    """docs/distributed.md, "A designer's stator file": the example study of the tuned stator."""
    cmd = ("lusm explore examples/studies/tuned_60k_length.toml --out t60.nc (variables split "
           "and stall_force at the first and last length)")
    return tuple(Claim(f"study_t60_{k}", k.rsplit("_", 1)[1], cmd,
                       lambda k=k: _tuned_length_study()[k], batch="study_t60")
                 for k in ("split_short_Hz", "split_long_Hz", "stall_short_N", "stall_long_N"))


@cache
def _mesh_noise() -> dict[str, float]:
    """``python benchmarks/parametric_mesh_noise.py``: the tuned stator's split against gmsh's
    element size, over plates a rounding error apart."""
    return _bench("parametric_mesh_noise").measure()


def _mesh_noise_claims() -> tuple[Claim, ...]:
    """docs/distributed.md: how sure a parametric stator's split is (gmsh mesh noise)."""
    cmd = ("python benchmarks/parametric_mesh_noise.py (30 s; the column named by the key, "
           "n = the element size's divisions)")
    keys = ("split_spread_8_Hz", "split_spread_16_Hz", "split_8_Hz", "split_16_Hz",
            "split_32_Hz")
    return tuple(Claim(f"mesh_noise_{k}", "Hz", cmd, lambda k=k: _mesh_noise()[k],
                       batch="mesh_noise") for k in keys)


# --- figures the docs had marked as inputs (a review of the <!--input--> markers) ----------


def _b2_half_wavelength_m() -> float:
    """Half-wavelength (m) of the free-free B2 shape of Eq. 3 on the paper's 30 mm plate."""
    from fem.beam_shapes import BETA2_L
    from rom.table2 import TABLE1

    return math.pi * TABLE1["length_m"] / BETA2_L


def _prepass_settle_periods() -> float:
    """Drive periods (40 kHz) in which Table 2's L1 start transient decays to
    ``PRE_PASS_SETTLE`` (``contact.transient.pre_pass.pre_pass_periods`` takes 1.5 times them)."""
    from contact.transient.pre_pass import PRE_PASS_SETTLE

    p = _table2()  # the L1 free transient decays at C_l / (2 M_l), as pre_pass_periods says
    return math.log(1.0 / PRE_PASS_SETTLE) / (p.C_l / (2.0 * p.M_l) / 40e3)


def _drive_phase_deg() -> float:
    """Phase (degrees) between Table 2's free L1 and B2 tip responses at its auto frequency."""
    import numpy as np

    from contact.drive import auto_frequency
    from rom.damping import free_tip_phasors

    n, t = free_tip_phasors(_table2(), auto_frequency(_table2()))
    d = float(np.angle(n) - np.angle(t))
    return abs(math.degrees(math.remainder(d, 2.0 * math.pi)))


@cache
def _fem_set():
    from rom.sources import get_params

    return get_params("fem")


def _fem_speed_300V_14N(frequency_Hz: float) -> float:
    """Steady speed from rest (m/s) of the FE set at 300 V / 14 N (auto coupling)."""
    from contact.simulate import simulate

    return simulate(_fem_set(), 300.0, 14.0, frequency_Hz,
                    method="steady").steady.velocity_m_s


@cache
def _tuned60k():
    """The FE set of examples/tuned_60k."""
    from rom.from_fem import fem_params_from_file

    return fem_params_from_file(ROOT / "examples" / "tuned_60k" / "stator.toml")


@cache
def _tuned60k_140V_14N():
    """The exact steady state of examples/tuned_60k at 140 V / 14 N, --frequency auto."""
    from contact.drive import auto_frequency
    from contact.steady.engine import steady_state

    p = _tuned60k()
    return steady_state(p, 140.0, 14.0, frequency_Hz=auto_frequency(p), accuracy="exact",
                        energy=False)


def _tuned60k_fold_m_s() -> float:
    """Where the stick-slip sheet of examples/tuned_60k at 140 V / 14 N ends (m/s): the
    averaged orbit at the root a start from rest reaches (contact.steady.from_rest) continued
    upward in v as the probe continues a sheet (steps of SHEET_STEP, halved at a change of
    the period or a jump of a phase fraction by more than PHASE_JUMP, down to
    SHEET_MIN_STEP); the last orbit on the sheet."""
    import numpy as np

    from contact.drive import auto_frequency
    from contact.model import OperatingPoint, resolve_coupling
    from contact.steady.from_rest import PHASE_JUMP, SHEET_MIN_STEP, SHEET_STEP, probe_from_rest
    from contact.steady.full_orbit import full_system
    from contact.steady.periodic_orbit import find_orbit, orbit_phases
    from contact.steady.slow import slow_problem

    p = _tuned60k()
    coupling = resolve_coupling(p, "auto")
    op = OperatingPoint(140.0, 14.0, auto_frequency(p))
    sp = slow_problem(p, op, coupling=coupling, accuracy="exact")
    prev = probe_from_rest(sp, full_system(p, op, sp.mu_d_eff, coupling)).orbit

    def fractions(o):
        phase = orbit_phases(sp.fs, o, sp.average_periods)
        return phase / np.sum(phase)

    frac, ratio = fractions(prev), SHEET_STEP
    while True:
        o = find_orbit(sp.fs, prev.velocity_m_s * ratio, prev.z, prev.mode, tol=sp.orbit_tol,
                       max_periods=sp.search_periods, average_periods=sp.average_periods,
                       jacobian=prev.jacobian)
        if o.k != prev.k or np.max(np.abs(fractions(o) - frac)) > PHASE_JUMP:
            if ratio <= SHEET_MIN_STEP:
                return prev.velocity_m_s
            ratio = math.sqrt(ratio)
            continue
        prev, frac = o, fractions(o)


def _tuned60k_slip_m_s() -> float:
    """The stable pure-slip branch that a start from rest does not reach (m/s)."""
    return next(b.velocity_m_s for b in _tuned60k_140V_14N().branches
                if b.stable and b.motion == "pure-slip")


def _capacitance_pF() -> dict[str, float]:
    """The 2D capacitance matrix of the default plate (F): entries, row sum, parallel plate."""
    from fem.material import get_material, plane_stress

    c = _fe2d_model().capacitance_matrix_F
    st = _fe2d_model().stator
    g = st.electrode_gap_m
    area = 0.25 * (st.length_m - g) * (st.width_m - g)
    return {"C_ee": float(c[0, 0]), "C_13": float(c[0, 2]), "C_12": float(c[0, 1]),
            "C_14": float(c[0, 3]), "row_sum": float(c[0].sum()),
            "parallel_plate": plane_stress(get_material("pzt8")).eps33_F_m * area
            / st.thickness_m}


def _gap_weight_centre() -> float:
    """Top-face potential fraction of one electrode at the centre of the default 0.5 mm strip."""
    from fem.capacitance import gap_cross_section, lateral_permittivity_F_m
    from fem.material import get_material, plane_stress

    mat = get_material("pzt8")
    w = 0.5 * (7.5e-3 - 0.5e-3)
    cs = gap_cross_section(0.5e-3, 3e-3, w, w, lateral_permittivity_F_m(mat),
                           plane_stress(mat).eps33_F_m)
    return float(cs.weight(0.0))


def _bricks(gap_m: float = 0.5e-3, refine: int = 3, layers: int = 3, grading: int = 0) -> int:
    """Bricks of the generated 3D mesh of the paper's plate (``hex_grid_lines``)."""
    from fem.geometry import PlateStator
    from fem.solid3d.model import hex_grid_lines

    x, y, z = hex_grid_lines(PlateStator(electrode_gap_m=gap_m), refine, layers, grading)
    return (len(x) - 1) * (len(y) - 1) * (len(z) - 1)


def _chamfered_bricks(layers: int = 3) -> int:
    """Bricks of examples/chamfered extruded in ``layers`` layers (planform cells x layers)."""
    from fem.meshing.meshed_stator import planform_mesh
    from fem.stator_file import load_stator

    st = load_stator(ROOT / "examples" / "chamfered" / "stator.toml").stator
    return planform_mesh(st).quads.shape[1] * layers


def _b2_port_fa_shift_Hz() -> float:
    """How far the isolated B2 port's antiresonance f_p moves down (Hz) from zeta = 1e-4 to
    0.01 (the port of :func:`_isolated_b2_damping_drift`)."""
    from fem.admittance import plate_admittance

    fa = [plate_admittance(f_min_Hz=50e3, f_max_Hz=60e3, n_points=3001, electrodes=(1, 2, 3, 4),
                           polarity=(1, -1, -1, 1), zeta=z).pairs[0].f_antiresonance_Hz
          for z in (1e-4, 1e-2)]
    return fa[0] - fa[1]


def _table2_zetas() -> tuple[float, float]:
    """Table 2's damping ratios of L1 and B2, which the CLI's admittance borrows."""
    t = _table2()
    return (t.C_l / (2 * math.sqrt(t.K_l * t.M_l)), t.C_b / (2 * math.sqrt(t.K_b * t.M_b)))


def _one_quadrant_b2_coupling() -> float:
    """B2's coupling k_r to the port of electrode 1 alone (``ModalPort.coupling``)."""
    from fem.admittance import design_band_Hz, modal_port

    port = modal_port(_fe2d_model(), design_band_Hz(_fe2d())[1], (1,), None, *_table2_zetas())
    return float(port.coupling()[list(port.mode_names).index("B2")])


def _retained_modes() -> int:
    """Modes ``lusm admittance`` keeps in its default band (``retained_modes``)."""
    from fem.admittance import design_band_Hz, plate_admittance

    f_min, f_max = design_band_Hz(_fe2d())
    z_l, z_b = _table2_zetas()
    return int(plate_admittance(f_min_Hz=f_min, f_max_Hz=f_max, zeta_L1=z_l,
                                zeta_B2=z_b).port.frequencies_Hz.size)


def _default_elements() -> int:
    """Elements of the default generated 2D mesh of the paper's plate."""
    from fem.geometry import PlateStator
    from fem.meshing.mesh import DEFAULT_REFINE, structured_mesh

    return int(structured_mesh(PlateStator(), DEFAULT_REFINE).quads.shape[1])


def _steady_steps(params, frequency_Hz: float) -> int:
    from contact.model import default_coupling
    from contact.steady.slow import steps_per_period

    return steps_per_period(params, frequency_Hz, default_coupling(params)[0])


@cache
def _study_plate_28mm():
    """The FE set of a 28 x 7.5 x 3 mm plate at fe_refine 1 (tests/test_explore.py)."""
    from fem.geometry import PlateStator
    from rom.from_fem import fem_params

    return fem_params(PlateStator(length_m=28e-3), "pzt8", MeshSettings(2, 1))


def _steady_lowest_frequency_Hz(max_steps: int = 20_000) -> float:
    """Lowest whole-hertz drive frequency at which Table 2's set needs at most ``max_steps``
    steady-engine steps per drive period."""
    lo, hi = 1, 1000
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if _steady_steps(_table2(), mid) > max_steps else (lo, mid)
    return float(hi)


def _scale_voltage_V() -> float:
    """The voltage that deflects Table 2's stator statically by ``MAX_STATIC_DEFLECTION_M``."""
    from contact.model import MAX_STATIC_DEFLECTION_M

    p = _table2()
    return MAX_STATIC_DEFLECTION_M / max(abs(p.A_l) / p.K_l, abs(p.A_b) / p.K_b)


def _prepass_zeta(which: str) -> float:
    """zeta_L1 below which the A_N pre-pass (drive at L1's resonance) hits its cap, or warns."""
    from contact.transient.pre_pass import MAX_PRE_PASS_PERIODS, PRE_PASS_SETTLE, UNSETTLED_SHARE

    if which == "cap":  # 1.5 ln(1/settle) / (2 pi zeta) = the cap
        return 1.5 * math.log(1.0 / PRE_PASS_SETTLE) / (2.0 * math.pi * MAX_PRE_PASS_PERIODS)
    # the window (last third) of the capped pre-pass starts with UNSETTLED_SHARE left
    return math.log(1.0 / UNSETTLED_SHARE) / (2.0 * math.pi * MAX_PRE_PASS_PERIODS * 2.0 / 3.0)


def _undriven_friction_N(which: str) -> float:
    """Static (hold) or sliding friction of tip and guide at 0 V / 14 N on Table 2's set."""
    from rom.params import GRAVITY_M_S2

    p, fp = _table2(), 14.0
    guide = p.mu_sd * (fp + p.M_slider * GRAVITY_M_S2)
    return (p.mu_s if which == "hold" else p.mu_d) * fp + guide


@cache
def _fem_char_400V_14N(accuracy: str):
    from contact.characteristic import characteristic
    from contact.drive import auto_frequency

    return characteristic(_fem_set(), 400, 14, frequency_Hz=auto_frequency(_fem_set()),
                          accuracy=accuracy)


_SHOW = "python -m tools.doc_numbers --show {}"
_FEM_STEADY = ("lusm simulate --geometry " + _T2_FEM
               + " --voltage 300 --preload 14 --steady --frequency {}")
_CHAR_T60 = ("lusm characteristic --geometry examples/tuned_60k/stator.toml --voltage 140 "
             "--preload 14 --frequency auto --json")
_T60 = ("lusm simulate --geometry examples/tuned_60k/stator.toml --voltage 140 --preload 14 "
        "--frequency auto --steady --json")
_CAP = ("python -c 'from fem.model import plate_model; "
        "print(plate_model().capacitance_matrix_F)' ({})")


def _reviewed_input_claims() -> tuple[Claim, ...]:
    """Figures the docs quote in prose, computed here so that the tests check them."""
    return (*_design_input_claims(), *_fe_input_claims(), *_limits_input_claims())


def _design_input_claims() -> tuple[Claim, ...]:
    """Reviewed figures of the beam's B2, the contact pre-pass, the drive and the tuned
    60 kHz design."""
    return (
        Claim("beam_B2_half_wavelength_m", "m", _SHOW.format("beam_B2_half_wavelength_m")
              + " (pi l / (beta_2 l), the free-free B2 shape of Eq. 3)",
              _b2_half_wavelength_m, cheap=True, rel_tol=1e-9),
        Claim("beam_B2_half_wavelength_over_width", "-",
              "beam_B2_half_wavelength_m / b_s (7.5 mm)",
              lambda: _b2_half_wavelength_m() / 7.5e-3, cheap=True, rel_tol=1e-9),
        Claim("contact_prepass_settle_periods_table2", "-",
              _SHOW.format("contact_prepass_settle_periods_table2")
              + " (drive periods in which exp(-C_l t / 2M_l) reaches 1e-9, Table 2, 40 kHz)",
              _prepass_settle_periods, cheap=True, rel_tol=1e-9),
        Claim("contact_prepass_needed_table2", "-",
              "ceil(1.5 contact_prepass_settle_periods_table2) (the rule of "
              "contact.transient.pre_pass.pre_pass_periods before its 60-period floor)",
              lambda: float(math.ceil(1.5 * _prepass_settle_periods())), cheap=True,
              rel_tol=0.0),
        Claim("drive_phase_table2_deg", "deg", _SHOW.format("drive_phase_table2_deg")
              + " (angle between rom.damping.free_tip_phasors at auto_frequency(table2()))",
              _drive_phase_deg, cheap=True, rel_tol=1e-6),
        Claim("drive_fem_57500Hz_v_m_s", "m/s", _FEM_STEADY.format(57500),
              lambda: _fem_speed_300V_14N(57.5e3), cheap=True, rel_tol=1e-6),
        Claim("drive_share_fem_40kHz", "-",
              "python -c 'from contact.drive import drive_share; from rom.sources import "
              "get_params; print(drive_share(get_params(\"fem\"), 40e3))' (the first)",
              lambda: __import__("contact.drive", fromlist=["x"]).drive_share(
                  _fem_set(), 40e3)[0], cheap=True, rel_tol=1e-6),
        Claim("tuned60k_140V_14N_rest_m_s", "m/s", _T60 + " (steady_velocity_m_s)",
              lambda: _tuned60k_140V_14N().velocity_m_s, cheap=True, rel_tol=1e-6),
        Claim("tuned60k_140V_14N_fold_m_s", "m/s", _SHOW.format("tuned60k_140V_14N_fold_m_s")
              + " (examples/tuned_60k, 140 V / 14 N, auto frequency: the stick-slip sheet "
              "continued upward from the root a start from rest reaches, to a 1.002 step)",
              _tuned60k_fold_m_s, cheap=True, rel_tol=3e-3),
        Claim("tuned60k_140V_14N_slip_m_s", "m/s", _T60 + " (branches: the stable pure-slip one)",
              _tuned60k_slip_m_s, cheap=True, rel_tol=1e-6),
    )


def _fe_input_claims() -> tuple[Claim, ...]:
    """Reviewed figures of the 2D and 3D FE models: capacitances, gap weights, MAC, element
    counts, admittance."""
    return (
        Claim("fe2d_C_ee_F", "F", _CAP.format("diagonal"),
              lambda: _capacitance_pF()["C_ee"], cheap=True, rel_tol=1e-8),
        Claim("fe2d_C_13_F", "F", _CAP.format("[0, 2]"),
              lambda: _capacitance_pF()["C_13"], cheap=True, rel_tol=1e-8),
        Claim("fe2d_C_12_F", "F", _CAP.format("[0, 1]"),
              lambda: _capacitance_pF()["C_12"], cheap=True, rel_tol=1e-8),
        Claim("fe2d_C_row_sum_F", "F", _CAP.format("a row's sum"),
              lambda: _capacitance_pF()["row_sum"], cheap=True, rel_tol=1e-8),
        Claim("fe2d_C_parallel_plate_F", "F", _SHOW.format("fe2d_C_parallel_plate_F")
              + " (eps33* of fem.plane_stress times a quadrant's area over h)",
              lambda: _capacitance_pF()["parallel_plate"], cheap=True, rel_tol=1e-9),
        Claim("fe2d_gap_weight_centre", "-", _SHOW.format("fe2d_gap_weight_centre")
              + " (fem.capacitance.gap_cross_section(...).weight(0), g = 0.5 mm)",
              _gap_weight_centre, cheap=True, rel_tol=1e-8),
        Claim("fe2d_L1_mac", "-", _MODES + " (mac)", lambda: _fe2d().L1.mac, cheap=True,
              rel_tol=1e-8),
        Claim("fe2d_B2_mac", "-", _MODES + " (mac)", lambda: _fe2d().B2.mac, cheap=True,
              rel_tol=1e-8),
        Claim("fe2d_default_elements", "-", _SHOW.format("fe2d_default_elements")
              + " (fem.meshing.mesh.structured_mesh of the paper's plate at the default refine)",
              lambda: float(_default_elements()), cheap=True, rel_tol=0.0),
        Claim("fe3d_default_bricks", "-", _SHOW.format("fe3d_default_bricks")
              + " (fem.solid3d.model.hex_grid_lines, refine 3, layers 3)",
              lambda: float(_bricks()), cheap=True, rel_tol=0.0),
        Claim("fe3d_bricks_gap002_graded1", "-", _SHOW.format("fe3d_bricks_gap002_graded1")
              + " (fem.solid3d.model.hex_grid_lines at g = 0.02 mm, default mesh graded once)",
              lambda: float(_bricks(0.02e-3, 3, 3, 1)), cheap=True, rel_tol=0.0),
        Claim("fe3d_chamfered_bricks_3_layers", "-",
              _SHOW.format("fe3d_chamfered_bricks_3_layers")
              + " (examples/chamfered's planform cells x 3 layers)",
              lambda: float(_chamfered_bricks()), cheap=True, rel_tol=0.0),
        Claim("adm_B2_isolated_fa_damping_shift_Hz", "Hz",
              _SHOW.format("adm_B2_isolated_fa_damping_shift_Hz")
              + " (the port of adm_B2_isolated_keff_damping_drift: f_p at zeta = 1e-4 minus "
              "f_p at 0.01)", _b2_port_fa_shift_Hz, cheap=True, rel_tol=1e-3),
        Claim("adm_B2_one_quadrant_coupling", "-", _SHOW.format("adm_B2_one_quadrant_coupling")
              + " (fem.admittance.ModalPort.coupling of electrode 1 alone, B2)",
              _one_quadrant_b2_coupling, cheap=True, rel_tol=1e-6),
        Claim("adm_retained_modes", "-", "lusm admittance --json (retained_modes)",
              lambda: float(_retained_modes()), cheap=True, rel_tol=0.0),
    )


def _limits_input_claims() -> tuple[Claim, ...]:
    """Reviewed figures behind the work bounds: steady steps per period, the lowest
    frequency, scales of the pre-pass and of the undriven slider, stall forces of the FE set."""
    return (
        Claim("study_steps_per_period_28mm_1kHz", "-",
              "contact.steady.slow.steps_per_period of a 28 x 7.5 mm plate's FE set at fe_refine "
              "1, 1 kHz (tests/test_explore.py)",
              lambda: float(_steady_steps(_study_plate_28mm(), 1e3)), cheap=True, rel_tol=0.0),
        Claim("study_steps_per_period_28mm_40kHz", "-",
              "contact.steady.slow.steps_per_period of a 28 x 7.5 mm plate's FE set at fe_refine "
              "1, 40 kHz", lambda: float(_steady_steps(_study_plate_28mm(), 40e3)),
              cheap=True, rel_tol=0.0),
        Claim("steady_steps_per_period_table2_40kHz", "-",
              "contact.steady.slow.steps_per_period(table2(), 40e3)",
              lambda: float(_steady_steps(_table2(), 40e3)), cheap=True, rel_tol=0.0),
        Claim("steady_steps_per_period_table2_20Hz", "-",
              "contact.steady.slow.steps_per_period(table2(), 20)",
              lambda: float(_steady_steps(_table2(), 20.0)), cheap=True, rel_tol=0.0),
        Claim("limits_steady_points_20Hz", "-",
              "5e5 // steady_steps_per_period_table2_20Hz (limits.MAX_STEADY_WORK)",
              lambda: float(__import__("lusm.limits", fromlist=["x"]).MAX_STEADY_WORK
                            // _steady_steps(_table2(), 20.0)), cheap=True, rel_tol=0.0),
        Claim("limits_steady_lowest_frequency_Hz", "Hz",
              _SHOW.format("limits_steady_lowest_frequency_Hz")
              + " (lowest whole hertz at which steps_per_period(table2(), f) <= 20 000)",
              _steady_lowest_frequency_Hz, cheap=True, rel_tol=0.0),
        Claim("limits_scale_voltage_V", "V", _SHOW.format("limits_scale_voltage_V")
              + " (contact.model.MAX_STATIC_DEFLECTION_M over Table 2's static deflection "
              "per volt)", _scale_voltage_V, cheap=True, rel_tol=1e-9),
        *(Claim(f"limits_prepass_{k}_zeta", "-", _SHOW.format(f"limits_prepass_{k}_zeta")
                + f" ({formula})", lambda k=k: _prepass_zeta(k), cheap=True, rel_tol=1e-9)
          for k, formula in (("cap", "1.5 ln(1/PRE_PASS_SETTLE) / (2 pi MAX_PRE_PASS_PERIODS)"),
                             ("warn", "ln(1/UNSETTLED_SHARE) / (2 pi 2/3 MAX_PRE_PASS_PERIODS)"))),
        *(Claim(f"steady_undriven_14N_{k}_N", "N", _SHOW.format(f"steady_undriven_14N_{k}_N")
                + f" ({mu} F_P + mu_sd (F_P + M g), Table 2, 14 N)",
                lambda k=k: _undriven_friction_N(k), cheap=True, rel_tol=1e-12)
          for k, mu in (("hold", "mu_s"), ("slide", "mu_d"))),
        Claim("steady_char_fem_400V_14N_stall_N", "N",
              "lusm characteristic --geometry " + _T2_FEM + " --voltage 400 --preload 14 "
              "--frequency auto --json (stall_force_N)",
              lambda: _fem_char_400V_14N("exact").stall_force_N, cheap=True, rel_tol=1e-6),
        Claim("steady_char_fem_400V_14N_fast_stall_N", "N",
              "lusm characteristic --geometry " + _T2_FEM + " --voltage 400 --preload 14 "
              "--frequency auto --accuracy fast --json (stall_force_N)",
              lambda: _fem_char_400V_14N("fast").stall_force_N, cheap=True, rel_tol=1e-6),
    )


# --- the claims --------------------------------------------------------------------------


# --- docs/fem.md: every mode in a band (fem.band), issue 38's designer stator ---------------

BAND_DESIGNER_TOML = """name = "issue 38: 35 x 8 x 3 mm PZT-8 plate with a 2 x 1 mm tip"
[plate]
length_mm = 35.0
width_mm = 8.0
thickness_mm = 3.0
[electrodes]
gap_mm = 0.5
drive = [1, 4]
[material]
name = "pzt8"
[tip]
length_mm = 1.0
width_mm = 2.0
"""
"""Issue 38's stator before tuning (``lusm tune --geometry FILE --fix length`` tunes it)."""

_BAND_KEYS = ("width_mm", "f2d_Hz", "OB3_Hz", "B2_Hz", "L1_Hz", "T3_Hz", "OB3_offset",
              "T3_offset", "count")
"""Keys of :func:`_band_designer`."""


@cache
def _band_designer() -> dict[str, float]:
    """Issue 38's stator tuned with ``--fix length``, then the default 3D model's band
    (``lusm modes --geometry TUNED --model 3d --band``)."""
    import tempfile
    from pathlib import Path

    from fem.band import band_modes, default_band_Hz
    from fem.solid3d.model import modes_of_solid_model, solid_model
    from fem.stator_file import load_stator
    from fem.tuning import tune_plate

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "designer.toml"
        path.write_text(BAND_DESIGNER_TOML, encoding="utf-8")
        design = load_stator(path)
    tuned = tune_plate(fix="length", start=design.stator, material=design.material)
    model = solid_model(tuned.stator, design.material)
    pair = modes_of_solid_model(model)
    ops = {"L1": pair.L1.f_short_Hz, "B2": pair.B2.f_short_Hz}
    band = band_modes(model, *default_band_Hz(ops), ops)
    by = {m.name: m for m in band.modes}
    return {"width_mm": tuned.stator.width_m * 1e3, "f2d_Hz": tuned.L1.f_short_Hz,
            **{f"{n}_Hz": by[n].f_short_Hz for n in ("OB3", "B2", "L1", "T3")},
            "OB3_offset": by["OB3"].offset, "T3_offset": by["T3"].offset,
            "count": float(len(band.modes))}


def _band_claims() -> tuple[Claim, ...]:
    """docs/fem.md's band table of issue 38's stator (a tune and a 3D band: not cheap)."""
    cmd = ("lusm tune --geometry FILE --fix length, then lusm modes --geometry TUNED "
           "--model 3d --band (FILE: tools.doc_numbers.BAND_DESIGNER_TOML)")
    units = {"width_mm": "mm", "count": "-"}
    return tuple(Claim(f"band_designer_{k}", units.get(k, "Hz" if k.endswith("Hz") else "-"),
                       cmd, lambda k=k: _band_designer()[k]) for k in _BAND_KEYS)


@cache
def _bvd_default() -> dict[str, float]:
    """``lusm admittance --zeta 0.002``'s fitted circuit and port on the paper's plate."""
    from fem.admittance import design_band_Hz, plate_admittance
    from fem.equivalent_circuit import equivalent_circuit
    from fem.modes import plate_modes

    res = plate_admittance(None, "pzt8", *design_band_Hz(plate_modes()), 2001, zeta=0.002)
    circuit = equivalent_circuit(res)
    return {"C0_F": circuit.C0_F, "C0_clamped_F": res.port.C0_F, "max_rel": circuit.max_rel}


def _bvd_claims() -> tuple[Claim, ...]:
    """docs/fem3d.md's equivalent-circuit figures (one admittance: cheap)."""
    return tuple(Claim(f"bvd_{k}", "F" if k.endswith("_F") else "-",
                       "lusm admittance --zeta 0.002 --json (equivalent_circuit, C0_F)",
                       lambda k=k: _bvd_default()[k], cheap=True, rel_tol=1e-3)
                 for k in ("C0_F", "C0_clamped_F", "max_rel"))


CLAIMS: tuple[Claim, ...] = (
    Claim("table2_f_L1_Hz", "Hz", "lusm params --source table2",
          lambda: _table2().f_L1_Hz, cheap=True, rel_tol=1e-12),
    Claim("table2_f_B2_Hz", "Hz", "lusm params --source table2",
          lambda: _table2().f_B2_Hz, cheap=True, rel_tol=1e-12),
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
          "python -m tools.doc_numbers --show fe2d_default_time_ratio (order 2, wall "
          "time of refine 16 over the default refine, validation.work_precision."
          "fe_work_precision({2: (4, 16)}); the report's section 3b stops at refine 6)",
          lambda: _fe_precision()[1]),
    Claim("dead_zone_14N_V", "V", "lusm report (section 4, dead-zone edge); "
          "python -m tools.doc_numbers --show dead_zone_14N_V",
          lambda: _dead_zone_edge(14.0), cheap=True, rel_tol=1e-3),
    Claim("dead_zone_14N_vs_paper", "-", "dead_zone_14N_V / 120 V - 1 (paper, Fig. 24)",
          lambda: _dead_zone_edge(14.0) / 120.0 - 1.0, cheap=True, rel_tol=1e-2),
    Claim("dead_zone_14N_consistent_V", "V",
          "python -m tools.doc_numbers --show dead_zone_14N_consistent_V",
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
    Claim("A_N_400V_10N_m", "m", _SIM.format(v=400, f=10) + " (normal_amplitude_m)",
          lambda: _sim(400.0, 10.0).normal_amplitude_m, cheap=True, rel_tol=1e-6),
    *(Claim(f"mu_d_2AN_{v}V_{f}N", "-", f"python -m tools.doc_numbers --show "
            f"mu_d_2AN_{v}V_{f}N (Eq. 11 at twice the normal_amplitude_m of "
            + _SIM.format(v=v, f=f) + ")",
            lambda v=v, f=f: _mu_at_twice_an(float(v), float(f)), cheap=True, rel_tol=1e-6)
      for v, f in ((400, 10), (400, 14), (400, 26), (450, 14), (50, 14))),
    *(Claim(f"v_2AN_{v}V_14N_gain", "-", "python -m tools.doc_numbers --show "
            f"v_2AN_{v}V_14N_gain (the run of " + _SIM.format(v=v, f=14)
            + (" --duration 0.2" if d else "") + " with b_mu doubled, Eq. 11 at twice A_N, "
            "coupling paper, over the same run on Table 2 - 1)",
            lambda v=v, d=d: _gain_at_twice_an(float(v), d), cheap=True, rel_tol=1e-4)
      for v, d in ((200, None), (400, 0.2))),
    Claim("free_L1_tip_200V_m", "m", "python -c \"from rom.damping import free_tip_amplitudes; "
          "from rom import table2; print(free_tip_amplitudes(table2(), 40e3, 200.0))\" (L1, "
          "the first)",
          lambda: _free_tip_amplitudes(200.0)[0], cheap=True, rel_tol=1e-9),
    *(Claim(f"mean_FN_{v}V_{f}N_N", "N", f"python -c \"from contact.steady import "
            f"steady_state; from rom import table2; print(steady_state(table2(), {v}, {f}, "
            "energy=False).from_rest.mean_FN_N)\"",
            lambda v=v, f=f: _mean_normal_force(v, f), rel_tol=1e-6)
      for v, f in ((400, 14), (450, 6), (450, 2))),
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
    Claim("render_mirror_L1", "-", "python -m tools.doc_numbers --show render_mirror_L1",
          lambda: _render_measures()["L1_mirror"]),
    Claim("render_mirror_B2", "-", "python -m tools.doc_numbers --show render_mirror_B2",
          lambda: _render_measures()["B2_mirror"]),
    Claim("render_offset_L1_px", "px", "python -m tools.doc_numbers --show "
          "render_offset_L1_px", lambda: _render_measures()["L1_offset"]),
    Claim("render_offset_B2_px", "px", "python -m tools.doc_numbers --show "
          "render_offset_B2_px", lambda: _render_measures()["B2_offset"]),
    Claim("fe_order1_refine_target", "-",
          "python -m tools.doc_numbers --show fe_order1_refine_target (order-1 refines "
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
    Claim("tune_fixlen35_width_m", "m",
          "python -m lusm.cli tune --fix length --length-mm 35 --json (width_mm)",
          lambda: _tuned_fixed_length().stator.width_m),
    Claim("tune_fixlen35_frequency_Hz", "Hz",
          "python -m lusm.cli tune --fix length --length-mm 35 --json (frequency_Hz)",
          lambda: _tuned_fixed_length().frequency_Hz),
    Claim("tune_fixlen35_split", "-",
          "python -m lusm.cli tune --fix length --length-mm 35 --json "
          "(relative_mismatch)", lambda: _tuned_fixed_length().relative_mismatch),
    Claim("tune_fixlen35_fe_solves", "-",
          "python -m lusm.cli tune --fix length --length-mm 35 --json (fe_solves)",
          lambda: _tuned_fixed_length().fe_solves),
    Claim("tune_fixlen35_3d_width_m", "m",
          "python -m lusm.cli tune --fix length --length-mm 35 --model 3d --json "
          "(width_mm)", lambda: _tuned_fixed_length("3d").stator.width_m),
    Claim("tune_fixlen35_3d_frequency_Hz", "Hz",
          "python -m lusm.cli tune --fix length --length-mm 35 --model 3d --json "
          "(frequency_Hz)", lambda: _tuned_fixed_length("3d").frequency_Hz),
    Claim("tune_fixlen35_3d_split", "-",
          "python -m lusm.cli tune --fix length --length-mm 35 --model 3d --json "
          "(relative_mismatch)", lambda: _tuned_fixed_length("3d").relative_mismatch),
    Claim("tune_fixlen35_3d_fe_solves", "-",
          "python -m lusm.cli tune --fix length --length-mm 35 --model 3d --json "
          "(fe_solves)", lambda: _tuned_fixed_length("3d").fe_solves),
    Claim("tune_fixlen35_split_refine8", "-",
          "python -m tools.doc_numbers --show tune_fixlen35_split_refine8 ((f_B2 - f_L1) "
          "/ f_L1 of the 2D design on a refine-8 2D mesh)",
          lambda: _fixed_length_checks()["split_refine8"]),
    Claim("tune_fixlen35_split_3d", "-",
          "python -m tools.doc_numbers --show tune_fixlen35_split_3d ((f_B2 - f_L1) / "
          "f_L1 of the 2D design on the default 3D mesh)",
          lambda: _fixed_length_checks()["split_3d"]),
    *(Claim(f"tune_fixlen35_h_{k}_{m}", "-",
            "python benchmarks/tune_fixed_length_3d.py --json (h = 1..5 mm at l = 35 mm; "
            "about a minute)", lambda k=k, m=m: _fixed_length_thickness_spans()[m][k],
            batch="tune_fixlen_h")
      for m in ("2d", "3d") for k in ("frequency_span", "width_span")),
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
    Claim("adm_L1_isolated_fr_Hz", "Hz", _ISOLATED.format("L1"),
          lambda: _isolated_pairs()["L1"].f_resonance_Hz, cheap=True, rel_tol=1e-6),
    Claim("adm_L1_isolated_fa_Hz", "Hz", _ISOLATED.format("L1"),
          lambda: _isolated_pairs()["L1"].f_antiresonance_Hz, cheap=True, rel_tol=1e-6),
    Claim("adm_L1_fa_below_modal_Hz", "Hz",
          "python -m tools.doc_numbers --show adm_L1_fa_below_modal_Hz (modal L1 f_open "
          "minus the isolated-L1 antiresonance of the admittance)",
          lambda: _fe2d().L1.f_open_Hz - _isolated_pairs()["L1"].f_antiresonance_Hz,
          cheap=True, rel_tol=1e-4),
    Claim("fe2d_inertia_L1_short_shift_Hz", "Hz",
          "python -m tools.doc_numbers --show fe2d_inertia_L1_short_shift_Hz (L1 short "
          "with minus without the thickness inertia, docs/fem.md 1.3)",
          lambda: _fe2d().L1.f_short_Hz - _fe2d_no_inertia().L1.f_short_Hz,
          cheap=True, rel_tol=1e-5),
    Claim("adm_L1_isolated_keff", "-", _ISOLATED.format("L1"),
          lambda: _isolated_pairs()["L1"].k_eff, cheap=True, rel_tol=1e-5),
    Claim("adm_B2_isolated_keff_damping_drift", "-",
          "python -m tools.doc_numbers --show adm_B2_isolated_keff_damping_drift "
          "(plate_admittance(f_min_Hz=50e3, f_max_Hz=60e3, n_points=3001, electrodes=(1, 2, 3, "
          "4), polarity=(1, -1, -1, 1), zeta=Z), k_eff at Z = 0.01 over Z = 1e-4, minus 1)",
          _isolated_b2_damping_drift, cheap=True, rel_tol=1e-3),
    Claim("adm_B2_isolated_keff", "-", _ISOLATED.format("B2"),
          lambda: _isolated_pairs()["B2"].k_eff, cheap=True, rel_tol=1e-5),
    Claim("fe2d_L1_keff", "-", _MODES, lambda: _fe2d().L1.k_eff, cheap=True, rel_tol=1e-6),
    Claim("fe2d_B2_keff", "-", _MODES, lambda: _fe2d().B2.k_eff, cheap=True, rel_tol=1e-6),
    Claim("contact_speed_ratio", "-", "python benchmarks/contact_speed.py (200 V / 14 N row)",
          lambda: _speed_stick_slip()[0]),
    Claim("contact_vs_reference_dv", "-", "python benchmarks/contact_speed.py (dv/v column)",
          lambda: _speed_stick_slip()[1]),
    *_coupling_claims(),
    *_beam_claims(),
    *_designer_claims(),
    *_parametric_claims(),
    *_fitted_damping_claims(),
    *_operating_limit_claims(),
    *_default_coupling_claims(),
    *_drive_proxy_claims(),
    *_motor_claims(),
    *_contact_claims(),
    *_steady_claims(),
    *_limits_claims(),
    *_explore_claims(),
    *_tuned_length_claims(),
    *_mesh_noise_claims(),
    *_reviewed_input_claims(),
    *_steady_input_claims(),
    *_band_claims(),
    *_bvd_claims(),
)
"""Every quoted result, in the order the generator computes them."""


def claims_by_key() -> dict[str, Claim]:
    """The claims indexed by key.

    Raises
    ------
    ValueError
        If two claims share a key: a marker must name one number, and a dictionary would keep
        the last definition silently.
    """
    table: dict[str, Claim] = {}
    for c in CLAIMS:
        if c.key in table:
            raise ValueError(f"the claim {c.key!r} is defined twice in CLAIMS")
        table[c.key] = c
    return table


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
    wanted = keys or list(table)
    batches: dict[str, list[str]] = {}
    for key in wanted:
        if table[key].batch:
            batches.setdefault(table[key].batch, []).append(key)
    values: dict[str, float] = {}
    for batch_keys in batches.values():
        values.update(zip(batch_keys, _in_fresh_process(batch_keys), strict=True))
    numbers = {}
    for key in wanted:
        c = table[key]
        if key in values:
            value = values[key]
        else:
            value = _in_fresh_process([key])[0] if c.timing else float(c.compute())
        numbers[key] = {"value": value if math.isfinite(value) else None, "unit": c.unit,
                        "command": c.command}
    return {"generated_by": "python -m tools.doc_numbers",
            "date": time.strftime("%Y-%m-%d", time.gmtime()), "machine": machine(),
            "numbers": numbers}


def main(argv: list[str] | None = None) -> int:
    """``python -m tools.doc_numbers [--out docs/numbers.json] [--show KEY ...]``."""
    ap = argparse.ArgumentParser(prog="python -m tools.doc_numbers",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=NUMBERS_JSON, help="where to write the JSON")
    ap.add_argument("--show", nargs="+", metavar="KEY",
                    help="compute and print these claims only (keys or glob patterns such "
                         "as 'steady_branch_*'; nothing written)")
    ap.add_argument("--update", nargs="+", metavar="PATTERN",
                    help="recompute only the claims matching these keys or glob patterns "
                         "(e.g. 'beam_*') and merge them into --out; the rest is kept")
    ap.add_argument("--fill", action="store_true",
                    help="rewrite the marked numbers in the docs from --out (no computing)")
    args = ap.parse_args(argv)
    if args.fill:
        n = fill(json.loads(args.out.read_text()))
        print(f"{n} quoted numbers updated from {args.out}")
        return 0
    if args.update:
        keys = [k for k in claims_by_key() if any(fnmatch.fnmatchcase(k, p) for p in args.update)]
        if not keys:
            print(f"doc_numbers: error: --update {' '.join(args.update)} matches no claim")
            return 2
        fresh = compute(keys)
        old = json.loads(args.out.read_text()) if args.out.exists() else {"numbers": {}}
        numbers = {k: old["numbers"][k] for k in claims_by_key() if k in old["numbers"]}
        numbers.update(fresh["numbers"])
        doc = {**fresh, "numbers": {k: numbers[k] for k in claims_by_key() if k in numbers}}
        if old.get("machine") not in (None, doc["machine"]):
            doc["machine"] += f" (partly: {old['machine']}, {old.get('date')})"
        args.out.write_text(json.dumps(doc, indent=1) + "\n")
        print(f"{len(keys)} numbers updated in {args.out}")
        return 0
    if args.show:  # keys or glob patterns
        table = claims_by_key()
        args.show = [k for p in args.show for k in ([p] if p in table else
                                                    fnmatch.filter(list(table), p) or [p])]
    try:
        doc = compute(args.show)
    except ValueError as exc:
        print(f"doc_numbers: error: {exc}")
        return 2
    if args.show:
        for key, entry in doc["numbers"].items():
            print(f"{key} = {entry['value']:.10g} {entry['unit']}   ({entry['command']})")
        return 0
    tmp = args.out.with_name(args.out.name + ".partial")
    tmp.write_text(json.dumps(doc, indent=1) + "\n")
    os.replace(tmp, args.out)
    print(f"{len(doc['numbers'])} numbers written to {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
