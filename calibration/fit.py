"""Weighted least squares of a parameter set against measurements, with its uncertainty.

The fit runs :func:`scipy.optimize.least_squares` (trust-region reflective, bounded) on the
residuals ``(model - measured) / sigma`` of every measured value, in parameters scaled to
their box (``u`` in [0, 1]: ``(value - min) / (max - min)``, or ``log(value / min) /
log(max / min)`` for a positive range of more than a decade, whose scale is the question, as
the friction law's ``b_mu``), from the file's start and from the best of points drawn
uniformly in ``u``; the lowest chi-square wins. SciPy is a core dependency already, and the
fit needs its own covariance and profiles anyway (a slow model wants bounded work, not
lmfit's open-ended ``conf_interval``), so no fitting library is added.

Uncertainty, with the measurement file's standard deviations taken as absolute:

* covariance ``(J^T J)^-1`` from the Jacobian at the optimum (SVD; a direction the data do
  not see has no finite variance), standard errors and correlations;
* profile likelihood: each parameter stepped away from its optimum by half a standard
  error at a time (:data:`PROFILE_STEPS`, then its bound), the others fitted again at every
  step by continuation (a trust-region fit of at most :data:`REFIT_NFEV` evaluations on the
  Jacobian of the step before, from that step's point or its straight-line extension:
  bounded work that stays on the side of the speeds' steps the optimum is on), until
  chi-square rises by :data:`DELTA_CHI2_95` (3.84, a 95 % interval of one parameter). A
  step that meets a cliff (a speed reaching another steady state) is re-fitted from a
  small friction screen (:func:`_rescue`); a point :data:`RECENTER_CHI2` below the optimum
  starts the fit again from there, once. The optimum's Jacobian is taken from both sides
  (:func:`_two_sided_jacobian`), so that a cliff within one step stays out of it;
* a parameter is *not identifiable* when the data see no direction of it, when its profile
  stays below 3.84 up to both bounds, or when it correlates with another above
  :data:`MAX_CORRELATION` in magnitude: the report names it and gives no number. One the
  data do not depend on at all keeps its start value in the calibrated set.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares
from scipy.stats import qmc

from bounds import ParameterError
from calibration.measurements import STEADY_KINDS, MeasurementError, Measurements
from calibration.model import predict, row_pool
from calibration.parameters import ORDER, FitParameter, apply, base_value
from rom.params import MotorParams

DELTA_CHI2_95 = 3.841458820694124
"""Rise of chi-square that bounds a 95 % profile-likelihood interval of one parameter
(the 95 % quantile of chi-square with one degree of freedom)."""
MAX_CORRELATION = 0.95
"""|Correlation| above which two parameters are not identifiable apart."""
DIFF_STEP = 3e-5
"""Finite-difference step of the Jacobian, as a share of each parameter's box."""
LOG_RANGE = 10.0
"""A positive parameter whose ``max / min`` exceeds this is scaled logarithmically."""
SINGULAR_RTOL = 1e-8
"""Singular values of the scaled Jacobian below this share of the largest: no information."""
MAX_NFEV = 200
"""Most residual evaluations of one start (the Jacobian's not counted)."""
REFIT_NFEV = 10
"""Most model evaluations of each re-fit along a profile (its Jacobian's not counted)."""
REFIT_FTOL = 1e-4
"""Relative change of chi-square that ends a re-fit along a profile (0.005 near the
example's 46 degrees of freedom)."""
TOLERANCE = 1e-6
"""Relative change of chi-square and of the scaled parameters that ends a start."""
SCREEN_PER_PARAMETER = 8
"""Points per fitted parameter drawn in the box to choose the starts after the file's."""
SCREEN_FRICTION_LOG2 = 7
"""log2 of the most quasi-random (Sobol) points of the friction screen: 128, reached with
two friction parameters (one alone gets 32: ``2 ** (3 + 2 k)``)."""
SCREEN_KEEP = 2
"""Points of least chi-square of the friction screen that start a local fit each."""
SCREEN_RERANK = 8
"""Points of least chi-square by the steady engine's ``fast`` level (2.5 times cheaper)
that the screen ranks again at the fit's level: on the example's three seeds the exact
ranking's best two are among the fast ranking's best four."""
FRICTION = ("mu_s", "mu_d", "a_mu", "b_mu", "mu_sd")
"""Parameters that move a steady speed across the dead zone's edge: the speed steps between
zero and a finite value in them, so a gradient fit stops on those steps."""
SCREEN_FTOL = 1e-4
"""Relative change of chi-square that ends a local fit from the screen: near its degrees of
freedom (46 on the example) that is a change of chi-square below 0.01, statistically nothing,
where the flat valley of ``a_mu`` against ``b_mu`` lets a fit to :data:`TOLERANCE` walk along
it for hundreds of evaluations."""
ACCEPT_SIGMAS = 2.0
"""A local fit from the screen whose chi-square is within this many standard deviations
(``sqrt(2 dof)``) above its degrees of freedom follows the data: the screen's next points
are not fitted."""
RESCUE_LOG2 = 6
"""log2 of the friction screen's points (64) at a profile step whose re-fit meets a cliff."""
RESCUE_RERANK = 4
"""Points of that screen ranked again at the fit's level."""
RECENTER_CHI2 = 0.5
"""Drop of chi-square below the optimum, found along a profile, from which the fit starts
again there (once) and the profiles are traced anew."""
PROFILE_STEPS = (0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 6.0, 8.0)
"""Points of a profile, in standard errors from the optimum (then the bound): half a
standard error apart through the 95 % end (1.96 for a quadratic profile), so that each
re-fit starts near its minimum and on the same side of the speeds' steps."""


