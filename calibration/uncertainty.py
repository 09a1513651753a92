"""A calibration's parameter uncertainty, stored in the calibrated file and carried to any
prediction by Monte Carlo.

The calibrated file holds the fit in machine-readable form beside its comments: a stator
file's ``[calibration]`` table, a parameter file's ``"calibration"`` object, with

* ``names``, ``values`` (SI), ``stderr`` (SI; ``inf`` where the data see no direction of
  the parameter), ``identifiable`` and ``reasons`` of every fitted parameter;
* ``covariance`` (SI): of the identifiable parameters only, in their order, with the others
  held at their values (the inverse of the Fisher information restricted to them, i.e. the
  covariance conditional on the held values);
* ``chi2``, ``dof``, ``points``, ``coupling`` of the fit.

:func:`propagate` draws parameter sets from the normal distribution of the identifiable
parameters (seeded; a draw that leaves the set invalid, e.g. ``a_mu > mu_d``, is drawn again),
holds the others at their values, maps a callable over the sets and gives per output value
the mean, standard deviation and 2.5 / 97.5 % quantiles (:class:`Band`). A normal
distribution is the fit's own (linearised) picture of its uncertainty; the Monte Carlo
carries it through a model that is not linear in the parameters (the dead zone's threshold)
without a derivative of that model.
"""

from __future__ import annotations

import math
import tomllib
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from calibration.parameters import PARAMETERS, apply
from rom.params import MotorParams

DEFAULT_SAMPLES = 64
"""Monte Carlo draws of ``--uncertainty`` without a number: the standard deviation to about
9 % (``1 / sqrt(2 (N - 1))``), the 2.5 / 97.5 % quantiles to about 1.5 standard deviations'
worth of draws each side."""
MAX_DRAWS_PER_SAMPLE = 10
"""Most draws per wanted sample before :func:`propagate` gives up on invalid sets."""
TABLE = "calibration"
"""Name of the table (stator file) or key (parameter file) that carries the fit."""
KEYS = ("names", "values", "stderr", "identifiable", "reasons", "covariance", "chi2", "dof",
        "points", "coupling")
"""Keys of the table, in the order written."""
SCALES = ("A_l_scale", "A_b_scale")
"""Parameters that multiply a force factor of the set they are applied to."""


class CalibrationFileError(ValueError):
    """A ``[calibration]`` table that cannot be read (its message names the key)."""


@dataclass(frozen=True)
class Calibration:
    """The stored fit of a calibrated file (module docstring).

    Attributes
    ----------
    names : tuple of str
        Fitted parameters (keys of :data:`calibration.parameters.PARAMETERS`).
    values, stderr : ndarray
        Fitted values and standard errors (SI), in the order of ``names``.
    identifiable : tuple of bool
    reasons : tuple of str
        Why a parameter is not identifiable ('' where it is).
    covariance : ndarray
        Covariance (SI) of the identifiable parameters, the others held.
    chi2 : float or None
    dof, points : int or None
    coupling : str or None
        The steady engine's coupling the fit ran with.
    """

    names: tuple[str, ...]
    values: np.ndarray
    stderr: np.ndarray
    identifiable: tuple[bool, ...]
    reasons: tuple[str, ...]
    covariance: np.ndarray
    chi2: float | None = None
    dof: int | None = None
    points: int | None = None
    coupling: str | None = None

    @property
    def sampled(self) -> tuple[str, ...]:
        """The identifiable parameters: those a Monte Carlo draws."""
        return tuple(n for n, ok in zip(self.names, self.identifiable, strict=True) if ok)

    @property
    def held(self) -> tuple[str, ...]:
        """The parameters held at their values (not identifiable)."""
        return tuple(n for n, ok in zip(self.names, self.identifiable, strict=True) if not ok)

    def to_table(self, json_ready: bool = False) -> dict:
        """The table as written (``json_ready``: non-finite numbers as None, which JSON
        lacks; TOML writes ``inf``)."""
        def num(x: float) -> float | None:
            return None if json_ready and not math.isfinite(x) else float(x)

        return {"names": list(self.names), "values": [float(v) for v in self.values],
                "stderr": [num(s) for s in self.stderr],
                "identifiable": list(self.identifiable), "reasons": list(self.reasons),
                "covariance": [[float(c) for c in row] for row in self.covariance],
                "chi2": self.chi2, "dof": self.dof, "points": self.points,
                "coupling": self.coupling}


def of_result(result) -> Calibration:
    """The :class:`Calibration` of a :class:`calibration.fit.CalibrationResult`."""
    return Calibration(
        names=result.names, values=np.asarray(result.values, dtype=float),
        stderr=np.asarray(result.stderr, dtype=float), identifiable=result.identifiable,
        reasons=result.reasons, covariance=np.asarray(result.held_covariance, dtype=float),
        chi2=float(result.chi2), dof=int(result.dof), points=int(result.points),
        coupling=result.coupling)


