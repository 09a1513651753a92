r"""Butterworth-Van Dyke equivalent circuit of the driven electrodes, fitted to the admittance.

The circuit is the clamped capacitance ``C0`` in parallel with one motional branch
``R1 - L1 - C1`` in series per mode in the band::

    Y(w) = j w C0 + sum_r 1 / (R_r + j w L_r + 1 / (j w C_r)).

A mode of the modal superposition (:mod:`fem.admittance`) *is* such a branch: with the
mass-normalized mode ``r`` of natural frequency ``w_r``, damping ratio ``zeta_r`` and port
force factor ``a_r = g^T phi_r`` (N/V per sqrt(kg)),

    j w a_r^2 / (w_r^2 - w^2 + 2 j zeta_r w_r w) = 1 / (R_r + j w L_r + 1 / (j w C_r)),
    C_r = a_r^2 / w_r^2,   L_r = 1 / a_r^2 (modal mass 1 kg over the force factor squared),
    R_r = 2 zeta_r w_r L_r,

so the fit starts there; ``C0`` starts from the computed admittance less those branches,
averaged over the band (the modes outside the band and the residual mode act there as a
slowly varying capacitance, which the fitted ``C0`` takes up). The fit (:func:`fit_bvd`:
variable projection, the capacitances by linear least squares inside a nonlinear fit of each
branch's series resonance and Q) then adjusts every element to the computed curve.

Per mode, as IEEE Std 176 and IEC 60483 define them for an isolated branch: the series
resonance ``f_s = 1 / (2 pi sqrt(L1 C1))``, the parallel resonance ``f_p = f_s sqrt(1 + C1 /
C0)``, the mechanical quality factor ``Q_m = sqrt(L1 / C1) / R1 = 1 / (2 pi f_s R1 C1)``, the
capacitance ratio ``r = C0 / C1`` and ``k_eff^2 = 1 - (f_s / f_p)^2 = C1 / (C0 + C1)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from fem.frozen import freeze_arrays


@dataclass(frozen=True)
class MotionalBranch:
    """One motional branch ``R1 - L1 - C1`` of the circuit.

    Attributes
    ----------
    mode : str
        The mode's name (``'L1'``, ``'B2'``) or ``''``.
    R_ohm, L_H, C_F : float
        Motional resistance (ohm), inductance (H) and capacitance (F).
    f_mode_Hz : float
        The FE mode's short-circuit natural frequency the branch stands for (Hz).
    """

    mode: str
    R_ohm: float
    L_H: float
    C_F: float
    f_mode_Hz: float

    @property
    def f_s_Hz(self) -> float:
        """Series resonance ``1 / (2 pi sqrt(L1 C1))`` (Hz)."""
        return 1.0 / (2.0 * math.pi * math.sqrt(self.L_H * self.C_F))

    @property
    def Q_m(self) -> float:
        """Mechanical quality factor ``sqrt(L1 / C1) / R1`` (-)."""
        return math.sqrt(self.L_H / self.C_F) / self.R_ohm

    def f_p_Hz(self, C0_F: float) -> float:
        """Parallel resonance ``f_s sqrt(1 + C1 / C0)`` beside the clamped ``C0_F`` (Hz)."""
        return self.f_s_Hz * math.sqrt(1.0 + self.C_F / C0_F)

    def k_eff(self, C0_F: float) -> float:
        """``sqrt(1 - (f_s / f_p)^2) = sqrt(C1 / (C0 + C1))`` (-)."""
        return math.sqrt(self.C_F / (C0_F + self.C_F))


@dataclass(frozen=True)
class EquivalentCircuit:
    """A fitted Butterworth-Van Dyke circuit.

    Attributes
    ----------
    C0_F : float
        Parallel (clamped) capacitance (F).
    branches : tuple of MotionalBranch
        One per mode, by increasing frequency.
    f_Hz : numpy.ndarray
        The frequencies fitted (Hz).
    rms_rel : float
        Root mean square of ``|Y_fit - Y| / |Y|`` over them (-).
    max_rel : float
        Largest ``|Y_fit - Y| / |Y|`` (-).
    """

    C0_F: float
    branches: tuple
    f_Hz: np.ndarray
    rms_rel: float
    max_rel: float

    def __post_init__(self) -> None:
        freeze_arrays(self)

    def admittance_S(self, f_Hz: np.ndarray) -> np.ndarray:
        """The circuit's complex admittance at ``f_Hz`` (S)."""
        return bvd_admittance_S(f_Hz, self.C0_F, [(b.R_ohm, b.L_H, b.C_F)
                                                  for b in self.branches])

    def to_dict(self) -> dict[str, object]:
        """JSON-ready: the ``equivalent_circuit`` object of ``lusm admittance --json``."""
        return {"C0_F": self.C0_F, "fit_rms_rel": self.rms_rel, "fit_max_rel": self.max_rel,
                "modes": [{"mode": b.mode, "R1_ohm": b.R_ohm, "L1_H": b.L_H, "C1_F": b.C_F,
                           "f_s_Hz": b.f_s_Hz, "f_p_Hz": b.f_p_Hz(self.C0_F), "Q_m": b.Q_m,
                           "k_eff": b.k_eff(self.C0_F), "C0_over_C1": self.C0_F / b.C_F,
                           "f_mode_Hz": b.f_mode_Hz,
                           "f_s_rel_to_mode": b.f_s_Hz / b.f_mode_Hz - 1.0}
                          for b in self.branches]}


