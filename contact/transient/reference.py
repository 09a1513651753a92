"""Slow, independent reference of the switch model: event-driven ``scipy.integrate.solve_ivp``.

Scheme ``method="reference"`` of :func:`contact.simulate.simulate`.

The equations are written out here term by term from the paper (Eqs. 4-19), without the
matrix form of :mod:`contact.model`, and integrated with an adaptive high-order method at
tight tolerances. Every switch (separation, re-contact, v_rel = 0, stick break, slider
stopping or starting on its guide) is a terminal event; the integration restarts in the new
mode from the event state. ``solve_ivp`` sees a crossing only as a sign change between its
step ends, so each guard's maximum (the zero of its time derivative, exact from the linear
mode dynamics) is an event too: a maximum above zero is a pair of crossings stepped over
(a brief separation past its onset), and the first crossing is located on the dense output of
that step (:func:`_stepped_over`).

It is the yardstick of the fast kernel in the tests and in the work-precision benchmark, and
it counts steps and right-hand-side evaluations the way ``solve_ivp`` does (those of the
event functions, the guards' derivatives among them, not included).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from bounds import ParameterError
from contact.model import OperatingPoint, gamma_T, static_deflection_m
from contact.results import SchemeOutput
from contact.state import BACKWARD, FORWARD, HELD, SLIP_NEG, SLIP_POS, STICK
from contact.transient.window import MIN_PERIODS, WORK_ENV, RunWindow, work_factor
from rom.params import GRAVITY_M_S2, MotorParams

Guard = Callable[[float, np.ndarray], float]
"""A switching function ``g(v, y)`` of the drive voltage (V) and the state: positive outside
the current mode."""

MAX_EVENTS = 10_000_000
"""Switches after which a reference run is abandoned."""

MAX_REFERENCE_PERIODS = 20_000
"""Most drive periods (``duration_s * frequency_Hz``) of one reference run, times
``LUSM_MAX_WORK``.

The reference restarts ``solve_ivp`` at every switch, a few times per period, and costs about
3-4 ms of CPU per period on Table 2's set (200 V / 14 N at 40 kHz, and at 10 MHz). The
longest run the tests, docs, benchmarks and ``lusm report`` ask of it is the default 50 ms
at 40 kHz, 2 000 periods (7-12 s); the bound is ten times that, a minute or two. The default
50 ms at 10 MHz (500 000 periods, about 1e6 restarts and half an hour) is refused before it
starts (:func:`check_reference_work`)."""

def check_reference_work(op: OperatingPoint, duration_s: float) -> float:
    """Refuse a reference run longer than :data:`MAX_REFERENCE_PERIODS` drive periods.

    Parameters
    ----------
    op : OperatingPoint
        The drive (its frequency sets the period).
    duration_s : float
        Length of the run (s).

    Returns
    -------
    float
        The number of drive periods of the run.

    Raises
    ------
    ValueError
        Naming ``duration_s`` and ``frequency_Hz`` with the range each may take given the
        other, when the run exceeds the bound (times ``LUSM_MAX_WORK``).
    """
    periods = duration_s * op.frequency_Hz
    top = MAX_REFERENCE_PERIODS * work_factor()
    if not periods <= top:
        f, d = op.frequency_Hz, duration_s
        raise ParameterError(
            "duration_s", d, MIN_PERIODS / f, top / f, "s",
            reason=f"method='reference' runs {MIN_PERIODS} to {top:.6g} drive periods",
            message=f"method='reference' runs {MIN_PERIODS} to {top:.6g} drive periods: "
            "duration_s "
            f"must lie in [{MIN_PERIODS / f:.4g}, {top / f:.4g}] s at frequency_Hz = {f:g} Hz, "
            f"or frequency_Hz in [{MIN_PERIODS / d:.4g}, {top / d:.4g}] Hz for duration_s = "
            f"{d:g} s (got {periods:.4g} periods, a few solve_ivp restarts each); use the "
            f"event scheme for long runs, or set {WORK_ENV}=N to allow N times more")
    return periods


_DIRECTION = {HELD: 0.0, FORWARD: 1.0, BACKWARD: -1.0}
"""Sign of the slider's motion in each guide mode."""


