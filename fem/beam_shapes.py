"""Free-free Euler-Bernoulli mode shapes of Eq. 3 (paper), used as assumed modes.

``phi_L(y) = cos(pi y / l)`` for L1 and
``phi_B(y) = alpha2 (cos b y + cosh b y) + (sin b y + sinh b y)`` for B2 with
``b l = 2.499753 pi`` (the second free-free root, 7.853205) and
``alpha2 = (sin b l - sinh b l) / (cosh b l - cos b l)``.

The paper's normalization is kept as printed: ``phi_L(0) = 1`` and
``|phi_B(0)| = |phi_B(l)| = 2 |alpha2| ~ 1.998``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

BETA2_L = 2.499753 * np.pi
"""Dimensionless B2 wavenumber ``beta_2 l`` as printed under Eq. 3 (-)."""

ALPHA2 = (np.sin(BETA2_L) - np.sinh(BETA2_L)) / (np.cosh(BETA2_L) - np.cos(BETA2_L))
"""Coefficient ``alpha_2`` of Eq. 3 (-)."""


def phi_L(y: ArrayLike, length_m: float) -> np.ndarray:
    """L1 shape ``cos(pi y / l)`` at axial positions ``y`` (m) of a stator of length ``l`` (m)."""
    return np.cos(np.pi * np.asarray(y, dtype=float) / length_m)


def phi_B(y: ArrayLike, length_m: float, derivative: int = 0) -> np.ndarray:
    """B2 shape of Eq. 3 or its ``derivative``-th derivative (0-2) with respect to ``y`` (m).

    Parameters
    ----------
    y : array_like
        Axial positions in [0, l] (m).
    length_m : float
        Stator length l (m).
    derivative : int
        0 for the shape (-), 1 for its slope (1/m), 2 for its curvature (1/m^2).
    """
    b = BETA2_L / length_m
    by = b * np.asarray(y, dtype=float)
    c, ch, s, sh = np.cos(by), np.cosh(by), np.sin(by), np.sinh(by)
    if derivative == 0:
        return ALPHA2 * (c + ch) + (s + sh)
    if derivative == 1:
        return b * (ALPHA2 * (-s + sh) + (c + ch))
    if derivative == 2:
        return b**2 * (ALPHA2 * (-c + ch) + (-s + sh))
    raise ValueError(f"derivative must be 0, 1 or 2, got {derivative!r}")
