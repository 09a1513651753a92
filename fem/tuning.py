"""Design for degeneracy: the plate dimensions at which L1 and B2 coincide.

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
  ``W`` and has one root: the crossing of the two branches. At a fixed width it decreases
  monotonically with ``l`` (``f_B2 / f_L1 ~ W / l``).

**What can be held** (``fix``, :data:`FIX_OPTIONS`). Two conditions, ``f_L1 = f_B2`` and
``f_L1 = f_target``, need two free dimensions that move them. The thickness is not one of
them: in 2D it moves the frequencies only through the thickness inertia (``~(h/l)^2``) and the
gap's cross-section capacitances, and in 3D it is hardly more: at l = 35 mm the common
frequency of the degenerate plate moves by 0.13 % (2D) and 0.17 % (3D) over h = 1-5 mm
(``python benchmarks/tune_fixed_length_3d.py``, docs/designer.md), so a held length or width
together with a free thickness could reach only targets in a window of a few tenths of a per
cent. Hence:

* ``fix="thickness"`` (default) or ``"thickness_ratio"`` (``h/l`` kept): ``l`` and ``W`` are
  tuned so that L1 = B2 = ``target_frequency_Hz`` (40 kHz when not given).
* ``fix="length"``: the length is kept exactly; the width is tuned until L1 = B2, and their
  common frequency *follows from the length*: it is reported, and a target is refused
  (``ValueError`` naming ``target_frequency_Hz``).
* ``fix="width"``: the width is kept; the length is tuned until L1 = B2, frequency reported,
  target refused likewise.
* ``fix`` may be a tuple to say what the thickness does next to a held length or width,
  e.g. ``("width", "thickness_ratio")``; without a thickness entry the thickness is held.
  Holding both the length and the width leaves nothing that can make L1 and B2 meet and is
  refused.

Algorithm (:func:`tune_plate`): at the current length (width), bracket the width (length)
where ``ln(f_B2/f_L1)`` changes sign (multiplicative steps of at most ``STEP_FACTOR``), solve
with Brent's method. With a target, scale ``l`` and ``W`` by ``sqrt(f_L1 f_B2) / f_target``
and repeat until both frequencies are within ``rel_tol`` of the target; with a held length or
width one crossing is the answer. With ``model="3d"`` that search runs on the 2D model, and
Newton steps on the logarithms of the tuned dimensions then tune the 3D model from the 2D
design (:func:`_tune_3d`: the 2D Jacobian first, Broyden's update from each 3D solve; 2-4 3D
solves on the fine mesh of ``lusm modes --model 3d``'s default, where bracketing on the 3D
model took about 15). L1 and B2 are identified by shape at every FE solve
(:func:`fem.modes.plate_modes`, or :func:`fem.solid3d.model.solid_modes` for ``model="3d"``), so
the search is indifferent to which of the two is lower at the starting point. Each solve is
counted.

A stator with its own mesh (:class:`fem.meshing.meshed_stator.MeshedStator`, a mesh file) cannot be
rescaled here and is refused. A parametric stator (:class:`fem.meshing.parametric.ParametricStator`:
a tip, chamfers, holes) is rescaled like a plain plate: its plate length and width change,
the features keep their size and position, and gmsh remeshes every plate tried (its element
size is the file's ``[mesh] size_mm`` or ``min(l, W) / 8`` of each plate).
"""

from __future__ import annotations

import math
import numbers
import warnings
from dataclasses import dataclass, replace

import numpy as np

from bounds import ParameterError
from fem.geometry import PlateStator
from fem.material import PiezoMaterial, get_material
from fem.mesh_settings import MeshSettings