class _Motor:
    """Forces and right-hand sides of Eqs. 4-19 for one parameter set and operating point."""

    def __init__(self, p: MotorParams, op: OperatingPoint, mu_d: float, coupling: str):
        self.p, self.op, self.mu_d = p, op, mu_d
        self.gT = gamma_T(p, coupling)
        self.dphi = p.phi_Ll - p.phi_L0
        self.u_st = p.eta_N * op.preload_N * self.dphi / p.K_l  # Eq. 7
        self.Mg = p.M_slider * GRAVITY_M_S2
        # the drive's amplitude and circular frequency, read once: the right-hand side runs
        # about 12 times per step and OperatingPoint.omega is a property
        self.V0, self.omega = op.voltage_V, op.omega
        self._zero_state = np.zeros(6)
        self._rate_key: tuple | None = None
        self._rate = self._zero_state

    def drive(self, t: float) -> float:
        return self.V0 * math.sin(self.omega * t)

    def drive_rate(self, t: float) -> float:
        """Time derivative of :meth:`drive` (V/s)."""
        return self.V0 * self.omega * math.cos(self.omega * t)

    def fn_arg(self, y: np.ndarray) -> float:
        """``F_P + k (u_d - u_st)``: the normal force while in contact (Eq. 7)."""
        return self.op.preload_N + self.p.k_contact * (self.dphi * y[0] - self.u_st)

    def v_rel(self, y: np.ndarray) -> float:
        return self.p.phi_Bl * y[3] - y[5]  # Eq. 8

    # The forces take the drive voltage ``v`` rather than the time: each guard of
    # :meth:`events` is then affine in ``(v, y)``, and its time derivative is the same
    # expression at ``(dv/dt, dy/dt)`` less its constant part (:meth:`guard_rate`).
    def hold_force(self, v: float, y: np.ndarray) -> float:
        """F_T keeping tip and slider at rest (B2 frozen) at drive voltage ``v``."""
        p = self.p
        return (p.K_b * y[2] - p.A_b * v) / self.gT

    def stick_force(self, v: float, y: np.ndarray, direction: float) -> float:
        """Eq. 10 with the guide friction of a slider moving in ``direction``."""
        p = self.p
        f_f = -direction * p.mu_sd * (self.fn_arg(y) + self.Mg)
        num = p.phi_Bl / p.M_b * (p.C_b * y[3] + p.K_b * y[2] - p.A_b * v)
        num += f_f / p.M_slider
        return num / (p.phi_Bl * self.gT / p.M_b - 1.0 / p.M_slider)

    def forces(self, v: float, y: np.ndarray, mode: tuple[int, int, int]):
        """(F_N, F_T, F_f) in a mode ``(contact, tip, guide)`` at drive voltage ``v``."""
        contact, tip, guide = mode
        p = self.p
        direction = _DIRECTION[guide]
        if not contact:
            fn, ft = 0.0, 0.0
        else:
            fn = self.fn_arg(y)
            if tip == STICK:
                ft = self.hold_force(v, y) if guide == HELD else self.stick_force(v, y, direction)
            else:
                ft = (1.0 if tip == SLIP_POS else -1.0) * self.mu_d * fn
        ff = -ft if guide == HELD else -direction * p.mu_sd * (fn + self.Mg)
        return fn, ft, ff

    def rhs(self, t: float, y: np.ndarray, mode: tuple[int, int, int]) -> np.ndarray:
        p = self.p
        contact, tip, guide = mode
        v = self.drive(t)
        fn, ft, ff = self.forces(v, y, mode)
        d = np.empty(6)
        d[0] = y[1]
        d[1] = (-p.K_l * y[0] - p.C_l * y[1] + p.A_l * v + p.eta_N * fn) / p.M_l  # Eq. 4
        if contact and tip == STICK and guide == HELD:
            d[2] = d[3] = d[4] = d[5] = 0.0
            return d
        d[2] = y[3]
        d[3] = (-p.K_b * y[2] - p.C_b * y[3] + p.A_b * v + self.gT * ft) / p.M_b  # Eq. 5
        d[4] = y[5]
        d[5] = 0.0 if guide == HELD else (ft + ff) / p.M_slider  # Eq. 6
        return d

    # --- switching rules (the same physics as the kernel, written independently) ---
    def tip_at_zero(self, t: float, y: np.ndarray, guide: int) -> tuple[int, int]:
        """Tip and guide modes on reaching ``v_rel = 0`` in contact at time ``t``."""
        p = self.p
        v = self.drive(t)
        fn = self.fn_arg(y)
        if guide == HELD:
            fh = self.hold_force(v, y)
            if abs(fh) <= p.mu_sd * (fn + self.Mg):
                return (STICK, HELD) if abs(fh) <= p.mu_s * fn else (
                    SLIP_POS if fh > 0 else SLIP_NEG, HELD)
            guide = FORWARD if fh > 0 else BACKWARD
        fs = self.stick_force(v, y, 1.0 if guide == FORWARD else -1.0)
        if abs(fs) <= p.mu_s * fn:
            return STICK, guide
        return (SLIP_POS if fs > 0 else SLIP_NEG), guide

    def events(self, mode: tuple[int, int, int]) -> list[tuple[str, Guard]]:
        """Guards of a mode with their kinds: functions ``g(v, y)`` of the drive voltage and
        the state, positive outside the mode, each affine in ``(v, y)``."""
        contact, tip, guide = mode
        p = self.p
        out: list[tuple[str, Guard]] = []
        if contact:
            out.append(("separate", lambda v, y: -self.fn_arg(y)))
            if tip == STICK:
                def fs(v, y, g=guide):
                    if g == HELD:
                        return self.hold_force(v, y)
                    return self.stick_force(v, y, 1.0 if g == FORWARD else -1.0)
                out.append(("break", lambda v, y: fs(v, y) - p.mu_s * self.fn_arg(y)))
                out.append(("break", lambda v, y: -fs(v, y) - p.mu_s * self.fn_arg(y)))
            else:
                sigma = 1.0 if tip == SLIP_POS else -1.0
                out.append(("vrel", lambda v, y: -sigma * self.v_rel(y)))
        else:
            out.append(("contact", lambda v, y: self.fn_arg(y)))
        if guide == HELD:
            def ft(v, y):
                return self.forces(v, y, mode)[1]

            def ng(y):
                return (self.fn_arg(y) if contact else 0.0) + self.Mg

            out.append(("release", lambda v, y: ft(v, y) - p.mu_sd * ng(y)))
            out.append(("release", lambda v, y: -ft(v, y) - p.mu_sd * ng(y)))
        else:
            s = 1.0 if guide == FORWARD else -1.0
            out.append(("xdot", lambda v, y: -s * y[5]))
        return out

    def guard_rate(self, guard: Guard, mode: tuple[int, int, int]
                   ) -> Callable[[float, np.ndarray], float]:
        """Time derivative ``(t, y) -> d/dt guard(drive(t), y)`` along the flow of ``mode``.

        Every guard is affine in ``(v, y)``: ``g = L(v, y) + c``. Its derivative is
        ``L(dv/dt, dy/dt)`` exactly, i.e. the guard at ``(dv/dt, dy/dt)`` less its value at
        ``(0, 0)``; ``dy/dt`` is the mode's right-hand side (Eqs. 4-6).
        """
        c = guard(0.0, self._zero_state)

        def rate(t: float, y: np.ndarray) -> float:
            return guard(self.drive_rate(t), self.rate(t, y, mode)) - c
        return rate

    def rate(self, t: float, y: np.ndarray, mode: tuple[int, int, int]) -> np.ndarray:
        """:meth:`rhs`, remembered for the last ``(t, y, mode)``: ``solve_ivp`` evaluates
        every guard's derivative at the same step end, one after the other."""
        key = (t, y.tobytes(), mode)
        if key != self._rate_key:
            self._rate_key, self._rate = key, self.rhs(t, y, mode)
        return self._rate

    def switch(self, kind, t, y, mode):
        contact, tip, guide = mode
        p = self.p
        if kind == "separate":
            contact, tip = 0, SLIP_POS
        elif kind == "contact":
            contact = 1
            vr = self.v_rel(y)
            tip = SLIP_POS if vr > 0 else SLIP_NEG
            if vr == 0.0:
                tip, guide = self.tip_at_zero(t, y, guide)
        elif kind == "vrel":
            tip, guide = self.tip_at_zero(t, y, guide)
        elif kind == "break":
            fs = self.forces(self.drive(t), y, mode)[1]
            tip = SLIP_POS if fs > 0 else SLIP_NEG
        elif kind == "xdot":
            if contact and tip == STICK:
                tip, guide = self.tip_at_zero(t, y, HELD)
            else:
                fn = self.fn_arg(y) if contact else 0.0
                ft = 0.0 if not contact else (1.0 if tip == SLIP_POS else -1.0) * self.mu_d * fn
                if abs(ft) <= p.mu_sd * (fn + self.Mg):
                    guide = HELD
                else:
                    guide = FORWARD if ft > 0 else BACKWARD
        elif kind == "release":
            if contact and tip == STICK:
                fh = self.hold_force(self.drive(t), y)
                tip, guide = self.tip_at_zero(t, y, FORWARD if fh > 0 else BACKWARD)
            else:
                fn = self.fn_arg(y) if contact else 0.0
                ft = (1.0 if tip == SLIP_POS else -1.0) * self.mu_d * fn
                guide = FORWARD if ft > 0 else BACKWARD
        y = y.copy()
        if contact and tip == STICK:
            if guide == HELD:
                y[3] = y[5] = 0.0
            else:
                # v_rel = 0 set on the lighter of tip and slider, as the kernel does
                # (event_kernel._stick_exact): the event state may lie a hair past the zero
                # (docs/contact.md §3)
                if p.phi_Bl**2 * p.M_slider >= p.M_b:
                    y[3] = y[5] / p.phi_Bl
                else:
                    y[5] = p.phi_Bl * y[3]
        elif guide == HELD:
            y[5] = 0.0
        return (contact, tip, guide), y


