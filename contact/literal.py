"""The paper's switch model taken literally, for contrast (Section 3.2 with RK4).

Fixed-step fourth-order Runge-Kutta with the mode decided at the start of each step from the
stick band ``|v_rel| <= eps``, as the paper describes. With ``eps = 1e-10`` and any practical
step, ``v_rel`` jumps over the band, so stick is almost never entered and the answer depends on
``eps`` and ``dt``; the work-precision study of the report shows how far this lands from the
event-located solution. Not used for results.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from contact.kernels import integrate_literal_switch
from contact.model import OperatingPoint, gamma_T
from rom.params import GRAVITY_M_S2, MotorParams


@dataclass(frozen=True)
class LiteralResult:
    """Steady metrics of the literal scheme.

    Attributes
    ----------
    velocity_m_s : float
        Mean slider velocity over the window (m/s).
    stick_fraction, transition_fraction, slip_fraction, separation_fraction : float
        Fractions of the window's steps spent in each mode of Section 3.2 (-).
    steps : int
    wall_time_s : float
    """

    velocity_m_s: float
    stick_fraction: float
    transition_fraction: float
    slip_fraction: float
    separation_fraction: float
    steps: int
    wall_time_s: float


def simulate_literal(
    params: MotorParams,
    voltage_V: float,
    preload_N: float,
    frequency_Hz: float = 40e3,
    duration_s: float = 0.05,
    dt_s: float = 1e-7,
    eps_m_s: float = 1e-10,
    mu_d_eff: float | None = None,
    coupling: str = "paper",
    steady_periods: int = 20,
) -> LiteralResult:
    """Run the literal fixed-step, fixed-band switch model from the same initial state."""
    op = OperatingPoint(float(voltage_V), float(preload_N), float(frequency_Hz))
    if not (math.isfinite(dt_s) and 0 < dt_s <= op.period_s / 20):
        raise ValueError(f"dt_s must be in (0, {op.period_s / 20:.4g}] s, got {dt_s!r}")
    if not (math.isfinite(eps_m_s) and eps_m_s >= 0):
        raise ValueError(f"eps_m_s must be finite and >= 0, got {eps_m_s!r}")
    pr = params
    mu_d = pr.mu_d if mu_d_eff is None else mu_d_eff
    dphi = pr.phi_Ll - pr.phi_L0
    u_st = pr.eta_N * op.preload_N * dphi / pr.K_l
    p = np.array([
        pr.M_l, pr.C_l, pr.K_l, pr.A_l * op.voltage_V, pr.M_b, pr.C_b, pr.K_b,
        pr.A_b * op.voltage_V, gamma_T(pr, coupling), pr.M_slider, pr.mu_s, mu_d, pr.mu_sd,
        pr.M_slider * GRAVITY_M_S2, pr.k_contact, op.preload_N, dphi, u_st, pr.eta_N,
        pr.phi_Bl, op.omega,
    ])
    y0 = np.zeros(6)
    y0[0] = pr.eta_N * op.preload_N / pr.K_l
    n = int(round(duration_s / dt_s))
    win = int(round(min(steady_periods, n * dt_s * frequency_Hz / 2) / frequency_Hz / dt_s))
    t0 = time.perf_counter()
    y, x_win, counts = integrate_literal_switch(y0, n, dt_s, p, eps_m_s, n - win)
    wall = time.perf_counter() - t0
    frac = counts / max(counts.sum(), 1.0)
    return LiteralResult(
        velocity_m_s=float((y[4] - x_win) / (win * dt_s)),
        stick_fraction=float(frac[0]),
        transition_fraction=float(frac[1]),
        slip_fraction=float(frac[2]),
        separation_fraction=float(frac[3]),
        steps=n,
        wall_time_s=wall,
    )
