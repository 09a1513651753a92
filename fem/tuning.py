"""Design for degeneracy: the plate length and width at which L1 and B2 coincide.

The first step of designing a standing-wave L1-B2 motor is to make the two modes share one
frequency, the drive frequency. For a rectangular plate of fixed material:

* **Scaling.** If every dimension (and the electrode gap) is multiplied by ``s`` all natural
  frequencies are divided by ``s``. In the 2D plane-stress model the thickness only scales
  ``K`` and ``M`` together, so its frequencies depend on the length and width (and gap)
  only: with the thickness fixed, scaling ``l`` and ``W`` by ``s`` still divides them by
  ``s`` up to the (fixed, absolute) electrode gap. In the 3D model the thickness matters and
  the scaling is only approximate.
* **Shape.** ``L1`` depends mainly on the length (``~ c / 2l``), ``B2`` grows with the width
  (bending stiffness), so at a fixed length ``ln(f_B2 / f_L1)`` increases monotonically with
  ``W`` and has one root: the crossing of the two branches.

Algorithm (:func:`tune_plate`): at the current length, bracket the width where
``ln(f_B2/f_L1)`` changes sign (multiplicative steps of at most ``STEP_FACTOR``), solve with
Brent's method; scale ``l`` and ``W`` by ``sqrt(f_L1 f_B2) / f_target``; repeat until both
frequencies are within ``rel_tol`` of the target. L1 and B2 are identified by shape at every
FE solve (:func:`fem.modes.plate_modes`), so the search is indifferent to which of the two is
lower at the starting point. Each solve is counted.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from fem.geometry import PlateStator
from fem.material import PiezoMaterial, get_material

FIX_OPTIONS = ("thickness", "thickness_ratio")
"""``'thickness'``: keep ``h`` fixed; ``'thickness_ratio'``: scale ``h`` with the plate."""
MODELS = ("2d", "3d")
"""FE models the tuning can use."""
STEP_FACTOR = 1.15
"""Multiplicative width step used to bracket the crossing."""
MAX_BRACKET_STEPS = 30
"""Give up bracketing after this many steps."""


@dataclass(frozen=True)
class ModeSummary:
    """Frequencies and coupling of one mode (the keys of ``lusm modes --json``).

    Attributes
    ----------
    f_short_Hz, f_open_Hz : float
        Short- and open-circuit natural frequencies (Hz).
    k_eff : float
        Effective coupling factor (-).
    """

    f_short_Hz: float
    f_open_Hz: float
    k_eff: float

    def to_dict(self) -> dict[str, float]:
        """JSON-ready dictionary."""
        return {"f_short_Hz": self.f_short_Hz, "f_open_Hz": self.f_open_Hz, "k_eff": self.k_eff}


@dataclass(frozen=True)
class TunedDesign:
    """Result of :func:`tune_plate`.

    Attributes
    ----------
    stator : PlateStator
        The tuned plate (length, width; thickness per ``fix``; the starting gap and drive).
    target_frequency_Hz : float
        Requested common frequency (Hz).
    L1, B2 : ModeSummary
        Both modes of the tuned plate.
    fe_solves : int
        Number of FE modal solutions (short + open circuit counted as one).
    fix : str
        What was held: see :data:`FIX_OPTIONS`.
    model : str
        ``'2d'`` or ``'3d'``.
    material : str
        Material name.
    history : tuple of tuple
        ``(length_m, width_m, f_L1_Hz, f_B2_Hz)`` of every FE solve, in order (short circuit).
    outer_iterations : int
        Scale-and-recross iterations taken (1 when the first crossing already hits the target).
    """

    stator: PlateStator
    target_frequency_Hz: float
    L1: ModeSummary
    B2: ModeSummary
    fe_solves: int
    fix: str
    model: str
    material: str
    history: tuple
    outer_iterations: int = 0

    @property
    def relative_mismatch(self) -> float:
        """``|f_L1 - f_B2| / f_target`` (short circuit) (-)."""
        return abs(self.L1.f_short_Hz - self.B2.f_short_Hz) / self.target_frequency_Hz

    def to_dict(self) -> dict[str, object]:
        """JSON-ready dictionary (the ``lusm tune --json`` keys)."""
        return {
            "length_mm": self.stator.length_m * 1e3,
            "width_mm": self.stator.width_m * 1e3,
            "thickness_mm": self.stator.thickness_m * 1e3,
            "gap_mm": self.stator.electrode_gap_m * 1e3,
            "target_frequency_Hz": self.target_frequency_Hz,
            "fe_solves": self.fe_solves,
            "outer_iterations": self.outer_iterations,
            "relative_mismatch": self.relative_mismatch,
            "fix": self.fix,
            "model": self.model,
            "material": self.material,
            "L1": self.L1.to_dict(),
            "B2": self.B2.to_dict(),
        }


class _Solver:
    """Counts and memoizes FE modal solutions of plates that differ in length and width."""

    def __init__(self, base: PlateStator, material: PiezoMaterial, model: str, fix: str,
                 order: int, refine: int | None) -> None:
        self.base = base
        self.material = material
        self.model = model
        self.fix = fix
        self.order = order
        self.refine = refine
        self.cache: dict[tuple[float, float], object] = {}
        self.history: list[tuple[float, float, float, float]] = []

    def stator(self, length_m: float, width_m: float) -> PlateStator:
        h = self.base.thickness_m
        if self.fix == "thickness_ratio":
            h = h * length_m / self.base.length_m
        return replace(self.base, length_m=float(length_m), width_m=float(width_m),
                       thickness_m=float(h))

    def modes(self, length_m: float, width_m: float):
        key = (float(length_m), float(width_m))
        if key not in self.cache:
            st = self.stator(*key)
            if self.model == "2d":
                from fem.mesh import DEFAULT_REFINE
                from fem.modes import plate_modes

                res = plate_modes(st, self.material, self.order,
                                  DEFAULT_REFINE if self.refine is None else self.refine)
            else:
                from fem.solid3d import DEFAULT_REFINE_3D, solid_modes

                res = solid_modes(st, self.material, self.order,
                                  DEFAULT_REFINE_3D if self.refine is None else self.refine)
            self.cache[key] = res
            self.history.append((key[0], key[1], res.L1.f_short_Hz, res.B2.f_short_Hz))
        return self.cache[key]

    def log_ratio(self, length_m: float, width_m: float) -> float:
        res = self.modes(length_m, width_m)
        return math.log(res.B2.f_short_Hz / res.L1.f_short_Hz)


def _crossing_width(solver: _Solver, length_m: float, width_m: float, rel_tol: float) -> float:
    """Width (m) at which ``f_B2 = f_L1`` for the given length: bracket, then Brent."""
    from scipy.optimize import brentq

    w_min = 1.05 * solver.base.electrode_gap_m
    w_max = length_m
    w0 = min(max(width_m, w_min), w_max)
    r0 = solver.log_ratio(length_m, w0)
    if r0 == 0.0:
        return w0
    # d ln(f_B2/f_L1) / d ln(W) is about 0.7..1, so a step of 1.5 |r0| in ln W usually
    # brackets the root at once; the step doubles (up to ln STEP_FACTOR) until it does
    step = min(max(1.5 * abs(r0), 1e-7), math.log(STEP_FACTOR))
    sign = -1.0 if r0 > 0 else 1.0  # B2 above L1: narrow the plate
    a, ra = w0, r0
    for _ in range(MAX_BRACKET_STEPS):
        b = min(max(a * math.exp(sign * step), w_min), w_max)
        step = min(2.0 * step, math.log(STEP_FACTOR))
        if b == a:
            break
        rb = solver.log_ratio(length_m, b)
        if np.sign(rb) != np.sign(ra):
            lo, hi = (a, b) if a < b else (b, a)
            # the root is a zero of ln(fB2/fL1); tolerance on W well below rel_tol
            return brentq(lambda w: solver.log_ratio(length_m, w), lo, hi,
                          xtol=0.1 * rel_tol * lo, rtol=0.1 * rel_tol)
        a, ra = b, rb
    raise ValueError(
        f"could not bracket the L1/B2 crossing for length {length_m * 1e3:.4g} mm between "
        f"widths {w_min * 1e3:.4g} and {w_max * 1e3:.4g} mm"
    )


def tune_plate(
    target_frequency_Hz: float = 40e3,
    fix: str = "thickness",
    material: PiezoMaterial | str = "pzt8",
    start: PlateStator | None = None,
    model: str = "2d",
    order: int = 2,
    refine: int | None = None,
    rel_tol: float = 1e-5,
    max_iter: int = 10,
) -> TunedDesign:
    """Length and width at which L1 and B2 coincide at ``target_frequency_Hz``.

    Parameters
    ----------
    target_frequency_Hz : float
        Common short-circuit frequency wanted (Hz), > 0.
    fix : str
        ``'thickness'`` (default: ``h`` kept at the starting value) or ``'thickness_ratio'``
        (``h/l`` kept).
    material : PiezoMaterial or str
        ``'pzt8'`` (default), ``'paper'`` or a material.
    start : PlateStator, optional
        Starting design (default: the paper's 30 x 7.5 x 3 mm plate); its thickness, gap and
        drive electrodes are kept (thickness per ``fix``).
    model : str
        ``'2d'`` (plane stress, default) or ``'3d'`` (:mod:`fem.solid3d`, slower).
    order : int
        Element order.
    refine : int, optional
        Mesh refinement (default: the model's default).
    rel_tol : float
        Stop when both frequencies are within ``rel_tol`` of the target (-).
    max_iter : int
        Maximum number of scale-and-recross iterations.

    Returns
    -------
    TunedDesign

    Raises
    ------
    ValueError
        On bad input, or if no crossing can be bracketed or the iteration does not converge.
    """
    if not (isinstance(target_frequency_Hz, (int, float)) and math.isfinite(target_frequency_Hz)
            and target_frequency_Hz > 0):
        raise ValueError(f"target_frequency_Hz must be a finite number > 0, got "
                         f"{target_frequency_Hz!r}")
    if fix not in FIX_OPTIONS:
        raise ValueError(f"fix must be one of {', '.join(FIX_OPTIONS)}, got {fix!r}")
    if model not in MODELS:
        raise ValueError(f"model must be one of {', '.join(MODELS)}, got {model!r}")
    if not (0.0 < rel_tol < 1e-2):
        raise ValueError(f"rel_tol must lie in (0, 1e-2), got {rel_tol!r}")
    mat = get_material(material)
    base = PlateStator() if start is None else start
    solver = _Solver(base, mat, model, fix, order, refine)
    length, width = base.length_m, base.width_m
    iterations = 0
    for _ in range(max_iter):
        iterations += 1
        width = _crossing_width(solver, length, width, rel_tol)
        res = solver.modes(length, width)
        f_l, f_b = res.L1.f_short_Hz, res.B2.f_short_Hz
        if (abs(f_l / target_frequency_Hz - 1) < rel_tol
                and abs(f_b / target_frequency_Hz - 1) < rel_tol):
            break
        s = math.sqrt(f_l * f_b) / target_frequency_Hz
        length, width = length * s, width * s
        if width <= base.electrode_gap_m:
            raise ValueError(
                f"the tuned width {width * 1e3:.4g} mm would not exceed the electrode gap "
                f"{base.electrode_gap_m * 1e3:.4g} mm; lower the target frequency"
            )
    else:
        raise ValueError(f"tune_plate did not converge in {max_iter} iterations "
                         f"(last: L1 {f_l:.2f} Hz, B2 {f_b:.2f} Hz)")
    return TunedDesign(
        stator=solver.stator(length, width),
        target_frequency_Hz=float(target_frequency_Hz),
        L1=ModeSummary(res.L1.f_short_Hz, res.L1.f_open_Hz, res.L1.k_eff),
        B2=ModeSummary(res.B2.f_short_Hz, res.B2.f_open_Hz, res.B2.k_eff),
        fe_solves=len(solver.history),
        fix=fix,
        model=model,
        material=mat.name,
        history=tuple(solver.history),
        outer_iterations=iterations,
    )
