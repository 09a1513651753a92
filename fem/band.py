r"""Every natural mode of the plate in a frequency band, named by its shape.

One entry point, :func:`band_modes`, for the 2D plate model (:mod:`fem.model`) and the 3D
solid (:mod:`fem.solid3d.model`): the short-circuit modes in ``[f_min, f_max]``, each with its
open-circuit partner, its ``k_eff`` and a name where the shape says it, and a flag on every
mode other than the operating pair (L1, B2) within ``risk_pct`` of the pair's frequencies: a
mode the drive can excite beside the ones it is meant to.

Completeness
------------
The band is solved by shift-invert at the middle of the band in ``omega^2``, so the
eigenvalues nearest the shift are exactly those in the band. The solve asks for a few more
modes than the band holds and is complete when the farthest mode computed lies outside the
band (then every eigenvalue nearer the shift, the whole band, is among those computed). The
number of modes in the band is also counted independently by Sylvester's law of inertia: the
count of eigenvalues below ``(2 pi f)^2`` is the number of negative pivots of an ``L D L^T``
factorization of ``K - (2 pi f)^2 M`` (:func:`fem.admittance.modes_below`); for the 3D model
the free potentials make the matrix a saddle point ``[[K_uu - s M, K_uphi], [K_uphi^T,
-K_phiphi]]``, whose inertia is that of ``-K_phiphi`` (all negative) plus that of the
condensed stiffness ``K_uu - s M + K_uphi K_phiphi^-1 K_uphi^T`` (Haynsworth), so the
count is the negative pivots less the free potentials. Where both counts exist they must
agree, or the solve is repeated with more modes.

Names
-----
Each short-circuit shape is sampled on the grid of :mod:`fem.modes` (mid-plane, and just
inside the top and bottom faces in 3D) and sorted by its symmetry classes:

* through the thickness (3D): in-plane (``u_x, u_y`` even in z, ``u_z`` odd) or out-of-plane;
* about the length axis ``x = 0``: in-plane modes mirror-symmetric (``u_y`` even, ``u_x`` odd:
  longitudinal ``Ln``) or antisymmetric (in-plane bending ``Bn``); out-of-plane modes with
  ``u_z`` even in x (out-of-plane bending ``OBn``) or odd (torsion ``Tn``);

with at least :data:`MIN_CLASS` of the sampled energy in the class. The order ``n`` is the
node count along the centre line (``Ln``: n nodes of ``u_y``; ``Bn``, ``OBn``: n + 1 nodes of
the free-free beam's n-th bending mode; ``Tn``: n nodes of the twist), and the name is given
when the shape correlates (MAC >= :data:`fem.modes.MIN_MAC`) with that beam mode
(``cos(n pi y / l)``, the free-free bending shape of :func:`bending_shape`). A name is given
once, to the best correlated mode; every other mode is ``"other"`` (width modes, plate modes,
modes mixed across classes).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from fem.beam_shapes import free_free_root
from fem.limits import work_factor
from fem.modes import (
    MIN_MAC,
    PAIR_MAC,
    ModeSolverError,
    best_shape_match,
    modal_assurance,
    sign_changes,
    symmetric_fraction,
)

MIN_CLASS = 0.9
"""Least share of a mode's sampled energy in a symmetry class for it to be named by it (-)."""

RISK_PCT = 5.0
"""Default risk window: a mode within this many per cent of an operating mode's frequency."""

BAND_HALF_WIDTH = 0.2
"""Default band: the operating pair's frequencies minus / plus this share (-)."""

OPEN_REACH = 1.2
"""The open-circuit solve reaches this factor above the band's top: a mode's open-circuit
frequency is ``1 / sqrt(1 - k_eff^2)`` above its short-circuit one (1.155 at k_eff 0.5)."""

SPARE_MODES = 4
"""Modes asked for beyond those the band is known (or guessed) to hold."""

MAX_BAND_MODES = 400
"""Most modes one band solve computes, times ``LUSM_MAX_WORK``: a band reaching the top of a
fine mesh's spectrum holds thousands, and ARPACK's work grows as the square of their
number."""

FAMILIES = {"L": "longitudinal", "B": "in-plane bending", "OB": "out-of-plane bending",
            "T": "torsion"}
"""The named families by the prefix of their names."""