@dataclass(frozen=True)
class Profile:
    """The profile likelihood of one parameter.

    Attributes
    ----------
    values : ndarray
        Parameter values visited (SI), sorted.
    delta_chi2 : ndarray
        Chi-square of the best fit with the parameter held there, minus the optimum's.
    lower, upper : float
        Ends of the 95 % interval (SI); a bound where the profile stays below
        :data:`DELTA_CHI2_95` up to it (``lower_open``, ``upper_open``).
    """

    values: np.ndarray
    delta_chi2: np.ndarray
    lower: float
    upper: float
    lower_open: bool
    upper_open: bool

    @property
    def flat(self) -> bool:
        """Whether the data leave the parameter anywhere between its bounds."""
        return self.lower_open and self.upper_open


@dataclass(frozen=True)
class CalibrationResult:
    """A calibration: fitted values, their uncertainty and the fit's figures.

    Attributes
    ----------
    parameters : tuple of FitParameter
    values : ndarray
        Best-fit values (SI), in the order of ``parameters``.
    stderr : ndarray
        Standard errors (SI); inf where the data see no direction of the parameter.
    correlation : ndarray
        Correlation matrix (NaN rows for such parameters).
    covariance : ndarray
        Covariance (SI).
    identifiable : tuple of bool
    reasons : tuple of str
        Why a parameter is not identifiable ('' if it is).
    profiles : dict of str to Profile
    chi2 : float
        Weighted sum of squared residuals at the optimum.
    points : int
        Measured values fitted.
    starts : tuple of (ndarray, ndarray, float)
        Each start's (start values, end values, chi-square), SI.
    params : MotorParams
        The fitted set.
    c0_F : float or None
        Fitted clamped capacitance (F), if fitted.
    predictions : tuple of dict
        The model's values at the optimum, per data set (measured quantity -> SI array).
    coupling, accuracy : str
        How the steady engine ran.
    evaluations : int
        Residual evaluations in all (fits, Jacobians, profiles).
    wall_time_s, profile_time_s : float
        Time of the whole calibration and of its profiles (s).
    held_covariance : ndarray
        Covariance (SI) of the identifiable parameters alone, in their order, with the
        others held at their values: the inverse of the Fisher information restricted to
        them (what a Monte Carlo that holds the others draws from, :mod:`calibration.
        uncertainty`).
    """

    parameters: tuple[FitParameter, ...]
    values: np.ndarray
    stderr: np.ndarray
    correlation: np.ndarray
    covariance: np.ndarray
    identifiable: tuple[bool, ...]
    reasons: tuple[str, ...]
    profiles: dict[str, Profile]
    chi2: float
    points: int
    starts: tuple
    params: MotorParams
    c0_F: float | None
    predictions: tuple[dict[str, np.ndarray], ...]
    coupling: str
    accuracy: str
    evaluations: int = 0
    wall_time_s: float = 0.0
    profile_time_s: float = 0.0
    notes: tuple[str, ...] = field(default=())
    held_covariance: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))

    @property
    def dof(self) -> int:
        """Degrees of freedom: measured values less fitted parameters."""
        return self.points - len(self.parameters)

    @property
    def names(self) -> tuple[str, ...]:
        """Parameter names, in order."""
        return tuple(p.name for p in self.parameters)