def solve_reference(params: MotorParams, op: OperatingPoint, opts, window: RunWindow,
                    mu_d_eff: float) -> SchemeOutput:
    """Event-driven solution from rest with ``solve_ivp`` (DOP853 at ``opts.rtol``).

    The scheme ``"reference"`` of :func:`contact.simulate.simulate`; it measures on the same
    windows as the other schemes, exactly at their start and end times.
    :func:`contact.simulate.simulate` refuses a run of more than
    :data:`MAX_REFERENCE_PERIODS` drive periods before its A_N pre-pass
    (:func:`check_reference_work`).
    """
    rtol = opts.rtol
    motor = _Motor(params, op, mu_d_eff, opts.coupling)
    y = np.zeros(6)
    y[0] = static_deflection_m(params, op.preload_N)
    mode = (1, STICK, HELD) if motor.fn_arg(y) > 0 else (0, SLIP_POS, HELD)
    atol, tol = _tolerances(motor, y, rtol)
    t_end, t_win = window.end_s, window.window_start_s
    marks = sorted({m for m in (window.previous_start_s, window.previous_end_s, t_win)
                    if 0.0 < m < t_end})
    x_at = {0.0: 0.0}
    t = 0.0
    phase_time = np.zeros(4)  # stick, slip v_rel > 0, slip v_rel < 0, separation
    n_steps = nfev = n_events = 0
    while t < t_end:
        t_stop = next((m for m in marks if m > t), t_end)
        t_new, y_new, kind, steps, evals = _segment(motor, t, t_stop, y, mode, rtol, atol, tol)
        n_steps += steps
        nfev += evals
        lo = max(t, t_win)
        if t_new > lo:  # phase time inside the window
            phase = 3 if not mode[0] else (0 if mode[1] == STICK else
                                           1 if mode[1] == SLIP_POS else 2)
            phase_time[phase] += t_new - lo
        if kind is None and t_new in marks:  # segments stop at the marks exactly
            x_at[t_new] = float(y_new[4])
        t, y = t_new, y_new
        if kind is not None:  # a switch ended the segment
            mode, y = motor.switch(kind, t, y, mode)
            n_events += 1
            if n_events > MAX_EVENTS:
                raise RuntimeError(f"reference: more than {MAX_EVENTS} switches (Zeno?) by "
                                   f"t = {t:.6g} s")
    x_win = x_at.get(t_win, 0.0)
    if window.previous_start_s in x_at and window.previous_end_s in x_at:
        v_prev = (x_at[window.previous_end_s] - x_at[window.previous_start_s]) / window.window_s
    else:
        v_prev = float("nan")
    nan = float("nan")
    return SchemeOutput(
        velocity_m_s=float((y[4] - x_win) / window.window_s), previous_velocity_m_s=v_prev,
        phase_time=phase_time, y_tip_min_m=nan, y_tip_max_m=nan, trace=None, window=None,
        energy=None, steps=n_steps, events=n_events, nfev=nfev,
    )


