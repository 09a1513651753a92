"""The switch model of Eqs. 4-19 written as a piecewise-linear hybrid system.

For a given parameter set and operating point every mode of the switch model (stick, slip in
either direction, separation, each with the slider moving or held on its guide) is a linear
ODE ``dz/dt = A_m z`` on the augmented state of :mod:`contact.state`, and every switching
condition is the zero of a linear functional. This module builds those matrices and
functionals once per run; :mod:`contact.transient.event_kernel` integrates them.

Conventions (see ``docs/contact.md``):

* ``F_N = max(0, F_P + k (u_d - u_st))`` with ``u_d = (phi_L(l) - phi_L(0)) u_l`` and
  ``u_st = eta_N F_P (phi_L(l) - phi_L(0)) / K_l`` (Eq. 7).
* ``v_rel = phi_B(l) dw_b - dx`` (Eq. 8); ``F_T`` is the force of the tip on the slider
  (Eq. 6) and its generalized force on B2 is ``gamma_T F_T`` with ``gamma_T = eta_T`` as
  printed (``coupling="paper"``) or ``gamma_T = -phi_B(l)``, the reaction at the tip, which is
  work-consistent (``coupling="consistent"``).
* Guide friction ``F_f = -sign(dx) mu_sd N`` with ``N = F_N + M g`` in contact and ``M g`` when
  separated (Eqs. 6, 19); at ``dx = 0`` the guide holds the slider while it can.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import warnings
from dataclasses import dataclass

import numpy as np

from bounds import ParameterError
from contact import state as S
from contact.expm import expm_stack
from rom.params import GRAVITY_M_S2, MotorParams

COUPLINGS = ("paper", "consistent")
COUPLING_CHOICES = (*COUPLINGS, "auto")
"""What the entry points accept: a coupling, or ``"auto"`` (:func:`resolve_coupling`)."""

REST_METHODS = ("probe", "transient")
"""How the steady engine's exact level decides the branch a start from rest reaches
(:func:`contact.steady.engine.steady_state` ``rest=``). Here, not in :mod:`contact.steady.engine`:
the transient's options check it, and importing the steady engine for that loaded its compiled orbit
kernels and ``scipy.optimize`` into every transient run."""


def check_rest(rest: str) -> None:
    """Refuse a ``rest=`` that is not one of :data:`REST_METHODS`."""
    if rest not in REST_METHODS:
        raise ValueError(f"rest must be one of {REST_METHODS}, got {rest!r}")


def default_coupling(params: MotorParams) -> tuple[str, str]:
    """The tangential coupling a parameter set is run with unless one is asked for, and why.

    Table 2's own set (its numbers, whatever its ``source`` text) keeps the paper's
    ``eta_T F_T`` (``"paper"``): it exists to reproduce the paper. Every other set (FE, beam,
    a stator file, an edited set) gets the work-consistent reaction ``-phi_B(l) F_T``
    (``"consistent"``): the paper's coefficient doubles the tip reaction on B2, so the
    interface does work that friction cannot (``EnergyBalance.non_conservative_J``), and on
    stator-derived sets it makes the speed non-monotone in the voltage (``docs/contact.md``
    section 2.3 has the evidence).

    Returns
    -------
    (str, str)
        The coupling and a short reason for printing.
    """
    # by the numbers, not the free-text source: a set saved without its label, or relabelled,
    # keeps its coupling (the other one runs 5.7 times faster at 200 V / 14 N)
    if is_table2(params):
        return "paper", "auto: Table 2's set reproduces the paper"
    return "consistent", "auto: work-consistent for a set that is not Table 2's"


def is_table2(params: MotorParams) -> bool:
    """Whether ``params`` holds Table 2's numbers, whatever its ``source`` text, each to the
    rounding of single precision (:data:`rom.params.STORAGE_ROUNDOFF`, twice: the value's and
    the storage's): a Table 2 set written through float32, which ``MotorParams.from_dict``
    takes as unedited, keeps the paper's coupling (the consistent one runs 5.7 times
    faster). An edit is a change far above 1e-7."""
    from rom.params import STORAGE_ROUNDOFF
    from rom.table2 import table2

    ref = table2()
    for f in dataclasses.fields(params):
        if f.name in ("source", "shape"):  # text, and the limits' data: not the dynamics
            continue
        a, b = getattr(params, f.name), getattr(ref, f.name)
        if isinstance(a, float) and isinstance(b, float) and not isinstance(a, bool):
            if not abs(a - b) <= 2.0 * STORAGE_ROUNDOFF * abs(b):
                return False
        elif a != b:
            return False
    return True


class CouplingSwitchWarning(UserWarning):
    """``coupling="auto"`` runs an edited copy of Table 2's set (its ``source`` still Table
    2's) with the work-consistent coupling, not the paper's that Table 2 itself runs with."""


def _edited_table2(params: MotorParams) -> bool:
    """Whether ``params`` is a copy of Table 2's set with some value changed: its source text
    is still Table 2's (``dataclasses.replace`` keeps it; a ``--params`` file's edit note is
    appended after " [edited in ")."""
    from rom.table2 import table2

    return params.source.split(" [edited in ")[0] == table2().source


def resolve_coupling(params: MotorParams, coupling: str) -> str:
    """``coupling`` itself, or for ``"auto"`` (every entry point's default, as the CLI's)
    :func:`default_coupling` of ``params``: the library and the CLI run a set with the same
    coupling (the beam set at 300 V / 14 N is held with the paper's and moves at
    4.1e-5 m/s with the consistent one).

    An edited copy of Table 2's set gets the consistent coupling under ``"auto"``, with a
    :class:`CouplingSwitchWarning`: a slider mass changed by 1e-9 moves 200 V / 14 N from
    0.0076 to 0.043 m/s, which the caller should hear of."""
    if coupling == "auto":
        chosen = default_coupling(params)[0]
        if chosen != "paper" and _edited_table2(params):
            warnings.warn(CouplingSwitchWarning(
                "coupling='auto': this set is an edited copy of Table 2's (its source is "
                "still Table 2's), so it runs with the work-consistent coupling, not the "
                "paper's that Table 2's own set runs with; the switch alone changes the "
                "speed several-fold: pass coupling='paper' to see the effect of the edit "
                "alone (docs/contact.md 2.3.1)"), stacklevel=3)
        return chosen
    if coupling not in COUPLINGS:
        raise ValueError(f"coupling must be one of {COUPLING_CHOICES}, got {coupling!r}")
    return coupling


@dataclass(frozen=True)
class OperatingPoint:
    """Drive and load of one simulation.

    Attributes
    ----------
    voltage_V : float
        Amplitude V0 of the drive voltage ``V0 sin(omega t)`` (V), >= 0.
    preload_N : float
        Preload F_P pressing the stator on the slider (N), >= 0.
    frequency_Hz : float
        Drive frequency f (Hz), > 0.
    load_N : float
        External load (N): a constant force of magnitude ``load_N`` on the slider pointing
        in -x, i.e. opposing positive slider velocity (the drive direction of this model).
        A negative value pushes the slider forward. Default 0.
    """

    voltage_V: float
    preload_N: float
    frequency_Hz: float = 40e3
    load_N: float = 0.0

    def __post_init__(self) -> None:
        for name, unit, strict in (
            ("voltage_V", "V", False),
            ("preload_N", "N", False),
            ("frequency_Hz", "Hz", True),
        ):
            value = getattr(self, name)
            allowed = f"{'> 0' if strict else '>= 0'} {unit}"
            # NumPy scalars are numbers (np.int64(200) too); True is not 1 V
            if isinstance(value, bool) or not isinstance(value, numbers.Real):
                raise ParameterError(name, value, 0.0, None, unit, low_open=strict,
                                     message=f"{name} must be a finite number {allowed}, got "
                                     f"{value!r}")
            value = float(value)
            object.__setattr__(self, name, value)
            if (
                not math.isfinite(value)
                or value < 0.0
                or (strict and value == 0.0)
            ):
                raise ParameterError(name, value, 0.0, None, unit, low_open=strict,
                                     message=f"{name} must be a finite number {allowed}, got "
                                     f"{value!r}")
        if isinstance(self.load_N, bool) or not isinstance(self.load_N, numbers.Real) \
                or not math.isfinite(self.load_N):
            raise ParameterError("load_N", self.load_N, unit="N",
                                 message=f"load_N must be a finite number (N), got "
                                 f"{self.load_N!r}")
        object.__setattr__(self, "load_N", float(self.load_N))

    @property
    def omega(self) -> float:
        """Drive circular frequency (rad/s)."""
        return 2.0 * math.pi * self.frequency_Hz

    @property
    def period_s(self) -> float:
        """Drive period (s)."""
        return 1.0 / self.frequency_Hz


@dataclass(frozen=True)
class HybridSystem:
    """Matrices and functionals of all modes for one run (built by :func:`build_system`).

    Attributes
    ----------
    A : ndarray, shape (18, 9, 9)
        Generator of each mode.
    ev_h, ev_dh : ndarray, shape (18, 5, 9)
        Event functionals (an event fires where ``ev_h . z`` becomes > 0) and their time
        derivatives ``A^T ev_h``.
    ev_type : ndarray of int, shape (18, 5)
        Event type per slot (:data:`contact.state.EV_NONE` for an empty slot).
    fn_m, ft_m, ff_m : ndarray, shape (18, 9)
        Per mode: normal force, tangential force on the slider, guide force on the slider.
    funcs : ndarray, shape (7, 9)
        Mode-independent functionals (rows named ``F_*`` in :mod:`contact.state`).
    scalars : ndarray
        ``[mu_s, mu_d, mu_sd, phi_Ll, gamma_N, gamma_T, A_l V0, A_b V0, C_l, C_b, M_l, K_l,
        M_b, K_b, M, k, omega]``.
    z0 : ndarray, shape (9,)
        Initial state: static equilibrium under the preload, slider at rest.
    mode0 : int
        Initial mode.
    """

    A: np.ndarray
    ev_h: np.ndarray
    ev_dh: np.ndarray
    ev_type: np.ndarray
    fn_m: np.ndarray
    ft_m: np.ndarray
    ff_m: np.ndarray
    funcs: np.ndarray
    scalars: np.ndarray
    z0: np.ndarray
    mode0: int

    def propagators(self, dt_s: float) -> tuple[np.ndarray, np.ndarray]:
        """Exact one-step and half-step propagators ``expm(A dt)``, ``expm(A dt/2)``."""
        return expm_stack(self.A * dt_s), expm_stack(self.A * (0.5 * dt_s))


def static_deflection_m(params: MotorParams, preload_N: float) -> float:
    """L1 coordinate of the static equilibrium under the preload (m), where F_N = F_P.

    Every scheme starts from it: B2, slider and velocities at rest, ``V(0) = 0``.
    """
    return params.eta_N * preload_N / params.K_l


def gamma_T(params: MotorParams, coupling: str) -> float:
    """Generalized-force coefficient of F_T on the B2 coordinate for a coupling choice.

    Raises
    ------
    ValueError
        An unknown coupling, or one under which no tangential force keeps a stuck tip stuck:
        ``gamma_T = 0`` (``phi_B0 == phi_Bl`` with the paper's coupling), or
        ``phi_Bl gamma_T / M_b`` not below ``1 / M_slider``. The stick force divides by
        both; with ``phi_B0`` next to ``phi_Bl`` the literal scheme returned 6.6e30 m/s and
        the event scheme a time-step or chattering error that blamed ``dt_s``.
    """
    coupling = resolve_coupling(params, coupling)  # "auto" too, as every entry point takes it
    g = params.eta_T if coupling == "paper" else -params.phi_Bl
    p = params
    if g == 0.0 or not p.phi_Bl * g * p.M_slider <= (1.0 - 1e-6) * p.M_b:
        raise ValueError(
            f"phi_B0 = {p.phi_B0!r}, phi_Bl = {p.phi_Bl!r} with coupling={coupling!r} give "
            f"gamma_T = {g:.4g} (the tip force on B2): it must be non-zero and "
            f"phi_Bl * gamma_T / M_b below 1 / M_slider = {1.0 / p.M_slider:.4g} 1/kg (got "
            f"{p.phi_Bl * g / p.M_b:.4g}), or no tangential force keeps a stuck tip stuck")
    return g


def _unit(i: int) -> np.ndarray:
    e = np.zeros(S.N_STATE)
    e[i] = 1.0
    return e


MAX_STATIC_DEFLECTION_M = 1e-2
"""Largest static deflection (m) of a modal coordinate under the drive amplitude
(``|A| V0 / K``) or the preload (``eta_N F_P / K_l``) that :func:`build_system` accepts. On
Table 2's set 400 V give 2.3e-7 m. A centimetre is far beyond linear piezoelasticity, and far
enough beyond it the arithmetic breaks: at 1e200 V the event functions overflowed and a run
reported pure stick at 0 m/s."""


def check_scale(params: MotorParams, op: OperatingPoint) -> None:
    """Refuse an operating point whose drive or preload deflects the stator beyond
    :data:`MAX_STATIC_DEFLECTION_M`, naming the input and the deflection it gives."""
    p = params
    for name, unit, value, deflection in (
        ("voltage_V", "V", op.voltage_V,
         op.voltage_V * max(abs(p.A_l) / p.K_l, abs(p.A_b) / p.K_b)),
        ("preload_N", "N", op.preload_N, p.eta_N * op.preload_N / p.K_l),
        ("load_N", "N", op.load_N, p.eta_N * abs(op.load_N) / p.K_l),  # its sign kept
    ):
        if not deflection <= MAX_STATIC_DEFLECTION_M:
            raise ValueError(
                f"{name} = {value:g} {unit} deflects the stator statically by {deflection:.3g} "
                f"m, beyond {MAX_STATIC_DEFLECTION_M:g} m: the linear model means nothing "
                f"there (Table 2's motor runs at 50-450 V and 6-40 N)")


@dataclass(frozen=True, eq=False)
class _Forces:
    """The forces the modes are made of, each a row over the state vector (N, or m/s for
    ``vrel``): the contact's normal force ``fn``, the slider's normal load on the guide in
    contact and separated, the tip's velocity relative to the slider, the external load, the
    tangential force that keeps the tip stuck (slider held, moving forward, moving
    backward: :data:`contact.state.HELD` ...) and the sliding friction by the sign of
    ``v_rel``."""

    fn: np.ndarray
    ng_contact: np.ndarray
    ng_sep: np.ndarray
    vrel: np.ndarray
    load: np.ndarray
    stuck: tuple[np.ndarray, np.ndarray, np.ndarray]
    slip: dict[float, np.ndarray]

    def of_mode(self, contact: int, tip: int, guide: int,
                zero: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(normal force, tangential force on the slider, guide's normal load)`` of a mode
        (``zero`` for the forces a separated tip does not feel)."""
        if contact == S.SEPARATED:
            return zero, zero, self.ng_sep
        if tip == S.STICK:
            return self.fn, self.stuck[guide], self.ng_contact
        return self.fn, self.slip[1.0 if tip == S.SLIP_POS else -1.0], self.ng_contact


_GUIDE_SIGNS = (0.0, 1.0, -1.0)
"""Sign of the slider's velocity per guide state (held, forward, backward)."""


def _contact_forces(p: MotorParams, op: OperatingPoint, mu_d_eff: float,
                    g_T: float) -> _Forces:
    """The rows of Eqs. 6-10 for one set and operating point (see :class:`_Forces`)."""
    e = [_unit(i) for i in range(S.N_STATE)]
    dphi = p.phi_Ll - p.phi_L0
    u_st = p.eta_N * op.preload_N * dphi / p.K_l
    Mg = p.M_slider * GRAVITY_M_S2
    phi = p.phi_Bl

    fn = p.k_contact * dphi * e[S.U] + (op.preload_N - p.k_contact * u_st) * e[S.ONE]
    ng_contact = fn + Mg * e[S.ONE]
    ng_sep = Mg * e[S.ONE]
    vrel = phi * e[S.DW] - e[S.DX]
    denom = phi * g_T / p.M_b - 1.0 / p.M_slider  # < 0 for both couplings, on sane sets

    # the external load acts on the slider like the guide does: both enter ff_m ("guide
    # and load"), so the energy balance's guide work includes the load's work
    load = op.load_N * e[S.ONE]

    def stick_force(gsign: float) -> np.ndarray:
        # Eq. 10 generalized: the force keeping v_rel = 0, from phi*ddw_b = ddx.
        ff = -gsign * p.mu_sd * ng_contact - load
        b_part = (p.C_b * e[S.DW] + p.K_b * e[S.W] - p.A_b * op.voltage_V * e[S.SIN]) * (
            phi / p.M_b
        )
        return (b_part + ff / p.M_slider) / denom

    # tip and slider both at rest: B2 frozen, so 0 = -K_b w_b + A_b V sin + gamma_T F_T
    hold = (p.K_b * e[S.W] - p.A_b * op.voltage_V * e[S.SIN]) / g_T
    slip = {1.0: 1.0 * mu_d_eff * fn, -1.0: -1.0 * mu_d_eff * fn}
    return _Forces(fn, ng_contact, ng_sep, vrel, load,
                   (hold, stick_force(1.0), stick_force(-1.0)), slip)


def _modes():
    """``(mode index, contact, tip, guide)`` of every mode."""
    for contact in (S.SEPARATED, S.CONTACT):
        for tip in (S.STICK, S.SLIP_POS, S.SLIP_NEG):
            for guide in (S.HELD, S.FORWARD, S.BACKWARD):
                yield S.mode_index(contact, tip, guide), contact, tip, guide


def _mode_generators(p: MotorParams, op: OperatingPoint, f: _Forces, zero: np.ndarray,
                     g_N: float, g_T: float):
    """Generator ``A`` of every mode and its normal, tangential and guide force rows."""
    e = [_unit(i) for i in range(S.N_STATE)]
    A = np.zeros((S.N_MODES, S.N_STATE, S.N_STATE))
    fn_m = np.zeros((S.N_MODES, S.N_STATE))
    ft_m = np.zeros((S.N_MODES, S.N_STATE))
    ff_m = np.zeros((S.N_MODES, S.N_STATE))
    # Each mode's rows depend on its normal force (2 kinds) and tangential force (6 kinds):
    # they are computed once per kind (the same expressions, so the same bits) and shared.
    l_row = {id(fk): (-p.K_l * e[S.U] - p.C_l * e[S.DU] + p.A_l * op.voltage_V * e[S.SIN]
                      + g_N * fk) / p.M_l for fk in (zero, f.fn)}
    b_row = {id(fk): (-p.K_b * e[S.W] - p.C_b * e[S.DW] + p.A_b * op.voltage_V * e[S.SIN]
                      + g_T * fk) / p.M_b for fk in (zero, *f.stuck, *f.slip.values())}
    sin_row, cos_row = op.omega * e[S.COS], -op.omega * e[S.SIN]
    for m, contact, tip, guide in _modes():
        fn_mode, ft, ng = f.of_mode(contact, tip, guide, zero)
        tip_stuck = contact == S.CONTACT and tip == S.STICK
        held = guide == S.HELD
        # a held slider is balanced by static guide friction (and the load)
        ff = -ft if held else -_GUIDE_SIGNS[guide] * p.mu_sd * ng - f.load
        a = A[m]
        a[S.U] = e[S.DU]
        a[S.DU] = l_row[id(fn_mode)]
        if not (tip_stuck and held):
            a[S.W] = e[S.DW]
            a[S.DW] = b_row[id(ft)]
        if not held:
            a[S.X] = e[S.DX]
            a[S.DX] = (ft + ff) / p.M_slider
        a[S.SIN] = sin_row
        a[S.COS] = cos_row
        fn_m[m], ft_m[m], ff_m[m] = fn_mode, ft, ff
    return A, fn_m, ft_m, ff_m


def _mode_events(p: MotorParams, f: _Forces, zero: np.ndarray):
    """Event functionals ``ev_h`` (an event fires where ``ev_h . z`` becomes > 0) and their
    types, per mode: separation or contact, stick break or a zero of ``v_rel``, the guide's
    release or the slider's stop."""
    dx = _unit(S.DX)
    ev_h = np.zeros((S.N_MODES, S.MAX_EVENTS, S.N_STATE))
    ev_type = np.full((S.N_MODES, S.MAX_EVENTS), S.EV_NONE, dtype=np.int64)
    for m, contact, tip, guide in _modes():
        _, ft, ng = f.of_mode(contact, tip, guide, zero)
        events: list[tuple[int, np.ndarray]] = []
        if contact == S.CONTACT:
            events.append((S.EV_SEPARATE, -f.fn))
            if tip == S.STICK:
                events.append((S.EV_STICK_BREAK, f.stuck[guide] - p.mu_s * f.fn))
                events.append((S.EV_STICK_BREAK, -f.stuck[guide] - p.mu_s * f.fn))
            else:
                sigma = 1.0 if tip == S.SLIP_POS else -1.0
                events.append((S.EV_VREL_ZERO, -sigma * f.vrel))
        else:
            events.append((S.EV_CONTACT, f.fn))
        if guide == S.HELD:
            events.append((S.EV_GUIDE_RELEASE, ft - f.load - p.mu_sd * ng))
            events.append((S.EV_GUIDE_RELEASE, -ft + f.load - p.mu_sd * ng))
        else:
            events.append((S.EV_XDOT_ZERO, -_GUIDE_SIGNS[guide] * dx))
        for j, (etype, h) in enumerate(events):
            ev_type[m, j] = etype
            ev_h[m, j] = h
    return ev_h, ev_type


def _initial_state(p: MotorParams, op: OperatingPoint, fn: np.ndarray) -> tuple[np.ndarray, int]:
    """Static equilibrium under the preload, slider at rest, and its mode (the tip stuck in
    contact, or separated with no preload)."""
    z0 = np.zeros(S.N_STATE)
    z0[S.U] = static_deflection_m(p, op.preload_N)
    z0[S.COS] = 1.0
    z0[S.ONE] = 1.0
    in_contact = float(fn @ z0) > 0.0
    mode0 = (
        S.mode_index(S.CONTACT, S.STICK, S.HELD)
        if in_contact
        else S.mode_index(S.SEPARATED, S.SLIP_POS, S.HELD)
    )
    return z0, mode0


def _check_finite_system(p: MotorParams, arrays) -> None:
    """Refuse a set whose mode matrices overflow, naming its most extreme value (the one
    farthest from 1 in magnitude, either way): NumPy's eigensolver would fail later with
    "Array must not contain infs or NaNs", naming nothing (phi_Bl = 1e300 in a --params
    file)."""
    if all(np.isfinite(m).all() for m in arrays):
        return
    name, value = max(((f.name, getattr(p, f.name)) for f in dataclasses.fields(p)
                       if isinstance(getattr(p, f.name), float) and getattr(p, f.name)),
                      key=lambda nv: abs(math.log10(abs(nv[1]))))
    from contact.errors import OverflowingParametersError

    raise OverflowingParametersError(name, value)


def build_system(
    params: MotorParams,
    op: OperatingPoint,
    mu_d_eff: float,
    coupling: str = "paper",
    stick_band_m_s: float = 1e-10,
) -> HybridSystem:
    """Build the hybrid system of Eqs. 4-19 for one parameter set and operating point.

    Parameters
    ----------
    params : MotorParams
        Reduced-order parameters.
    op : OperatingPoint
        Drive voltage, preload and frequency.
    mu_d_eff : float
        Dynamic friction coefficient used in slip (Eq. 11 already applied, or ``mu_d``).
    coupling : {"paper", "consistent"}
        Generalized force of F_T on B2: ``eta_T F_T`` (Eq. 5 as printed) or ``-phi_B(l) F_T``.
    stick_band_m_s : float
        The paper's epsilon (m/s). Stick is entered at located zeros of v_rel, so epsilon only
        decides whether a tip touching down with ``|v_rel| <= epsilon`` is tested for stick.

    Returns
    -------
    HybridSystem
    """
    p = params
    check_scale(p, op)
    g_T = gamma_T(p, coupling)
    g_N = p.eta_N
    if not (math.isfinite(stick_band_m_s) and stick_band_m_s >= 0.0):
        raise ValueError(f"stick_band_m_s must be finite and >= 0, got {stick_band_m_s!r}")
    if not (0.0 <= mu_d_eff <= p.mu_s):
        raise ValueError(f"mu_d_eff must lie in [0, mu_s={p.mu_s}], got {mu_d_eff!r}")
    f = _contact_forces(p, op, mu_d_eff, g_T)
    zero = np.zeros(S.N_STATE)
    A, fn_m, ft_m, ff_m = _mode_generators(p, op, f, zero, g_N, g_T)
    ev_h, ev_type = _mode_events(p, f, zero)
    ev_dh = np.matmul(ev_h, A)  # d/dt (h . z) = h . A z = (A^T h) . z

    funcs = np.zeros((S.N_FUNCS, S.N_STATE))
    funcs[S.F_FN] = f.fn
    funcs[S.F_NG_CONTACT] = f.ng_contact
    funcs[S.F_VREL] = f.vrel
    funcs[S.F_HOLD], funcs[S.F_FS1], funcs[S.F_FS2] = f.stuck
    funcs[S.F_NG_SEP] = f.ng_sep

    scalars = np.array(  # order: the SC_* indices of contact.state
        [
            p.mu_s, mu_d_eff, p.mu_sd, p.phi_Ll, g_N, g_T,
            p.A_l * op.voltage_V, p.A_b * op.voltage_V, p.C_l, p.C_b, p.M_l, p.K_l,
            p.M_b, p.K_b, p.M_slider, p.k_contact, op.omega, g_N - p.eta_N,
            stick_band_m_s, p.phi_Bl, op.load_N,
        ]
    )
    assert scalars.shape == (S.N_SCALARS,)
    z0, mode0 = _initial_state(p, op, f.fn)
    _check_finite_system(p, (A, ev_h, fn_m, ft_m, ff_m, funcs))
    return HybridSystem(A, ev_h, ev_dh, ev_type, fn_m, ft_m, ff_m, funcs, scalars, z0, mode0)


def normal_force_zero_tip_displacement(params: MotorParams, preload_N: float) -> float:
    """Critical tip normal displacement ``y_tip^c`` at which F_N reaches 0 (m), Eq. 21.

    Generalizes ``-F_P/(2k) - eta_N F_P / K_l`` to any ``phi_L`` end values:
    ``y_tip = phi_L(l) u_l`` with ``u_l`` solving ``F_P + k (u_d - u_st) = 0``.
    """
    p = params
    dphi = p.phi_Ll - p.phi_L0
    u_st = p.eta_N * preload_N * dphi / p.K_l
    u_crit = (u_st - preload_N / p.k_contact) / dphi
    return p.phi_Ll * u_crit


def linear_normal_amplitude(params: MotorParams, op: OperatingPoint) -> float | None:
    """Steady normal tip amplitude A_N (m) of Eqs. 4 + 7 in closed form, or None.

    While the tip stays in contact, Eq. 4 with the normal force of Eq. 7 is linear in
    ``u_l`` (``eta_N F_N = eta_N (F_P - k u_st) - eta_N^2 k u_l``, since
    ``phi_L(l) - phi_L(0) = -eta_N``): its periodic orbit under ``A_l V0 sin(omega t)`` is
    harmonic with amplitude ``A_l V0 / |K_l + eta_N^2 k - M_l omega^2 + i C_l omega|``, and
    ``A_N = |phi_L(l)|`` times that. The mean normal force of that orbit is ``F_P`` and its
    swing ``k |eta_N| U``; when the swing reaches the mean the tip separates, the orbit is
    not harmonic and None is returned (the caller then simulates the pre-pass of
    :func:`contact.transient.pre_pass.normal_amplitude`, its reference).
    """
    p = params
    k_eff = p.K_l + p.eta_N ** 2 * p.k_contact
    denom = abs(complex(k_eff - p.M_l * op.omega ** 2, p.C_l * op.omega))
    if not denom > 0.0:
        return None
    u_amp = abs(p.A_l) * op.voltage_V / denom
    dphi = p.phi_Ll - p.phi_L0
    u_st = p.eta_N * op.preload_N * dphi / p.K_l
    u_mean = p.eta_N * (op.preload_N - p.k_contact * u_st) / k_eff
    fn_mean = op.preload_N + p.k_contact * (dphi * u_mean - u_st)
    fn_swing = p.k_contact * abs(dphi) * u_amp
    if not fn_swing < (1.0 - 1e-9) * fn_mean:  # separation (or touching zero): simulate
        return None
    return abs(p.phi_Ll) * u_amp
