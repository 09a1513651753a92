"""Choice of the drive frequency of a parameter set (``--frequency auto``)."""

from __future__ import annotations

import numpy as np

from rom.damping import free_tip_amplitudes
from rom.params import MotorParams

__all__ = ["auto_frequency", "free_tip_amplitudes", "tip_ellipse_area", "grid_frequency"]

GRID_POINTS = 401
"""Frequencies of :func:`grid_frequency`'s search between the widened resonances."""


def tip_ellipse_area(params: MotorParams, frequency_Hz: float) -> float:
    """The product of the free tip's L1 and B2 amplitudes (m^2 per V^2 at unit drive): the
    free tip ellipse's area over pi."""
    a, b = free_tip_amplitudes(params, frequency_Hz)
    return float(a * b)


def grid_frequency(params: MotorParams) -> tuple[float, float]:
    """``(f, step)`` (Hz): the largest free tip ellipse on :data:`GRID_POINTS` frequencies
    between the two resonances widened by 20 % on both sides, and the grid's step. No SciPy:
    a check that needs only the ellipse's size stays off the optimizer's import."""
    f1, f2 = sorted((params.f_L1_Hz, params.f_B2_Hz))
    grid = np.linspace(0.8 * f1, 1.2 * f2, GRID_POINTS)
    area = np.array([tip_ellipse_area(params, f) for f in grid])
    if not np.max(area) > 0.0:
        # one force factor zero: no ellipse anywhere, and the argmax of zeros was the
        # grid's first point, returned as an operating frequency
        raise ValueError(f"the set drives no tip ellipse (A_l = {params.A_l:g}, A_b = "
                         f"{params.A_b:g} N/V): no operating frequency; drive both modes")
    best = grid[int(np.argmax(area))]
    return float(best), float(grid[1] - grid[0])


def auto_frequency(params: MotorParams) -> float:
    """Operating frequency of a parameter set (Hz): where the free tip ellipse is largest.

    The tip of the free stator traces an ellipse with semi-axes equal to its L1 (normal) and
    B2 (tangential) amplitudes; the frequency maximizing their product (the ellipse area) is
    searched between the two resonances widened by 20 % on both sides
    (:func:`grid_frequency`), then refined on the grid's neighbours. With well-separated
    modes this lands between them, close to the one with the larger force factor.
    """
    from scipy.optimize import minimize_scalar

    best, step = grid_frequency(params)
    res = minimize_scalar(lambda f: -tip_ellipse_area(params, f),
                          bounds=(best - step, best + step), method="bounded",
                          options={"xatol": 1e-3})
    return float(res.x)