FIX_OPTIONS = ("length", "width", "thickness", "thickness_ratio")
"""What :func:`tune_plate` can hold: ``'length'``, ``'width'`` (keep that dimension exactly),
``'thickness'`` (keep ``h``), ``'thickness_ratio'`` (scale ``h`` with the length)."""
THICKNESS_RULES = ("thickness", "thickness_ratio")
"""The entries of :data:`FIX_OPTIONS` that say what the thickness does (at most one)."""
MODELS = ("2d", "3d")
"""FE models the tuning can use."""
DEFAULT_TARGET_HZ = 40e3
"""Target frequency (Hz) when the length and width are both free and none is given."""
DEFAULT_REL_TOL = 1e-5
"""Default ``rel_tol`` of :func:`tune_plate`: the relative distance (-) of both frequencies
from the target (or from each other, with no target) at which a tuning stops."""
STEP_FACTOR = 1.15
"""Multiplicative step used to bracket the crossing."""
MAX_BRACKET_STEPS = 30
"""Give up bracketing after this many steps."""
MAX_LENGTH_OVER_WIDTH = 20.0
"""Upper end of the length bracket (times the width) when the width is held (-)."""
CROSSING_ASPECT = 0.27
"""Width over length of a plate with L1 = B2 (-): 11.43 / 42.13 mm at 40 kHz (PZT-8, 3 mm),
6.60 / 25.69 mm for the tuned 60 kHz stator (material ``paper``). Where the search starts when
the starting plate lies outside :data:`START_ASPECT`."""
START_ASPECT = (0.12, 0.5)
"""Width over length (-) of a starting plate the search starts from as given. Wider than half
its length, L1 and B2 are not identified (:mod:`fem.modes`: 30 x 16 mm is the widest plate of
the paper's length that passes), so a held length of 10 mm at the default 7.5 mm width failed
on its first solve; below 0.12 the bracket's steps (at most :data:`STEP_FACTOR` each) may not
reach the crossing in :data:`MAX_BRACKET_STEPS`. Outside, the free dimension starts at
:data:`CROSSING_ASPECT`: it is a starting value (docs/designer.md), the held one is kept."""


