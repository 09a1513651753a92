"""Second free-free in-plane bending frequency of a Timoshenko beam, by Rayleigh-Ritz.

The reference the beam-theory set's B2 (Euler-Bernoulli, or bending and shear condensed in
series, :mod:`rom.beam`) is compared with: shear flexibility and rotary inertia kept as
independent fields.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg

from rom.beam_stator import SHEAR_FACTOR, BeamStator


def timoshenko_b2_frequency(
    beam: BeamStator | None = None,
    *,
    shear_factor: float = SHEAR_FACTOR,
    rotary_inertia: bool = True,
    degree: int = 24,
) -> float:
    """Second free-free bending frequency of a Timoshenko beam, in-plane (Hz).

    Rayleigh-Ritz with independent Legendre expansions (degree ``degree``) of the lateral
    displacement ``w`` and the section rotation ``psi``; free ends need no constraint. The
    first two eigenvalues are the rigid-body modes, the fourth is B2.

    Parameters
    ----------
    beam : BeamStator, optional
        Geometry and density; ``cE11`` is the axial and ``cE66`` the shear modulus
        (default Table 1).
    shear_factor : float
        Shear correction factor ``kappa`` (-), > 0.
    rotary_inertia : bool
        Include the ``rho I psi_t^2`` kinetic energy.
    degree : int
        Highest Legendre degree of each field, >= 6.

    Returns
    -------
    float
        The B2 natural frequency (Hz).
    """
    beam = BeamStator() if beam is None else beam
    l_, rho = beam.length_m, beam.rho_kg_m3
    e_mod, g_mod = beam.cE11_Pa, beam.cE66_Pa
    if not (math.isfinite(shear_factor) and shear_factor > 0):
        raise ValueError(f"shear_factor must lie in (0, inf), got {shear_factor!r}")
    kappa = float(shear_factor)
    if isinstance(degree, bool) or not isinstance(degree, int) or degree < 6:
        raise ValueError(f"degree must be an integer in [6, inf), got {degree!r}")
    area, inertia = beam.area_m2, beam.inertia_m4
    n = degree + 1
    xi, wq = np.polynomial.legendre.leggauss(degree + 2)
    eye = np.eye(n)
    p = np.polynomial.legendre.legvander(xi, degree)  # values
    dp = np.stack([np.polynomial.legendre.legval(xi, np.polynomial.legendre.legder(eye[k]))
                   for k in range(n)], axis=1)  # d/dxi
    jac = 0.5 * l_  # dy = jac dxi
    # Dimensionless unknowns: w / l and psi, derivatives d/dy = d/dxi / jac.
    ppw = (p.T * wq) @ p * jac
    dpw = (dp.T * wq) @ dp / jac
    dpp = (dp.T * wq) @ p
    ks = kappa * g_mod * area
    # U = 1/2 int EI psi'^2 + ks (w' - psi)^2 with w = l * wt.
    k_ww = ks * l_**2 * dpw
    k_wp = -ks * l_ * dpp
    k_pp = e_mod * inertia * dpw + ks * ppw
    m_ww = rho * area * l_**2 * ppw
    m_pp = (rho * inertia if rotary_inertia else 0.0) * ppw
    k = np.block([[k_ww, k_wp], [k_wp.T, k_pp]])
    m = np.block([[m_ww, np.zeros((n, n))], [np.zeros((n, n)), m_pp]])
    # Without rotary inertia psi is condensed statically (its mass block is zero).
    if not rotary_inertia:
        k_red = k_ww - k_wp @ np.linalg.solve(k_pp, k_wp.T)
        lam = scipy.linalg.eigh(k_red, m_ww, eigvals_only=True)
    else:
        lam = scipy.linalg.eigh(k, m, eigvals_only=True)
    lam = np.sort(lam)
    return float(math.sqrt(lam[3]) / (2.0 * math.pi))