def _tolerances(motor: _Motor, y0: np.ndarray, rtol: float) -> tuple[np.ndarray, dict]:
    """The integration's absolute tolerances (per state component, from its amplitude
    scale) and each event kind's threshold.

    An event fires once its function exceeds roundoff of its own scale, not at zero:
    ``solve_ivp`` counts ``g = 0 -> 0`` as a crossing, and with no drive and no preload
    (0 V / 0 N) the normal force is exactly 0, so that "contact" and "separate" would fire
    in turn at the same instant, forever (the event kernel's landing past the zero,
    docs/contact.md §3, is the same rule).
    """
    p, op = motor.p, motor.op
    u_scale = max(abs(p.A_l) * op.voltage_V / p.K_l, abs(y0[0]), 1e-12) * 10
    w_scale = max(abs(p.A_b) * op.voltage_V / p.K_b, 1e-12) * 10
    atol = rtol * np.array(
        [u_scale, u_scale * op.omega, w_scale, w_scale * op.omega, 1e-6, 1e-3]
    )
    force_tol = 1e-12 * (op.preload_N + motor.Mg + (abs(p.A_l) + abs(p.A_b)) * op.voltage_V)
    speed_tol = 1e-12 * op.omega * (u_scale + w_scale)
    tol = {"separate": force_tol, "contact": force_tol, "break": force_tol,
           "release": force_tol, "vrel": speed_tol, "xdot": speed_tol}
    return atol, tol


