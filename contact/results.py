"""Result types of the contact simulation: traces, steady-state metrics, energy balance."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

MOTION_CLASSES = (
    "slip-separation",
    "stick-slip",
    "stick-slip-separation",
    "pure-stick",
    "pure-slip",
    "separated",
)
"""Motion classes: the paper's four (Section 4.3), pure slip, which it does not show, and
``separated``: the tip never presses on the slider in the window (no stick, no slip), e.g.
zero preload and zero voltage."""


class FrozenArrays:
    """Base of the frozen result dataclasses that carry arrays (declare them with
    ``eq=False``: ``==`` of arrays has no truth value, so they compare and hash by identity).

    Each array field becomes the result's own read-only copy: frozen means frozen, and a
    caller's array stays the caller's (``trace.x_m[:] = 0`` changed a returned trace; a
    characteristic kept the caller's ``loads`` array, so editing it relabelled the curve).
    """

    def __post_init__(self) -> None:
        for name, value in list(vars(self).items()):
            if isinstance(value, np.ndarray):
                own = np.array(value)
                own.setflags(write=False)
                object.__setattr__(self, name, own)


@dataclass(frozen=True, eq=False)
class Trace(FrozenArrays):
    """Time traces of one run (all arrays share the length of ``t_s``).

    Attributes
    ----------
    t_s : time (s); x_m : slider position (m); v_m_s : slider velocity (m/s);
    u_l_m : L1 coordinate (m); w_b_m : B2 coordinate (m); F_N_N : normal force (N);
    F_T_N : tangential force on the slider (N); v_rel_m_s : relative velocity (m/s);
    y_tip_m : tip normal displacement ``phi_L(l) u_l`` (m);
    phase : 0 stick, 1 slip with v_rel > 0, 2 slip with v_rel < 0, 3 separation.
    """

    t_s: np.ndarray
    x_m: np.ndarray
    v_m_s: np.ndarray
    u_l_m: np.ndarray
    w_b_m: np.ndarray
    F_N_N: np.ndarray
    F_T_N: np.ndarray
    v_rel_m_s: np.ndarray
    y_tip_m: np.ndarray
    phase: np.ndarray

    @classmethod
    def from_array(cls, a: np.ndarray) -> Trace:
        """Build from the kernel's (n, 10) array."""
        return cls(*(np.ascontiguousarray(a[:, i]) for i in range(9)), a[:, 9].astype(np.int8))

    def x_tip_m(self, phi_Bl: float) -> np.ndarray:
        """Tangential tip displacement ``phi_B(l) w_b`` (m), abscissa of the paper's Fig. 12."""
        return phi_Bl * self.w_b_m


@dataclass(frozen=True)
class SteadyState:
    """Metrics over the steady-state window (the last periods of a run).

    Attributes
    ----------
    velocity_m_s : float
        Mean slider velocity over the window (m/s).
    stick_fraction, slip_fraction, separation_fraction : float
        Fractions of the window spent in each interface state (-); they sum to 1.
    driving_slip_fraction, braking_slip_fraction : float
        Slip split by whether v_rel has the sign of the mean slider velocity (driving) or not.
    motion : str
        One of :data:`MOTION_CLASSES`.
    y_tip_min_m, y_tip_max_m : float
        Extremes of the tip normal displacement in the window (m).
    window_s : float
        Length of the window (s).
    previous_velocity_m_s : float
        Mean velocity over an equal window ending a fifth of the run earlier (m/s), with both
        ends marked in the run (NaN for a run too short for it).
    settled : bool
        Whether the two windows agree within 1 % (+ :data:`SETTLED_ABS_M_S`), or, in pure
        stick, both lie below :data:`HELD_ABS_M_S` (the slider held, its ring decaying).
    """

    velocity_m_s: float
    stick_fraction: float
    slip_fraction: float
    separation_fraction: float
    driving_slip_fraction: float
    braking_slip_fraction: float
    motion: str
    y_tip_min_m: float
    y_tip_max_m: float
    window_s: float
    previous_velocity_m_s: float
    settled: bool


@dataclass(frozen=True)
class EnergyBalance:
    """Work integrals over the steady-state window (J), for the equations as implemented.

    ``residual = dE - (input - damping + tangential_on_stator + tangential_on_slider + guide
    + load)`` with E the kinetic, modal-strain and contact-spring energy; the normal force's
    work on the stator is exchanged with the contact spring and drops out. ``guide`` is the
    linear guide's friction alone and ``load`` the external load's work on the slider
    (``-load_N`` times its displacement: minus the motor's output work), kept apart so that
    a loaded run's guide loss does not hold the output work. ``non_conservative`` is the
    part of the tangential work that the paper's coupling ``eta_T F_T`` adds beyond the
    reaction ``-phi_B(l) F_T`` at the tip (zero for the consistent coupling).
    """

    input_J: float
    damping_J: float
    normal_on_stator_J: float
    tangential_on_stator_J: float
    tangential_on_slider_J: float
    guide_J: float
    load_J: float
    interface_dissipation_J: float
    non_conservative_J: float
    delta_energy_J: float
    residual_J: float

    @property
    def relative_residual(self) -> float:
        """``|residual|`` over the largest work that drives the balance (-), NaN without any.

        Those are the electrical input, the tangential (stator and slider), guide and load work
        and the energy change; the damping is fed by them (at 0 V it holds roundoff alone). In a
        steady window the input is the largest; where a load does the work (a slider running
        away) the input alone made a roundoff-level residual read 5.6e-7 against 5.8e-12 of
        the slider's work.
        """
        scale = max(abs(self.input_J), abs(self.tangential_on_stator_J),
                    abs(self.tangential_on_slider_J), abs(self.guide_J),
                    abs(self.load_J), abs(self.delta_energy_J))
        return abs(self.residual_J) / scale if scale > 0 else float("nan")


@dataclass(frozen=True, eq=False)
class SchemeOutput:
    """What one scheme of :func:`contact.simulate.simulate` hands back (SI units).

    ``phase_time`` is the time (s, or steps) spent in [stick, slip with v_rel > 0, slip with
    v_rel < 0, separation] over the steady-state window; the other fields are those of
    :class:`contact.simulate.SimulationResult` and :class:`SteadyState`. Schemes that do not
    track a quantity give NaN (floats) or None (``events`` of the steady engine, which
    counts no mode switches). ``branches``: the steady engine's every steady state at the
    point (:class:`contact.steady.branches.SteadyBranch`, by increasing velocity, unstable ones
    included); None for the transient schemes.
    """

    velocity_m_s: float
    previous_velocity_m_s: float
    phase_time: np.ndarray
    y_tip_min_m: float
    y_tip_max_m: float
    trace: Trace | None
    window: Trace | None
    energy: EnergyBalance | None
    steps: int
    events: int | None
    nfev: int
    branches: tuple | None = None


SETTLED_ABS_M_S = 1e-9
"""Absolute floor (m/s) of the ``settled`` test, for a held slider whose window means are
roundoff. A creep is judged by the 1 % like any other speed: a floor of 1e-6 m/s would pass
creeps of a few um/s whose two windows differ by 10-18 %."""

HELD_ABS_M_S = 1e-6
"""Window means (m/s) below which a pure-stick window counts as settled at rest: with no slip
the slider is held by the tip, and what is left is the ring of the slider on the stator's
tangential stiffness, decaying about zero (200 V / 150 N on Table 2's set: -2.5e-8 m/s after
-4.5e-8 m/s, which the 1 % test called not settled)."""

PHASE_THRESHOLD = 1e-4
"""A phase counts in the motion class when it fills more than this fraction of the window."""


def steady_metrics(velocity_m_s: float, previous_velocity_m_s: float, phase_time,
                   y_tip_min_m: float, y_tip_max_m: float, window_s: float) -> SteadyState:
    """The :class:`SteadyState` of a window from its mean velocities and phase times."""
    phase_time = np.asarray(phase_time, dtype=float)
    total = float(np.sum(phase_time))
    frac = phase_time / total if total > 0 else np.array([1.0, 0.0, 0.0, 0.0])
    stick, slip_pos, slip_neg, sep = (float(f) for f in frac)
    v, v_prev = float(velocity_m_s), float(previous_velocity_m_s)
    driving, braking = (slip_pos, slip_neg) if v >= 0 else (slip_neg, slip_pos)
    motion = classify_motion(stick, slip_pos + slip_neg, sep, PHASE_THRESHOLD)
    settled = (bool(abs(v - v_prev) <= 0.01 * abs(v) + SETTLED_ABS_M_S
                    or (motion == "pure-stick" and max(abs(v), abs(v_prev)) <= HELD_ABS_M_S))
               if math.isfinite(v_prev) else False)
    return SteadyState(
        velocity_m_s=v,
        stick_fraction=stick,
        slip_fraction=slip_pos + slip_neg,
        separation_fraction=sep,
        driving_slip_fraction=driving,
        braking_slip_fraction=braking,
        motion=motion,
        y_tip_min_m=float(y_tip_min_m),
        y_tip_max_m=float(y_tip_max_m),
        window_s=float(window_s),
        previous_velocity_m_s=v_prev,
        settled=settled,
    )


def classify_motion(stick: float, slip: float, separation: float, threshold: float) -> str:
    """Motion class from the phase fractions; a phase counts when its fraction > threshold."""
    has_stick, has_slip, has_sep = stick > threshold, slip > threshold, separation > threshold
    if has_stick and not has_slip and not has_sep:
        return "pure-stick"
    if has_stick and has_sep:
        return "stick-slip-separation"
    if has_stick:
        return "stick-slip"
    if has_sep and not has_slip:
        return "separated"
    if has_sep:
        return "slip-separation"
    return "pure-slip"