class BandTooWideError(ModeSolverError):
    """The band holds more modes than one band solve computes (:data:`MAX_BAND_MODES`).

    Attributes
    ----------
    n_modes : int or None
        Modes in the band by the inertia count, None where it is not available (-).
    limit : int
        The most modes one band solve computes (-).
    """

    def __init__(self, f_min_Hz: float, f_max_Hz: float, n_modes: int | None,
                 limit: int) -> None:
        held = f"{n_modes} modes" if n_modes is not None else "more modes"
        super().__init__(f"the band {f_min_Hz:.6g}-{f_max_Hz:.6g} Hz holds {held}, above the "
                         f"{limit} one band solve computes; narrow it")
        self.n_modes, self.limit = n_modes, limit


@dataclass(frozen=True)
class BandMode:
    """One mode in the band.

    Attributes
    ----------
    name : str
        ``'L1'``, ``'B2'``, ``'L2'``, ``'B3'``, ``'OB2'`` (out-of-plane bending), ``'T1'``
        (torsion), ... or ``'other'``.
    family : str
        ``'longitudinal'``, ``'in-plane bending'``, ``'out-of-plane bending'``,
        ``'torsion'`` or ``'other'``.
    f_short_Hz, f_open_Hz : float
        Short- and open-circuit frequencies (Hz); ``f_open_Hz`` is NaN where no open-circuit
        mode has this mode's shape (mass MAC below :data:`fem.modes.PAIR_MAC`).
    k_eff : float
        ``sqrt(1 - (f_short / f_open)^2)`` (-), NaN without an open partner.
    operating : bool
        The mode is one of the operating pair (named L1 or B2).
    risk : bool
        Not operating, and within the risk window of an operating frequency.
    offset : float
        ``f_short / f_op - 1`` to the nearest operating frequency (-).
    in_plane : float
        Share of the sampled energy in the in-plane (thickness-symmetric) class (-); 1 in 2D.
    mirror : float
        Share in the class mirror-symmetric about ``x = 0`` (-): for in-plane modes ``u_y``
        even, ``u_x`` odd; for out-of-plane modes ``u_z`` even.
    nodes : int
        Sign changes along the centre line of the component that names the family (-).
    mac : float
        Correlation with the named beam shape (-); NaN for ``'other'``.
    """

    name: str
    family: str
    f_short_Hz: float
    f_open_Hz: float
    k_eff: float
    operating: bool
    risk: bool
    offset: float
    in_plane: float
    mirror: float
    nodes: int
    mac: float

    def to_dict(self) -> dict[str, object]:
        """JSON-ready dictionary (NaN as None)."""
        def num(x: float) -> float | None:
            return None if not math.isfinite(x) else float(x)

        return {"name": self.name, "family": self.family, "f_short_Hz": self.f_short_Hz,
                "f_open_Hz": num(self.f_open_Hz), "k_eff": num(self.k_eff),
                "operating": self.operating, "risk": self.risk, "offset": self.offset,
                "in_plane": self.in_plane, "mirror": self.mirror, "nodes": self.nodes,
                "mac": num(self.mac)}


@dataclass(frozen=True)
class BandModes:
    """Every mode of a model in a band.

    Attributes
    ----------
    f_min_Hz, f_max_Hz : float
        The band (Hz).
    modes : tuple of BandMode
        By increasing short-circuit frequency.
    operating_Hz : tuple of (str, float)
        The operating pair's names and short-circuit frequencies (Hz).
    risk_pct : float
        The risk window (%).
    model : str
        ``'2d'`` or ``'3d'``.
    counted : int or None
        Modes in the band by the inertia count (None where the factorization pivoted).
    wall_time_s : float
        Counts, both solves and the classification (s), assembly excluded.
    """

    f_min_Hz: float
    f_max_Hz: float
    modes: tuple
    operating_Hz: tuple
    risk_pct: float
    model: str
    counted: int | None
    wall_time_s: float

    @property
    def risks(self) -> tuple:
        """The modes flagged as a risk to the drive."""
        return tuple(m for m in self.modes if m.risk)

    def to_dict(self) -> dict[str, object]:
        """JSON-ready dictionary: the ``band_modes`` object of ``lusm modes --json``."""
        return {"f_min_Hz": self.f_min_Hz, "f_max_Hz": self.f_max_Hz, "model": self.model,
                "risk_pct": self.risk_pct, "operating_Hz": dict(self.operating_Hz),
                "counted": self.counted, "wall_time_s": self.wall_time_s,
                "modes": [m.to_dict() for m in self.modes]}


