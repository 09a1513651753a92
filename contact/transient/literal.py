"""The paper's switch model taken literally, for contrast (Section 3.2 with RK4).

Scheme ``method="literal"`` of :func:`contact.simulate.simulate`. Fixed-step fourth-order
Runge-Kutta with the mode decided at the start of each step from the stick band
``|v_rel| <= eps`` (``options.stick_band_m_s``), as the paper describes. With ``eps = 1e-10``
and any practical step, ``v_rel`` jumps over the band, so stick is almost never entered and the
answer depends on ``eps`` and ``dt``; the work-precision study of the report shows how far this
lands from the event-located solution. Not used for results.
"""

from __future__ import annotations

import numpy as np

from contact.deferred_signals import call_held
from contact.model import OperatingPoint, build_system, gamma_T, static_deflection_m
from contact.results import SchemeOutput
from contact.transient import literal_kernel as lk
from contact.transient.event import check_spectrum
from contact.transient.window import RunWindow
from rom.params import GRAVITY_M_S2, MotorParams


def pack_parameters(params: MotorParams, op: OperatingPoint, mu_d_eff: float,
                    coupling: str) -> np.ndarray:
    """The kernel's parameter array (layout: the ``P_*`` indices of the kernel module)."""
    p = np.empty(lk.N_P)
    dphi = params.phi_Ll - params.phi_L0
    p[lk.P_M_L], p[lk.P_C_L], p[lk.P_K_L] = params.M_l, params.C_l, params.K_l
    p[lk.P_ALV] = params.A_l * op.voltage_V
    p[lk.P_M_B], p[lk.P_C_B], p[lk.P_K_B] = params.M_b, params.C_b, params.K_b
    p[lk.P_ABV] = params.A_b * op.voltage_V
    p[lk.P_GAMMA_T] = gamma_T(params, coupling)
    p[lk.P_M] = params.M_slider
    p[lk.P_MU_S], p[lk.P_MU_D], p[lk.P_MU_SD] = params.mu_s, mu_d_eff, params.mu_sd
    p[lk.P_MG] = params.M_slider * GRAVITY_M_S2
    p[lk.P_K], p[lk.P_FP] = params.k_contact, op.preload_N
    p[lk.P_DPHI] = dphi
    p[lk.P_U_ST] = params.eta_N * op.preload_N * dphi / params.K_l  # Eq. 7
    p[lk.P_ETA_N], p[lk.P_PHI_BL], p[lk.P_OMEGA] = params.eta_N, params.phi_Bl, op.omega
    return p


def solve_literal(params: MotorParams, op: OperatingPoint, opts, window: RunWindow,
                  mu_d_eff: float) -> SchemeOutput:
    """Run the literal fixed-step, fixed-band switch model from the static equilibrium."""
    dt = window.dt_s
    # the event scheme's step bound: RK4 above it is unstable (NaN, for a contact stiffness
    # of 1e12 N/m at 1e-7 s)
    check_spectrum(build_system(params, op, mu_d_eff, opts.coupling), dt)
    y0 = np.zeros(6)
    y0[0] = static_deflection_m(params, op.preload_N)
    marks = np.array([window.win_start,
                      int(round(window.previous_start_s / dt)),
                      int(round(window.previous_end_s / dt))], dtype=np.int64)
    y, x_marks, counts, n_switches, nfev = call_held(lk.integrate_literal_switch,
        y0, window.n_steps, dt, pack_parameters(params, op, mu_d_eff, opts.coupling),
        float(opts.stick_band_m_s), window.win_start, marks)
    v_prev = ((x_marks[2] - x_marks[1]) / window.window_s if window.previous_start_s >= 0
              else float("nan"))
    nan = float("nan")
    return SchemeOutput(
        velocity_m_s=float((y[4] - x_marks[0]) / window.window_s),
        previous_velocity_m_s=float(v_prev),
        phase_time=np.array([counts[0], counts[2], counts[3], counts[4]]),
        y_tip_min_m=nan, y_tip_max_m=nan, trace=None, window=None, energy=None,
        steps=window.n_steps, events=int(n_switches), nfev=int(nfev),
    )
