"""Speed against error: contact integrators and FE meshes, each against a reference.

Contact: the event-located numba kernel at several steps, the paper's literal fixed-step,
fixed-band scheme (RK4) alongside for contrast, and ``solve_ivp`` at looser tolerances, all
measured against the event-driven ``solve_ivp`` reference at rtol 1e-11 in the same run.
FE: order 1 and 2 structured meshes against the Richardson extrapolation of the two finest
order-2 meshes.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

from contact.simulate import simulate
from rom.params import MotorParams
from rom.table2 import PAPER_DRIVE_HZ


@dataclass(frozen=True)
class PrecisionPoint:
    """One method at one setting: its error and its cost.

    Attributes
    ----------
    method : str
        ``"event-located (numba)"``, ``"literal RK4, eps=..."`` or ``"solve_ivp events"``.
    case : str
        Operating point.
    setting : str
        ``dt = ...`` or ``rtol = ...``.
    velocity_error : float
        ``|v - v_ref| / |v_ref|`` (-).
    stick_error : float
        ``|stick - stick_ref|`` (-).
    wall_time_s : float
        Wall time of the run (s).
    """

    method: str
    case: str
    setting: str
    velocity_error: float
    stick_error: float
    wall_time_s: float


@dataclass(frozen=True)
class FEPoint:
    """One FE mesh: frequencies, errors against the extrapolated reference, cost."""

    order: int
    refine: int
    dofs: int
    f_L1_Hz: float
    f_B2_Hz: float
    error_L1: float
    error_B2: float
    wall_time_s: float
    eig_time_s: float = float("nan")
    """Short-circuit eigensolution alone (s), part of ``wall_time_s``."""


def richardson(f1: float, f2: float, h1_m: float, h2_m: float, rate: float) -> float:
    """Richardson extrapolation ``f2 + (f2 - f1) / ((h1/h2)**rate - 1)`` of two meshes."""
    return f2 + (f2 - f1) / ((h1_m / h2_m) ** rate - 1.0)


def aitken(x0: float, x1: float, x2: float) -> float:
    """Limit of a geometrically converging sequence from its last three terms (Aitken's
    delta-squared); ``x2`` itself when the differences do not shrink with one sign (not, or
    not yet, geometric)."""
    d1, d2 = x1 - x0, x2 - x1
    if d1 == d2 or d1 * d2 <= 0.0 or abs(d2) >= abs(d1):
        return x2
    return x2 - d2 * d2 / (d2 - d1)


def contact_work_precision(
    params: MotorParams,
    cases: tuple[tuple[float, float], ...] = ((200.0, 14.0), (400.0, 14.0)),
    dts: tuple[float, ...] = (1.25e-6, 5e-7, 2.5e-7, 1e-7, 5e-8, 2.5e-8),
    literal_dts: tuple[float, ...] = (1e-7, 5e-8, 2.5e-8),
    literal_eps: tuple[float, ...] = (1e-10, 1e-4),
    rtols: tuple[float, ...] = (1e-6, 1e-8),
    duration_s: float = 0.05,
    frequency_Hz: float = PAPER_DRIVE_HZ,
    progress: Callable[[str], None] | None = None,
) -> tuple[list[PrecisionPoint], dict]:
    """Error in steady velocity and stick fraction against wall time for each method.

    Returns the points and, per case, the reference's own figures (velocity, stick fraction,
    steps, right-hand-side evaluations, wall time).
    """
    say = progress or (lambda _m: None)
    points: list[PrecisionPoint] = []
    refs: dict = {}
    for method in ("event", "literal"):  # JIT warm-up
        simulate(params, 200.0, 14.0, frequency_Hz, duration_s=10 / frequency_Hz, method=method)
    for v, f in cases:
        case = f"{v:g} V / {f:g} N"

        def run(method: str, v: float = v, f: float = f, **kw):
            return simulate(params, v, f, frequency_Hz, duration_s=duration_s, method=method,
                            **kw)

        say(f"reference {case}")
        ref = run("reference", rtol=1e-11)
        refs[case] = {"velocity_m_s": ref.steady.velocity_m_s,
                      "stick_fraction": ref.steady.stick_fraction, "steps": ref.steps,
                      "nfev": ref.nfev, "events": ref.events, "wall_time_s": ref.wall_time_s}

        def point(label: str, setting: str, r, case: str = case, ref=ref) -> PrecisionPoint:
            v_ref = ref.steady.velocity_m_s
            return PrecisionPoint(
                label, case, setting,
                abs(r.steady.velocity_m_s - v_ref) / max(abs(v_ref), 1e-9),
                abs(r.steady.stick_fraction - ref.steady.stick_fraction), r.wall_time_s)

        say(f"event-located kernel {case}")
        for dt in dts:
            points.append(point("event-located (numba)", f"dt = {dt:.3g} s",
                                run("event", dt_s=dt)))
        say(f"literal scheme {case}")
        for eps in literal_eps:
            for dt in literal_dts:
                points.append(point(f"literal RK4, eps = {eps:g}", f"dt = {dt:.3g} s",
                                    run("literal", dt_s=dt, stick_band_m_s=eps)))
        say(f"solve_ivp {case}")
        for rtol in rtols:
            points.append(point("solve_ivp events (DOP853)", f"rtol = {rtol:g}",
                                run("reference", rtol=rtol)))
    return points, refs


def fe_work_precision(
    refines: dict[int, tuple[int, ...]] | None = None,
    reference_refines: tuple[int, int] = (8, 16),
    material: str = "pzt8",
    repeat: int = 1,
) -> tuple[list[FEPoint], dict]:
    """FE frequency error against wall time for order 1 and 2 meshes of the default plate.

    The reference is the Richardson extrapolation (rate h^4) of the order-2 meshes
    ``reference_refines``. Wall time = mesh + assembly + short- and open-circuit solutions,
    the best of ``repeat`` uncached runs.
    """
    from fem.geometry import PlateStator
    from fem.meshing.mesh import max_element_size_m, structured_mesh
    from fem.model import build_model
    from fem.modes import modes_of_model

    refines = refines or {1: (4, 8, 16, 32), 2: (2, 3, 4, 6)}
    stator = PlateStator()

    def solve(order: int, refine: int):
        t0 = time.perf_counter()
        model = build_model(structured_mesh(stator, refine), stator, material, order)
        res = modes_of_model(model, refine=refine)
        return (res.L1.f_short_Hz, res.B2.f_short_Hz, res.dofs, time.perf_counter() - t0,
                res.solve_time_s)

    r1, r2 = reference_refines
    a, b = solve(2, r1), solve(2, r2)
    h1, h2 = max_element_size_m(stator, r1), max_element_size_m(stator, r2)
    ref = [richardson(a[i], b[i], h1, h2, 4) for i in (0, 1)]
    points = []
    for order, rs in refines.items():
        for r in rs:
            fl, fb, dofs, wall, eig = min((solve(order, r) for _ in range(max(1, repeat))),
                                          key=lambda out: out[3])
            points.append(FEPoint(order, r, dofs, fl, fb, abs(fl / ref[0] - 1),
                                  abs(fb / ref[1] - 1), wall, eig))
    return points, {"f_L1_Hz": ref[0], "f_B2_Hz": ref[1], "material": material,
                    "reference": f"Richardson (h^4) of order-2 refine {r1} and {r2}"}