def _segment(motor: _Motor, t: float, t_stop: float, y: np.ndarray, mode, rtol: float,
             atol: np.ndarray, tol: dict):
    """Integrate one mode from ``t`` to the first switch or ``t_stop`` (s).

    Returns ``(t_new, y_new, kind, steps, nfev)``: where the segment ends, the event kind
    that ended it (None at ``t_stop``), and the accepted steps and right-hand-side
    evaluations spent, a pair of crossings stepped over included (:func:`_stepped_over`).
    """
    evs = motor.events(mode)
    crossings, maxima = [], []
    for kind, g in evs:
        def ev(tt, yy, _mode, g=g, tol=tol[kind]):
            return g(motor.drive(tt), yy) - tol
        ev.terminal = True
        ev.direction = 1.0
        crossings.append(ev)

        # the guard's time derivative falling through zero: a maximum of the guard, where
        # a pair of crossings inside one step shows (both step ends negative)
        rate = motor.guard_rate(g, mode)

        def peak(tt, yy, _mode, rate=rate):
            return rate(tt, yy)
        peak.direction = -1.0
        maxima.append(peak)
    sol = solve_ivp(
        motor.rhs, (t, t_stop), y, method="DOP853", rtol=rtol, atol=atol,
        events=crossings + maxima, args=(mode,), first_step=min(1e-8, (t_stop - t) / 2),
    )
    if sol.status < 0:
        raise RuntimeError(f"reference integration failed at t = {t:.6g} s: {sol.message}")
    steps, nfev = len(sol.t) - 1, sol.nfev
    t_new = float(sol.t[-1])
    y_new = sol.y[:, -1].copy()
    kind = None
    if sol.status == 1:  # a crossing ended the segment
        kind = evs[next(i for i, te in enumerate(sol.t_events[:len(evs)]) if len(te))][0]
    graze = _stepped_over(motor, sol, evs, crossings, mode, rtol, atol)
    if graze is not None:
        t_new, y_new, i, extra = graze
        kind = evs[i][0]
        steps += len(extra.t) - 1
        nfev += extra.nfev
    return t_new, y_new, kind, steps, nfev