def bvd_admittance_S(f_Hz: np.ndarray, C0_F: float, branches) -> np.ndarray:
    """``j w C0 + sum 1 / (R + j w L + 1 / (j w C))`` at ``f_Hz`` (S); ``branches``: an
    iterable of ``(R_ohm, L_H, C_F)``."""
    w = 2.0 * math.pi * np.asarray(f_Hz, dtype=float)
    y = 1j * w * C0_F
    for r, ell, c in branches:
        y = y + 1.0 / (r + 1j * w * ell + 1.0 / (1j * w * c))
    return y


REGULARISATION = 1e-6
"""Weight of the start in the fit, against residuals of order 1 per frequency: it decides
only what the admittance cannot, such as how two branches of one frequency and one Q share
their capacitance (a stator tuned to L1 = B2 with one damping for both), and moves a
determined fit by far less than 1e-9."""


def _branch_columns(w: np.ndarray, f_s: np.ndarray, q: np.ndarray) -> np.ndarray:
    """``j w / (1 - (w / w_s)^2 + j w / (Q w_s))`` per branch (n_f, n_b): a branch's
    admittance per farad of its ``C1``, given its series resonance and Q (S/F)."""
    ws = 2.0 * math.pi * f_s
    return 1j * w[:, None] / (1.0 - (w[:, None] / ws) ** 2 + 1j * w[:, None] / (q * ws))