def normalize_fix(fix: str | tuple[str, ...] | list[str]) -> tuple[str, ...]:
    """The canonical tuple of what is held: ``fix`` plus ``'thickness'`` if no thickness rule.

    Parameters
    ----------
    fix : str or sequence of str
        Entries of :data:`FIX_OPTIONS`.

    Returns
    -------
    tuple of str
        In :data:`FIX_OPTIONS` order; always contains exactly one of
        :data:`THICKNESS_RULES`.

    Raises
    ------
    ValueError
        Unknown or repeated entries, both thickness rules, or both the length and the width.
    """
    items = (fix,) if isinstance(fix, str) else tuple(fix)
    bad = [f for f in items if f not in FIX_OPTIONS]
    if not items or bad:
        raise ValueError(f"fix must be one or more of {', '.join(FIX_OPTIONS)}, got {fix!r}")
    if len(set(items)) != len(items):
        raise ValueError(f"fix names an entry twice: {fix!r}")
    held = set(items)
    if set(THICKNESS_RULES) <= held:
        raise ValueError("fix cannot hold both the thickness and the thickness ratio; "
                         "choose one")
    if {"length", "width"} <= held:
        raise ValueError("fix cannot hold both the length and the width: only the thickness "
                         "would be left, and it moves L1 and B2 too little to make them meet; "
                         "hold one of them")
    if not held & set(THICKNESS_RULES):
        held.add("thickness")
    return tuple(f for f in FIX_OPTIONS if f in held)


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
        The tuned plate (its held dimensions as given; the starting gap and drive).
    target_frequency_Hz : float or None
        Requested common frequency (Hz); None when a held length or width sets it.
    L1, B2 : ModeSummary
        Both modes of the tuned plate.
    fe_solves : int
        Number of FE modal solutions (short + open circuit counted as one), 2D and 3D.
    fix : str
        What was held: entries of :data:`FIX_OPTIONS` joined by ``'+'`` (e.g.
        ``'thickness'``, ``'length+thickness'``; see :func:`normalize_fix`).
    model : str
        ``'2d'`` or ``'3d'``.
    material : str
        Material name.
    history : tuple of tuple
        ``(length_m, width_m, f_L1_Hz, f_B2_Hz)`` of every FE solve, in order (short circuit).
    outer_iterations : int
        Scale-and-recross iterations taken (1 when the first crossing already hits the target,
        or with a held length or width).
    tuned : tuple of str
        The dimensions the search changed: ``('length', 'width')``, ``('width',)`` or
        ``('length',)`` (the thickness follows the length with ``'thickness_ratio'``).
    solves_3d : int
        How many of the solves were 3D (a 3D tuning starts from the 2D one).
    """

    stator: PlateStator
    target_frequency_Hz: float | None
    L1: ModeSummary
    B2: ModeSummary
    fe_solves: int
    fix: str
    model: str
    material: str
    history: tuple
    outer_iterations: int = 0
    tuned: tuple = ("length", "width")
    solves_3d: int = 0

    @property
    def frequency_Hz(self) -> float:
        """Common frequency ``sqrt(f_L1 f_B2)`` (short circuit) (Hz)."""
        return math.sqrt(self.L1.f_short_Hz * self.B2.f_short_Hz)

    @property
    def relative_mismatch(self) -> float:
        """``|f_L1 - f_B2| / f`` (short circuit), ``f`` the target or, without one,
        :attr:`frequency_Hz` (-)."""
        f = self.frequency_Hz if self.target_frequency_Hz is None else self.target_frequency_Hz
        return abs(self.L1.f_short_Hz - self.B2.f_short_Hz) / f

    def to_dict(self) -> dict[str, object]:
        """JSON-ready dictionary (the ``lusm tune --json`` keys)."""
        return {
            "length_mm": self.stator.length_m * 1e3,
            "width_mm": self.stator.width_m * 1e3,
            "thickness_mm": self.stator.thickness_m * 1e3,
            "gap_mm": self.stator.electrode_gap_m * 1e3,
            **(self.stator.features_mm() if hasattr(self.stator, "features_mm") else {}),
            "target_frequency_Hz": self.target_frequency_Hz,
            "frequency_Hz": self.frequency_Hz,
            "fe_solves": self.fe_solves,
            "fe_solves_3d": self.solves_3d,
            "outer_iterations": self.outer_iterations,
            "relative_mismatch": self.relative_mismatch,
            "fix": self.fix,
            "tuned": list(self.tuned),
            "model": self.model,
            "material": self.material,
            "L1": self.L1.to_dict(),
            "B2": self.B2.to_dict(),
        }


class _Solver:
    """Counts and memoizes FE modal solutions of plates that differ in length and width."""

    def __init__(self, base: PlateStator, material: PiezoMaterial, model: str,
                 scale_thickness: bool, mesh: MeshSettings) -> None:
        self.base = base
        self.material = material
        self.model = model
        self.scale_thickness = scale_thickness
        self.mesh = mesh
        self.cache: dict[tuple[float, float], object] = {}
        self.history: list[tuple[float, float, float, float]] = []
        self.bar = None  # a tqdm bar counting the solves, when asked for

    def stator(self, length_m: float, width_m: float) -> PlateStator:
        h = self.base.thickness_m
        if self.scale_thickness and length_m != self.base.length_m:
            h = h * length_m / self.base.length_m
        return replace(self.base, length_m=float(length_m), width_m=float(width_m),
                       thickness_m=float(h))

    def modes(self, length_m: float, width_m: float):
        key = (float(length_m), float(width_m))
        if key not in self.cache:
            st = self.stator(*key)
            if self.model == "2d":
                from fem.modes import plate_modes

                res = plate_modes(st, self.material, self.mesh)
            else:
                res = _solve_3d(st, self.material, self.mesh)
            self.cache[key] = res
            self.history.append((key[0], key[1], res.L1.f_short_Hz, res.B2.f_short_Hz))
            if self.bar is not None:
                self.bar.set_postfix_str(f"L1 {res.L1.f_short_Hz:.0f} Hz, "
                                         f"B2 {res.B2.f_short_Hz:.0f} Hz", refresh=False)
                self.bar.update()
        return self.cache[key]

    def log_ratio(self, length_m: float, width_m: float) -> float:
        res = self.modes(length_m, width_m)
        return math.log(res.B2.f_short_Hz / res.L1.f_short_Hz)


def _solve_3d(stator: PlateStator, material: PiezoMaterial, mesh: MeshSettings):
    """The 3D modes a tuning solves: with ``mesh.refine`` None the fine mesh of ``lusm modes
    --model 3d``'s default pair (:func:`fem.solid3d.estimate.default_meshes`, on the quarter
    plate where it applies) in ``mesh``'s order, so that the tuned plate re-solved by ``lusm
    modes --model 3d`` gives the tuning's numbers; else the full plate on ``mesh``."""
    from fem.solid3d.model import solid_modes

    if mesh.refine is not None:
        return solid_modes(stator, material, mesh)
    from fem.solid3d.estimate import default_meshes
    from fem.solid3d.symmetric import quarter_model_applies, symmetric_solid_modes

    fine = default_meshes(stator)[1]
    solve = (symmetric_solid_modes if quarter_model_applies(stator, fine.edge_grading)
             else solid_modes)
    return solve(stator, material, fine.settings(mesh.order))


