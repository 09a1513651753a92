"""The branch a start from rest reaches: the full model out of the ripple zone, then the sheet.

The averaged slow equation of :mod:`contact.steady.engine` can be many-valued: at one slider
velocity the fixed-velocity fast problem can have several stable orbits (a stick-slip and a
pure-slip orbit, say), each a *sheet* ``G(v)`` of its own, and the scan follows one of them.
Which sheet a start from rest is on is decided while the slider is slower than its velocity
ripple, where the averaging does not hold (a tuned 60 kHz stator at 140 V / 14 N: the full
model from rest takes the stick-slip sheet, the fixed-velocity problem from rest the pure-slip
one).

So the full model itself is run from rest, in blocks of :data:`PROBE_BLOCK_PERIODS`, until the
slider is :data:`PROBE_FACTOR` times faster than the ripple scale. There the fast orbit the
full model is on is found by shooting from its state, and the premise of the averaging is
checked on the full model's own next :data:`TRACK_BLOCKS` blocks: the slider's velocity must
change as ``M dv/dt = G(v)`` on that sheet says, to :data:`TRACK_RTOL`. The sheet is then
followed by continuation in the direction ``G`` pushes the slider (steps of
:data:`SHEET_STEP` in v, halved at a jump of the orbit's period or phase fractions) to its
first root, the stable steady state a slider moving along it stops at. A fold on the way
(the sheet ends and the slider falls to another one, which only the full model can choose), a
slider that stays in the ripple zone for :data:`PROBE_PERIODS` periods, or a failed check
leaves the decision to the transient from rest (:mod:`contact.steady.engine`), which continues this
run. The caller shoots the full model from the root (:func:`contact.steady.full_orbit.shoot`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from contact import state as S
from contact.errors import ChatteringError
from contact.steady.full_orbit import FullSystem, run_periods
from contact.steady.periodic_orbit import Orbit, find_orbit, orbit_phases
from contact.steady.slow import SlowProblem

PROBE_FACTOR = 20.0
"""The probe leaves the full model once the slider is this many times faster than the scan's
floor (the ripple scale ``mu_d_eff F_P / (M omega)``, :func:`contact.steady.slow.ripple_scale`):
the slider's velocity then swings by about 5 % of its value in a period."""

PROBE_BLOCK_PERIODS = 10
"""Drive periods per block of the full model's run from rest (and of the tracking check)."""

PROBE_PERIODS = 400
"""Periods of the full model from rest after which a slider still in the ripple zone (a
creep, the dead zone, a slow period-k orbit) is left to the transient from rest."""

TRACK_BLOCKS = 2
"""Blocks of the full model, after the slider leaves the ripple zone, on which the sheet's
slow flow is checked."""

TRACK_RTOL = 0.2
"""Largest relative difference between the full model's velocity change over a block and
the sheet's ``G(v) / M`` times the block's duration. On 450 points of four parameter sets
the accepted ones differed by at most 0.18 (the stator lagging a slider that still
accelerates: Q_m = 60 at 60 kHz); the one wrong sheet met (Table 2 at 126.9 V / 14.72 N under
-1.57 N, whose start from rest settles on a slower period-2 orbit) differed by 0.63."""

SHEET_STEP = 1.25
"""Continuation ratio in |v| along the sheet (halved in log v at a jump, down to
:data:`SHEET_MIN_STEP`)."""

SHEET_MIN_STEP = 1.002
"""Smallest continuation ratio: a jump still there is a fold of the sheet."""

SHEET_MAX_STEPS = 200
"""Continuation steps at most along the sheet (Table 2's map at 450 V takes about 25)."""

PHASE_JUMP = 0.1
"""Change of any phase fraction (stick, slip+, slip-, separation) between neighbouring orbits
taken as a jump to another sheet."""


class _Chatter(Exception):
    """The fast problem chatters at a velocity of the root search (args: the velocity)."""