def _stepped_over(motor: _Motor, sol, evs: list[tuple[str, Guard]],
                  crossings: list[Callable], mode: tuple[int, int, int], rtol: float,
                  atol: np.ndarray) -> tuple[float, np.ndarray, int, object] | None:
    """The first pair of guard crossings that ``solve_ivp`` stepped over in ``sol``, if any.

    ``solve_ivp`` sees a crossing only as a sign change between step ends. A guard that rises
    through zero and falls back inside one step (a brief separation just past its onset: F_N
    dips below zero for ~1e-7 s, against steps of ~1e-6 s) goes unseen. Its maximum is a
    zero of its derivative, recorded by the ``peak`` events of the segment (all those before
    the segment's terminal crossing, if any); a maximum above zero means the guard crossed
    before it. The step holding that maximum is integrated again from its start with dense
    output, and the crossing is located on it by Brent's method between the step start
    (guard negative) and the maximum (positive).

    Parameters
    ----------
    motor : _Motor
        The equations.
    sol : OdeResult
        The segment's ``solve_ivp`` result, its events ``crossings`` followed by one
        ``peak`` event per guard.
    evs : list of (str, Guard)
        The mode's guards with their kinds.
    crossings : list of callables
        The ``solve_ivp`` event functions of the guards (guard less its tolerance).
    mode : tuple of int
        The segment's mode.
    rtol, atol : float, ndarray
        ``solve_ivp``'s tolerances, also used for the step integrated again.

    Returns
    -------
    tuple or None
        ``(t, y, i, extra)``: the earliest such crossing, its state, the index of its guard
        in ``evs`` and the ``solve_ivp`` result of the step integrated again (for the
        counters); ``None`` when no guard's maximum lies above zero.
    """
    eps4 = 4.0 * np.finfo(float).eps
    best = None
    for i in range(len(evs)):
        event = crossings[i]
        # the earliest maximum above zero: a later one's first crossing lies after it
        peaks = sol.t_events[len(evs) + i]
        hit = next((j for j, y_m in enumerate(sol.y_events[len(evs) + i])
                    if event(peaks[j], y_m, mode) > 0.0), None)
        if hit is None:
            continue
        t_m = float(peaks[hit])
        # the step holding the maximum starts at the last step end before it; the guard is
        # negative at every step end before the segment's terminal crossing
        k = max(int(np.searchsorted(sol.t, t_m, side="left")) - 1, 0)
        t_k, y_k = float(sol.t[k]), sol.y[:, k]
        if t_m <= t_k or (best is not None and t_k >= best[0]) or event(t_k, y_k, mode) >= 0.0:
            continue
        extra = solve_ivp(motor.rhs, (t_k, t_m), y_k, method="DOP853", rtol=rtol, atol=atol,
                          args=(mode,), dense_output=True, first_step=t_m - t_k)
        dense = extra.sol
        if extra.status < 0 or event(t_m, dense(t_m), mode) <= 0.0:
            continue  # the maximum lies on the tolerance: no crossing at this accuracy

        def guard_at(s: float, event=event, dense=dense) -> float:
            return event(s, dense(s), mode)

        t_c = brentq(guard_at, t_k, t_m, xtol=eps4, rtol=eps4)
        if best is None or t_c < best[0]:
            best = (t_c, np.asarray(dense(t_c), dtype=float), i, extra)
    return best
