"""Choice of the drive frequency of a parameter set (``--frequency auto``)."""

from __future__ import annotations

import warnings
from functools import lru_cache

import numpy as np

from rom.damping import free_tip_amplitudes, free_tip_phasors
from rom.params import MotorParams
from rom.table2 import PAPER_DRIVE_HZ

__all__ = ["auto_frequency", "free_tip_amplitudes", "tip_amplitude_product",
           "tip_ellipse_area", "grid_frequency",
           "drive_share", "default_drive_Hz", "WeakDriveWarning", "settling_time_s",
           "default_duration_s", "PAPER_DURATION_S"]

GRID_POINTS = 401
"""Frequencies of :func:`grid_frequency`'s search between the widened resonances."""


def tip_amplitude_product(params: MotorParams, frequency_Hz: float) -> float:
    """The product of the free tip's L1 (normal) and B2 (tangential) amplitudes (m^2 per V^2
    at unit drive): the size :func:`auto_frequency` maximizes."""
    a, b = free_tip_amplitudes(params, frequency_Hz)
    return float(a * b)


def tip_ellipse_area(params: MotorParams, frequency_Hz: float) -> float:
    """The area over pi of the free tip's path (m^2 per V^2 at unit drive).

    The L1 (normal) and B2 (tangential) tip motions share one drive, so the tip traces an
    ellipse of area ``pi |n| |t| |sin(dtheta)|``, ``dtheta`` the phase difference of the two
    modes' responses (:func:`rom.damping.free_tip_phasors`): a line where they are in phase.
    (Until 2026-11-25 this function returned the amplitudes' product,
    :func:`tip_amplitude_product`, under this name.)
    """
    n, t = free_tip_phasors(params, frequency_Hz)
    return float(np.abs(np.imag(np.conj(n) * t)))


def grid_frequency(params: MotorParams) -> tuple[float, float]:
    """``(f, step)`` (Hz): the largest product of the free tip amplitudes
    (:func:`tip_amplitude_product`) on :data:`GRID_POINTS` frequencies between the two
    resonances widened by 20 % on both sides, and the grid's step. No SciPy: a check that
    needs only the product stays off the optimizer's import."""
    f1, f2 = sorted((params.f_L1_Hz, params.f_B2_Hz))
    grid = np.linspace(0.8 * f1, 1.2 * f2, GRID_POINTS)
    a, b = free_tip_amplitudes(params, grid)  # one array call: 60 us against 2.2 ms
    area = a * b
    if not np.max(area) > 0.0:
        # one force factor zero: no ellipse anywhere, and the argmax of zeros would be the
        # grid's first point, taken for an operating frequency
        raise ValueError(f"the set drives no tip ellipse (A_l = {params.A_l:g}, A_b = "
                         f"{params.A_b:g} N/V): no operating frequency; drive both modes")
    best = grid[int(np.argmax(area))]
    return float(best), float(grid[1] - grid[0])


def auto_frequency(params: MotorParams) -> float:
    """Operating frequency of a parameter set (Hz): where the product of the free tip's L1
    (normal) and B2 (tangential) amplitudes is largest.

    It is searched between the two resonances widened by 20 % on both sides
    (:func:`grid_frequency`), then refined on the grid's neighbours. With well-separated
    modes this lands between them, close to the one with the larger force factor. It is a
    proxy, not the fastest drive: the product ignores the phase between the two motions,
    which sets the free tip's ellipse (:func:`tip_ellipse_area`), yet the product's point
    drove a tuned plate (L1 = B2, nearly in phase there) 13 times faster than the largest
    ellipse's point did (docs/contact.md section 6); the contact's stiffness shifts the
    loaded phases away from the free ones.
    """
    from scipy.optimize import minimize_scalar

    best, step = grid_frequency(params)
    res = minimize_scalar(lambda f: -tip_amplitude_product(params, f),
                          bounds=(best - step, best + step), method="bounded",
                          options={"xatol": 1e-3})
    return float(res.x)


WEAK_DRIVE_SHARE = 0.5
"""Share of the free tip amplitudes' product at its own operating point
(:func:`auto_frequency`) below which the default drive frequency is said to miss a set's
modes."""


class WeakDriveWarning(UserWarning):
    """The default 40 kHz drive is far from the set's modes: the product of its free tip
    amplitudes there is below :data:`WEAK_DRIVE_SHARE` of the one at its own operating
    point."""


def drive_share(params: MotorParams, frequency_Hz: float) -> tuple[float, float]:
    """``(share, best)``: the product of the free tip amplitudes at ``frequency_Hz`` over the
    one at the set's operating point ``best`` (Hz, :func:`auto_frequency`);
    ``(1, frequency_Hz)`` when the set drives no tip motion anywhere (no better frequency
    exists).

    The grid's best is tried first: a drive at least :data:`WEAK_DRIVE_SHARE` of it needs no
    optimizer (the refined best is at least the grid's, so the share could only fall), and
    SciPy's import is left out of such a call; the share is then against the grid's best.
    """
    at_drive = tip_amplitude_product(params, frequency_Hz)
    try:
        best, _ = grid_frequency(params)
    except ValueError:  # a force factor zero: no product at any frequency
        return 1.0, float(frequency_Hz)
    top = tip_amplitude_product(params, best)
    if at_drive >= 1.01 * WEAK_DRIVE_SHARE * top:
        return at_drive / top, best
    best = auto_frequency(params)
    top = tip_amplitude_product(params, best)
    return (at_drive / top if top > 0 else 1.0), best