@dataclass(frozen=True)
class RestProbe:
    """What the run from rest found (:func:`probe_from_rest`).

    Attributes
    ----------
    orbit : Orbit or None
        The averaged orbit at the sheet's root (its velocity ``orbit.velocity_m_s``, m/s);
        None when the transient from rest has to decide.
    z, mode : ndarray, int
        The full model's state where the run from rest stopped, ``full_periods`` drive
        periods after rest (the transient from rest goes on from there).
    full_periods : int
        Periods of the full model run from rest.
    periods, newton_iterations : int
        All the work: the full model's periods plus the fast problem's (Newton's runs).
    reason : str
        Why the probe left the decision to the transient, or how it found the root.
    track_error : float
        Largest relative difference of the tracking check (NaN where it was not reached).
    """

    orbit: Orbit | None
    z: np.ndarray
    mode: int
    full_periods: int
    periods: int
    newton_iterations: int
    reason: str
    track_error: float = math.nan


def _fractions(sp: SlowProblem, o: Orbit) -> np.ndarray:
    phase = orbit_phases(sp.fs, o, sp.average_periods)
    total = float(np.sum(phase))
    return phase / total if total > 0 else phase


class _GiveUp(Exception):
    """The probe leaves the decision to the transient from rest (args: why)."""


class _Probe:
    """The run from rest in progress: the full model's state ``(z, mode)`` after ``n``
    periods, the fast problem's work (periods, Newton iterations) and the tracking check's
    largest relative error (``worst``, NaN until it runs)."""

    def __init__(self, sp: SlowProblem, fsys: FullSystem) -> None:
        self.sp, self.fsys = sp, fsys
        self.z, self.mode, self.n = fsys.system.z0, fsys.system.mode0, 0
        self.periods = self.newton = 0
        self.worst = math.nan

    def run_block(self) -> None:
        """Run the full model :data:`PROBE_BLOCK_PERIODS` periods on."""
        self.z, self.mode, _, _, _ = run_periods(self.fsys, self.z, self.mode,
                                                 PROBE_BLOCK_PERIODS)
        self.n += PROBE_BLOCK_PERIODS

    def orbit(self, v: float, near: Orbit | None, z=None, mode=None) -> Orbit | None:
        """The fast orbit at ``v`` continued from ``near`` (or from a full-model state);
        None where the fast problem chatters."""
        sp = self.sp
        if near is not None:
            z, mode = near.z, near.mode
        try:
            o = find_orbit(sp.fs, v, z, mode, tol=sp.orbit_tol,
                           max_periods=sp.search_periods, average_periods=sp.average_periods,
                           jacobian=None if near is None else near.jacobian)
        except ChatteringError:
            return None
        self.periods += o.periods
        self.newton += o.newton_iterations
        return o

    def thrust(self, o: Orbit) -> float:
        """``G(v) - F_load`` (N) on the sheet at the orbit's velocity."""
        sp = self.sp
        return (o.mean_FT_N - math.copysign(1.0, o.velocity_m_s) * sp.guide_N(o)
                - sp.op.load_N)

    def result(self, orbit: Orbit | None, reason: str) -> RestProbe:
        return RestProbe(orbit, self.z, self.mode, self.n, self.n + self.periods, self.newton,
                         reason, self.worst)


def probe_from_rest(sp: SlowProblem, fsys: FullSystem) -> RestProbe:
    """Run the full model from rest out of the ripple zone and follow the sheet it is on.

    ``sp`` is the operating point's slow problem (its tolerances and load), ``fsys`` its full
    model. See the module's docstring for the method and the cases it leaves to the
    transient from rest. A chattering fast problem leaves the decision to the transient too
    (a chattering full model raises, as the transient would).
    """
    probe = _Probe(sp, fsys)
    try:
        found = _sheet_root(probe, _tracked_sheet(probe))
    except _GiveUp as exc:
        return probe.result(None, exc.args[0])
    return probe.result(found, f"the sheet's root, slow flow followed to {probe.worst:.2g}")