def _crossing(solver: _Solver, free: str, length_m: float, width_m: float,
              rel_tol: float) -> float:
    """The ``free`` dimension (``'width'`` or ``'length'``, m) at which ``f_B2 = f_L1``, the
    other one held: bracket, then Brent.

    ``ln(f_B2/f_L1)`` rises with the width and falls with the length.
    """
    from scipy.optimize import brentq

    if free == "width":
        lo_bound, hi_bound = 1.05 * solver.base.electrode_gap_m, length_m
        x0, rising = width_m, True

        def f(x: float) -> float:
            return solver.log_ratio(length_m, x)
    else:
        lo_bound = max(width_m, 1.05 * solver.base.electrode_gap_m)
        hi_bound = MAX_LENGTH_OVER_WIDTH * width_m
        x0, rising = length_m, False

        def f(x: float) -> float:
            return solver.log_ratio(x, width_m)

    if not START_ASPECT[0] <= width_m / length_m <= START_ASPECT[1]:
        # a starting plate whose modes cannot be identified, or too far from the crossing for
        # the bracket: the free dimension starts where the crossing lies (it is a start only)
        x0 = CROSSING_ASPECT * length_m if free == "width" else width_m / CROSSING_ASPECT
    x0 = min(max(x0, lo_bound), hi_bound)
    r0 = f(x0)
    if r0 == 0.0:
        return x0
    # |d ln(f_B2/f_L1) / d ln x| is about 0.7..1, so a step of 1.5 |r0| in ln x usually
    # brackets the root at once; the step doubles (up to ln STEP_FACTOR) until it does
    step = min(max(1.5 * abs(r0), 1e-7), math.log(STEP_FACTOR))
    sign = -1.0 if (r0 > 0) == rising else 1.0  # B2 above L1: narrow (lengthen) the plate
    a, ra = x0, r0
    for _ in range(MAX_BRACKET_STEPS):
        b = min(max(a * math.exp(sign * step), lo_bound), hi_bound)
        step = min(2.0 * step, math.log(STEP_FACTOR))
        if b == a:
            break
        rb = f(b)
        if np.sign(rb) != np.sign(ra):
            lo, hi = (a, b) if a < b else (b, a)
            # the root is a zero of ln(fB2/fL1); tolerance on x well below rel_tol
            return brentq(f, lo, hi, xtol=0.1 * rel_tol * lo, rtol=0.1 * rel_tol)
        a, ra = b, rb
    held = (f"length {length_m * 1e3:.4g} mm" if free == "width"
            else f"width {width_m * 1e3:.4g} mm")
    raise ValueError(
        f"could not bracket the L1/B2 crossing for {held} between {free}s "
        f"{lo_bound * 1e3:.4g} and {hi_bound * 1e3:.4g} mm"
    )