def default_band_Hz(operating_Hz: Mapping[str, float],
                    half_width: float = BAND_HALF_WIDTH) -> tuple[float, float]:
    """The default band (Hz): the operating frequencies' lowest minus ``half_width`` of it,
    their highest plus ``half_width`` of it."""
    f = [float(v) for v in operating_Hz.values()]
    return min(f) * (1.0 - half_width), max(f) * (1.0 + half_width)


def bending_shape(n: int, y: np.ndarray, length_m: float, derivative: int = 0) -> np.ndarray:
    """The n-th free-free Euler-Bernoulli bending shape (n + 1 nodes; n = 2 is B2) or its
    first derivative at ``y`` in [0, l] (m), in a form that stays exact for large ``n``.

    ``phi = cos(b y) - s sin(b y) + cosh(b y) - s sinh(b y)``, ``s = (cosh bl - cos bl) /
    (sinh bl - sin bl)``; the hyperbolic part is written as ``e^{-b y} (1 + s) / 2 +
    e^{b y} (1 - s) / 2`` with ``1 - s`` from its own exact expression (``s`` is 1 to
    ``e^{-bl}``, so the plain sum cancels digits).
    """
    bl = free_free_root(n)
    b = bl / length_m
    by = b * np.asarray(y, dtype=float)
    den = math.sinh(bl) - math.sin(bl)
    s = (math.cosh(bl) - math.cos(bl)) / den
    one_minus_s = (math.cos(bl) - math.sin(bl) - math.exp(-bl)) / den
    em, ep = np.exp(-by), np.exp(by)
    if derivative == 0:
        return np.cos(by) - s * np.sin(by) + 0.5 * (em * (1.0 + s) + ep * one_minus_s)
    if derivative == 1:
        return b * (-np.sin(by) - s * np.cos(by) + 0.5 * (-em * (1.0 + s) + ep * one_minus_s))
    raise ValueError(f"derivative must be 0 or 1, got {derivative!r}")


@dataclass(frozen=True)
class _Shape:
    """The classification of one sampled shape (before names are made unique)."""

    name: str
    in_plane: float
    mirror: float
    nodes: int
    mac: float


def classify(X: np.ndarray, Y: np.ndarray, inside: np.ndarray, mid: np.ndarray,
             length_m: float, top: np.ndarray | None = None,
             bottom: np.ndarray | None = None) -> _Shape:
    """Name one mode from its samples (module docstring).

    Parameters
    ----------
    X, Y : numpy.ndarray
        The sampling grid (ny, nx) (m), symmetric about ``x = 0`` with a centre column.
    inside : numpy.ndarray
        Mask (ny, nx) of the grid points sampled (the others are zero in the samples).
    mid : numpy.ndarray
        Displacement samples (2 or 3, ny, nx) at the mid-plane (zero outside the planform).
    length_m : float
        The overall length the reference shapes span (m).
    top, bottom : numpy.ndarray, optional
        3D samples (3, ny, nx) just inside the top and bottom faces.
    """
    in_plane = 1.0
    if top is not None and bottom is not None:
        from fem.solid3d.model import thickness_symmetric_fraction

        in_plane = thickness_symmetric_fraction(top, bottom)
    mask = inside.astype(float)
    centre = X.shape[1] // 2
    if in_plane >= MIN_CLASS:
        u = mid[:2]
        mirror = symmetric_fraction(u)
        if mirror >= MIN_CLASS:
            n = sign_changes(u[1][:, centre])
            ref = np.stack((np.zeros_like(X), np.cos(n * np.pi * Y / length_m))) * mask
            return _named("L", n, u, ref, in_plane, mirror, n)
        if 1.0 - mirror >= MIN_CLASS:
            nodes = sign_changes(u[0][:, centre])
            n = nodes - 1
            if n < 1:
                return _Shape("other", in_plane, mirror, nodes, math.nan)
            ref = np.stack((bending_shape(n, Y, length_m),
                            -X * bending_shape(n, Y, length_m, derivative=1))) * mask
            return _named("B", n, u, ref, in_plane, mirror, nodes)
        return _Shape("other", in_plane, mirror, -1, math.nan)
    w = mid[2]
    even = 0.5 * (w + w[:, ::-1])
    total = float(np.sum(w * w))
    mirror = float(np.sum(even * even)) / total if total > 0 else 0.0
    if 1.0 - in_plane < MIN_CLASS:
        return _Shape("other", in_plane, mirror, -1, math.nan)
    if mirror >= MIN_CLASS:
        nodes = sign_changes(w[:, centre])
        n = nodes - 1
        if n < 1:
            return _Shape("other", in_plane, mirror, nodes, math.nan)
        ref = bending_shape(n, Y, length_m) * mask
        return _named("OB", n, w, ref, in_plane, mirror, nodes)
    if 1.0 - mirror >= MIN_CLASS:
        twist = w[:, 0] - w[:, -1]  # the edges' difference: the twist angle times the width
        n = sign_changes(twist)
        ref = X * np.cos(n * np.pi * Y / length_m) * mask
        return _named("T", n, w, ref, in_plane, mirror, n)
    return _Shape("other", in_plane, mirror, -1, math.nan)


