"""Slow, independent reference of the switch model: event-driven ``scipy.integrate.solve_ivp``.

Scheme ``method="reference"`` of :func:`contact.simulate.simulate`.

The equations are written out here term by term from the paper (Eqs. 4-19), without the
matrix form of :mod:`contact.model`, and integrated with an adaptive high-order method at
tight tolerances. Every switch (separation, re-contact, v_rel = 0, stick break, slider
stopping or starting on its guide) is a terminal event; the integration restarts in the new
mode from the event state. It is the yardstick of the fast kernel in the tests and in the
work-precision benchmark, and it counts steps and right-hand-side evaluations the way
``solve_ivp`` does.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from contact.model import OperatingPoint, gamma_T, static_deflection_m
from contact.results import SchemeOutput
from contact.state import BACKWARD, FORWARD, HELD, SLIP_NEG, SLIP_POS, STICK
from contact.window import RunWindow
from rom.params import GRAVITY_M_S2, MotorParams

MAX_EVENTS = 10_000_000
"""Switches after which a reference run is abandoned."""


class _Motor:
    """Forces and right-hand sides of Eqs. 4-19 for one parameter set and operating point."""

    def __init__(self, p: MotorParams, op: OperatingPoint, mu_d: float, coupling: str):
        self.p, self.op, self.mu_d = p, op, mu_d
        self.gT = gamma_T(p, coupling)
        self.dphi = p.phi_Ll - p.phi_L0
        self.u_st = p.eta_N * op.preload_N * self.dphi / p.K_l  # Eq. 7
        self.Mg = p.M_slider * GRAVITY_M_S2

    def drive(self, t: float) -> float:
        return self.op.voltage_V * math.sin(self.op.omega * t)

    def fn_arg(self, y: np.ndarray) -> float:
        """``F_P + k (u_d - u_st)``: the normal force while in contact (Eq. 7)."""
        return self.op.preload_N + self.p.k_contact * (self.dphi * y[0] - self.u_st)

    def v_rel(self, y: np.ndarray) -> float:
        return self.p.phi_Bl * y[3] - y[5]  # Eq. 8

    def hold_force(self, t: float, y: np.ndarray) -> float:
        """F_T keeping tip and slider at rest (B2 frozen)."""
        p = self.p
        return (p.K_b * y[2] - p.A_b * self.drive(t)) / self.gT

    def stick_force(self, t: float, y: np.ndarray, direction: float) -> float:
        """Eq. 10 with the guide friction of a slider moving in ``direction``."""
        p = self.p
        f_f = -direction * p.mu_sd * (self.fn_arg(y) + self.Mg)
        num = p.phi_Bl / p.M_b * (p.C_b * y[3] + p.K_b * y[2] - p.A_b * self.drive(t))
        num += f_f / p.M_slider
        return num / (p.phi_Bl * self.gT / p.M_b - 1.0 / p.M_slider)

    def forces(self, t: float, y: np.ndarray, mode: tuple[int, int, int]):
        """(F_N, F_T, F_f) in a mode ``(contact, tip, guide)``."""
        contact, tip, guide = mode
        p = self.p
        direction = {HELD: 0.0, FORWARD: 1.0, BACKWARD: -1.0}[guide]
        if not contact:
            fn, ft = 0.0, 0.0
        else:
            fn = self.fn_arg(y)
            if tip == STICK:
                ft = self.hold_force(t, y) if guide == HELD else self.stick_force(t, y, direction)
            else:
                ft = (1.0 if tip == SLIP_POS else -1.0) * self.mu_d * fn
        ff = -ft if guide == HELD else -direction * p.mu_sd * (fn + self.Mg)
        return fn, ft, ff

    def rhs(self, t: float, y: np.ndarray, mode: tuple[int, int, int]) -> np.ndarray:
        p = self.p
        contact, tip, guide = mode
        fn, ft, ff = self.forces(t, y, mode)
        v = self.drive(t)
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
    def tip_at_zero(self, t, y, guide):
        p = self.p
        fn = self.fn_arg(y)
        if guide == HELD:
            fh = self.hold_force(t, y)
            if abs(fh) <= p.mu_sd * (fn + self.Mg):
                return (STICK, HELD) if abs(fh) <= p.mu_s * fn else (
                    SLIP_POS if fh > 0 else SLIP_NEG, HELD)
            guide = FORWARD if fh > 0 else BACKWARD
        fs = self.stick_force(t, y, 1.0 if guide == FORWARD else -1.0)
        if abs(fs) <= p.mu_s * fn:
            return STICK, guide
        return (SLIP_POS if fs > 0 else SLIP_NEG), guide

    def events(self, mode):
        """Event functions (positive outside the mode) with their kinds."""
        contact, tip, guide = mode
        p = self.p
        out = []
        if contact:
            out.append(("separate", lambda t, y: -self.fn_arg(y)))
            if tip == STICK:
                def fs(t, y, g=guide):
                    if g == HELD:
                        return self.hold_force(t, y)
                    return self.stick_force(t, y, 1.0 if g == FORWARD else -1.0)
                out.append(("break", lambda t, y: fs(t, y) - p.mu_s * self.fn_arg(y)))
                out.append(("break", lambda t, y: -fs(t, y) - p.mu_s * self.fn_arg(y)))
            else:
                sigma = 1.0 if tip == SLIP_POS else -1.0
                out.append(("vrel", lambda t, y: -sigma * self.v_rel(y)))
        else:
            out.append(("contact", lambda t, y: self.fn_arg(y)))
        if guide == HELD:
            def ft(t, y):
                return self.forces(t, y, mode)[1]

            def ng(y):
                return (self.fn_arg(y) if contact else 0.0) + self.Mg

            out.append(("release", lambda t, y: ft(t, y) - p.mu_sd * ng(y)))
            out.append(("release", lambda t, y: -ft(t, y) - p.mu_sd * ng(y)))
        else:
            s = 1.0 if guide == FORWARD else -1.0
            out.append(("xdot", lambda t, y: -s * y[5]))
        return out

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
            fs = self.forces(t, y, mode)[1]
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
                fh = self.hold_force(t, y)
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
    """
    rtol = opts.rtol
    motor = _Motor(params, op, mu_d_eff, opts.coupling)
    p = params
    y = np.zeros(6)
    y[0] = static_deflection_m(p, op.preload_N)
    mode = (1, STICK, HELD) if motor.fn_arg(y) > 0 else (0, SLIP_POS, HELD)
    # amplitude scales of each component for the absolute tolerance
    u_scale = max(abs(p.A_l) * op.voltage_V / p.K_l, abs(y[0]), 1e-12) * 10
    w_scale = max(abs(p.A_b) * op.voltage_V / p.K_b, 1e-12) * 10
    atol = rtol * np.array(
        [u_scale, u_scale * op.omega, w_scale, w_scale * op.omega, 1e-6, 1e-3]
    )
    # an event fires once its function exceeds roundoff of its own scale, not at zero:
    # solve_ivp counts g = 0 -> 0 as a crossing, and with no drive and no preload (0 V /
    # 0 N) the normal force is exactly 0, so "contact" and "separate" fired in turn at the
    # same instant, forever (the event kernel's landing past the zero, docs/contact.md §3,
    # is the same rule)
    force_tol = 1e-12 * (op.preload_N + motor.Mg + (abs(p.A_l) + abs(p.A_b)) * op.voltage_V)
    speed_tol = 1e-12 * op.omega * (u_scale + w_scale)
    tol = {"separate": force_tol, "contact": force_tol, "break": force_tol,
           "release": force_tol, "vrel": speed_tol, "xdot": speed_tol}
    t_end, t_win = window.end_s, window.window_start_s
    marks = sorted({m for m in (window.previous_start_s, window.previous_end_s, t_win)
                    if 0.0 < m < t_end})
    x_at = {0.0: 0.0}
    t = 0.0
    phase_time = np.zeros(4)  # stick, slip v_rel > 0, slip v_rel < 0, separation
    n_steps = nfev = n_events = 0
    while t < t_end:
        t_stop = next((m for m in marks if m > t), t_end)
        evs = motor.events(mode)
        funcs = []
        for kind, f in evs:
            def ev(tt, yy, _mode, f=f, tol=tol[kind]):
                return f(tt, yy) - tol
            ev.terminal = True
            ev.direction = 1.0
            funcs.append(ev)
        sol = solve_ivp(
            motor.rhs, (t, t_stop), y, method="DOP853", rtol=rtol, atol=atol,
            events=funcs, args=(mode,), first_step=min(1e-8, (t_stop - t) / 2),
        )
        if sol.status < 0:
            raise RuntimeError(f"reference integration failed at t = {t:.6g} s: {sol.message}")
        n_steps += len(sol.t) - 1
        nfev += sol.nfev
        t_new = float(sol.t[-1])
        y_new = sol.y[:, -1].copy()
        lo = max(t, t_win)
        if t_new > lo:  # phase time inside the window
            phase = 3 if not mode[0] else (0 if mode[1] == STICK else
                                           1 if mode[1] == SLIP_POS else 2)
            phase_time[phase] += t_new - lo
        if sol.status == 0 and t_new in marks:  # segments stop at the marks exactly
            x_at[t_new] = float(y_new[4])
        t, y = t_new, y_new
        if sol.status == 1:  # an event ended the segment
            hit = [i for i, te in enumerate(sol.t_events) if len(te)]
            kind = evs[hit[0]][0]
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