def _crossing_width(solver: _Solver, length_m: float, width_m: float, rel_tol: float) -> float:
    """Width (m) at which ``f_B2 = f_L1`` for the given length."""
    return _crossing(solver, "width", length_m, width_m, rel_tol)


def bar_length_m(material: PiezoMaterial | str, f_Hz: float) -> float:
    """Length (m) of a free bar whose first longitudinal mode is at ``f_Hz`` (Hz).

    ``c / (2 f)`` with the bar speed ``c = sqrt(1 / (s^E_22 rho))`` along the plate's length:
    the L1 of a slender plate, a first estimate of what a target asks for (56.4 kHz at the
    paper's 30 mm against the 2D model's 56.2 kHz).
    """
    mat = get_material(material)
    s22 = float(np.linalg.inv(mat.cE_Pa)[1, 1])
    return math.sqrt(1.0 / (s22 * mat.rho_kg_m3)) / (2.0 * float(f_Hz))


def tune_plate(
    target_frequency_Hz: float | None = None,
    fix: str | tuple[str, ...] = "thickness",
    material: PiezoMaterial | str = "pzt8",
    start: PlateStator | None = None,
    model: str = "2d",
    mesh: MeshSettings | None = None,
    rel_tol: float = DEFAULT_REL_TOL,
    max_iter: int = 10,
    progress: bool = False,
) -> TunedDesign:
    """Plate dimensions at which L1 and B2 coincide (at ``target_frequency_Hz`` if free).

    Parameters
    ----------
    target_frequency_Hz : float, optional
        Common short-circuit frequency wanted (Hz), > 0. With the length and width free the
        default is :data:`DEFAULT_TARGET_HZ` (40 kHz). With a held length or width it must be
        left out: the common frequency then follows from the held dimension and is reported.
    fix : str or tuple of str
        What is held (:data:`FIX_OPTIONS`, module docstring): ``'thickness'`` (default: ``h``
        kept at the starting value), ``'thickness_ratio'`` (``h/l`` kept), ``'length'``
        (width tuned), ``'width'`` (length tuned), or a tuple such as
        ``('width', 'thickness_ratio')``. A held length or width keeps the thickness unless
        ``'thickness_ratio'`` is named.
    material : PiezoMaterial or str
        ``'pzt8'`` (default), ``'paper'`` or a material.
    start : PlateStator, optional
        Starting design (default: the paper's 30 x 7.5 x 3 mm plate); its held dimensions,
        thickness, gap and drive electrodes are kept. A stator with its own mesh is refused.
    model : str
        ``'2d'`` (plane stress, default) or ``'3d'`` (:mod:`fem.solid3d.model`, slower).
    mesh : MeshSettings, optional
        The FE mesh (default :class:`fem.mesh_settings.MeshSettings`). A 2D tuning solves
        every plate on it. A 3D tuning starts from a 2D tuning on the default 2D mesh of
        ``mesh.order``, then solves the full plate on ``mesh`` or, with ``mesh.refine``
        None, on the fine mesh of ``lusm modes --model 3d``'s default pair.
    rel_tol : float
        Stop when both frequencies are within ``rel_tol`` of the target; with a held length
        or width, the tolerance of the crossing (-).
    max_iter : int
        Maximum number of scale-and-recross iterations.
    progress : bool
        Show a progress bar of the FE solves (after a second; a tuning takes 10-40 solves).

    Returns
    -------
    TunedDesign

    Raises
    ------
    ValueError
        On bad input (a target next to a held length or width included), or if no crossing
        can be bracketed or the iteration does not converge.
    """
    held = normalize_fix(fix)
    fixed_dim = "length" if "length" in held else "width" if "width" in held else None
    target_frequency_Hz = _checked_target(target_frequency_Hz, fix, fixed_dim, model, rel_tol,
                                          max_iter)
    mat = get_material(material)
    base = _start_plate(start)
    mesh = MeshSettings() if mesh is None else mesh
    solver = _Solver(base, mat, "2d", "thickness_ratio" in held,
                     mesh if model == "2d" else MeshSettings(order=mesh.order))
    solver.bar = _progress_bar(progress)
    try:
        d2 = _tune(solver, base, mat, held, fixed_dim, target_frequency_Hz, "2d", rel_tol,
                   max_iter)
        if model == "2d":
            return d2
        solver3 = _Solver(base, mat, "3d", "thickness_ratio" in held, mesh)
        solver3.bar = solver.bar
        return _tune_3d(solver3, solver, d2, rel_tol)
    finally:
        if solver.bar is not None:
            solver.bar.close()