class _Problem:
    """Residuals of the measurements as a function of the scaled parameters ``u``."""

    def __init__(self, meas: Measurements, base: MotorParams, coupling: str, accuracy: str,
                 c0_F: float | None, pool: Executor | None = None) -> None:
        self.meas, self.base, self.coupling, self.accuracy = meas, base, coupling, accuracy
        self.c0_F, self.pool = c0_F, pool
        self.lower = np.array([p.lower for p in meas.parameters])
        upper = np.array([p.upper for p in meas.parameters])
        self.log = (self.lower > 0) & (upper > LOG_RANGE * self.lower)
        # u -> value: lower + span u, or lower exp(span u) on a log scale
        ratio = np.divide(upper, self.lower, out=np.ones_like(upper), where=self.log)
        self.span = np.where(self.log, np.log(ratio), upper - self.lower)
        self.evaluations = 0
        self.least: tuple[float, np.ndarray | None] = (math.inf, None)
        """The least chi-square of all the data seen at the problem's level, and where."""

    def values(self, u: np.ndarray) -> np.ndarray:
        """SI values of scaled parameters."""
        return self.value(slice(None), u)

    def value(self, i: int | slice, ui: np.ndarray | float) -> np.ndarray:
        """SI value(s) of parameter ``i`` (or of the parameters a slice picks) at scaled
        ``ui``."""
        log, lower, span = self.log[i], self.lower[i], self.span[i]
        ui = np.asarray(ui, dtype=float)
        grow = np.exp(np.where(log, span * ui, 0.0))  # no overflow on a linear scale
        return np.where(log, lower * grow, lower + span * ui)

    def scaled(self, values: np.ndarray) -> np.ndarray:
        """Scaled parameters of SI values."""
        v = np.asarray(values, dtype=float)
        ratio = np.divide(v, self.lower, out=np.ones_like(v), where=self.log)
        return np.where(self.log, np.log(ratio) / self.span, (v - self.lower) / self.span)

    def slope(self, u: np.ndarray) -> np.ndarray:
        """``d value / d u`` (SI) of each parameter at ``u``."""
        return np.where(self.log, self.span * self.values(u), self.span)

    def model(self, u: np.ndarray) -> tuple[MotorParams, float | None]:
        """The parameter set and clamped capacitance of ``u``."""
        given = dict(zip((p.name for p in self.meas.parameters), self.values(u), strict=True))
        return apply(self.base, given), given.get("C0_F", self.c0_F)

    def predictions(self, u: np.ndarray, sets=None,
                    accuracy: str | None = None) -> list[dict[str, np.ndarray]]:
        """Model values of every data set (or of ``sets``) at ``u``, the steady engine at
        ``accuracy`` (default the problem's)."""
        params, c0 = self.model(u)
        self.evaluations += 1
        return [predict(s, params, c0, self.coupling, accuracy or self.accuracy, self.pool)
                for s in (self.meas.sets if sets is None else sets)]

    def residuals(self, u: np.ndarray, sets=None, accuracy: str | None = None) -> np.ndarray:
        """``(model - measured) / sigma`` of every measured value (of ``sets``, a part of
        the measurements' data sets, where given), the steady engine at ``accuracy``
        (default the problem's)."""
        out = []
        every = sets is None
        sets = self.meas.sets if sets is None else sets
        for s, pred in zip(sets, self.predictions(u, sets, accuracy), strict=True):
            for q, y in s.observed.items():
                ok = np.isfinite(y)
                out.append((pred[q][ok] - y[ok]) / s.sigma[q][ok])
        r = np.concatenate(out)
        if every and accuracy in (None, self.accuracy) and r @ r < self.least[0]:
            self.least = (float(r @ r), np.array(u, dtype=float))
        return r


def check_box(meas: Measurements, base: MotorParams) -> None:
    """Refuse bounds that leave the set invalid somewhere in the box, naming the key: the
    friction law's order ``a_mu <= mu_d <= mu_s`` must hold for every value allowed, and the
    set must be valid at both corners.

    Raises
    ------
    MeasurementError
    """
    src = f"{meas.path}: [parameters]"
    fitted = {p.name: p for p in meas.parameters}
    for low, high in ORDER:
        if low not in fitted and high not in fitted:
            continue
        top = fitted[low].upper if low in fitted else getattr(base, low)
        bottom = fitted[high].lower if high in fitted else getattr(base, high)
        if top > bottom:
            lo_txt = f"{low} max = {top:g}" if low in fitted else f"{low} = {top:g} (fixed)"
            hi_txt = (f"{high} min = {bottom:g}" if high in fitted
                      else f"{high} = {bottom:g} (fixed)")
            raise MeasurementError(f"{src} {low if low in fitted else high}: {lo_txt} must "
                                   f"not exceed {hi_txt}: the friction law needs a_mu <= mu_d "
                                   f"<= mu_s everywhere in the box")
    for corner in ("lower", "upper"):
        values = {p.name: getattr(p, corner) for p in meas.parameters}
        bad = [n for n, v in values.items() if v <= 0 and n not in ("a_mu", "b_mu", "mu_sd")]
        if bad:
            raise MeasurementError(f"{src} {bad[0]}: min must be > 0, got {values[bad[0]]:g}")
        try:
            apply(base, values)
        except ValueError as exc:
            text = exc.said(exc.name) if isinstance(exc, ParameterError) else str(exc)
            raise MeasurementError(f"{src}: the set is invalid at every parameter's "
                                   f"{'min' if corner == 'lower' else 'max'}: {text}") from None


