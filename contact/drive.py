"""Choice of the drive frequency of a parameter set (``--frequency auto``)."""

from __future__ import annotations

import numpy as np
from scipy.optimize import minimize_scalar

from rom.damping import free_tip_amplitudes
from rom.params import MotorParams

__all__ = ["auto_frequency", "free_tip_amplitudes"]


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