def _start_plate(start: PlateStator | None) -> PlateStator:
    """The plate the tuning starts from (default: the paper's); a stator with its own mesh
    is refused, as its mesh cannot be rescaled."""
    base = PlateStator() if start is None else start
    if getattr(base, "mesh", None) is not None:
        raise ValueError(f"start is a {type(base).__name__} with its own mesh, which "
                         "tune_plate cannot rescale; start from a plain PlateStator")
    return base


def _progress_bar(progress: bool):
    """A tqdm bar of the FE solves on stderr after a second, or None without ``progress``;
    on a terminal only (``disable=None``: a log or a pipe gets no carriage-return lines)."""
    if not progress:
        return None
    from tqdm import tqdm

    return tqdm(desc="tune", unit="FE solve", delay=1.0, leave=False, disable=None)


def _checked_target(target_frequency_Hz: float | None, fix, fixed_dim: str | None, model: str,
                    rel_tol: float, max_iter: int) -> float | None:
    """The target (Hz) as a float, None where left out; refuses options out of range and a
    target next to a held length or width, naming them."""
    if target_frequency_Hz is not None and not (  # NumPy scalars too (float32 included)
            isinstance(target_frequency_Hz, numbers.Real)
            and not isinstance(target_frequency_Hz, bool)
            and math.isfinite(target_frequency_Hz) and target_frequency_Hz > 0):
        raise ParameterError("target_frequency_Hz", target_frequency_Hz, 0.0, None, "Hz",
                             low_open=True, message=f"target_frequency_Hz must be a finite "
                             f"number > 0, got {target_frequency_Hz!r}")
    if target_frequency_Hz is not None:
        target_frequency_Hz = float(target_frequency_Hz)
    if not (isinstance(rel_tol, numbers.Real) and 0.0 < rel_tol < 1e-2):
        raise ValueError(f"rel_tol must lie in (0, 1e-2), got {rel_tol!r}")
    if fixed_dim is not None and target_frequency_Hz is not None:
        other = "width" if fixed_dim == "length" else "length"
        raise ValueError(
            f"target_frequency_Hz cannot be imposed with the {fixed_dim} held (fix={fix!r}): "
            f"the {other} "
            f"makes L1 and B2 meet and their common frequency then follows from the "
            f"{fixed_dim} (the thickness hardly moves it); leave the target out, or hold "
            "only the thickness to tune length and width to a target")
    if model not in MODELS:
        raise ValueError(f"model must be one of {', '.join(MODELS)}, got {model!r}")
    if (isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer))
            or not 1 <= max_iter <= MAX_ITER):  # each iteration is a crossing's FE solves
        raise ValueError(f"max_iter must be an integer in [1, {MAX_ITER}], got {max_iter!r}")
    return target_frequency_Hz


MAX_3D_SOLVES = 6
"""3D solves a 3D tuning may take after its 2D start (:func:`_tune_3d`; the designer's
35 mm stator with a tip and the paper's plate take 2-4). The work bound of ``lusm tune
--model 3d`` counts this many."""