def _covariance(jac: np.ndarray, slope: np.ndarray) -> tuple[np.ndarray, list[list[int]]]:
    """Covariance (SI) from the Jacobian of the scaled parameters and their ``slope``
    (``d value / d u`` at the optimum, :meth:`_Problem.slope`), and for each parameter
    the parameters of a direction the data do not see that it takes part in (empty: none;
    itself alone: the data do not depend on it). Such parameters have infinite variance."""
    n = jac.shape[1]
    _, s, vt = np.linalg.svd(jac, full_matrices=False)
    keep = s > SINGULAR_RTOL * (s[0] if s.size and s[0] > 0 else 1.0)
    blind: list[list[int]] = [[] for _ in range(n)]
    for k in range(n):
        if k < s.size and keep[k]:
            continue
        row = vt[k] if k < vt.shape[0] else np.eye(n)[k]
        members = [int(j) for j in np.flatnonzero(np.abs(row) > 0.1)]
        for j in members:
            blind[j] = sorted(set(blind[j]) | set(members))
    cov_u = (vt[keep].T / s[keep] ** 2) @ vt[keep]
    cov = cov_u * np.outer(slope, slope)
    lost = [j for j in range(n) if blind[j]]
    cov[lost, :] = np.nan
    cov[:, lost] = np.nan
    return cov, blind


def _draw(problem: _Problem, count: int, rng: np.random.Generator) -> list[np.ndarray]:
    """``count`` scaled points drawn uniformly in the box."""
    return [rng.uniform(size=len(problem.meas.parameters)) for _ in range(count)]


def _friction_screen(problem: _Problem, u_best: np.ndarray, seed: int,
                     keep: int = SCREEN_KEEP, log2_max: int = SCREEN_FRICTION_LOG2,
                     rerank: int = SCREEN_RERANK, fixed: int | None = None
                     ) -> list[np.ndarray]:
    """The ``keep`` points of least chi-square among (at most ``2 ** log2_max``) Sobol
    points over the fitted :data:`FRICTION` parameters' scaled box (but ``fixed``), every
    other parameter held at ``u_best``; none without a speed set or a fitted friction
    parameter. The steady engine's ``fast`` level ranks them all and the fit's level the
    ``rerank`` best. The speeds' dead-zone steps leave a
    narrow valley of chi-square in the friction law (``a_mu`` against ``b_mu``) that random
    starts in the whole box seldom land in, while the smooth parameters are fixed near
    enough by the local fit."""
    params = problem.meas.parameters
    which = [i for i, p in enumerate(params) if p.name in FRICTION and i != fixed]
    if not which or not any(s.kind in STEADY_KINDS for s in problem.meas.sets):
        return []
    log2 = min(log2_max, 3 + 2 * len(which))
    points = qmc.Sobol(len(which), seed=seed).random_base2(log2)
    drawn = [_put(u_best, which, row) for row in points]
    if len(drawn) > max(keep, rerank):
        drawn = _least_chi2(problem, drawn, max(keep, rerank), "fast")
    return _least_chi2(problem, drawn, keep)


def _least_chi2(problem: _Problem, points: list[np.ndarray], keep: int,
                accuracy: str | None = None) -> list[np.ndarray]:
    """The ``keep`` points of least chi-square, the steady engine at ``accuracy``."""
    chi2 = [float(r @ r) for r in (problem.residuals(u, accuracy=accuracy) for u in points)]
    return [points[k] for k in np.argsort(chi2)[:keep]]


def _starts(problem: _Problem, count: int, seed: int) -> list[np.ndarray]:
    """The file's start, then the ``count - 1`` points of least chi-square among
    :data:`SCREEN_PER_PARAMETER` per parameter drawn in the box (a model with a dead zone
    has plateaus and steps that hold a start far from the data), scaled."""
    first = problem.scaled([p.start for p in problem.meas.parameters])
    if count <= 1:
        return [first]
    rng = np.random.default_rng(seed)
    drawn = _draw(problem, SCREEN_PER_PARAMETER * len(problem.meas.parameters), rng)
    chi2 = [float(r @ r) for r in map(problem.residuals, drawn)]
    return [first, *(drawn[k] for k in np.argsort(chi2)[:count - 1])]


