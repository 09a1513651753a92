"""Modal damping identified from free tip amplitudes, as the paper identified Table 2's.

Section 4.1 of the paper computes every constant of Eqs. (4)-(5) from the stator except the
modal dampings ``C_l`` and ``C_b``, which it fits so that the free (unloaded) tip amplitudes
at the 40 kHz drive match laser-vibrometer measurements (Figs. 5 and 6). The same
identification applied to another parameter set answers: *what damping makes this stator
vibrate as much as the paper's did?*

For one mode with force factor ``A``, tip value ``phi`` and drive ``V sin(omega t)`` the free
steady amplitude is

    a = |phi A| V / sqrt((K - M omega^2)^2 + (C omega)^2),

so a measured amplitude per volt ``a/V`` gives

    C = sqrt((phi A / (a/V))^2 - (K - M omega^2)^2) / omega,

which exists only if the undamped amplitude at that frequency already exceeds the target
(damping can only lower an amplitude). The paper's measured points are not tabulated; its
fitted lines are Table 2's own Eq. (4)-(5) amplitudes at 40 kHz, which are linear in the
voltage, so :func:`table2_free_amplitudes_m_per_V` is the default target; another stator is
fitted at its own drive frequency, so that it vibrates, free, as much as the paper's did.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bounds import ParameterError
from rom.errors import UnreachableAmplitudeError
from rom.params import MotorParams
from rom.table2 import PAPER_DRIVE_HZ, table2


@dataclass(frozen=True)
class IdentifiedDamping:
    """Damping fitted to free tip amplitudes.

    Attributes
    ----------
    params : MotorParams
        The input set with ``C_l`` and ``C_b`` replaced (everything else unchanged).
    frequency_Hz : float
        Drive frequency of the fit (Hz).
    target_L1_m_per_V, target_B2_m_per_V : float
        Free tip amplitudes per volt that were matched (m/V): L1 (normal) and B2
        (tangential).
    """

    params: MotorParams
    frequency_Hz: float
    target_L1_m_per_V: float
    target_B2_m_per_V: float


def free_tip_phasors(params: MotorParams, frequency_Hz: np.ndarray | float,
                     voltage_V: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Free (no contact) steady tip displacements of the L1 and B2 modes as phasors (m).

    For the drive ``voltage_V sin(omega t)`` the tip's normal (L1) displacement is
    ``Im(n exp(i omega t))`` and its tangential (B2) one ``Im(t exp(i omega t))``, with
    ``n = phi_L(l) A_l V / (K_l - M_l omega^2 + i C_l omega)`` and ``t`` likewise. The two
    share one drive, so their phase difference is that of the two resonances: the tip's
    ellipse is as wide as ``|n| |t| |sin(arg t - arg n)|`` allows, a line where they are in
    phase.
    """
    p = params
    w = 2 * np.pi * np.asarray(frequency_Hz, dtype=float)
    ul = p.A_l * voltage_V / (p.K_l - p.M_l * w**2 + 1j * p.C_l * w)
    wb = p.A_b * voltage_V / (p.K_b - p.M_b * w**2 + 1j * p.C_b * w)
    return p.phi_Ll * ul, p.phi_Bl * wb


def free_tip_amplitudes(params: MotorParams, frequency_Hz: np.ndarray | float,
                        voltage_V: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Free (no contact) steady tip amplitudes (m) of the L1 and B2 modes at a frequency.

    Returns ``(|phi_L(l) u_l|, |phi_B(l) w_b|)`` for the drive ``voltage_V sin(omega t)``:
    the normal (L1) and tangential (B2) amplitudes of the free tip (the magnitudes of
    :func:`free_tip_phasors`).
    """
    n, t = free_tip_phasors(params, frequency_Hz, voltage_V)
    return np.abs(n), np.abs(t)


def table2_free_amplitudes_m_per_V(frequency_Hz: float = PAPER_DRIVE_HZ) -> tuple[float, float]:
    """Table 2's free tip amplitudes per volt ``(L1, B2)`` (m/V) at ``frequency_Hz``: the
    fitted lines of the paper's Figs. 5 and 6 at 40 kHz."""
    a_l, a_b = free_tip_amplitudes(table2(), frequency_Hz, 1.0)
    return float(a_l), float(a_b)


def _damping(M: float, K: float, A: float, phi: float, omega: float, target: float,
             mode: str) -> float:
    """``C`` (N s/m) that gives the amplitude per volt ``target`` at ``omega``."""
    if not (math.isfinite(target) and target > 0.0):
        raise ParameterError(f"target_{mode}_m_per_V", target, 0.0, None, "m/V", low_open=True,
                             message=f"the {mode} target amplitude must be a finite number "
                             f"> 0 m/V, got {target!r}")
    drive = abs(phi * A) / target  # the dynamic stiffness magnitude the target needs (N/m)
    detuning = K - M * omega**2
    if drive <= abs(detuning):
        raise UnreachableAmplitudeError.of_mode(mode, target, omega, M, K,
                                                abs(phi * A) / abs(detuning))
    return math.sqrt(drive**2 - detuning**2) / omega


def identify_damping(params: MotorParams, frequency_Hz: float = PAPER_DRIVE_HZ,
                     targets_m_per_V: tuple[float, float] | None = None) -> IdentifiedDamping:
    """Fit ``C_l`` and ``C_b`` so that the free tip amplitudes match ``targets_m_per_V``.

    Parameters
    ----------
    params : MotorParams
        The set whose dampings are identified (its masses, stiffnesses, force factors and
        tip values are kept).
    frequency_Hz : float
        Drive frequency (Hz) at which this stator must reach the target amplitudes: its
        own drive frequency; default the paper's 40 kHz.
    targets_m_per_V : (float, float), optional
        Free tip amplitudes per volt of L1 (normal) and B2 (tangential) (m/V); default
        Table 2's at the paper's 40 kHz drive (:func:`table2_free_amplitudes_m_per_V`):
        the stator then vibrates, free, as much as the paper's measured stator did.

    Returns
    -------
    IdentifiedDamping

    Raises
    ------
    rom.errors.UnreachableAmplitudeError
        When a target cannot be reached at that frequency (its fields say how far the
        undamped mode gets and where its natural frequency lies).
    bounds.ParameterError
        When the frequency or a target is not a positive number.
    """
    if not (math.isfinite(frequency_Hz) and frequency_Hz > 0.0):
        raise ParameterError("frequency_Hz", frequency_Hz, 0.0, None, "Hz", low_open=True,
                             message=f"frequency_Hz must be a finite number > 0, got "
                             f"{frequency_Hz!r}")
    t_l, t_b = targets_m_per_V or table2_free_amplitudes_m_per_V()
    p = params
    omega = 2.0 * math.pi * frequency_Hz
    c_l = _damping(p.M_l, p.K_l, p.A_l, p.phi_Ll, omega, t_l, "L1")
    c_b = _damping(p.M_b, p.K_b, p.A_b, p.phi_Bl, omega, t_b, "B2")
    return IdentifiedDamping(p.with_(C_l=c_l, C_b=c_b), float(frequency_Hz), t_l, t_b)