JACOBIAN_STEP = 1e-3
"""Relative step of the 2D finite differences that give a 3D tuning its first Jacobian (-)."""


def _residual(res, target_Hz: float | None) -> np.ndarray:
    """``[ln(f_B2/f_L1)]``, and with a target ``ln(sqrt(f_L1 f_B2) / target)``: zero at a
    tuned plate."""
    f_l, f_b = res.L1.f_short_Hz, res.B2.f_short_Hz
    r = [math.log(f_b / f_l)]
    if target_Hz is not None:
        r.append(0.5 * math.log(f_l * f_b) - math.log(target_Hz))
    return np.array(r)


def _tuned(res, target_Hz: float | None, rel_tol: float) -> bool:
    """Both frequencies within ``rel_tol`` of the target, or of each other without one."""
    f_l, f_b = res.L1.f_short_Hz, res.B2.f_short_Hz
    if target_Hz is None:
        return abs(f_b / f_l - 1.0) < rel_tol
    return abs(f_l / target_Hz - 1.0) < rel_tol and abs(f_b / target_Hz - 1.0) < rel_tol


def _tune_3d(solver3: _Solver, solver2: _Solver, d2: TunedDesign, rel_tol: float
             ) -> TunedDesign:
    """The 3D tuning from the 2D one ``d2``: Newton steps on the logarithms of the tuned
    dimensions, one 3D solve each, the first with the 2D model's Jacobian (finite
    differences, :data:`JACOBIAN_STEP`) and then Broyden's update of it from the 3D solves.
    The 2D and 3D models differ by a few 1e-4 in frequency, so the 2D plate starts within
    reach and 2-4 3D solves tune it, where bracketing took about 15.

    Raises
    ------
    ValueError
        If the plate is not tuned after :data:`MAX_3D_SOLVES` 3D solves.
    """
    target = d2.target_frequency_Hz
    dims = d2.tuned  # ('width',), ('length',) or ('length', 'width')
    st = d2.stator
    u = np.log([st.length_m if d == "length" else st.width_m for d in dims])

    def dims_of(v: np.ndarray) -> tuple[float, float]:
        x = dict(zip(dims, np.exp(v), strict=True))
        return float(x.get("length", st.length_m)), float(x.get("width", st.width_m))

    f0 = _residual(solver2.modes(*dims_of(u)), target)
    jac = np.empty((f0.size, u.size))
    for j in range(u.size):
        du = np.zeros(u.size)
        du[j] = JACOBIAN_STEP
        jac[:, j] = (_residual(solver2.modes(*dims_of(u + du)), target) - f0) / JACOBIAN_STEP
    solves_2d = len(solver2.history)
    prev = None
    for _ in range(MAX_3D_SOLVES):
        res = solver3.modes(*dims_of(u))
        f = _residual(res, target)
        if _tuned(res, target, rel_tol):
            break
        if prev is not None:  # Broyden's update from the last step
            du, df = u - prev[0], f - prev[1]
            jac = jac + np.outer(df - jac @ du, du) / float(du @ du)
        prev = (u, f)
        u = u - np.linalg.lstsq(jac, f, rcond=None)[0]
    else:
        length, width = dims_of(u)
        raise ValueError(f"the 3D tuning did not converge in {MAX_3D_SOLVES} 3D solves from "
                         f"the 2D tuning (last plate {length * 1e3:.5g} x {width * 1e3:.5g} mm: "
                         f"L1 {res.L1.f_short_Hz:.2f} Hz, B2 {res.B2.f_short_Hz:.2f} Hz)")
    length, width = dims_of(u)
    return replace(
        d2,
        stator=solver3.stator(length, width),
        L1=ModeSummary(res.L1.f_short_Hz, res.L1.f_open_Hz, res.L1.k_eff),
        B2=ModeSummary(res.B2.f_short_Hz, res.B2.f_open_Hz, res.B2.k_eff),
        fe_solves=solves_2d + len(solver3.history),
        model="3d",
        history=tuple(solver2.history) + tuple(solver3.history),
        solves_3d=len(solver3.history),
    )


