"""Choice of the drive frequency of a parameter set (``--frequency auto``)."""

from __future__ import annotations

import numpy as np
from scipy.optimize import minimize_scalar

from rom.params import MotorParams


def free_tip_amplitudes(params: MotorParams, frequency_Hz: np.ndarray | float, voltage_V=1.0):
    """Free (no contact) steady tip amplitudes (m) of the L1 and B2 modes at a frequency.

    Returns ``(|phi_L(l) u_l|, |phi_B(l) w_b|)`` for the drive ``voltage_V sin(omega t)``.
    """
    p = params
    w = 2 * np.pi * np.asarray(frequency_Hz, dtype=float)
    ul = p.A_l * voltage_V / np.abs(p.K_l - p.M_l * w**2 + 1j * p.C_l * w)
    wb = p.A_b * voltage_V / np.abs(p.K_b - p.M_b * w**2 + 1j * p.C_b * w)
    return np.abs(p.phi_Ll * ul), np.abs(p.phi_Bl * wb)


def auto_frequency(params: MotorParams) -> float:
    """Operating frequency of a parameter set (Hz): where the free tip ellipse is largest.

    The tip of the free stator traces an ellipse with semi-axes equal to its L1 (normal) and
    B2 (tangential) amplitudes; the frequency maximizing their product (the ellipse area) is
    searched between the two resonances widened by 20 % on both sides. With well-separated
    modes this lands between them, close to the one with the larger force factor.
    """
    f1, f2 = sorted((params.f_L1_Hz, params.f_B2_Hz))
    lo, hi = 0.8 * f1, 1.2 * f2

    def neg_area(f: float) -> float:
        a, b = free_tip_amplitudes(params, f)
        return -float(a * b)

    grid = np.linspace(lo, hi, 401)
    best = grid[int(np.argmin([neg_area(f) for f in grid]))]
    step = grid[1] - grid[0]
    res = minimize_scalar(neg_area, bounds=(best - step, best + step), method="bounded",
                          options={"xatol": 1e-3})
    return float(res.x)
