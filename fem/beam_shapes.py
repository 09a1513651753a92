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


FREE_FREE_ROOTS = (4.730040745, 7.853204624, 10.995607838, 14.137165491, 17.278759657)
"""The first roots ``beta_n l`` of the free-free beam's ``cos(beta l) cosh(beta l) = 1`` (-);
beyond them ``(n + 1/2) pi`` is exact to 3e-9 (:func:`free_free_root`)."""


def free_free_root(n: int) -> float:
    """``beta_n l`` of the n-th free-free bending mode (n >= 1; n = 2 is B2, Eq. 3) (-)."""
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n!r}")
    return FREE_FREE_ROOTS[n - 1] if n <= len(FREE_FREE_ROOTS) else (n + 0.5) * np.pi


def bending_over_rod_frequency(n: int, slenderness: float) -> float:
    """Euler-Bernoulli frequency of the n-th in-plane free-free bending mode of a bar
    ``slenderness`` = length / width times longer than wide, over its rod L1 frequency
    ``c / (2 l)`` (-): ``(beta_n l)^2 / (pi sqrt(12) l / w)``, whatever the material (both
    take the same Young's modulus along the bar; the width is the bending depth)."""
    return free_free_root(n) ** 2 / (np.pi * np.sqrt(12.0) * slenderness)