def _numbers(table: dict, key: str, n: int, src: str) -> np.ndarray:
    """``table[key]``: ``n`` numbers (None read as inf), else :class:`CalibrationFileError`."""
    v = table.get(key)
    if not isinstance(v, list) or len(v) != n or not all(
            x is None or (isinstance(x, int | float) and not isinstance(x, bool)) for x in v):
        raise CalibrationFileError(f"{src}: [{TABLE}] {key} must be a list of {n} numbers")
    return np.array([math.inf if x is None else float(x) for x in v])


def from_table(table: object, src: str) -> Calibration:
    """The :class:`Calibration` of a stored table (:meth:`Calibration.to_table`).

    Raises
    ------
    CalibrationFileError
        A missing or malformed key, named; a covariance that is not symmetric positive
        semi-definite.
    """
    if not isinstance(table, dict):
        raise CalibrationFileError(f"{src}: {TABLE} must be a table")
    unknown = sorted(set(table) - set(KEYS))
    if unknown:
        raise CalibrationFileError(f"{src}: unknown key {unknown[0]!r} in [{TABLE}]; allowed: "
                                   f"{', '.join(KEYS)}")
    names = table.get("names")
    if (not isinstance(names, list) or not names
            or not all(isinstance(n, str) and n in PARAMETERS for n in names)):
        raise CalibrationFileError(f"{src}: [{TABLE}] names must list fitted parameters "
                                   f"({', '.join(PARAMETERS)})")
    n = len(names)
    ok = table.get("identifiable")
    if not isinstance(ok, list) or len(ok) != n or not all(isinstance(b, bool) for b in ok):
        raise CalibrationFileError(f"{src}: [{TABLE}] identifiable must be {n} true/false")
    m = sum(ok)
    cov = table.get("covariance")
    if not isinstance(cov, list) or len(cov) != m:
        raise CalibrationFileError(f"{src}: [{TABLE}] covariance must be {m} rows of {m} "
                                   "numbers (the identifiable parameters)")
    rows = np.array([_numbers({"covariance": r}, "covariance", m, src) for r in cov]
                    ).reshape(m, m)
    if m and (not np.all(np.isfinite(rows)) or not np.allclose(rows, rows.T, rtol=1e-9)
              or np.linalg.eigvalsh(rows).min() < -1e-9 * max(np.abs(rows).max(), 1e-300)):
        raise CalibrationFileError(f"{src}: [{TABLE}] covariance must be symmetric and "
                                   "positive semi-definite")
    reasons = table.get("reasons", [""] * n)
    if not isinstance(reasons, list) or len(reasons) != n:
        raise CalibrationFileError(f"{src}: [{TABLE}] reasons must be {n} strings")
    return Calibration(
        names=tuple(names), values=_numbers(table, "values", n, src),
        stderr=_numbers(table, "stderr", n, src), identifiable=tuple(ok),
        reasons=tuple(str(r or "") for r in reasons), covariance=rows,
        chi2=table.get("chi2"), dof=table.get("dof"), points=table.get("points"),
        coupling=table.get("coupling"))


def read_calibration(path: str | Path) -> Calibration | None:
    """The stored fit of a calibrated stator file (``.toml``) or parameter file (``.json``);
    None when the file has none.

    Raises
    ------
    CalibrationFileError
        A table that cannot be read.
    OSError, ValueError
        A file that cannot be read or parsed.
    """
    import json

    path = Path(path)
    text = path.read_text(encoding="utf-8")
    data = json.loads(text) if path.suffix.lower() == ".json" else tomllib.loads(text)
    if not isinstance(data, dict) or TABLE not in data:
        return None
    return from_table(data[TABLE], str(path))


def perturbed(params: MotorParams, cal: Calibration, sample: dict[str, float]) -> MotorParams:
    """``params`` (the calibrated set) with the sampled values ``sample`` (name -> SI) put
    in: a force-factor scale as its ratio to the fitted one (the set carries the fitted
    scale already), every other parameter as its value.

    Raises
    ------
    ValueError
        If the sample leaves the set invalid.
    """
    fitted = dict(zip(cal.names, cal.values, strict=True))
    given = {n: (v / fitted[n] if n in SCALES else v) for n, v in sample.items()}
    return apply(params, given)