class TuningWarning(UserWarning):
    """A tuning that ended with L1 and B2 still apart: the split jumps across a change of the
    mesh (grid lines gained or lost as the plate grows) without crossing zero."""


MAX_ITER = 100
"""Largest ``max_iter`` of :func:`tune_plate` (the paper's plate to 40 kHz takes 3)."""

UNTUNED_FACTOR = 10.0
"""A held-dimension tuning whose final ``|f_B2/f_L1 - 1|`` exceeds this many times ``rel_tol``
is said not to be tuned (Brent's method converges onto a jump of the split as onto a root)."""


def _warn_untuned(solver: _Solver, free: str, x: float, res, rel_tol: float) -> None:
    """Warn when the crossing ``x`` (m) of the ``free`` dimension left the modes apart: the
    3D order-1 tuning of the paper's plate at fixed length ends at a width of 7.375 mm with
    the split 4.1e-3, where the mesh gains two grid lines and the split jumps from -229 Hz
    to +393 Hz, which Brent's method takes for the crossing."""
    split = res.B2.f_short_Hz / res.L1.f_short_Hz - 1.0
    if abs(split) <= UNTUNED_FACTOR * rel_tol:
        return
    k = 1 if free == "width" else 0
    seen = sorted((h[k], h[3] / h[2] - 1.0) for h in solver.history)
    below = [sp for v, sp in seen if v < x and sp * split < 0]
    above = [sp for v, sp in seen if v > x and sp * split < 0]
    side = below[-1] if below else above[0] if above else None
    jump = ("" if side is None else
            f", where it jumps between {min(side, split):+.2e} and {max(side, split):+.2e} "
            "without crossing zero (the mesh changes there: grid lines are gained or lost)")
    warnings.warn(TuningWarning(
        f"the {free} is not tuned: f_B2/f_L1 - 1 = {split:+.2e} remains at {free} "
        f"{x * 1e3:.5g} mm{jump}; a finer mesh (refine) moves the jump"), stacklevel=4)


def _tune(solver: _Solver, base: PlateStator, mat: PiezoMaterial, held: tuple[str, ...],
          fixed_dim: str | None, target_frequency_Hz: float | None, model: str,
          rel_tol: float, max_iter: int) -> TunedDesign:
    """The iteration of :func:`tune_plate` on a prepared ``solver``."""
    length, width = base.length_m, base.width_m
    if fixed_dim is not None:
        free = "width" if fixed_dim == "length" else "length"
        x = _crossing(solver, free, length, width, rel_tol)
        if free == "width":
            width = x
        else:
            length = x
        res = solver.modes(length, width)
        _warn_untuned(solver, free, x, res, rel_tol)
        iterations = 1
        tuned: tuple[str, ...] = (free,)
        target = None
    else:
        target = DEFAULT_TARGET_HZ if target_frequency_Hz is None else float(target_frequency_Hz)
        tuned = ("length", "width")
        iterations = 0
        for _ in range(max_iter):
            iterations += 1
            width = _crossing(solver, "width", length, width, rel_tol)
            res = solver.modes(length, width)
            f_l, f_b = res.L1.f_short_Hz, res.B2.f_short_Hz
            if abs(f_l / target - 1) < rel_tol and abs(f_b / target - 1) < rel_tol:
                break
            s = math.sqrt(f_l * f_b) / target
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
        target_frequency_Hz=target,
        L1=ModeSummary(res.L1.f_short_Hz, res.L1.f_open_Hz, res.L1.k_eff),
        B2=ModeSummary(res.B2.f_short_Hz, res.B2.f_open_Hz, res.B2.k_eff),
        fe_solves=len(solver.history),
        fix="+".join(held),
        model=model,
        material=mat.name,
        history=tuple(solver.history),
        outer_iterations=iterations,
        tuned=tuned,
    )