def _named(prefix: str, n: int, u: np.ndarray, ref: np.ndarray, in_plane: float,
           mirror: float, nodes: int) -> _Shape:
    """``prefix + n`` where the shape correlates with its beam reference, else ``'other'``."""
    mac = modal_assurance(u, ref) if n >= 1 and np.any(ref) else 0.0
    name = f"{prefix}{n}" if n >= 1 and mac >= MIN_MAC else "other"
    return _Shape(name, in_plane, mirror, nodes, mac)


def _is_solid(model) -> bool:
    """Whether ``model`` is the 3D solid (its stiffness is ``Kuu``) rather than the 2D plate."""
    return hasattr(model, "Kuu")


def count_below(model, f_Hz: float) -> int | None:
    """Short-circuit modes of ``model`` (2D or 3D, rigid-body modes included) below ``f_Hz``
    by the inertia of ``K - (2 pi f)^2 M`` (module docstring), or None where the sparse
    factorization pivoted off the diagonal."""
    from fem.admittance import modes_below

    if not _is_solid(model):
        return modes_below(model.K, model.M, f_Hz)
    t = model.potential_map(open_circuit=False)
    kup = (model.Kuphi @ t).tocsr()
    kpp = (t.T @ model.Kphiphi @ t).tocsr()
    # the potentials scaled to the displacements' size, as the eigensolver's saddle point
    # (fem.solid3d.model._condensed_operators): a congruence, so the inertia is kept
    alpha = math.sqrt(float(model.Kuu.diagonal().mean()) / float(kpp.diagonal().mean()))
    stiff = sp.bmat([[model.Kuu, alpha * kup], [alpha * kup.T, -alpha**2 * kpp]], format="csr")
    mass = sp.block_diag((model.M, sp.csr_matrix(kpp.shape)), format="csr")
    negative = modes_below(stiff, mass, f_Hz)
    return None if negative is None else negative - kpp.shape[0]


def _frequencies(model):
    """The model's eigensolver ``(model, k, f_center_Hz, open_circuit, maxiter)``."""
    if _is_solid(model):
        from fem.solid3d.model import solid_frequencies_Hz

        return solid_frequencies_Hz
    from fem.modes import natural_frequencies_Hz

    return natural_frequencies_Hz


