"""The paper's switch model taken literally (numba): fixed-step RK4, mode frozen per step.

Stick when ``|v_rel| <= eps`` and ``|F_s| <= mu_s F_N``, transition when ``|v_rel| <= eps``
and ``|F_s| > mu_s F_N``, slip otherwise, separation when F_N <= 0 (Section 3.2). Parameters
arrive as one float array whose layout the ``P_*`` indices name; :func:`pack_parameters` in
:mod:`contact.transient.literal` fills it. The thin typed wrapper is
:func:`contact.simulate.simulate` with ``method="literal"``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

# Layout of the parameter array (all SI).
P_M_L = 0  # L1 modal mass (kg)
P_C_L = 1  # L1 damping (N s/m)
P_K_L = 2  # L1 stiffness (N/m)
P_ALV = 3  # A_l V0 (N)
P_M_B = 4  # B2 modal mass (kg)
P_C_B = 5  # B2 damping (N s/m)
P_K_B = 6  # B2 stiffness (N/m)
P_ABV = 7  # A_b V0 (N)
P_GAMMA_T = 8  # tangential coupling factor on B2 (-)
P_M = 9  # slider mass (kg)
P_MU_S = 10  # static friction coefficient (-)
P_MU_D = 11  # dynamic friction coefficient in slip (-)
P_MU_SD = 12  # guide friction coefficient (-)
P_MG = 13  # slider weight (N)
P_K = 14  # contact stiffness (N/m)
P_FP = 15  # preload (N)
P_DPHI = 16  # phi_L(l) - phi_L(0) (-)
P_U_ST = 17  # static elongation under the preload (m)
P_ETA_N = 18  # normal coupling factor (-)
P_PHI_BL = 19  # phi_B(l) (-)
P_OMEGA = 20  # drive circular frequency (rad/s)
N_P = 21
"""Length of the parameter array."""

STICK, TRANSITION, SLIP, SEPARATION = 0, 1, 2, 3
"""Modes of Section 3.2."""


@njit(cache=True)
def _rhs(t, y, mode, fs_sign, p, out):
    """Right-hand side in one mode (frozen per step); returns the tangential force F_T (N).

    ``y = [u_l, du_l, w_b, dw_b, x, dx]``; ``fs_sign`` the slip or transition direction.
    """
    s = np.sin(p[P_OMEGA] * t)
    fn = p[P_FP] + p[P_K] * (p[P_DPHI] * y[0] - p[P_U_ST])
    if mode == SEPARATION or fn <= 0.0:
        fn = 0.0
    ng = fn + p[P_MG]
    ff = 0.0
    if y[5] > 0.0:
        ff = -p[P_MU_SD] * ng
    elif y[5] < 0.0:
        ff = p[P_MU_SD] * ng
    if mode == STICK:  # Eq. 10
        num = p[P_PHI_BL] / p[P_M_B] * (p[P_C_B] * y[3] + p[P_K_B] * y[2] - p[P_ABV] * s)
        num += ff / p[P_M]
        ft = num / (p[P_PHI_BL] * p[P_GAMMA_T] / p[P_M_B] - 1.0 / p[P_M])
    elif mode == TRANSITION:
        ft = fs_sign * p[P_MU_S] * fn  # Eqs. 14-15
    elif mode == SLIP:
        ft = fs_sign * p[P_MU_D] * fn  # Eqs. 16-17
    else:
        ft = 0.0  # Eqs. 18-19
    out[0] = y[1]
    out[1] = (-p[P_K_L] * y[0] - p[P_C_L] * y[1] + p[P_ALV] * s + p[P_ETA_N] * fn) / p[P_M_L]
    out[2] = y[3]
    out[3] = (-p[P_K_B] * y[2] - p[P_C_B] * y[3] + p[P_ABV] * s + p[P_GAMMA_T] * ft) / p[P_M_B]
    out[4] = y[5]
    out[5] = (ft + ff) / p[P_M]
    return ft


@njit(cache=True, nogil=True)
def integrate_literal_switch(y0, n_steps, dt, p, eps, win_start, marks):
    """Integrate from ``y0`` for ``n_steps`` RK4 steps of ``dt`` (s).

    Parameters
    ----------
    y0 : (6,) array
        Initial ``[u_l, du_l, w_b, dw_b, x, dx]``.
    p : (N_P,) array
        Parameters, see the ``P_*`` indices.
    eps : float
        Stick band (m/s).
    win_start : int
        First step of the window over which the modes are counted.
    marks : (k,) int array
        Steps after which the slider position is recorded.

    Returns
    -------
    y_end, x_marks, counts, n_switches, nfev
        ``counts`` = steps in [stick, transition, slip with v_rel > 0, slip with v_rel < 0,
        separation] over the window (transition steps also count as slip in their direction);
        ``n_switches`` = mode changes between steps;
        ``nfev`` = right-hand-side evaluations.
    """
    y = y0.copy()
    k1 = np.empty(6)
    k2 = np.empty(6)
    k3 = np.empty(6)
    k4 = np.empty(6)
    yt = np.empty(6)
    counts = np.zeros(5)
    x_marks = np.zeros(marks.size)
    for j in range(marks.size):
        if marks[j] == 0:
            x_marks[j] = y[4]
    n_switches = 0
    nfev = 0
    last = -1
    for n in range(n_steps):
        t = n * dt
        fn = p[P_FP] + p[P_K] * (p[P_DPHI] * y[0] - p[P_U_ST])
        v_rel = p[P_PHI_BL] * y[3] - y[5]
        fs_sign = 1.0
        if fn <= 0.0:
            mode = SEPARATION
        elif abs(v_rel) <= eps:
            # int64, not the literal STICK: one compiled _rhs for every call
            fs = _rhs(t, y, np.int64(STICK), 1.0, p, k1)
            nfev += 1
            if abs(fs) <= p[P_MU_S] * fn:
                mode = STICK
            else:
                mode = TRANSITION
                fs_sign = 1.0 if fs > 0.0 else -1.0
        else:
            mode = SLIP
            fs_sign = 1.0 if v_rel > 0.0 else -1.0
        if last >= 0 and mode != last:
            n_switches += 1
        last = mode
        _rhs(t, y, mode, fs_sign, p, k1)
        for i in range(6):
            yt[i] = y[i] + 0.5 * dt * k1[i]
        _rhs(t + 0.5 * dt, yt, mode, fs_sign, p, k2)
        for i in range(6):
            yt[i] = y[i] + 0.5 * dt * k2[i]
        _rhs(t + 0.5 * dt, yt, mode, fs_sign, p, k3)
        for i in range(6):
            yt[i] = y[i] + dt * k3[i]
        _rhs(t + dt, yt, mode, fs_sign, p, k4)
        nfev += 4
        for i in range(6):
            y[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        if n >= win_start:
            if mode == SLIP or mode == TRANSITION:
                counts[2 if fs_sign > 0.0 else 3] += 1.0
                if mode == TRANSITION:
                    counts[1] += 1.0
            elif mode == STICK:
                counts[0] += 1.0
            else:
                counts[4] += 1.0
        for j in range(marks.size):
            if marks[j] == n + 1:
                x_marks[j] = y[4]
    return y, x_marks, counts, n_switches, nfev