def draw(cal: Calibration, params: MotorParams, samples: int,
         seed: int = 0) -> tuple[list[MotorParams], int]:
    """``samples`` valid parameter sets drawn about ``params`` (module docstring), and how
    many draws were refused as invalid sets.

    Raises
    ------
    ValueError
        If fewer than ``samples`` of :data:`MAX_DRAWS_PER_SAMPLE` times as many draws are
        valid (the covariance reaches far outside the valid region).
    """
    names = cal.sampled
    mean = np.array([v for v, ok in zip(cal.values, cal.identifiable, strict=True) if ok])
    rng = np.random.default_rng(seed)
    out: list[MotorParams] = []
    refused = 0
    while len(out) < samples:
        if refused > MAX_DRAWS_PER_SAMPLE * samples:
            raise ValueError(f"only {len(out)} of {len(out) + refused} parameter sets drawn "
                             "from the calibration's covariance are valid")
        x = rng.multivariate_normal(mean, cal.covariance, method="eigh") if names else mean
        try:
            out.append(perturbed(params, cal, dict(zip(names, x, strict=True))))
        except ValueError:
            refused += 1
    return out, refused


@dataclass(frozen=True)
class Band:
    """A prediction's spread over the Monte Carlo draws.

    Attributes
    ----------
    values : ndarray
        The prediction of every draw, shape ``(samples, *shape)``; NaN where a draw has none
        (a slider that runs away).
    sampled, held : tuple of str
        Parameters drawn and parameters held at their values.
    refused : int
        Draws refused as invalid sets (and drawn again).
    seed : int
    """

    values: np.ndarray
    sampled: tuple[str, ...]
    held: tuple[str, ...]
    refused: int
    seed: int

    def part(self, index) -> Band:
        """The band of the output values ``values[:, index]``."""
        return Band(self.values[:, index], self.sampled, self.held, self.refused, self.seed)

    @property
    def samples(self) -> int:
        """Number of draws."""
        return int(self.values.shape[0])

    def _stat(self, fn: Callable) -> np.ndarray:
        """``fn`` over the draws, those without a value left out (NaN where none has one)."""
        x = np.where(np.isfinite(self.values), self.values, np.nan)
        with warnings.catch_warnings():  # a point no draw reaches: NaN, said by `missing`
            warnings.simplefilter("ignore", RuntimeWarning)
            return np.asarray(fn(x))

    @property
    def mean(self) -> np.ndarray:
        """Mean over the draws with a value."""
        return self._stat(lambda x: np.nanmean(x, axis=0))

    @property
    def std(self) -> np.ndarray:
        """Sample standard deviation over the draws with a value (ddof 1)."""
        return self._stat(lambda x: np.nanstd(x, axis=0, ddof=1))

    @property
    def low(self) -> np.ndarray:
        """2.5 % quantile."""
        return self._stat(lambda x: np.nanquantile(x, 0.025, axis=0))

    @property
    def high(self) -> np.ndarray:
        """97.5 % quantile."""
        return self._stat(lambda x: np.nanquantile(x, 0.975, axis=0))

    @property
    def missing(self) -> np.ndarray:
        """Draws without a value, per output value."""
        return (~np.isfinite(self.values)).sum(axis=0)

    def summary(self) -> dict:
        """JSON-ready: ``mean``, ``std``, ``q2.5``, ``q97.5`` (scalars or nested lists, NaN
        as None) and ``missing`` (draws without a value)."""
        def clean(a: np.ndarray):
            a = np.asarray(a, dtype=float)
            if a.ndim == 0:
                return float(a) if math.isfinite(a) else None
            return [clean(x) for x in a]

        return {"mean": clean(self.mean), "std": clean(self.std), "q2.5": clean(self.low),
                "q97.5": clean(self.high), "missing": np.asarray(self.missing).tolist()}

    def header(self) -> dict:
        """JSON-ready: how the band was drawn."""
        return {"samples": self.samples, "seed": self.seed, "sampled": list(self.sampled),
                "held": list(self.held), "refused_draws": self.refused}


def propagate(cal: Calibration, params: MotorParams, fn: Callable[[MotorParams], object],
              samples: int = DEFAULT_SAMPLES, seed: int = 0,
              progress: Callable[[int, int], None] | None = None) -> Band:
    """The spread of ``fn`` (a parameter set -> a number or an array of fixed shape) over
    ``samples`` sets drawn from the calibration (module docstring).

    Parameters
    ----------
    cal : Calibration
        The stored fit (:func:`read_calibration`).
    params : MotorParams
        The calibrated set (the file's), about which the draws are made.
    fn : callable
        The prediction; NaN where a set has none.
    samples : int
        Draws, >= 2.
    seed : int
        Seed of the draws.
    progress : callable, optional
        Called with (draws done, draws) after each.

    Returns
    -------
    Band
    """
    sets, refused = draw(cal, params, samples, seed)
    values = []
    for k, p in enumerate(sets, start=1):
        values.append(np.asarray(fn(p), dtype=float))
        if progress is not None:
            progress(k, samples)
    return Band(np.array(values), cal.sampled, cal.held, refused, seed)