def default_drive_Hz(params: MotorParams, frequency_Hz: float | None,
                     stacklevel: int = 3) -> float:
    """``frequency_Hz``, or the paper's 40 kHz when None, with :class:`WeakDriveWarning`
    when that default misses the set's modes (an FE or beam set, whose modes lie far above
    40 kHz: driven there it barely moves). A frequency the caller gave is theirs."""
    if frequency_Hz is not None:
        return frequency_Hz
    share, best = _default_share(params)
    if share < WEAK_DRIVE_SHARE:
        warnings.warn(WeakDriveWarning(
            f"frequency_Hz: the default {PAPER_DRIVE_HZ:g} Hz misses this set's modes (L1 "
            f"{params.f_L1_Hz:.0f} Hz, B2 {params.f_B2_Hz:.0f} Hz): the product of the free "
            f"tip's amplitudes there is {share:.2g} of the one at its own operating point, "
            f"{best:.0f} Hz "
            f"(contact.drive.auto_frequency)"), stacklevel=stacklevel)
    return PAPER_DRIVE_HZ


@lru_cache(maxsize=64)
def _default_share(params: MotorParams) -> tuple[float, float]:
    """:func:`drive_share` at the default drive, once per set (0.12 ms; a map or a
    characteristic asks it at every point)."""
    return drive_share(params, PAPER_DRIVE_HZ)


SETTLING_TIME_CONSTANTS = 5.0
"""Time constants a default transient runs (:func:`settling_time_s`): five of the slower
mode's envelope (``1 - exp(-5)``, 99.3 %) and five of the slider's (from rest to the free
tip's speed at full net friction force): the net force falls as the slider nears its steady
speed, so its approach is slower than the first time constant says. On issue 38's designer
stator at 400 V / 14 N three (0.78 s) leave the run unsettled at 97 % of the steady speed,
five (1.30 s) settle it to 0.3 %."""


def settling_time_s(params: MotorParams, voltage_V: float, preload_N: float,
                    frequency_Hz: float, load_N: float = 0.0) -> float:
    """An estimate of the time a transient from rest takes to settle (s).

    Two time scales add: the modes' envelopes grow as ``1 - exp(-t / tau)`` with
    ``tau = 1 / (zeta omega_n)`` (the slower of L1 and B2), and the slider, pushed by at most
    the net friction force ``F = mu_d F_P - mu_sd (F_P + M g) - max(load, 0)``, reaches the
    free tip's tangential speed amplitude ``v = omega |t| V``
    (:func:`rom.damping.free_tip_phasors`), an upper bound of its own steady speed, in
    ``M v / F``. The estimate is :data:`SETTLING_TIME_CONSTANTS` times their sum; a slider
    that the net force cannot move (``F <= 0``) counts the modes only.

    Parameters
    ----------
    params : MotorParams
        The parameter set.
    voltage_V, preload_N, frequency_Hz, load_N : float
        The drive amplitude (V), the preload (N), the drive frequency (Hz) and the external
        load against forward motion (N).

    Returns
    -------
    float
        The estimated settling time (s).
    """
    from rom.params import GRAVITY_M_S2

    p = params
    tau_modes = max(1.0 / (p.zeta_L1 * 2.0 * np.pi * p.f_L1_Hz),
                    1.0 / (p.zeta_B2 * 2.0 * np.pi * p.f_B2_Hz))
    _, t = free_tip_phasors(p, frequency_Hz, voltage_V)
    v_tip = 2.0 * np.pi * frequency_Hz * float(np.abs(t))
    force = (p.mu_d * preload_N - p.mu_sd * (preload_N + p.M_slider * GRAVITY_M_S2)
             - max(load_N, 0.0))
    tau_slider = p.M_slider * v_tip / force if force > 0.0 else 0.0
    return SETTLING_TIME_CONSTANTS * (tau_modes + tau_slider)


PAPER_DURATION_S = 0.05
"""The paper's run length (s): the default transient of Table 2's set, and the shortest
default of any other (:func:`default_duration_s`)."""


def default_duration_s(params: MotorParams, drives: list[tuple[float, float, float]],
                       top_s: float, load_N: float = 0.0) -> tuple[float, float]:
    """A default transient's run length (s) for the drive points ``drives``, each
    ``(voltage_V, preload_N, frequency_Hz)``, and the settling time it follows.

    :data:`PAPER_DURATION_S` for Table 2's set (the paper's runs); for any other, the longest
    :func:`settling_time_s` of ``drives``, at least :data:`PAPER_DURATION_S` and at most
    ``top_s`` (the step bound of the caller's work limit). Returns ``(duration_s,
    settle_s)``: the run length and the settling time before the bound (the caller says when
    the bound cuts it, ``settle_s > duration_s``)."""
    from contact.model import is_table2

    if is_table2(params):
        return PAPER_DURATION_S, PAPER_DURATION_S
    settle = max(PAPER_DURATION_S, max(settling_time_s(params, v, p, f, load_N)
                                       for v, p, f in drives))
    return min(settle, top_s), settle