def fit_bvd(f_Hz: np.ndarray, Y_S: np.ndarray, C0_F: float, branches,
            modes: tuple[str, ...] | None = None,
            f_modes_Hz: tuple[float, ...] | None = None,
            background_S: np.ndarray | None = None) -> EquivalentCircuit:
    """The circuit nearest the admittance ``Y_S`` at ``f_Hz`` from the start ``C0_F``,
    ``branches`` (``(R_ohm, L_H, C_F)`` each).

    Variable projection: given each branch's series resonance ``f_s`` and ``Q_m`` the
    admittance is linear in the capacitances (``C0``, and ``C1`` through ``j w C1 / (1 -
    (w/w_s)^2 + j w / (Q w_s))``), which a linear least-squares solve gives; the ``f_s`` and
    ``Q_m`` (their logarithms) are fitted around it by :func:`scipy.optimize.least_squares`.
    Residuals ``(Y_fit - Y) / |Y|`` (real and imaginary parts), with the start weighted by
    :data:`REGULARISATION`, tolerances at roundoff.

    Parameters
    ----------
    f_Hz, Y_S : numpy.ndarray
        Frequencies (Hz) and complex admittance (S).
    C0_F : float
        Start of the parallel capacitance (F).
    branches : sequence of (float, float, float)
        Start of each motional branch ``(R_ohm, L_H, C_F)``.
    modes : tuple of str, optional
        Each branch's mode name (default ``''``).
    f_modes_Hz : tuple of float, optional
        Each branch's mode frequency (default: its start's series resonance).
    background_S : numpy.ndarray, optional
        A known admittance beside the circuit's at ``f_Hz`` (S), taken off ``Y_S`` before
        the fit; ``rms_rel`` and ``max_rel`` then compare the circuit alone with ``Y_S``.
    """
    f = np.asarray(f_Hz, dtype=float)
    w = 2.0 * math.pi * f
    y_given = np.asarray(Y_S, dtype=complex)
    y = y_given if background_S is None else y_given - np.asarray(background_S)
    start = np.array(branches, dtype=float).reshape(-1, 3)
    c_start = np.concatenate(([C0_F], start[:, 2]))
    fs0 = 1.0 / (2.0 * math.pi * np.sqrt(start[:, 1] * start[:, 2]))
    x0 = np.log(np.concatenate((fs0, np.sqrt(start[:, 1] / start[:, 2]) / start[:, 0])))
    weight = 1.0 / np.where(np.abs(y_given) > 0.0, np.abs(y_given), 1.0)
    n_b = start.shape[0]
    lam = REGULARISATION

    def capacitances(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The least-squares capacitances given ``x`` and the weighted columns."""
        e = np.exp(x)
        cols = np.column_stack((1j * w, _branch_columns(w, e[:n_b], e[n_b:]))) * c_start
        a = cols * weight[:, None]
        mat = np.vstack((a.real, a.imag, lam * np.eye(n_b + 1)))
        rhs = np.concatenate(((y * weight).real, (y * weight).imag, lam * np.ones(n_b + 1)))
        scaled = np.linalg.lstsq(mat, rhs, rcond=None)[0]
        return scaled * c_start, cols @ scaled

    def residual(x: np.ndarray) -> np.ndarray:
        d = (capacitances(x)[1] - y) * weight
        return np.concatenate((d.real, d.imag, lam * (x - x0)))

    sol = least_squares(residual, x0, method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15,
                        max_nfev=200 * x0.size)
    c, y_fit = capacitances(sol.x)
    e = np.exp(sol.x)
    names = modes if modes is not None else ("",) * n_b
    out = []
    for i in range(n_b):
        ws, c1 = 2.0 * math.pi * e[i], float(c[i + 1])
        ell = 1.0 / (ws * ws * c1)
        out.append(MotionalBranch(names[i], float(1.0 / (e[n_b + i] * ws * c1)), float(ell),
                                  c1, float(f_modes_Hz[i] if f_modes_Hz is not None
                                            else fs0[i])))
    out.sort(key=lambda b: b.f_s_Hz)
    rel = np.abs(y_fit - y_given) * weight
    return EquivalentCircuit(C0_F=float(c[0]), branches=tuple(out), f_Hz=f,
                             rms_rel=float(np.sqrt(np.mean(rel**2))), max_rel=float(rel.max()))


def modal_branches(port, f_min_Hz: float, f_max_Hz: float, min_coupling: float):
    """The start of the fit from the modal data of ``port`` (:class:`fem.admittance.
    ModalPort`): ``(R_ohm, L_H, C_F)``, name and frequency of each mode in the band the port
    drives (coupling ``k_r >= min_coupling``), from its force factor and damping (module
    docstring)."""
    out = []
    for name, f_r, a, z, k in zip(port.mode_names, port.frequencies_Hz, port.a_N_V, port.zeta,
                                  port.coupling(), strict=True):
        if f_min_Hz <= f_r <= f_max_Hz and k >= min_coupling:
            w_r = 2.0 * math.pi * float(f_r)
            ell = 1.0 / float(a) ** 2
            out.append(((2.0 * float(z) * w_r * ell, ell, float(a) ** 2 / w_r**2), name,
                        float(f_r)))
    return out


def equivalent_circuit(result) -> EquivalentCircuit:
    """The BVD circuit of a computed admittance (:class:`fem.admittance.AdmittanceResult`):
    one branch per mode in its band that the port drives, started from the modal data
    (:func:`modal_branches`) and fitted to ``result.Y_S`` (:func:`fit_bvd`).

    The modes outside the band (and the residual mode) act in it as a slowly varying
    admittance, known from the same modal data: its mean capacitance over the band joins
    ``C0`` (the parallel capacitance an analyser sees beside the resonances, as IEEE Std 176
    fits it), and its variation about that mean (about 1e-3 of ``|Y|`` on the paper's plate)
    is taken off before the fit, which else bends the branches to it: two branches of one
    frequency and one Q (a stator tuned to L1 = B2) cannot be told apart by the admittance,
    and one of them wandered 0.5 % off to fit the background. ``rms_rel`` and ``max_rel``
    compare the circuit alone with the computed curve.

    Raises
    ------
    ValueError
        No mode in the band is driven by the port (a circuit of ``C0`` alone says nothing).
    """
    from fem.admittance import MIN_PORT_COUPLING

    f, y = result.f_Hz, result.Y_S
    start = modal_branches(result.port, float(f[0]), float(f[-1]), MIN_PORT_COUPLING)
    if not start:
        raise ValueError(f"no mode the port drives lies in {f[0]:.6g}-{f[-1]:.6g} Hz: no "
                         "motional branch to fit")
    branches = [b for b, _, _ in start]
    w = 2.0 * math.pi * f
    outside = y - bvd_admittance_S(f, result.port.C0_F, branches)
    c_out = float(np.mean(outside.imag / w))
    return fit_bvd(f, y, result.port.C0_F + c_out, branches, tuple(n for _, n, _ in start),
                   tuple(fr for _, _, fr in start), background_S=outside - 1j * w * c_out)
