"""Sweeps of one plate dimension: the L1/B2 crossing (veering) diagram.

Each point is one 2D FE modal solution (:func:`fem.modes.plate_modes`, cached); L1 and B2 are
identified by shape at every point, so their branches are followed through the crossing. L1
is mirror-symmetric and B2 mirror-antisymmetric about the plate's length axis: in a
symmetric plate they do not interact and the branches cross (a true crossing, not a
veering); any asymmetry (electrodes, tip) would turn it into a veering.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, replace

import numpy as np

from fem.frozen import freeze_arrays
from fem.geometry import PlateStator
from fem.limits import work_factor
from fem.material import PiezoMaterial, get_material
from fem.mesh_settings import MeshSettings

PARAMETERS = ("width", "length")
"""Dimensions that can be swept."""
MAX_SWEEP_VALUES = 2000
"""Values (FE solves) of one :func:`sweep_dimension` call, times ``LUSM_MAX_WORK`` (about
7 minutes of the default plate; ``lusm sweep`` allows 200)."""
PROGRESS_MIN_POINTS = 20
"""Sweeps with at least this many points show a tqdm progress bar (when ``progress``)."""


@dataclass(frozen=True, eq=False)
class SweepResult:
    """Frequencies of L1 and B2 along a sweep of one dimension.

    Attributes
    ----------
    parameter : str
        ``'width'`` or ``'length'``.
    values_m : numpy.ndarray
        Swept dimension (m).
    f_L1_short_Hz, f_B2_short_Hz, f_L1_open_Hz, f_B2_open_Hz : numpy.ndarray
        Identified frequencies (Hz), NaN where identification failed.
    spectrum_Hz : tuple of numpy.ndarray
        All short-circuit frequencies computed near the shift at each point (Hz).
    base : PlateStator
        The plate whose other dimensions were kept.
    material : str
    fe_solves : int
        Number of FE modal solutions.
    failures : tuple of str
        Why L1 and B2 were not identified at each point ('' where they were).
    """

    parameter: str
    values_m: np.ndarray
    f_L1_short_Hz: np.ndarray
    f_B2_short_Hz: np.ndarray
    f_L1_open_Hz: np.ndarray
    f_B2_open_Hz: np.ndarray
    spectrum_Hz: tuple
    base: PlateStator
    material: str
    fe_solves: int
    failures: tuple = ()

    def __post_init__(self) -> None:
        freeze_arrays(self)  # its own read-only arrays, not the caller's values_m

    def crossings_m(self) -> np.ndarray:
        """Values (m) where ``f_B2 - f_L1`` (short circuit) changes sign: the root of the
        cubic through the bracketing grid points and their neighbours where those exist,
        else of the line through the two (:meth:`crossing_estimates_m`)."""
        return np.array([best for best, _ in self.crossing_estimates_m()])

    def crossing_estimates_m(self) -> list[tuple[float, float]]:
        """``(value, uncertainty)`` (m) of each L1/B2 crossing on the grid.

        The value is the root of the cubic through up to four grid points around the sign
        change (the line through the two bracketing ones where no neighbour is finite), and
        the uncertainty the distance to the linear root (NaN with only the two bracketing
        points, where there is one estimate): a 4 mm grid put the crossing of a
        25 x 4 x 2 mm plate's length at 14.97 mm by the line, 0.21 mm from the bisected
        14.754 mm. ``lusm tune`` solves for the crossing itself.
        """
        d = self.f_B2_short_Hz - self.f_L1_short_Hz
        x = self.values_m
        ok = np.isfinite(d)
        out = []
        for i in range(d.size - 1):
            if d[i] == 0.0:
                out.append((float(x[i]), 0.0))
                continue
            if not (ok[i] and ok[i + 1] and d[i] * d[i + 1] < 0):
                continue
            linear = x[i] - d[i] * (x[i + 1] - x[i]) / (d[i + 1] - d[i])
            idx = [j for j in (i - 1, i, i + 1, i + 2) if 0 <= j < d.size and ok[j]]
            best = linear
            if len(idx) > 2:
                # scaled to [-1, 1] on the bracket: a well-conditioned polynomial fit
                mid, half = 0.5 * (x[i] + x[i + 1]), 0.5 * (x[i + 1] - x[i])
                poly = np.polynomial.Polynomial.fit(x[idx], d[idx], len(idx) - 1,
                                                    domain=[mid - half, mid + half])
                roots = [r.real for r in poly.roots() if abs(r.imag) < 1e-12 * half
                         and x[i] <= r.real <= x[i + 1]]
                if len(roots) == 1:
                    best = roots[0]
            # two points give one line: no second estimate, no uncertainty (NaN)
            err = abs(best - linear) if len(idx) > 2 else math.nan
            out.append((float(best), float(err)))
        return out

    def to_dict(self) -> dict[str, object]:
        """JSON-ready dictionary (mm and Hz)."""
        crossings = self.crossing_estimates_m()
        return {
            "parameter": self.parameter,
            "values_mm": (self.values_m * 1e3).tolist(),
            "f_L1_short_Hz": _nan_to_none(self.f_L1_short_Hz),
            "f_B2_short_Hz": _nan_to_none(self.f_B2_short_Hz),
            "f_L1_open_Hz": _nan_to_none(self.f_L1_open_Hz),
            "f_B2_open_Hz": _nan_to_none(self.f_B2_open_Hz),
            "crossings_mm": [x * 1e3 for x, _ in crossings],
            "crossing_uncertainties_mm": [u * 1e3 if math.isfinite(u) else None
                                          for _, u in crossings],
            "fe_solves": self.fe_solves,
            "material": self.material,
            "failures": [f or None for f in self.failures],
        }


def _nan_to_none(a: np.ndarray) -> list:
    return [None if not np.isfinite(v) else float(v) for v in a]


def _sweep_values(values_m) -> np.ndarray:
    """The swept values (m) as a 1D float array: numbers, at least one, at most
    :data:`MAX_SWEEP_VALUES` times ``LUSM_MAX_WORK``."""
    raw = np.atleast_1d(np.asarray(values_m, dtype=object))
    # numbers only: "7e-3" is text, and True would make a 1 m plate (alone or beside numbers)
    if not all(isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))
               for v in raw.ravel()):
        raise ValueError(f"values_m must be numbers (m), got {values_m!r}"[:300])
    values = raw.astype(float)
    if values.size == 0 or values.ndim != 1:
        raise ValueError("values_m must be a non-empty 1D sequence")
    top = MAX_SWEEP_VALUES * work_factor()
    if values.size > top:  # each is an FE solve (200 000 would take hours)
        raise ValueError(f"values_m has {values.size} values (FE solves), above the limit "
                         f"{top:.0f} of a library call (set LUSM_MAX_WORK=N to allow N times "
                         "more)")
    return values


def sweep_dimension(
    parameter: str,
    values_m: np.ndarray,
    base: PlateStator | None = None,
    material: PiezoMaterial | str = "pzt8",
    mesh: MeshSettings | None = None,
    progress: bool = False,
) -> SweepResult:
    """L1 and B2 frequencies while one dimension of ``base`` varies.

    Parameters
    ----------
    parameter : str
        ``'width'`` or ``'length'``.
    values_m : array_like
        Values of the dimension (m), each > 0.
    base : PlateStator, optional
        Default: the paper's plate.
    material : PiezoMaterial or str
    mesh : MeshSettings, optional
        The 2D mesh of every plate (:func:`fem.modes.plate_modes`); default
        :class:`fem.mesh_settings.MeshSettings`.
    progress : bool
        Show a tqdm progress bar (on stderr) for sweeps of at least
        :data:`PROGRESS_MIN_POINTS` points.

    Raises
    ------
    ValueError
        On an unknown parameter, an empty sweep or a value that makes an invalid plate.
    """
    from fem.modes import ModeSolverError, plate_modes

    if parameter not in PARAMETERS:
        raise ValueError(f"parameter must be one of {', '.join(PARAMETERS)}, got {parameter!r}")

    values = _sweep_values(values_m)
    base = PlateStator() if base is None else base
    mat = get_material(material)
    stators = [replace(base, **{f"{parameter}_m": float(v)}) for v in values]  # validates
    it = stators
    if progress and len(stators) >= PROGRESS_MIN_POINTS:
        from tqdm import tqdm

        it = tqdm(stators, desc=f"sweep {parameter}", unit="solve")
    rows = np.full((values.size, 4), np.nan)
    spectra = []
    failures = [""] * values.size
    for i, st in enumerate(it):
        try:
            res = plate_modes(st, mat, mesh)
        except ModeSolverError as exc:
            spectra.append(np.array([]))
            failures[i] = str(exc)
            continue
        rows[i] = (res.L1.f_short_Hz, res.B2.f_short_Hz, res.L1.f_open_Hz, res.B2.f_open_Hz)
        spectra.append(np.asarray(res.frequencies_short_Hz))
    return SweepResult(
        parameter=parameter,
        values_m=values,
        f_L1_short_Hz=rows[:, 0],
        f_B2_short_Hz=rows[:, 1],
        f_L1_open_Hz=rows[:, 2],
        f_B2_open_Hz=rows[:, 3],
        spectrum_Hz=tuple(spectra),
        base=base,
        material=mat.name,
        fe_solves=values.size,
        failures=tuple(failures),
    )