def solve_band(model, f_min_Hz: float, f_max_Hz: float, open_circuit: bool = False,
               expected: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Every mode of ``model`` with ``f_min_Hz <= f <= f_max_Hz`` and its shape.

    Shift-invert at the band's middle in ``omega^2`` with ``expected + SPARE_MODES`` modes
    (12 when the count is unknown), doubled until the farthest mode computed lies outside
    the band and, where ``expected`` is given, the band holds that many.

    Raises
    ------
    BandTooWideError
        The band needs more than :data:`MAX_BAND_MODES` modes.
    ModeSolverError
        The counts disagree at the largest solve, or the eigensolver failed.
    """
    solve = _frequencies(model)
    n_dofs = model.M.shape[0]
    lam = (2.0 * math.pi * np.array([f_min_Hz, f_max_Hz])) ** 2
    sigma, half = 0.5 * (lam[0] + lam[1]), 0.5 * (lam[1] - lam[0])
    f_centre = math.sqrt(sigma) / (2.0 * math.pi)
    top = min(int(MAX_BAND_MODES * work_factor()), n_dofs - 2)
    if expected is not None and expected > top:
        raise BandTooWideError(f_min_Hz, f_max_Hz, expected, top)
    k = min(top, (12 if expected is None else expected + SPARE_MODES))
    while True:
        f, v = solve(model, k, f_centre, open_circuit, None)
        lam_k = np.sign(f) * (2.0 * math.pi * f) ** 2
        inside = np.abs(lam_k - sigma) <= half
        reached = float(np.max(np.abs(lam_k - sigma))) > half
        if reached and (expected is None or int(inside.sum()) == expected):
            return f[inside], v[:, inside]
        if k >= top:
            if not reached:
                raise BandTooWideError(f_min_Hz, f_max_Hz, expected, top)
            raise ModeSolverError(
                f"the band {f_min_Hz:.6g}-{f_max_Hz:.6g} Hz: {int(inside.sum())} modes found "
                f"where the inertia count says {expected}")
        k = min(2 * k, top)


def _samples(model, shapes: np.ndarray):
    """``(X, Y, inside, {'mid', 'top', 'bottom'}: (c, ny, nx, n))`` of the shapes."""
    if _is_solid(model):
        from fem.solid3d.model import sampling_points_3d

        X, Y, probes, inside = sampling_points_3d(model)
        return X, Y, inside, {k: (p @ shapes).reshape(3, *X.shape, -1)
                              for k, p in probes.items()}
    from fem.modes import sampling_points

    X, Y, P, inside = sampling_points(model)
    return X, Y, inside, {"mid": (P @ shapes).reshape(2, *X.shape, -1)}


def _classified(model, shapes: np.ndarray) -> list[_Shape]:
    """Each shape's :func:`classify`, names kept by the best-correlated mode only."""
    from fem.meshing.meshed_stator import overall_length_m

    X, Y, inside, s = _samples(model, shapes)
    length = overall_length_m(model.stator)
    out = []
    for i in range(shapes.shape[1]):
        faces = {k: s[k][..., i] for k in ("top", "bottom") if k in s}
        out.append(classify(X, Y, inside, s["mid"][..., i], length, **faces))
    best: dict[str, int] = {}
    for i, c in enumerate(out):
        if c.name != "other" and (c.name not in best or c.mac > out[best[c.name]].mac):
            best[c.name] = i
    return [c if c.name == "other" or best[c.name] == i else
            _Shape("other", c.in_plane, c.mirror, c.nodes, math.nan)
            for i, c in enumerate(out)]


def _open_partners(model, f_min_Hz: float, f_max_Hz: float, shapes: np.ndarray) -> np.ndarray:
    """The open-circuit frequency (Hz) of each short-circuit mode ``shapes``: the open mode
    of the same shape (mass MAC >= :data:`fem.modes.PAIR_MAC`), NaN where none has it.

    One shift-invert solve at the middle (in ``omega^2``) of the band stretched by
    :data:`OPEN_REACH` (open-circuit modes lie above their short-circuit ones), with twice
    :data:`SPARE_MODES` modes more than the band holds, repeated with twice as many while a
    mode has no partner (at most :data:`MAX_BAND_MODES`).
    """
    n = shapes.shape[1]
    out = np.full(n, math.nan)
    if n == 0:
        return out
    solve = _frequencies(model)
    f_centre = math.sqrt(0.5 * (f_min_Hz**2 + (OPEN_REACH * f_max_Hz) ** 2))
    top = min(int(MAX_BAND_MODES * work_factor()), model.M.shape[0] - 2)
    k = min(top, n + 2 * SPARE_MODES)
    while True:
        fo, vo = solve(model, k, f_centre, True, None)
        for i in range(n):
            j, mac = best_shape_match(shapes[:, i], vo, model.M)
            out[i] = float(fo[j]) if mac >= PAIR_MAC else math.nan
        if np.all(np.isfinite(out)) or k >= top:
            return out
        k = min(2 * k, top)


def _solved(model, f_min_Hz: float, f_max_Hz: float):
    """``(counted, f_short_Hz, shapes, classes)`` of the band: the inertia count (or None),
    the short-circuit modes of :func:`solve_band` and their :func:`_classified` names."""
    if not (0.0 < f_min_Hz < f_max_Hz and math.isfinite(f_max_Hz)):
        raise ValueError(f"the band needs 0 < f_min_Hz < f_max_Hz, got {f_min_Hz!r}, "
                         f"{f_max_Hz!r}")
    lo, hi = count_below(model, f_min_Hz), count_below(model, f_max_Hz)
    counted = None if lo is None or hi is None else hi - lo
    fs, vs = solve_band(model, f_min_Hz, f_max_Hz, expected=counted)
    return counted, fs, vs, _classified(model, vs)


@dataclass(frozen=True, eq=False)
class BandShape:
    """One short-circuit mode of the band with its shape (for pictures).

    Attributes
    ----------
    index : int
        Its row in the band table (:func:`band_modes`' order, counted from 1).
    name : str
        As in :class:`BandMode`.
    f_short_Hz : float
        Short-circuit frequency (Hz).
    shape : numpy.ndarray
        The displacement shape (the model's displacement dofs), mass-normalized.
    """

    index: int
    name: str
    f_short_Hz: float
    shape: np.ndarray


def band_shapes(model, f_min_Hz: float, f_max_Hz: float) -> tuple[BandShape, ...]:
    """The short-circuit modes of :func:`band_modes` (same order, same names) with their
    shapes, without the open-circuit solve.

    Raises
    ------
    BandTooWideError, ModeSolverError
        :func:`solve_band`.
    """
    _, fs, vs, classes = _solved(model, f_min_Hz, f_max_Hz)
    return tuple(BandShape(i + 1, c.name, float(fs[i]), vs[:, i])
                 for i, c in enumerate(classes))


def band_modes(model, f_min_Hz: float, f_max_Hz: float, operating_Hz: Mapping[str, float],
               risk_pct: float = RISK_PCT) -> BandModes:
    """Every mode of ``model`` in ``[f_min_Hz, f_max_Hz]``: frequencies, k_eff, names, risks.

    Parameters
    ----------
    model : fem.model.PiezoPlateModel or fem.solid3d.model.SolidPlateModel
        The assembled 2D plate or 3D solid.
    f_min_Hz, f_max_Hz : float
        The band (Hz), ``0 < f_min_Hz < f_max_Hz``.
    operating_Hz : mapping
        The operating pair's short-circuit frequencies by name (``{'L1': .., 'B2': ..}``, Hz):
        the band's modes of those names are the pair, and the others within ``risk_pct`` of
        any of these frequencies are risks.
    risk_pct : float
        Risk window (%).

    Raises
    ------
    BandTooWideError, ModeSolverError
        :func:`solve_band`.
    """
    t0 = time.perf_counter()
    counted, fs, vs, shapes = _solved(model, f_min_Hz, f_max_Hz)
    f_open = _open_partners(model, f_min_Hz, f_max_Hz, vs)
    ops = {str(k): float(v) for k, v in operating_Hz.items()}
    modes = []
    for i, c in enumerate(shapes):
        k2 = 1.0 - (fs[i] / f_open[i]) ** 2
        near = min(ops.values(), key=lambda f: abs(fs[i] / f - 1.0)) if ops else math.nan
        offset = float(fs[i] / near - 1.0)
        operating = c.name in ops
        modes.append(BandMode(
            name=c.name, family=FAMILIES.get(c.name.rstrip("0123456789"), "other"),
            f_short_Hz=float(fs[i]), f_open_Hz=float(f_open[i]),
            k_eff=math.sqrt(max(k2, 0.0)) if math.isfinite(k2) else math.nan,
            operating=operating, risk=not operating and abs(offset) <= risk_pct / 100.0,
            offset=offset, in_plane=c.in_plane, mirror=c.mirror, nodes=c.nodes, mac=c.mac))
    return BandModes(f_min_Hz=float(f_min_Hz), f_max_Hz=float(f_max_Hz), modes=tuple(modes),
                     operating_Hz=tuple(ops.items()), risk_pct=float(risk_pct),
                     model="3d" if _is_solid(model) else "2d", counted=counted,
                     wall_time_s=time.perf_counter() - t0)