def _put(u: np.ndarray, cols: list[int], v: np.ndarray) -> np.ndarray:
    """A copy of the scaled parameters ``u`` with those ``cols`` names set to ``v``."""
    out = np.array(u, dtype=float)
    out[cols] = v
    return out


def _prefit(problem: _Problem, u0: np.ndarray) -> np.ndarray:
    """``u0`` with the parameters outside :data:`FRICTION` fitted to the data sets other
    than speeds (free amplitudes, admittance: microseconds an evaluation), the friction
    parameters held; ``u0`` itself where there are no such parameters or sets."""
    sets = [s for s in problem.meas.sets if s.kind not in STEADY_KINDS]
    smooth = [i for i, p in enumerate(problem.meas.parameters) if p.name not in FRICTION]
    if not sets or not smooth:
        return u0

    def fun(v: np.ndarray) -> np.ndarray:
        return problem.residuals(_put(u0, smooth, v), sets)

    return _put(u0, smooth, _solve(fun, u0[smooth], MAX_NFEV).x)


def _screened_fits(problem: _Problem, count: int, seed: int,
                   say: Callable[[str], None]) -> list:
    """Local fits from the ``count`` best points of the friction screen
    (:func:`_friction_screen`) about the file's start, its smooth parameters first fitted
    to the data other than speeds (:func:`_prefit`): with speed data a start off the dead
    zone's valley stops on its steps, so random starts in the whole box spend their
    evaluations (a few hundred each) on local minima."""
    u0 = _prefit(problem, problem.scaled([p.start for p in problem.meas.parameters]))
    say("friction screen")
    fits = []
    dof = sum(s.points for s in problem.meas.sets) - u0.size
    for k, u in enumerate(_friction_screen(problem, u0, seed, count), start=1):
        say(f"local fit {k} of {count}, from the screen")
        fit = _solve(problem.residuals, u, MAX_NFEV, SCREEN_FTOL)
        fits.append((u, fit))
        if dof > 0 and 2.0 * fit.cost <= dof + ACCEPT_SIGMAS * math.sqrt(2.0 * dof):
            break  # the data are followed: the next screen points would end in this valley
    return fits


def _solve(fun: Callable, u0: np.ndarray, nfev: int, ftol: float = TOLERANCE):
    """:func:`scipy.optimize.least_squares` on [0, 1] with the module's settings."""
    return least_squares(fun, np.clip(u0, 0.0, 1.0), bounds=(0.0, 1.0), method="trf",
                         diff_step=DIFF_STEP, x_scale=1.0, max_nfev=nfev, ftol=ftol,
                         xtol=TOLERANCE)


def _jacobian(problem: _Problem, u: np.ndarray, r: np.ndarray, cols, sign: int = 1
              ) -> np.ndarray:
    """One-sided finite-difference Jacobian of the residuals at ``u`` (where they are ``r``)
    in the scaled parameters ``cols`` (the others' columns zero): one model evaluation a
    column, the step :data:`DIFF_STEP` towards ``sign``, turned round where it would leave
    the box."""
    jac = np.zeros((r.size, u.size))
    for k in cols:
        h = sign * DIFF_STEP
        h = h if 0.0 <= u[k] + h <= 1.0 else -h
        up = np.array(u, dtype=float)
        up[k] += h
        jac[:, k] = (problem.residuals(up) - r) / h
    return jac


def _two_sided_jacobian(problem: _Problem, u: np.ndarray, r: np.ndarray,
                        ahead: np.ndarray) -> np.ndarray:
    """The Jacobian at the optimum from forward differences (``ahead``, the fit's own) and
    from backward ones, each column the one of lesser norm. A speed that reaches another
    steady state within one side's step (a cliff of chi-square beside the optimum, as the
    example's seeds 27 and 28 have) makes that side's column, and the standard error it
    gives, meaningless: on seed 27 it put ``C_b``'s at 1.5e-4 N s/m."""
    back = _jacobian(problem, u, r, range(u.size), -1)
    lesser = np.linalg.norm(ahead, axis=0) <= np.linalg.norm(back, axis=0)
    return np.where(lesser, ahead, back)


