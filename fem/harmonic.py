r"""Direct harmonic response of the free 2D plate: the tip's displacement against frequency.

The reference for the reduced model's free tip amplitudes (:func:`rom.damping.free_tip_phasors`,
the paper's Figs. 5 and 6 measured them with a laser vibrometer): at each frequency the full
FE system of :mod:`fem.model` is solved with the drive voltage on the driven electrodes (the
others grounded), no contact and no preload::

    (K - w^2 M + j w D) u = g V,      g = sum_{driven e} G_e   (N/V),

``K`` the short-circuit stiffness, ``V`` the amplitude of ``V sin(w t)`` and ``u`` the complex
displacement amplitude: the displacement is ``Im(u e^{j w t})``. The damping is the modal
damping of the reduced model on its two modes and nothing else::

    D = (M Phi) diag(2 zeta_r w_r) (M Phi)^T,    Phi = [phi_L1, phi_B2] (mass-normalized),

so that ``phi_r^T D phi_r = 2 zeta_r w_r`` as in ``C = 2 zeta sqrt(K M)`` of
:mod:`rom.from_fem`; every other mode is undamped. ``D`` is applied through the Woodbury
identity on one sparse LU of ``K - w^2 M`` per frequency (:func:`modally_damped_solve`). What
the reduced model leaves out, the quasi-static share of every other mode at the tip, is what
this solve keeps: the difference is the reduction's error.

The tip's tangential displacement is ``u_x`` and its normal one ``u_y`` at the stator's tip
point (the contact point of :mod:`rom.from_fem`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as sla


def modally_damped_solve(K, M, MPhi: np.ndarray, d: np.ndarray, rhs: np.ndarray,
                         omega: float) -> np.ndarray:
    """``u`` of ``(K - w^2 M + j w (M Phi) diag(d) (M Phi)^T) u = rhs`` (complex).

    One sparse LU of ``K - w^2 M``; the rank-``r`` damping through the Woodbury identity
    ``(A + U C U^T)^-1 b = A^-1 b - A^-1 U (C^-1 + U^T A^-1 U)^-1 U^T A^-1 b`` over the modes
    with ``d > 0`` (``d = 2 zeta_r w_r``, 1/s).

    Parameters
    ----------
    K, M : scipy.sparse matrix
        Stiffness (N/m) and mass (kg).
    MPhi : numpy.ndarray
        ``M`` times the mass-normalized damped shapes, (n_dofs, r).
    d : numpy.ndarray
        ``2 zeta_r w_r`` of each shape (1/s).
    rhs : numpy.ndarray
        The force (N), (n_dofs,).
    omega : float
        Angular frequency (rad/s), > 0.
    """
    lu = sla.splu((K - omega**2 * M).astype(complex).tocsc())
    a_rhs = lu.solve(np.asarray(rhs).astype(complex))
    mask = np.asarray(d) > 0
    if not np.any(mask):
        return a_rhs
    U = MPhi[:, mask]
    AU = lu.solve(U.astype(complex))
    cap = np.diag(1.0 / (1j * omega * np.asarray(d)[mask])) + U.T @ AU
    return a_rhs - AU @ np.linalg.solve(cap, U.T @ a_rhs)


def tip_arrays(frequency_Hz: np.ndarray, tangential_m: np.ndarray,
               normal_m: np.ndarray) -> dict[str, list]:
    """The JSON arrays of a tip response: ``frequency_Hz``, ``tip_tangential_um``,
    ``tip_normal_um`` (amplitudes, µm) and their phases against the drive (degrees)."""
    return {"frequency_Hz": np.asarray(frequency_Hz).tolist(),
            "tip_tangential_um": (np.abs(tangential_m) * 1e6).tolist(),
            "tip_normal_um": (np.abs(normal_m) * 1e6).tolist(),
            "tip_tangential_phase_deg": np.angle(tangential_m, deg=True).tolist(),
            "tip_normal_phase_deg": np.angle(normal_m, deg=True).tolist()}


@dataclass(frozen=True, eq=False)
class FeTipResponse:
    """The free tip's complex displacement amplitudes from the direct FE solve.

    Attributes
    ----------
    frequency_Hz : numpy.ndarray
        The frequencies solved (Hz).
    tangential_m, normal_m : numpy.ndarray
        Complex amplitudes (m) of the tip's ``u_x`` and ``u_y`` for the drive
        ``voltage_V sin(w t)``: the displacement is ``Im(a e^{j w t})``.
    voltage_V : float
        The drive amplitude (V).
    zeta_L1, zeta_B2 : float
        The modal damping ratios of L1 and B2 (-).
    dofs : int
        Unknowns of each solve.
    wall_time_s : float
        The solves' wall time (s).
    """

    frequency_Hz: np.ndarray
    tangential_m: np.ndarray
    normal_m: np.ndarray
    voltage_V: float
    zeta_L1: float
    zeta_B2: float
    dofs: int
    wall_time_s: float

    def to_dict(self) -> dict[str, object]:
        """JSON-ready dictionary: amplitudes in µm, phases in degrees (against the drive)."""
        return {**tip_arrays(self.frequency_Hz, self.tangential_m, self.normal_m),
                "dofs": self.dofs, "wall_time_s": self.wall_time_s}


def fe_tip_response(model, modes, frequency_Hz, voltage_V: float, zeta_L1: float,
                    zeta_B2: float) -> FeTipResponse:
    """Direct harmonic solve of the free plate at each frequency (module docstring).

    Parameters
    ----------
    model : fem.model.PiezoPlateModel
        The assembled 2D plate; its stator names the driven electrodes and the tip point.
    modes : fem.modes.PlateModes
        Its L1 and B2 (the damped shapes).
    frequency_Hz : array_like
        Frequencies (Hz), each > 0.
    voltage_V : float
        Drive amplitude (V).
    zeta_L1, zeta_B2 : float
        Modal damping ratios of L1 and B2 (-), as the reduced model's.

    Raises
    ------
    ValueError
        A frequency that is not a finite number > 0.
    """
    f = np.atleast_1d(np.asarray(frequency_Hz, dtype=float))
    if not np.all(np.isfinite(f) & (f > 0.0)):
        raise ValueError(f"frequency_Hz must be finite numbers > 0, got {frequency_Hz!r}")
    t0 = time.perf_counter()
    st = model.stator
    g = model.coupling(st.drive_electrodes) * float(voltage_V)
    shapes = np.column_stack([m.shape / math.sqrt(float(m.shape @ (model.M @ m.shape)))
                              for m in (modes.L1, modes.B2)])
    d = 2.0 * np.array([zeta_L1, zeta_B2]) * 2.0 * math.pi * np.array(
        [modes.L1.f_short_Hz, modes.B2.f_short_Hz])
    MPhi = model.M @ shapes
    P = model.probe(np.array([st.tip_point_m]).T)  # rows: u_x, u_y at the tip
    K, M = model.K.tocsc(), model.M.tocsc()
    tip = np.array([P @ modally_damped_solve(K, M, MPhi, d, g, 2.0 * math.pi * fk)
                    for fk in f])
    f.setflags(write=False)
    return FeTipResponse(frequency_Hz=f, tangential_m=tip[:, 0], normal_m=tip[:, 1],
                         voltage_V=float(voltage_V), zeta_L1=float(zeta_L1),
                         zeta_B2=float(zeta_B2), dofs=int(K.shape[0]),
                         wall_time_s=time.perf_counter() - t0)