def _tracked_sheet(probe: _Probe) -> Orbit:
    """The fast orbit of the sheet the full model is on once out of the ripple zone, after
    :data:`TRACK_BLOCKS` blocks in which the slider's velocity changes as the sheet's slow
    flow ``M dv/dt = G(v)`` says (to :data:`TRACK_RTOL`)."""
    sp = probe.sp
    threshold = PROBE_FACTOR * sp.v_floor_m_s
    while abs(probe.z[S.DX]) <= threshold:
        if probe.n >= PROBE_PERIODS:
            raise _GiveUp(f"the slider stays below {PROBE_FACTOR:g} x the ripple scale")
        probe.run_block()
    sheet = probe.orbit(float(probe.z[S.DX]), None, probe.z, probe.mode)
    if sheet is None or not sheet.k:
        raise _GiveUp("no periodic fast orbit where the slider left the ripple zone")
    changed = "the fast orbit changed its period while the slider left the ripple zone"
    mass, period = sp.params.M_slider, sp.op.period_s
    probe.worst = 0.0
    for _ in range(TRACK_BLOCKS):
        v0 = float(probe.z[S.DX])
        probe.run_block()
        v1 = float(probe.z[S.DX])
        mid = probe.orbit(0.5 * (v0 + v1), sheet)
        if mid is None or mid.k != sheet.k:
            raise _GiveUp(changed)
        sheet = mid
        predicted = probe.thrust(mid) / mass * PROBE_BLOCK_PERIODS * period
        probe.worst = max(probe.worst,
                          abs((v1 - v0) - predicted) / max(abs(predicted), 1e-300))
    if probe.worst > TRACK_RTOL:
        raise _GiveUp(f"the slider does not follow the sheet's slow flow (off by "
                      f"{probe.worst:.2g})")
    here = probe.orbit(float(probe.z[S.DX]), sheet)
    if here is None or here.k != sheet.k:
        raise _GiveUp(changed)
    return here


def _sheet_root(probe: _Probe, prev: Orbit) -> Orbit:
    """The first root of ``G(v) = F_load`` along the sheet from ``prev`` in the direction
    ``G`` pushes the slider: continuation in steps of :data:`SHEET_STEP` in v, halved in
    log v at a jump of the orbit's period or phase fractions (a fold where they reach
    :data:`SHEET_MIN_STEP`), then Brent's method inside the last step."""
    sp = probe.sp
    threshold = PROBE_FACTOR * sp.v_floor_m_s
    g = probe.thrust(prev)
    frac = _fractions(sp, prev)
    base = SHEET_STEP if g * prev.velocity_m_s > 0 else 1.0 / SHEET_STEP
    ratio = base
    for _ in range(SHEET_MAX_STEPS):
        v = prev.velocity_m_s * ratio
        if abs(v) < 0.5 * threshold or abs(v) > sp.v_max_m_s:
            raise _GiveUp("the sheet leaves the scanned velocities")
        nxt = probe.orbit(v, prev)
        if nxt is None:
            raise _GiveUp(f"the fast problem chatters at {v:.4g} m/s on the sheet")
        frac_n = _fractions(sp, nxt) if nxt.k else frac
        if nxt.k != prev.k or np.max(np.abs(frac_n - frac)) > PHASE_JUMP:
            if abs(math.log(ratio)) <= math.log(SHEET_MIN_STEP):
                raise _GiveUp(f"the sheet folds at {v:.4g} m/s")
            ratio = math.sqrt(ratio)
            continue
        g_n = probe.thrust(nxt)
        if g_n * g <= 0.0:
            return _root_between(probe, prev, v, frac)
        prev, frac, g = nxt, frac_n, g_n
        if abs(math.log(ratio)) < abs(math.log(base)):
            ratio *= ratio  # back towards the full step after a halving
    raise _GiveUp(f"no root within {SHEET_MAX_STEPS} continuation steps along the sheet")


def _root_between(probe: _Probe, prev: Orbit, v: float, frac: np.ndarray) -> Orbit:
    """The sheet's orbit at the root of ``G(v) = F_load`` between ``prev``'s velocity and
    ``v`` (m/s), each iterate continued from ``prev``; ``frac`` is ``prev``'s phase
    fractions."""
    sp = probe.sp

    def g_at(w: float) -> float:
        o = probe.orbit(w, prev)
        if o is None:
            raise _Chatter(w)
        return probe.thrust(o)

    try:
        root = brentq(g_at, prev.velocity_m_s, v, xtol=1e-12, rtol=sp.root_rtol)
    except _Chatter as exc:
        raise _GiveUp(f"the fast problem chatters at {exc.args[0]:.4g} m/s on the "
                      f"sheet") from None
    found = probe.orbit(root, prev)
    if (found is None or found.k != prev.k
            or np.max(np.abs(_fractions(sp, found) - frac)) > PHASE_JUMP):
        # Brent's iterates continue from one end; one that jumped to another sheet
        # leaves a root that is not this sheet's
        raise _GiveUp(f"the root search left the sheet at {root:.4g} m/s")
    return found