def _refit(problem: _Problem, i: int, ui: float, path: list[tuple[np.ndarray, np.ndarray]],
           jac: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The other parameters re-fitted with scaled parameter ``i`` held at ``ui``, from the
    profile's last re-fitted point (``path``: points ``(u, residuals)`` from the optimum
    out) or its straight-line extension through the point before, whichever has the lesser
    chi-square; a bounded trust-region fit of at most :data:`REFIT_NFEV` evaluations on
    ``jac``, the Jacobian at the last point. Returns the point and its residuals."""
    others = [k for k in range(path[-1][0].size) if k != i]
    last, memo = path[-1][0], {}

    def at(v: np.ndarray) -> np.ndarray:
        return _put(_put(last, [i], ui), others, v)

    def fun(v: np.ndarray) -> np.ndarray:
        key = np.asarray(v, dtype=float).tobytes()
        if key not in memo:
            memo[key] = problem.residuals(at(v))
        return memo[key]

    starts = [last[others]]
    if len(path) > 1 and path[-2][0][i] != last[i]:
        before = path[-2][0]
        slope = (last[others] - before[others]) / (last[i] - before[i])
        starts.append(np.clip(last[others] + slope * (ui - last[i]), 0.0, 1.0))
    start = min(starts, key=lambda v: float(fun(v) @ fun(v)))
    if not others:
        return at(start), fun(start)
    fixed = jac[:, others]
    fit = least_squares(fun, start, jac=lambda _v: fixed, bounds=(0.0, 1.0), method="trf",
                        x_scale=1.0, max_nfev=REFIT_NFEV, ftol=REFIT_FTOL, xtol=TOLERANCE)
    return at(fit.x), fun(fit.x)


def _rescue(problem: _Problem, i: int, u: np.ndarray, r: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray]:
    """A profile step whose re-fit rose past a cliff (a speed that reached another steady
    state from rest): a small friction screen about ``u``, parameter ``i`` kept, and a
    re-fit of the others from its best point; that, or ``(u, r)`` where it is no lower. The
    continuation follows one stretch of the friction law's valley, and the cliffs cut it into
    stretches that another part of the valley can go round."""
    found = _friction_screen(problem, u, 0, 1, RESCUE_LOG2, RESCUE_RERANK, fixed=i)
    if not found:
        return u, r
    others = [k for k in range(u.size) if k != i]

    def fun(v: np.ndarray) -> np.ndarray:
        return problem.residuals(_put(found[0], others, v))

    fit = _solve(fun, found[0][others], REFIT_NFEV, REFIT_FTOL)
    if 2.0 * float(fit.cost) >= float(r @ r):
        return u, r
    return _put(found[0], others, fit.x), fit.fun


def _profile_side(problem: _Problem, i: int, best, step: float, sign: int
                  ) -> tuple[list[tuple[float, float]], float, bool]:
    """One side of a profile, traced by continuation: points ``(u_i, delta chi2)`` at
    :data:`PROFILE_STEPS` times ``step`` and then the bound, each re-fitted from the last
    (:func:`_refit`, the Jacobian taken afresh at each point), stopping past
    :data:`DELTA_CHI2_95`, from ``best`` (the optimum's scipy result); returns the points,
    the scaled interval end and whether the profile reached the bound below 3.84."""
    bound = 1.0 if sign > 0 else 0.0
    u_best, jac, chi2 = best.x, best.jac, 2.0 * float(best.cost)
    others = [k for k in range(u_best.size) if k != i]
    path = [(np.array(u_best, dtype=float), best.fun)]
    points = [(float(u_best[i]), 0.0)]
    for t in [u_best[i] + sign * step * k for k in PROFILE_STEPS] + [bound]:
        t = min(t, 1.0) if sign > 0 else max(t, 0.0)
        if abs(t - points[-1][0]) < 1e-12:
            continue
        if len(path) > 1:
            jac = _jacobian(problem, *path[-1], others)
        u, r = _refit(problem, i, t, path, jac)
        if float(r @ r) - chi2 - points[-1][1] > DELTA_CHI2_95:
            u, r = _rescue(problem, i, u, r)
        path.append((u, r))
        points.append((float(t), float(r @ r) - chi2))
        if points[-1][1] >= DELTA_CHI2_95:
            (u0, d0), (u1, d1) = points[-2], points[-1]
            end = u0 + (DELTA_CHI2_95 - d0) * (u1 - u0) / (d1 - d0) if d1 != d0 else u1
            return points, float(end), False
        if t == bound:
            break
    return points, bound, True


def _profile(problem: _Problem, i: int, best, se_u: float) -> Profile:
    """The profile likelihood of parameter ``i`` (module docstring) about ``best``, the
    optimum's scipy result."""
    step = se_u if math.isfinite(se_u) and se_u > 1e-6 else 0.05
    step = min(step, 0.25)
    lo_pts, lo_end, lo_open = _profile_side(problem, i, best, step, -1)
    hi_pts, hi_end, hi_open = _profile_side(problem, i, best, step, +1)
    pts = sorted(set(lo_pts) | set(hi_pts))
    u = np.array([p[0] for p in pts])
    return Profile(problem.value(i, u), np.array([p[1] for p in pts]),
                   float(problem.value(i, lo_end)), float(problem.value(i, hi_end)),
                   lo_open, hi_open)


def _identifiability(names: tuple[str, ...], blind: list[list[int]], corr: np.ndarray,
                     profiles: dict[str, Profile]) -> tuple[tuple[bool, ...], tuple[str, ...]]:
    """Whether each parameter is identifiable and, if not, why (module docstring)."""
    ok, why = [], []
    for i, name in enumerate(names):
        reason = ""
        if blind[i] == [i]:
            reason = "the data do not depend on it"
        elif blind[i]:
            reason = ("the data fix only a combination of "
                      f"{', '.join(names[j] for j in blind[i])}")
        elif name in profiles and profiles[name].flat:
            reason = "its profile stays within 3.84 of the optimum between its bounds"
        else:
            row = np.where(np.arange(len(names)) == i, 0.0, np.abs(corr[i]))
            j = int(np.nanargmax(row)) if np.any(np.isfinite(row)) and row.size > 1 else -1
            if j >= 0 and row[j] > MAX_CORRELATION:
                reason = f"correlation {corr[i, j]:+.3f} with {names[j]}"
        ok.append(not reason)
        why.append(reason)
    return tuple(ok), tuple(why)


def calibrate(meas: Measurements, base: MotorParams, *, coupling: str = "consistent",
              accuracy: str = "exact", starts: int = 3, seed: int = 0,
              profile: tuple[str, ...] | None = None, screen: bool = True,
              progress: Callable[[str], None] | None = None,
              workers: int | None = None) -> CalibrationResult:
    """Fit the measurement file's parameters to its data (module docstring).

    Parameters
    ----------
    meas : Measurements
        The data and the parameters to fit (:func:`calibration.load_measurements`).
    base : MotorParams
        The start set: every constant not fitted keeps its value; ``A_l_scale`` and
        ``A_b_scale`` multiply its force factors.
    coupling : {"paper", "consistent"}
        Tangential coupling of the steady engine (the one the calibrated set is to be run
        with afterwards).
    accuracy : {"exact", "fast"}
        Level of the steady engine.
    starts : int
        Number of starts (the file's, then ``starts - 1`` drawn with ``seed``), >= 1; with
        the screen, the local fits from its ``max(1, starts - 1)`` best points instead.
    profile : tuple of str, optional
        Parameters whose profile likelihood is traced; default all (those the data see and
        can tell apart: a parameter not identifiable by its Jacobian or its correlations
        gets none).
    screen : bool
        Whether, with speed data and a fitted friction parameter, the local fits start from
        a Sobol screen of the friction parameters (:func:`_screened_fits`) instead of the
        file's start and random points.
    progress : callable, optional
        Called with a short line as each stage starts.
    workers : int, optional
        Processes for the steady rows of a large speed or power set (default every CPU;
        1: all in this process). See :func:`calibration.model.row_pool`.

    Returns
    -------
    CalibrationResult
    """
    t0 = time.perf_counter()
    say = progress or (lambda _text: None)
    check_box(meas, base)
    with row_pool(meas.sets, workers) as pool:
        problem = _Problem(meas, base, coupling, accuracy, None, pool)
        fits = _fits(problem, starts, seed, screen, say)
        return _result(problem, fits, profile, say, t0)


def _fits(problem: _Problem, starts: int, seed: int, screen: bool,
          say: Callable[[str], None]) -> list:
    """The local fits, ``(start, scipy result)`` each: from the friction screen
    (:func:`_screened_fits`) with speed data and a fitted friction parameter, else from the
    file's start and random points (:func:`_starts`)."""
    meas = problem.meas
    friction = any(p.name in FRICTION for p in meas.parameters)
    if screen and friction and any(s.kind in STEADY_KINDS for s in meas.sets):
        return _screened_fits(problem, max(1, starts - 1), seed, say)
    fits = []
    for k, u0 in enumerate(_starts(problem, max(1, starts), seed), start=1):
        say(f"start {k} of {max(1, starts)}")
        fits.append((u0, _solve(problem.residuals, u0, MAX_NFEV)))
    return fits


def _result(problem: _Problem, fits: list, profile: tuple[str, ...] | None,
            say: Callable[[str], None], t0: float, again: bool = True,
            spent_s: float = 0.0) -> CalibrationResult:
    """The calibration of the best of ``fits``: covariance, profiles, identifiability. Where
    a profile found a chi-square :data:`RECENTER_CHI2` below the optimum (``again``), the
    fit starts once more from there and the profiles are traced anew (``spent_s``: the
    profiles' time so far)."""
    meas = problem.meas
    names = tuple(p.name for p in meas.parameters)
    best = min(fits, key=lambda f: f[1].cost)[1]
    best.jac = _two_sided_jacobian(problem, best.x, best.fun, best.jac)
    chi2 = 2.0 * float(best.cost)
    slope = problem.slope(best.x)
    cov, blind = _covariance(best.jac, slope)
    alone = np.array([b == [i] for i, b in enumerate(blind)], dtype=bool)
    se = np.sqrt(np.where([bool(b) for b in blind], np.inf, np.diag(cov)))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(se, se)
    t_prof = time.perf_counter()
    profiles = _profiles(problem, best, se / slope, blind, corr, profile, say)
    profile_time = spent_s + time.perf_counter() - t_prof
    if again and problem.least[0] < chi2 - RECENTER_CHI2:
        say("fitting again from a lower chi-square a profile found")
        start = problem.least[1]
        fits = [*fits, (start, _solve(problem.residuals, start, MAX_NFEV, SCREEN_FTOL))]
        return _result(problem, fits, profile, say, t0, False, profile_time)
    ok, why = _identifiability(names, blind, corr, profiles)
    notes = _notes(profiles, problem, fits, best)
    # a parameter the data do not depend on keeps its start: the fit has no say in it
    u_best = np.where(alone, problem.scaled([p.start for p in meas.parameters]), best.x)
    params, c0 = problem.model(u_best)
    sampled = [i for i in range(len(names)) if ok[i]]
    held_cov = (_covariance(best.jac[:, sampled], slope[sampled])[0] if sampled
                else np.zeros((0, 0)))
    return CalibrationResult(
        parameters=meas.parameters, values=problem.values(u_best), stderr=se,
        correlation=corr, covariance=cov, identifiable=ok, reasons=why, profiles=profiles,
        chi2=chi2, points=sum(s.points for s in meas.sets),
        starts=tuple((problem.values(u0), problem.values(f.x), 2.0 * float(f.cost))
                     for u0, f in fits),
        params=params, c0_F=c0, predictions=tuple(problem.predictions(u_best)),
        coupling=problem.coupling, accuracy=problem.accuracy,
        evaluations=problem.evaluations,
        wall_time_s=time.perf_counter() - t0, profile_time_s=profile_time, notes=notes,
        held_covariance=held_cov)


def _profiles(problem: _Problem, best, se_u: np.ndarray, blind: list[list[int]],
              corr: np.ndarray, profile: tuple[str, ...] | None,
              say: Callable[[str], None]) -> dict[str, Profile]:
    """The profiles (``se_u``: the standard errors in scaled units) of the parameters
    ``profile`` names (all for None) that the Jacobian and the correlations leave
    identifiable: one the data do not see, or cannot tell from another, gets no interval,
    and its profile is not traced. Along the others' profiles it is re-fitted with the rest
    (:func:`_refit`): the profile of ``C_l`` on the example walks ``a_mu`` from 0 to 0.2
    along their valley."""
    names = tuple(p.name for p in problem.meas.parameters)
    seen, _ = _identifiability(names, blind, corr, {})
    out = {}
    for i, name in enumerate(names):
        if seen[i] and (profile is None or name in profile):
            say(f"profile of {name}")
            out[name] = _profile(problem, i, best, se_u[i])
    return out


def _notes(profiles: dict[str, Profile], problem: _Problem, fits, best) -> tuple[str, ...]:
    """Remarks on the fit: a profile that found a lower chi-square than the optimum (a fit
    that stopped short), starts that ended elsewhere."""
    out = []
    for name, prof in profiles.items():
        if prof.delta_chi2.min() < -0.1:
            out.append(f"the profile of {name} found a chi-square {-prof.delta_chi2.min():.3g} "
                       "below the optimum: the fit stopped short of the least chi-square; "
                       "more starts or a start nearer the data may help")
    others = [2.0 * f.cost for _, f in fits if 2.0 * (f.cost - best.cost) > 1.0]
    if others:
        out.append(f"{len(others)} of {len(fits)} starts ended at a higher chi-square "
                   f"(least {min(others):.4g} against {2.0 * best.cost:.4g}): local minima")
    points = best.fun.size
    dof = points - best.x.size
    if dof > 0 and 2.0 * best.cost > 2.0 * dof + 4.0 * math.sqrt(2.0 * dof):
        out.append(f"chi-square {2.0 * best.cost:.4g} is far above its {dof} degrees of "
                   "freedom: the fit does not follow the data within their standard "
                   "deviations (a local minimum: more starts; a model that cannot follow "
                   "them; or deviations given too small), so the uncertainties are too small")
    return tuple(out)


def base_values(meas: Measurements, base: MotorParams) -> dict[str, float | None]:
    """The start set's value of every fitted parameter (SI), for comparison."""
    return {p.name: base_value(base, p.name) for p in meas.parameters}
