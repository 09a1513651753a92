"""One description of a design-space study: the study TOML file, parsed and checked.

A study names its axes and the outputs it wants::

    [study]
    name = "length x width"

    [axes]                                   # every number carries its unit
    length = { start = "26 mm", stop = "34 mm", num = 3 }
    width = ["6.5 mm", "7.5 mm", "8.5 mm"]
    thickness = "3 mm"
    gap = "0.5 mm"
    material = "pzt8"                        # or a list: ["pzt8", "paper"]
    frequency = "auto"                       # or "40 kHz", a list or a range
    voltage = ["100 V", "200 V"]
    preload = "14 N"
    load = "0 N"

    [solver]
    fe_order = 2
    fe_refine = 4
    method = "steady"                        # or a transient: "event", ...
    duration = "50 ms"                       # a transient's run; default: each plate's
                                             # settling time, as lusm simulate's

    outputs = ["f_L1_short", "split", "no_load_velocity", "motion_class"]   # before [study]

An axis is one quantity (``"30 mm"``), a list of them, or an ascending range table with ``start``,
``stop`` and either ``num`` (points, both ends included) or ``step``. The geometry axes
(``length``, ``width``, ``thickness``, ``gap``, ``material``) make one FE solve each; the drive
axes (``frequency``, ``voltage``, ``preload``, ``load``) are the drive points of each geometry.
``frequency = "auto"`` drives each geometry at its own operating point
(:func:`contact.drive.auto_frequency`) and adds no dimension.

``[study] stator = "FILE.toml"`` starts every plate from a stator file
(:func:`fem.stator_file.load_stator`, a relative path from the study file's folder): its
features, material, damping and motor tables; ``length``, ``width``, ``thickness`` and
``gap`` vary its plate and default to the file's values; ``material`` is refused with it, and
``length``, ``width`` and ``gap`` with a stator that has its own mesh file. A parametric
stator's features are axes too (:data:`FEATURE_AXES`: ``tip_length``, ``tip_width``,
``chamfer``), dimensions only of the studies that name them.

A value is the double nearest the decimal typed in SI (``"6.5 mm"`` is 0.0065 m, as
``"0.0065 m"`` is), and a range's values the exact decimals ``start + i * step`` each rounded
once (:mod:`fem.units`), so that a coordinate is found by the number it stands for.

Every mistake (an unknown axis or output, an empty range, a number without its unit, a unit
of the wrong kind) raises ``ValueError`` with one line naming the key (``axes.length``).
Only the standard library (and :mod:`fem.units`, which imports no more) is imported at
module level (a stator file and the mesh bound load the FE modules they need when a study
asks for them).
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import os
import re
import tomllib
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

from fem.units import exact_si, nearest_float
from lusm import limits

GEOMETRY_AXES = ("length", "width", "thickness", "gap", "material")
"""Axes that change the stator (one FE solve per combination), in dimension order."""
FEATURE_AXES = ("tip_length", "tip_width", "chamfer")
"""Geometry axes of a parametric stator file's features (``[tip] length_mm``, ``width_mm``,
``[chamfers] size_mm``): dimensions of a study only when it names them, after
:data:`GEOMETRY_AXES`."""
FEATURE_FIELDS = {"tip_length": "tip_length_m", "tip_width": "tip_width_m",
                  "chamfer": "chamfer_m"}
"""The :class:`fem.meshing.parametric.ParametricStator` field each feature axis sets."""
DRIVE_AXES = ("frequency", "voltage", "preload", "load")
"""Axes of the drive points of one geometry, in dimension order."""

UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "mm": 1e-3, "um": 1e-6},
    "frequency": {"Hz": 1.0, "kHz": 1e3, "MHz": 1e6},
    "voltage": {"V": 1.0, "kV": 1e3},
    "force": {"N": 1.0, "mN": 1e-3, "kN": 1e3},
    "time": {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9},
}
"""Units accepted for each kind of quantity, and their factor to SI."""

AXIS_KIND = {"length": "length", "width": "length", "thickness": "length", "gap": "length",
             "tip_length": "length", "tip_width": "length", "chamfer": "length",
             "frequency": "frequency", "voltage": "voltage", "preload": "force",
             "load": "force"}
"""Kind of quantity of each numeric axis (``material`` is a name)."""
SI_UNIT = {"length": "m", "frequency": "Hz", "voltage": "V", "force": "N", "time": "s"}

DEFAULT_AXES: dict[str, Any] = {
    "length": "30 mm", "width": "7.5 mm", "thickness": "3 mm", "gap": "0.5 mm",
    "material": "pzt8", "frequency": "auto", "voltage": "200 V", "preload": "14 N",
    "load": "0 N",
}
"""The paper's plate and operating point, used for an axis the study does not name."""

OUTPUTS: dict[str, tuple[str, str]] = {
    "f_L1_short": ("Hz", "L1 natural frequency, electrodes short-circuited"),
    "f_L1_open": ("Hz", "L1 natural frequency, electrodes open"),
    "f_B2_short": ("Hz", "B2 natural frequency, electrodes short-circuited"),
    "f_B2_open": ("Hz", "B2 natural frequency, electrodes open"),
    "k_eff": ("1", "effective electromechanical coupling factor of L1 and B2"),
    "split": ("Hz", "L1-B2 split f_B2_short - f_L1_short"),
    "no_load_velocity": ("m/s", "steady slider velocity without load"),
    "stall_force": ("N", "load at which the slider stops"),
    "peak_efficiency": ("1", "largest mechanical/electrical efficiency along the characteristic"),
    "peak_power": ("W", "largest mechanical power v F along the characteristic"),
    "limit_ratio": ("1", "largest of the unloaded steady state's vibration velocity, stress, "
                         "drive field and heat density over the material's limit"),
    "motion_class": ("", "stick/slip/separation class of the unloaded steady state "
                         "(lusm simulate's)"),
    "velocity": ("m/s", "steady slider velocity at the point's load"),
}
"""Outputs a study may ask for: name -> (unit, meaning)."""
FE_OUTPUTS = ("f_L1_short", "f_L1_open", "f_B2_short", "f_B2_open", "k_eff", "split")
"""Outputs that need only the FE solve (no contact model)."""

FE_REFINE_DEFAULT = 4
"""The study's default mesh refinement: :data:`fem.meshing.mesh.DEFAULT_REFINE`, that of ``lusm
modes``, ``simulate`` and ``characteristic`` (written out so that parsing imports no FE module; a
test holds them equal). A default of 2 put the paper's plate's auto drive frequency 113 Hz and B2
145 Hz above the single-point commands' and a stall force 11 % low."""

SOLVER_DEFAULTS: dict[str, Any] = {"fe_order": 2, "fe_refine": FE_REFINE_DEFAULT,
                                   "duration": "50 ms", "dt": None, "method": "steady",
                                   "accuracy": "exact", "ultrasonic_friction": True,
                                   "rest": "probe"}
"""Solver settings when the study gives none: those of the single-point commands. A
transient without ``duration`` runs ``lusm simulate``'s default, each plate's settling time
of at least 50 ms (:attr:`Solver.settle`), and without ``dt`` its step is simulate's rule
(:func:`lusm.options.time_step_s`: the largest step up to 100 ns that divides the drive
period), so that a study's point and the command's are the same run."""

MAX_GEOMETRIES = 100_000
"""FE solves of one study (multiplied by ``LUSM_MAX_WORK``)."""
MAX_STUDY_FE_WORK = 10_000_000
"""2D elements x FE solves of one study, each plate counted at the study's largest mesh
(multiplied by ``LUSM_MAX_WORK``): a hundred times a sweep's bound
(:data:`lusm.limits.MAX_FE_WORK_2D`), as a study runs on a cluster: 100 000 default
plates (85 elements each) or 1 000 at ``fe_refine = 48``. The geometry count alone would
let 100 000 plates at ``fe_refine = 48`` start (days of work, gigabytes in the client)."""
MAX_DRIVE_POINTS = 10_000
"""Drive points of one geometry (multiplied by ``LUSM_MAX_WORK``)."""
MAX_STUDY_POINTS = 1_000_000
"""Drive points of a whole study, geometries x drive points (multiplied by ``LUSM_MAX_WORK``):
each is a contact solve (steady: milliseconds to ~0.5 s; transient: seconds), so the two
bounds above together allowed 1e9 of them."""

CURVE_LOADS = 21
"""Loads of the characteristic a steady drive point runs (:func:`contact.characteristic.
characteristic`'s default), for its stall force and peak efficiency."""
STEADY_MIN_STEPS_PER_PERIOD = 25
"""The fewest steps per drive period the steady engine takes on any set
(``contact.steady.periodic_orbit.STEPS_PER_PERIOD``, written out so that reading a study imports no
kernel module): a study's steady work is at least its solves times this, before any plate's
own figure (:func:`contact.steady.slow.steps_per_period`) is known."""

_QUANTITY = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z]+)\s*$")


@dataclass(frozen=True)
class Solver:
    """Solver settings of a study.

    Attributes
    ----------
    fe_order, fe_refine : int
        FE element order (1, 2) and mesh refinement (elements per smaller plate dimension).
    duration_s : float
        Simulated time of each transient drive point (s); with ``settle`` the shortest.
    dt_s : float or None
        Time step of each transient drive point (s); None: ``lusm simulate``'s default rule
        at the point's frequency (:meth:`step_s`).
    method : str
        ``"steady"``: the motor answers from :mod:`contact.steady.engine` and
        :func:`contact.characteristic.characteristic` (stall force, peak efficiency, velocity
        under load; ``duration``/``dt`` unused); otherwise a transient scheme of
        :func:`contact.simulate.simulate`, which gives the no-load velocity and motion class
        only (velocity under a load is then NaN).
    accuracy : str
        The steady engine's level with ``method = "steady"``: ``"exact"`` (the finite-mass
        motor from rest, as ``lusm characteristic`` and ``lusm map`` by default) or
        ``"fast"`` (averaged, slider mass -> infinity: about half the time, blind to creeps
        and holds below the slider's velocity ripple; at 400 V its stall force on the paper's
        plate is half the exact one).
    ultrasonic_friction : bool
        Eq. 11's ultrasonic reduction of the dynamic friction coefficient (True, as every
        single-point command by default); False takes the constant ``mu_d``, as their
        ``--no-ultrasonic-friction``.
    rest : str
        How the exact level decides the branch a start from rest reaches: ``"probe"`` (the
        default, as the commands') or ``"transient"`` (their ``--rest transient``;
        :func:`contact.steady.engine.steady_state`).
    settle : bool
        A transient without a typed ``duration``: each plate runs ``lusm simulate``'s default,
        its drive points' longest settling time (:func:`contact.drive.default_duration_s`),
        at least ``duration_s`` and at most the step bound (:func:`transient_top_s`), and the
        dataset records it per plate (``duration``). False: every plate runs ``duration_s``.
    """

    fe_order: int = 2
    fe_refine: int = FE_REFINE_DEFAULT
    duration_s: float = 0.05
    dt_s: float | None = None
    method: str = "steady"
    accuracy: str = "exact"
    ultrasonic_friction: bool = True
    rest: str = "probe"
    settle: bool = False

    def step_s(self, frequency_Hz: float) -> float:
        """The time step (s) of a transient at ``frequency_Hz`` (Hz): ``dt_s`` as the study
        gives it, else the largest step up to 100 ns that makes the drive period a whole
        number of steps (as ``lusm simulate``)."""
        if self.dt_s is not None:
            return float(self.dt_s)
        from contact.options import default_time_step_s

        return default_time_step_s(frequency_Hz)


@dataclass(frozen=True)
class Study:
    """A parsed study: axes in SI units, wanted outputs, solver settings.

    Attributes
    ----------
    name : str
    axes : dict
        Axis name -> tuple of values: SI floats (m, Hz, V, N) or material names. The
        ``frequency`` axis is ``("auto",)`` for the auto rule.
    outputs : tuple of str
        Keys of :data:`OUTPUTS`, in the order of :data:`OUTPUTS`.
    solver : Solver
    source : str
        The study file (or ``"<dict>"``), for provenance.
    text : str
        The study as canonical JSON (provenance and the resume check).
    stator : fem.stator_file.StatorDesign or None
        ``[study] stator``: the stator file the plates start from (its features, material,
        damping and motor tables; the geometry axes vary its plate), or None: the paper's
        plain plate with Table 2's motor constants.
    """

    name: str
    axes: dict[str, tuple]
    outputs: tuple[str, ...]
    solver: Solver
    source: str = "<dict>"
    text: str = field(default="", repr=False)
    stator: Any = field(default=None, repr=False, compare=False)

    @property
    def auto_frequency(self) -> bool:
        """True when each geometry is driven at its own operating point."""
        return self.axes["frequency"] == ("auto",)

    @property
    def meshed_by_gmsh(self) -> bool:
        """Whether the plates are meshed by gmsh: a parametric stator file (``[tip]``,
        ``[chamfers]``, ``[[holes]]``)."""
        return _parametric(self.stator)

    @property
    def geometry_axes(self) -> tuple[str, ...]:
        """The geometry dimensions: :data:`GEOMETRY_AXES`, then the :data:`FEATURE_AXES` the
        study names."""
        return GEOMETRY_AXES + tuple(a for a in FEATURE_AXES if a in self.axes)

    @property
    def geometry_shape(self) -> tuple[int, ...]:
        """Sizes of the geometry axes, in :attr:`geometry_axes` order."""
        return tuple(len(self.axes[a]) for a in self.geometry_axes)

    @property
    def drive_dims(self) -> tuple[str, ...]:
        """Drive dimensions of the dataset (``frequency`` only when it is not ``auto``)."""
        return tuple(a for a in DRIVE_AXES if not (a == "frequency" and self.auto_frequency))

    @property
    def n_geometries(self) -> int:
        """Number of FE solves."""
        return math.prod(self.geometry_shape)

    @property
    def n_drive_points(self) -> int:
        """Drive points of one geometry."""
        return math.prod(len(self.axes[a]) for a in self.drive_dims)

    @property
    def needs_motor(self) -> bool:
        """Whether any output needs the contact model."""
        return any(o not in FE_OUTPUTS for o in self.outputs)

    @property
    def fingerprint(self) -> str:
        """SHA-256 of the canonical study without its name (what resume compares): the name
        defaults to the file's stem, and a copy of the same study under another file name
        is the same study."""
        doc = json.loads(self.text) if self.text else {}
        if isinstance(doc, dict):
            doc.pop("name", None)
            # the stator file's contents count, not where it lies nor its comments and
            # layout (a trailing newline does not make it another study)
            doc.get("stator", {}).pop("file", None)
            doc.get("stator", {}).pop("sha256", None)
        return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()


def _canonical_solver(solver: Solver) -> dict:
    """The solver's settings as the study's canonical text holds them: ``settle`` only where
    it is set (a study that does not follow the settling time keeps its fingerprint)."""
    d = dict(solver.__dict__)
    if not d["settle"]:
        del d["settle"]
    return d


def transient_top_s(solver: Solver, frequency_Hz: float) -> float:
    """The longest transient (s) a drive point at ``frequency_Hz`` (Hz) may run: the step
    bound of :func:`transient_problem` (and the reference scheme's period bound)."""
    f = float(frequency_Hz)
    top = limits.work_bound(limits.MAX_STEPS) * solver.step_s(f) * (1 - 1e-12)
    if solver.method == "reference":
        from contact.transient.reference import MAX_REFERENCE_PERIODS

        top = min(top, limits.work_bound(MAX_REFERENCE_PERIODS) / f * (1 - 1e-12))
    return top


def _where(source: str) -> str:
    return "" if source == "<dict>" else f"{source}: "


def parse_quantity(value: Any, kind: str, key: str) -> float:
    """A quantity string (``"30 mm"``) in SI units; ``key`` names it in the error.

    The value is the double nearest the decimal typed times its unit (:func:`fem.units.
    to_si`): ``"6.5 mm"`` is 0.0065, as ``"0.0065 m"`` is (``6.5 * 1e-3`` is
    0.006500000000000001, a coordinate ``sel(width=0.0065)`` does not find, and the same
    study written in m would have another fingerprint)."""
    return nearest_float(_exact_quantity(value, kind, key))


def _exact_quantity(value: Any, kind: str, key: str) -> Fraction:
    """:func:`parse_quantity`'s value before it is rounded to a float: exact, for a range's
    arithmetic, and refused unless that float is finite."""
    if isinstance(value, bool) or not isinstance(value, (str, int, float)):
        raise ValueError(f"{key} must be a quantity such as '1 {_example_unit(kind)}', "
                         f"got {value!r}")
    if not isinstance(value, str):
        raise ValueError(f"{key}: the number {value!r} has no unit; write it as a string with "
                         f"its unit, e.g. '{value} {_example_unit(kind)}' "
                         f"(units: {', '.join(UNITS[kind])})")
    m = _QUANTITY.match(value)
    if m is None:
        if re.match(r"^\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*$", value):
            raise ValueError(f"{key}: the number {value!r} has no unit; write e.g. "
                             f"'{value.strip()} {_example_unit(kind)}' "
                             f"(units: {', '.join(UNITS[kind])})")
        raise ValueError(f"{key} must be a number with a unit such as "
                         f"'1 {_example_unit(kind)}', got {value!r}")
    number, unit = m.group(1), m.group(2)
    if unit not in UNITS[kind]:
        raise ValueError(f"{key}: unit {unit!r} is not a {kind}; use one of "
                         f"{', '.join(UNITS[kind])}")
    try:
        out = exact_si(number, UNITS[kind][unit])
        nearest_float(out)  # a finite float
    except ValueError:
        raise ValueError(f"{key} must be finite, got {value!r}") from None
    return out


def _example_unit(kind: str) -> str:
    return {"length": "mm", "frequency": "kHz", "voltage": "V", "force": "N",
            "time": "ms"}[kind]


def _axis_values(name: str, raw: Any, key: str) -> tuple:
    if name == "material":
        items = raw if isinstance(raw, list) else [raw]
        if not items:
            raise ValueError(f"{key} is an empty list; name at least one material")
        from fem.material import MATERIAL_NAMES

        for m in items:
            if not isinstance(m, str) or m.strip().lower().replace("-", "") not in MATERIAL_NAMES:
                raise ValueError(f"{key} must name materials among {', '.join(MATERIAL_NAMES)}, "
                                 f"got {m!r}")
        out = tuple(m.strip().lower().replace("-", "") for m in items)
    elif name == "frequency" and isinstance(raw, str) and raw.strip().lower() == "auto":
        return ("auto",)
    else:
        kind = AXIS_KIND[name]
        if isinstance(raw, list):
            if not raw:
                raise ValueError(f"{key} is an empty list; give at least one value")
            out = tuple(parse_quantity(v, kind, f"{key}[{i}]") for i, v in enumerate(raw))
        elif isinstance(raw, dict):
            out = _range(raw, kind, key)
        else:
            out = (parse_quantity(raw, kind, key),)
        check_range(name, out, key)
    if len(set(out)) != len(out):
        raise ValueError(f"{key} repeats a value; each value of an axis must be distinct")
    return out


def _range(raw: dict, kind: str, key: str) -> tuple[float, ...]:
    """A range table's values (SI): the decimals ``start + i * step``, or ``num`` points
    from ``start`` to ``stop`` evenly, computed exactly and each rounded once to the nearest
    double, so that a range's point is the value the same decimal gets typed alone
    (:func:`parse_quantity`). Summed in binary arithmetic, 25.9 mm is
    0.025900000000000003 m, one ulp from a stator file's ``length_mm = 25.9``, and a
    gmsh-meshed plate 1 ulp longer is meshed anew (its L1 0.6 Hz off the single-point
    command's)."""
    unknown = sorted(set(raw) - {"start", "stop", "num", "step"})
    if unknown:
        raise ValueError(f"{key}.{unknown[0]} is not a range key; use start, stop and num or "
                         "step")
    for k in ("start", "stop"):
        if k not in raw:
            raise ValueError(f"{key}.{k} is missing; a range needs start, stop and num or step")
    start = _exact_quantity(raw["start"], kind, f"{key}.start")
    stop = _exact_quantity(raw["stop"], kind, f"{key}.stop")
    if ("num" in raw) == ("step" in raw):
        raise ValueError(f"{key} needs exactly one of num or step")
    if stop < start:  # with num as with step (num took it silently, in descending order)
        raise ValueError(f"{key} is an empty range: stop {raw['stop']!r} is below start "
                         f"{raw['start']!r}; a range ascends from start to stop (a list takes "
                         "its values in any order)")
    top = limits.work_bound(limits.MAX_GRID_POINTS)
    if "num" in raw:
        num = raw["num"]
        if isinstance(num, bool) or not isinstance(num, int) or num < 1:
            raise ValueError(f"{key}.num must be an integer >= 1, got {num!r}")
        if num > top:
            raise ValueError(f"{key}.num must be <= {top}, got {num}")
        if num == 1:
            if start != stop:
                raise ValueError(f"{key}.num = 1 needs start == stop")
            return (nearest_float(start),)
        exact = [start + (stop - start) * i / (num - 1) for i in range(num)]
    else:
        step = _exact_quantity(raw["step"], kind, f"{key}.step")
        if step <= 0:
            raise ValueError(f"{key}.step must be > 0, got {raw['step']!r}")
        n = math.floor((stop - start) / step) + 1  # exact: stop itself when step divides
        if n > top:
            raise ValueError(f"{key} has {n} points, above the limit {top}; use a larger step")
        exact = [start + i * step for i in range(n)]
    out = tuple(nearest_float(v) for v in exact)
    if len(set(out)) < len(out):  # a range too fine, not a list that repeats a value
        raise ValueError(f"{key} is finer than a float can tell apart near its start "
                         f"{raw['start']!r}: use a larger step or fewer points")
    return out


def check_range(name: str, values: tuple[float, ...], key: str) -> None:
    """Refuse a value outside the CLI's range for the axis, in the range's unit (mm, Hz, V,
    N): lengths are stored in m but written, and reported, in mm."""
    kind = AXIS_KIND[name]
    scale, unit = 1.0, {"frequency": "Hz", "voltage": "V"}.get(kind, "N")
    if kind == "length":
        scale, unit = 1e3, "mm"
        lo, hi = limits.PLATE_MM  # a gap's lower end: below
    elif kind == "frequency":
        lo, hi = limits.FREQUENCY_HZ
    elif kind == "voltage":
        lo, hi = limits.VOLTAGE_V
    elif name == "preload":
        lo, hi = limits.PRELOAD_N
    else:  # load: a braking force, >= 0
        lo, hi = 0.0, limits.PRELOAD_N[1]
    if name in FEATURE_AXES:  # bounded by the plate: the stator checks each plate's
        bad = [v for v in values if not v > 0.0]
        if bad:
            raise ValueError(f"{key} values must be > 0 mm (a feature's size; the stator "
                             f"file's plate bounds it from above), got {bad[0] * scale:g} mm")
        return
    if name == "gap":
        # 0 (touching quadrants) or the CLI's --gap-mm range: below 1 um the gap's
        # cross-section solve cannot be modelled: refused here, in the study's terms, not
        # per geometry after the FE setup
        from fem.geometry import MIN_GAP_M

        lo = MIN_GAP_M * 1e3
        bad = [v for v in values if v != 0.0 and not lo <= v * scale <= hi]
        if bad:
            raise ValueError(f"{key} values must be 0 or lie in [{lo:g}, {hi:g}] {unit}, got "
                             f"{bad[0] * scale:g} {unit}")
        return
    bad = [v for v in values if not lo <= v * scale <= hi]
    if bad:
        raise ValueError(f"{key} values must lie in [{lo:g}, {hi:g}] {unit}, got "
                         f"{bad[0] * scale:g} {unit}")


def _solver(raw: dict, where: str) -> Solver:
    unknown = sorted(set(raw) - set(SOLVER_DEFAULTS))
    if unknown:
        raise ValueError(f"{where}solver.{unknown[0]} is not a solver setting; use "
                         f"{', '.join(SOLVER_DEFAULTS)}")
    s = {**SOLVER_DEFAULTS, **raw}
    for k in ("fe_order", "fe_refine"):
        if isinstance(s[k], bool) or not isinstance(s[k], int):
            raise ValueError(f"{where}solver.{k} must be an integer, got {s[k]!r}")
    if s["fe_order"] not in (1, 2):
        raise ValueError(f"{where}solver.fe_order must be 1 or 2, got {s['fe_order']!r}")
    if not 1 <= s["fe_refine"] <= limits.MAX_REFINE_2D:
        raise ValueError(f"{where}solver.fe_refine must lie in [1, {limits.MAX_REFINE_2D}], "
                         f"got {s['fe_refine']!r}")
    duration = parse_quantity(s["duration"], "time", f"{where}solver.duration")
    dt = None if s["dt"] is None else parse_quantity(s["dt"], "time", f"{where}solver.dt")
    if dt is not None and not (0 < dt <= 1e-3):
        raise ValueError(f"{where}solver.dt must lie in (0, 1 ms], got {s['dt']!r}")
    if not (0 < duration <= limits.DURATION_S[1]):
        raise ValueError(f"{where}solver.duration must lie in (0, {limits.DURATION_S[1]:g} s], "
                         f"got {s['duration']!r}")
    if s["method"] not in ("steady", "event", "reference", "literal"):
        raise ValueError(f"{where}solver.method must be steady, event, reference or literal, "
                         f"got {s['method']!r}")
    if s["accuracy"] not in ("fast", "exact"):
        raise ValueError(f"{where}solver.accuracy must be fast or exact, got "
                         f"{s['accuracy']!r}")
    if s["rest"] not in ("probe", "transient"):
        raise ValueError(f"{where}solver.rest must be probe or transient, got {s['rest']!r}")
    if not isinstance(s["ultrasonic_friction"], bool):
        raise ValueError(f"{where}solver.ultrasonic_friction must be true or false, got "
                         f"{s['ultrasonic_friction']!r}")
    return Solver(s["fe_order"], s["fe_refine"], duration, dt, s["method"], s["accuracy"],
                  s["ultrasonic_friction"], s["rest"],
                  settle="duration" not in raw and s["method"] != "steady")


def study_from_dict(doc: dict, source: str = "<dict>") -> Study:
    """Check a study given as the parsed TOML document and build a :class:`Study`.

    Raises
    ------
    ValueError
        One line naming the offending key (``axes.length``, ``outputs[2]``, ...).
    """
    where = _where(source)
    unknown = sorted(set(doc) - {"study", "axes", "outputs", "solver"})
    if unknown:
        raise ValueError(f"{where}{unknown[0]} is not a study section; use study, axes, "
                         "outputs and solver")
    name, meta = _study_table(doc.get("study", {}), source, where)
    raw_axes = doc.get("axes", {})
    if not isinstance(raw_axes, dict):
        raise ValueError(f"{where}axes must be a table of axes")
    _check_axis_names(raw_axes, where)
    design, stamp = (None, None) if "stator" not in meta else _stator(meta["stator"], source,
                                                                       where)
    axes = _axes(raw_axes, design, where)
    outputs = _outputs(doc.get("outputs", list(OUTPUTS)), where)
    _check_motor_drivable(outputs, axes, raw_axes, design, where)
    raw_solver = doc.get("solver", {})
    if not isinstance(raw_solver, dict):
        raise ValueError(f"{where}solver must be a table")
    solver = _solver(raw_solver, where)
    if design is not None and "fe_refine" in raw_solver and _planform(design):
        import warnings

        how = ("its own mesh file" if design.mesh_path is not None
               else "gmsh at its [mesh] size_mm (default min(length, width) / 8)")
        warnings.warn(f"{where}solver.fe_refine is unused: study.stator {design.path} is "
                      f"meshed by {how}", stacklevel=2)
    study = Study(name, axes, outputs, solver, source, stator=design)
    _warn_unused_solver(study, raw_solver, where)
    _warn_unused_drive(study, raw_axes, where)
    _check_geometry_count(study, where)  # before building the plates one by one
    if design is not None:
        _check_stator_plates(study, where)
    _check_work(study, where)
    # strict JSON: a stator mesh's gap (NaN) as null
    canonical = {"name": name, "axes": {a: [None if isinstance(v, float) and math.isnan(v)
                                            else v for v in vs] for a, vs in axes.items()},
                 "outputs": outputs, "solver": _canonical_solver(solver)}
    if stamp is not None:
        canonical["stator"] = stamp
    text = json.dumps(canonical, sort_keys=True)
    return Study(name, axes, outputs, solver, source, text, design)


def _study_table(meta: Any, source: str, where: str) -> tuple[str, dict]:
    """The study's name and its ``[study]`` table, checked."""
    if not isinstance(meta, dict):  # `study = "x"` is not a table
        raise ValueError(f"{where}study must be a table ([study] with name = \"...\"), got "
                         f"{meta!r}")
    if sorted(set(meta) - {"name", "stator"}):
        bad = sorted(set(meta) - {"name", "stator"})
        raise ValueError(f"{where}study.{bad[0]} is not a study key; use name or stator")
    if "name" in meta and not (isinstance(meta["name"], str) and meta["name"].strip()):
        raise ValueError(f"{where}study.name must be a non-empty string, got {meta['name']!r}")
    return str(meta.get("name", Path(source).stem if source != "<dict>" else "study")), meta


def _check_axis_names(raw_axes: dict, where: str) -> None:
    """Refuse an axis that does not exist, with the unit-free name where one was meant."""
    allowed = GEOMETRY_AXES + DRIVE_AXES + FEATURE_AXES
    for k in raw_axes:
        if k not in allowed:
            hint = ""
            m = re.match(r"^(\w+?)_(mm|m|um|hz|khz|v|n)$", k, re.IGNORECASE)
            if m and m.group(1) in allowed:
                hint = f" (write '{m.group(1)} = \"30 {m.group(2)}\"': units go with values)"
            raise ValueError(f"{where}axes.{k} is not an axis; use one of "
                             f"{', '.join(allowed)}{hint}")


def _axes(raw_axes: dict, design, where: str) -> dict[str, tuple]:
    """Every axis's values (SI): as the study gives them, else the stator file's plate, else
    the paper's; features only where the study varies them."""
    features = [a for a in FEATURE_AXES if a in raw_axes]
    if features and not _parametric(design):
        raise ValueError(f"{where}axes.{features[0]} varies a parametric stator's feature: it "
                         "needs study.stator naming a stator file with [tip], [chamfers] or "
                         "[[holes]] (docs/designer.md)")
    tip = [a for a in ("tip_length", "tip_width") if a in features]
    if len(tip) == 1 and not design.stator.tip_length_m > 0.0:
        other = "tip_width" if tip[0] == "tip_length" else "tip_length"
        raise ValueError(f"{where}axes.{tip[0]} needs a tip {other.split('_')[1]} too: the "
                         f"stator file {design.path} has no [tip]; give axes.{other} as well")
    if design is not None:
        _check_stator_axes(design, raw_axes, where)
    own = {} if design is None else _stator_values(design)
    axes = {a: own[a] if a in own and a not in raw_axes
            else _axis_values(a, raw_axes.get(a, DEFAULT_AXES.get(a)), f"{where}axes.{a}")
            for a in GEOMETRY_AXES + DRIVE_AXES + FEATURE_AXES
            if a not in FEATURE_AXES or a in raw_axes}
    for g in axes["gap"]:
        smallest = min(min(axes["length"]), min(axes["width"]))
        if g >= smallest:
            gap = (f"study.stator {design.path}'s [electrodes] gap_mm"
                   if design is not None and "gap" not in raw_axes else "axes.gap")
            raise ValueError(f"{where}{gap} {g * 1e3:g} mm must be below every length and "
                             f"width of the study (smallest {smallest * 1e3:g} mm)")
    return axes


def _outputs(outputs: Any, where: str) -> tuple[str, ...]:
    """The outputs asked for, each once, in :data:`OUTPUTS` order."""
    if not isinstance(outputs, list) or not outputs:
        raise ValueError(f"{where}outputs must be a non-empty list among {', '.join(OUTPUTS)}")
    for i, o in enumerate(outputs):
        if o not in OUTPUTS:
            raise ValueError(f"{where}outputs[{i}] {o!r} does not exist; use "
                             f"{', '.join(OUTPUTS)}")
        if o in outputs[:i]:  # as a repeated axis value is: a typo, most likely
            raise ValueError(f"{where}outputs[{i}] {o!r} is listed twice")
    return tuple(o for o in OUTPUTS if o in outputs)


def _check_motor_drivable(outputs: tuple[str, ...], axes: dict, raw_axes: dict, design,
                          where: str) -> None:
    """Refuse, before any FE solve, motor outputs that no plate of the study can give: a
    gap of 0 (one conductor, driven as a short circuit), or a stator file whose motor
    tables do not fit Table 2's other constants."""
    motor = [o for o in outputs if o not in FE_OUTPUTS]
    if not motor:
        return
    if design is not None and "gap" not in raw_axes and 0.0 in axes["gap"]:
        raise ValueError(f"{where}study.stator {design.path}: its [electrodes] gap_mm 0 makes "
                         "the four electrodes one conductor, which the motor outputs "
                         f"({', '.join(motor)}) would drive as a short circuit; give the file "
                         "a gap of at least 0.001 mm, or ask for FE outputs only")
    if design is not None:
        from rom.from_fem import design_base

        try:
            design_base(design)
        except ValueError as exc:
            raise ValueError(f"{where}study.stator {str(exc).splitlines()[0]}") from None
        _check_stator_wiring(design, where)
    if 0.0 in axes["gap"]:
        # one conductor cannot be driven at V on 1, 4 and grounded on 2, 3 (fem.model
        # ShortedDriveError)
        raise ValueError(f"{where}axes.gap 0 mm makes the four electrodes one conductor, "
                         f"which the motor outputs ({', '.join(motor)}) would drive as a short "
                         "circuit; give a gap of at least 0.001 mm, or ask for FE outputs only")


def _check_stator_wiring(design, where: str) -> None:
    """Refuse, before any FE work, a stator file with its own mesh whose drive puts two
    voltages on electrodes that touch (one conductor), in the words the single-point
    commands say it (:func:`fem.model.check_mesh_wiring`): every plate of the study would
    fail at its parameter set."""
    if design.mesh_path is None:  # a generated plate's gap is checked with the axes
        return
    from fem.meshing.meshed_stator import planform_mesh
    from fem.model import check_mesh_wiring

    try:
        check_mesh_wiring(planform_mesh(design.stator),
                          {e: 1.0 for e in design.stator.drive_electrodes})
    except ValueError as exc:
        raise ValueError(f"{where}study.stator {design.path} (a mesh whose electrode tags "
                         f"touch): {exc}; give a mesh with gap strips") from None


def _stator(value: Any, source: str, where: str):
    """``[study] stator``: the loaded :class:`fem.stator_file.StatorDesign` and its stamp
    (the file's path and the SHA-256 of the file and of its mesh file, what resume compares).
    A relative path is taken from the study file's folder (the working directory for a study
    given as a dict)."""
    if not (isinstance(value, str) and value.strip()):
        raise ValueError(f"{where}study.stator must name a stator TOML file (docs/designer.md), "
                         f"got {value!r}")
    from fem.stator_file import load_stator

    path = Path(value)
    if not path.is_absolute() and source != "<dict>":
        path = Path(source).parent / path
    try:
        design = load_stator(path)
        stamp = {"file": os.path.abspath(path), "sha256": _file_sha256(path),
                 "content_sha256": _toml_content_sha256(path)}
        if design.mesh_path is not None:
            stamp["mesh_sha256"] = _file_sha256(design.mesh_path)
    except (ValueError, OSError) as exc:
        from lusm.errors import design_error_text

        raise ValueError(f"{where}study.stator {design_error_text(path, exc)}") from None
    return design, stamp


def _parametric(design) -> bool:
    """Whether a stator file (None: none) is a parametric stator, meshed by gmsh."""
    if design is None:
        return False
    from fem.meshing.parametric import ParametricStator

    return isinstance(design.stator, ParametricStator)


def _toml_content_sha256(path: Path) -> str:
    """SHA-256 of a TOML file's parsed contents as canonical JSON: the same for the same
    keys and values whatever the comments, spacing and key order."""
    import tomllib

    with open(path, "rb") as f:
        doc = tomllib.load(f)
    return hashlib.sha256(json.dumps(doc, sort_keys=True, default=str).encode()).hexdigest()


def _file_sha256(path: Path) -> str:
    """SHA-256 of a file, read in blocks (a mesh file may be megabytes)."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def plate_with(base, dims: dict[str, float]):
    """``base`` (a :class:`fem.geometry.PlateStator` or a subclass) with the fields ``dims``
    (SI) replaced, checked as the class checks them; ``base`` itself where no value differs.
    A NaN value is no change: a stator with its own mesh has no gap of its own."""
    from dataclasses import replace

    changed = {k: v for k, v in dims.items() if not math.isnan(v) and getattr(base, k) != v}
    return replace(base, **changed) if changed else base


def _stator_values(design) -> dict[str, tuple]:
    """The geometry axes' values of a stator file's own plate (SI, material name); the gap of
    a stator with its own mesh is NaN: its electrodes are the mesh's tagged regions (the
    plate's nominal gap, 0, would be a short circuit for every motor output)."""
    from fem.meshing.meshed_stator import MeshedStator

    st = design.stator
    gap = math.nan if isinstance(st, MeshedStator) else st.electrode_gap_m
    return {"length": (st.length_m,), "width": (st.width_m,), "thickness": (st.thickness_m,),
            "gap": (gap,), "material": (design.material.name,)}


def _check_stator_axes(design, raw_axes: dict, where: str) -> None:
    """Refuse the geometry axes a stator file cannot take: ``material`` (the file sets it)
    and, for a stator with a mesh file of its own, ``length``, ``width`` and ``gap`` (a
    study cannot rescale a mesh; its plane-stress ``thickness`` can vary)."""
    if "material" in raw_axes:
        raise ValueError(f"{where}axes.material cannot be combined with study.stator: the "
                         f"stator file {design.path} sets the material; drop axes.material")
    given = [a for a in ("length", "width", "gap") if a in raw_axes]
    if given and design.mesh_path is not None:
        raise ValueError(f"{where}axes.{given[0]} cannot vary study.stator {design.path}: it has "
                         f"its own mesh ({design.mesh_path}), which a study cannot rescale "
                         "(axes.thickness can vary); drop those axes, or give a stator file "
                         "without [mesh] file")


def _check_stator_plates(study: Study, where: str) -> None:
    """Refuse, before any FE solve, a study whose plates no longer hold the stator file's
    features (tip, chamfers, holes: kept as the file gives them, as ``lusm sweep --geometry``
    keeps them), naming the axis values of the first plate that does not. (A stator with its
    own mesh varies in thickness only, which holds every feature.)"""
    from fem.meshing.meshed_stator import MeshedStator
    from lusm.errors import feature_reason

    design, ax = study.stator, study.axes
    base = design.stator
    if isinstance(base, MeshedStator):
        return
    fields = {"length": "length_m", "width": "width_m", "gap": "electrode_gap_m",
              **{a: f for a, f in FEATURE_FIELDS.items() if a in ax}}
    names = list(fields)
    for combo in itertools.product(*(ax[a] for a in names)):
        dims = {fields[a]: v for a, v in zip(names, combo, strict=True)}
        try:  # the file's own plate was checked when it was read
            plate_with(base, dims)
        except ValueError as exc:
            reason = feature_reason(exc).splitlines()[0]  # the file's terms (mm, hole numbers)
            named = [f"axes.{a} {v * 1e3:g} mm" for a, v in zip(names, combo, strict=True)
                     if len(ax[a]) > 1 or v != getattr(base, fields[a])]
            length, width = dims["length_m"], dims["width_m"]
            raise ValueError(
                f"{where}{', '.join(named)}: the {length * 1e3:g} x {width * 1e3:g} mm plate "
                f"no longer holds the features of study.stator {design.path} ({reason}); the "
                "study keeps the file's other features as given: choose axes whose plates "
                "keep them") from None


def _largest_mesh(study: Study) -> tuple[int, float, float, bool]:
    """Elements of the study's largest 2D mesh, its length and width (m), and whether the count
    is an estimate, all without making a 2D mesh: the mesh grows with the plate's elongation
    (at the default element size) or its area (at a fixed one), so one of the four corners of
    the length x width grid (at the smallest gap, which adds the most grid lines) has it.

    A generated plate's count is exact (its grid lines). A stator file's planform meshed by
    gmsh is estimated from the 1D mesh of its boundary
    (:func:`fem.meshing.parametric.estimated_elements`, milliseconds: within 4 % on fine meshes, 1.5
    times low at the default size, up to :data:`fem.meshing.parametric.ESTIMATE_LOW_FACTOR` low on
    blocks of holes, never high): an estimate above a bound refuses the study without a
    mesh, one that far below both bounds (the mesh's, and the study's FE work over its
    plates) cannot cross them passes, and a plate in between is meshed to count exactly (the
    estimate alone can be up to 6.5 times low against the study's bound). The area over the
    element size squared is 2.2 times low on the tuned 60 kHz stator's default mesh, so it is
    not used. One with its own mesh file is the file's, whatever the axes."""
    from fem.cell_count import fe_cell_count
    from fem.geometry import PlateStator
    from fem.meshing.meshed_stator import MeshedStator
    from fem.meshing.parametric import ESTIMATE_LOW_FACTOR, ParametricStator, estimated_elements
    from fem.modes import wider_than_long

    ax = study.axes
    base = PlateStator() if study.stator is None else study.stator.stator
    if isinstance(base, MeshedStator):  # its own mesh: the file's count
        return fe_cell_count(base, None), base.length_m, base.width_m, False
    gap = min(ax["gap"])
    # the tighter of the two bounds a plate's mesh is held to (per mesh; the study's FE work
    # shared over its plates)
    bound = min(limits.work_bound(limits.MAX_FE_CELLS_2D),
                limits.work_bound(MAX_STUDY_FE_WORK) / max(study.n_geometries, 1))
    # the feature axes at their largest area: the longest, widest tip, the smallest chamfer
    # (a 30 mm tip on the axis is refused as lusm modes refuses it, not meshed)
    features = {f: (min if a == "chamfer" else max)(ax[a])
                for a, f in FEATURE_FIELDS.items() if a in ax}
    corners = [(length, width, plate_with(base, {"length_m": length, "width_m": width,
                                                 "electrode_gap_m": gap, **features}))
               for length in (min(ax["length"]), max(ax["length"]))
               for width in (min(ax["width"]), max(ax["width"]))]
    if not isinstance(base, ParametricStator):
        return max((fe_cell_count(plate, study.solver.fe_refine), length, width, False)
                   for length, width, plate in corners)
    estimates = [(estimated_elements(plate), length, width, True)
                 for length, width, plate in corners]
    if max(estimates)[0] > bound:  # refused on the estimate: nothing to mesh
        return max(estimates)
    # the estimate's lowness could carry a plate across the bound: count its mesh itself,
    # unless the plate is wider than long, which its task refuses before any mesh
    # (fem.modes.WidePlateError): not meshed here only to count
    return max((fe_cell_count(plate, None), length, width, False)
               if bound < ESTIMATE_LOW_FACTOR * est[0] and not wider_than_long(plate) else est
               for est, (length, width, plate) in zip(estimates, corners, strict=True))


def _planform(design) -> bool:
    """Whether a stator file's plate is meshed from its planform (a mesh file, or gmsh for
    its features), where ``solver.fe_refine`` plays no part."""
    from fem.meshing.meshed_stator import has_planform

    return has_planform(design.stator)


def drive_triples(study: Study) -> int:
    """(frequency, voltage, preload) triples of one geometry: its contact runs. The loads do
    not multiply them: a transient's run answers the no-load point, and a steady triple's
    loads are counted in :func:`steady_solves`."""
    return study.n_drive_points // len(study.axes["load"])


def steady_solves(study: Study) -> int:
    """Steady solves of one drive triple, counted as ``lusm characteristic`` counts them (one
    per load of a characteristic): the steady state from rest, the :data:`CURVE_LOADS`-load
    characteristic, and one for each of the study's loads other than 0 N (a second
    characteristic; a load that happens to fall on the first curve costs nothing)."""
    return 1 + CURVE_LOADS + sum(1 for f in study.axes["load"] if f != 0.0)


def contact_work_problem(study: Study, plate_work: float, detail: str) -> str | None:
    """Why the contact work of a study is above its bound, in the study's keys, or None.

    ``plate_work`` is one plate's work: time steps of all its transient runs, or, with the
    steady method, its steady solves times their steps per drive period. The study is taken
    as :attr:`Study.n_geometries` plates like it and held to the bound of the same work in
    ``lusm map`` (:data:`lusm.limits.MAX_MAP_STEPS`, :data:`~lusm.limits.
    MAX_STEADY_WORK`). ``detail`` says how ``plate_work`` was counted.
    """
    total = study.n_geometries * plate_work
    steady = study.solver.method == "steady"
    top = limits.work_bound(limits.MAX_STEADY_WORK if steady else limits.MAX_MAP_STEPS)
    if total <= top:
        return None
    g = study.n_geometries
    if steady:
        fix = "a higher axes.frequency, " if not study.auto_frequency else ""
    elif study.solver.settle:  # each plate runs its settling time: a typed duration caps it
        fix = "a solver.duration or method = \"steady\", "
    else:
        fix = "a shorter solver.duration or larger solver.dt, "
    # one line short enough for a geometry's status (300 characters) with its prefix
    return (f"axes: {g} geometr{'y' if g == 1 else 'ies'} x {detail} = {total:.3g}"
            f"{'' if steady else ' time steps'}, above the {'steady ' if steady else ''}limit "
            f"{top:.3g}; use fewer geometries or axes.voltage/axes.preload points, {fix}or "
            f"{limits.more_work_hint()}")


def _check_contact_work(study: Study, where: str) -> None:
    """Refuse, before any FE solve, a study whose contact runs together are above the bound
    ``lusm map`` has for the same work: a 100 x 100 voltage x preload study of 2 s event
    runs (2e11 time steps, hours) is refused as ``lusm map --method transient`` refuses
    4e8. Transient steps are known here except for an auto frequency without solver.dt
    (counted at the default step's upper end, 100 ns: at least as many); a steady solve's
    steps per drive period depend on the plate's FE set, so they are counted at the fewest
    the engine takes (:data:`STEADY_MIN_STEPS_PER_PERIOD`), and each plate's own figure is
    checked in its task, before its drive points (``studies.explore``)."""
    s = study.solver
    n = len(study.axes["voltage"]) * len(study.axes["preload"])
    if s.method == "steady":
        k = steady_solves(study)
        detail = (f"{drive_triples(study)} drive points x {k} steady solves x at least "
                  f"{STEADY_MIN_STEPS_PER_PERIOD} steps per drive period")
        work = drive_triples(study) * k * STEADY_MIN_STEPS_PER_PERIOD
    elif study.auto_frequency:
        from contact.options import DEFAULT_DT_S

        steps = s.duration_s / (s.dt_s if s.dt_s is not None else DEFAULT_DT_S)
        least = "" if s.dt_s is not None and not s.settle else "at least "
        detail = (f"{n} drive points x {least}{steps:.3g} steps each ({_run_length(s)} / "
                  "solver.dt)")
        work = n * steps
    else:
        steps = [s.duration_s / s.step_s(f) for f in study.axes["frequency"]]
        least = "at least " if s.settle else ""
        detail = (f"{n} drive points x {least}{sum(steps):.3g} steps over axes.frequency "
                  f"({_run_length(s)} / solver.dt)")
        work = n * sum(steps)
    reason = contact_work_problem(study, work, detail)
    if reason is not None:
        raise ValueError(f"{where}{reason}")


def _run_length(solver: Solver) -> str:
    """How a study's transient run length is counted before any FE solve: ``solver.duration``
    as typed, or, with :attr:`Solver.settle`, its floor (each plate's settling time depends
    on the plate's modes, known after its FE solve; each plate's own is checked in its task,
    ``studies.task``)."""
    if not solver.settle:
        return "solver.duration"
    return (f"each plate's settling time, at least {show(solver.duration_s, 'time')} before "
            "its FE solve,")


def _warn_unused_solver(study: Study, raw: dict, where: str) -> None:
    """Warn of ``[solver]`` keys the study sets that its method does not use, as the commands
    warn of options that do nothing (``accuracy`` with a transient method, ``dt`` with the
    steady engine and ``rest`` at the fast level)."""
    import warnings

    contact_keys = ("method", "duration", "dt", "accuracy", "rest", "ultrasonic_friction")
    s = study.solver
    if not study.needs_motor:
        unused = {k: "the study asks for FE outputs only" for k in contact_keys}
    elif s.method == "steady":
        unused = {k: "the steady engine takes its own time step" for k in ("duration", "dt")}
        if s.accuracy == "fast":
            unused["rest"] = "it decides the start from rest at accuracy = \"exact\" only"
    else:
        why = f"a setting of the steady engine, and method = {s.method!r} is a transient"
        unused = {"accuracy": why, "rest": why}
    by_reason: dict[str, list[str]] = {}  # one clause per reason, each key with its own
    for k in unused:
        if k in raw:
            by_reason.setdefault(unused[k], []).append(k)
    if by_reason:
        clauses = [f"{' and '.join(f'solver.{k}' for k in keys)} "
                   f"{'is' if len(keys) == 1 else 'are'} unused: {why}"
                   for why, keys in by_reason.items()]
        warnings.warn(where + "; ".join(clauses), stacklevel=3)


def _warn_unused_drive(study: Study, raw_axes: dict, where: str) -> None:
    """Warn of the drive axes a study names when it asks for FE outputs only: they drive
    nothing and make no dimension of its dataset (``voltage = ["200 V", "300 V"]`` beside
    ``outputs = ["split"]``), as an unused solver key is said."""
    import warnings

    def default(axis: str) -> bool:  # frequency = "auto" written out changes nothing
        raw = raw_axes[axis]
        return isinstance(raw, str) and raw.strip().lower() == DEFAULT_AXES[axis].lower()

    # in the file's order; an axis written at its default is no request
    given = [f"axes.{a}" for a in raw_axes if a in DRIVE_AXES and not default(a)]
    if given and not study.needs_motor:
        names = " and ".join(given) if len(given) < 3 else \
            f"{', '.join(given[:-1])} and {given[-1]}"
        warnings.warn(f"{where}{names} {'is' if len(given) == 1 else 'are'} unused: the study "
                      "asks for FE outputs only, so its dataset has no drive dimension; ask "
                      "for a motor output (no_load_velocity, ...) to drive the plates",
                      stacklevel=3)


def _check_geometry_count(study: Study, where: str) -> None:
    """Refuse more FE solves than :data:`MAX_GEOMETRIES` by counting them, before any plate
    is built (a 1.8 M-plate stator study takes 15 s to build)."""
    top = limits.work_bound(MAX_GEOMETRIES)
    if study.n_geometries > top:
        raise ValueError(f"{where}axes: {study.n_geometries} geometries (FE solves) is above "
                         f"the limit {top} ({limits.more_work_hint()})")


def _check_work(study: Study, where: str) -> None:
    """Refuse a study above the work bounds (its geometry count is checked before, by
    :func:`_check_geometry_count`): each FE mesh, the drive points, the contact work."""
    # each FE mesh is bounded as lusm modes bounds it (a 30 x 1 mm plate at fe_refine 48 ran
    # for minutes at 2.8 GB where modes refuses at once)
    cells, length, width, estimated = _largest_mesh(study)
    top = limits.work_bound(limits.MAX_FE_CELLS_2D)
    if cells > top and study.stator is not None and _planform(study.stator):
        about = "about " if estimated else ""
        largest = (" (its largest tip, its smallest chamfer)"
                   if any(a in study.axes for a in FEATURE_AXES) else "")
        raise ValueError(f"{where}study.stator {study.stator.path}: the {length * 1e3:g} x "
                         f"{width * 1e3:g} mm plate of the study{largest} needs {about}{cells} 2D "
                         f"elements, above the limit {top}; coarsen the stator file's mesh "
                         f"([mesh] size_mm) or shrink the plates ({limits.more_work_hint()})")
    if cells > top:
        raise ValueError(f"{where}solver.fe_refine {study.solver.fe_refine}: the "
                         f"{length * 1e3:g} x {width * 1e3:g} mm plate of the study needs "
                         f"{cells} 2D elements, above the limit {top}; lower solver.fe_refine "
                         f"or make the plates less elongated ({limits.more_work_hint()})")
    top = limits.work_bound(MAX_STUDY_FE_WORK)
    fe_work = cells * study.n_geometries
    if fe_work > top:
        about = "about " if estimated else ""
        # the mesh the study's plates are meshed by: a stator file's own (or gmsh's, at its
        # [mesh] size_mm), where solver.fe_refine does nothing
        coarser = (f"a coarser mesh of study.stator {study.stator.path} (its [mesh] size_mm "
                   "or mesh file)"
                   if study.stator is not None and _planform(study.stator)
                   else f"a coarser mesh (solver.fe_refine {study.solver.fe_refine})")
        raise ValueError(f"{where}axes: {study.n_geometries} geometries (FE solves) x {about}"
                         f"{cells} 2D elements (the study's largest plate, {length * 1e3:g} x "
                         f"{width * 1e3:g} mm) = {fe_work:.3g} elements x solves is above the "
                         f"limit {top:.3g}; fewer geometries, or {coarser} "
                         f"({limits.more_work_hint()})")
    top = limits.work_bound(MAX_DRIVE_POINTS)
    if study.n_drive_points > top:
        raise ValueError(f"{where}axes: {study.n_drive_points} drive points per geometry is "
                         f"above the limit {top} ({limits.more_work_hint()})")
    top = limits.work_bound(MAX_STUDY_POINTS)
    total = study.n_geometries * study.n_drive_points
    if study.needs_motor and total > top:
        raise ValueError(f"{where}axes: {study.n_geometries} geometries x "
                         f"{study.n_drive_points} drive points = {total} contact solves is "
                         f"above the limit {top} ({limits.more_work_hint()})")
    # the steady engine takes its own step: solver.duration and solver.dt are not used
    if study.needs_motor and study.solver.method != "steady":
        _check_transient(study, where)  # each run first: its message is the more precise
    if study.needs_motor:
        _check_contact_work(study, where)


def show(value: float, kind: str) -> str:
    """``value`` (SI) as a study writes it: in the largest unit of :data:`UNITS` ``[kind]`` that
    keeps the number at least 1, to 4 significant digits (``1e-05`` s is ``"10 us"``)."""
    units = sorted(UNITS[kind].items(), key=lambda u: u[1])
    name, factor = units[0]
    for n, f in units:
        if abs(value) >= f * (1 - 1e-9):
            name, factor = n, f
    return f"{value / factor:.4g} {name}"


def transient_problem(solver: Solver, frequency_Hz: float, at: str) -> str | None:
    """Why a transient drive point at ``frequency_Hz`` (Hz) cannot run, in the study's keys and
    units, or None: the checks of ``lusm simulate`` (:func:`lusm.options.check_run_size`):
    a step of at most 1/(20 f), at least 10 drive periods, and the work bounds on the steps of a
    run and of its full-resolution window. ``at`` names the frequency (``"axes.frequency
    40 kHz"``, ``"the auto drive frequency 54.24 kHz of this plate"``)."""
    f = float(frequency_Hz)
    dt = solver.step_s(f)
    if solver.dt_s is not None and dt > 1.0 / (20.0 * f) * (1 + 1e-12):
        return (f"solver.dt {show(dt, 'time')} must be at most 1/(20 f) = "
                f"{show(1 / (20 * f), 'time')} at {at}")
    if solver.duration_s * f < 10 * (1 - 1e-12):
        return (f"solver.duration {show(solver.duration_s, 'time')} must cover at least 10 "
                f"drive periods, {show(10 / f, 'time')} at {at}")
    steps = solver.duration_s / dt
    top = limits.work_bound(limits.MAX_STEPS)
    if steps > top:
        return (f"solver.duration / solver.dt is {steps:.3g} time steps per drive point at {at}, "
                f"above the limit {top:.3g}; shorten solver.duration or raise solver.dt "
                f"({limits.more_work_hint()})")
    if solver.method == "reference":  # refused by every point otherwise, after the FE
        from contact.transient.reference import MAX_REFERENCE_PERIODS

        rtop = limits.work_bound(MAX_REFERENCE_PERIODS)
        if solver.duration_s * f > rtop:
            return (f"solver.duration {show(solver.duration_s, 'time')} must be at most "
                    f"{show(rtop / f, 'time')} ({rtop:g} drive periods) with solver.method "
                    f"'reference' at {at} ({limits.more_work_hint()})")
    window = min(steps, 5.0 / (f * dt))  # the last 5 periods, every step (as simulate's)
    wtop = limits.work_bound(limits.MAX_WINDOW_STEPS)
    if window > wtop:
        return (f"solver.dt {show(dt, 'time')} stores {window:.3g} steps of the last periods at "
                f"full resolution at {at}, above the limit {wtop:.3g}; raise solver.dt "
                f"({limits.more_work_hint()})")
    return None


def _check_transient(study: Study, where: str) -> None:
    """Refuse, before any FE solve, the transient settings no drive point could run with: at
    fixed frequencies each one is checked as ``lusm simulate`` checks it; with ``frequency =
    "auto"`` (known only after each plate's FE solve) what no frequency of the CLI's range
    could make valid (each plate's own frequency is checked in its task, before its drive
    points)."""
    s = study.solver
    if not study.auto_frequency:
        for f in study.axes["frequency"]:
            reason = transient_problem(s, f, f"axes.frequency {show(f, 'frequency')}")
            if reason is not None:
                raise ValueError(f"{where}{reason}")
        return
    hi = limits.FREQUENCY_HZ[1]
    if s.dt_s is not None:
        top = min(hi, 1.0 / (20.0 * s.dt_s))  # the highest frequency this step can resolve
        if s.duration_s * top < 10 * (1 - 1e-12):
            raise ValueError(
                f"{where}solver.duration {show(s.duration_s, 'time')} is shorter than 10 drive "
                f"periods at every frequency solver.dt {show(s.dt_s, 'time')} allows (up to "
                f"1/(20 dt) = {show(top, 'frequency')}, axes.frequency auto): give "
                f"solver.duration >= {show(10 / top, 'time')} or a smaller solver.dt")
        steps = s.duration_s / s.dt_s
    else:
        if s.duration_s * hi < 10 * (1 - 1e-12):
            raise ValueError(
                f"{where}solver.duration {show(s.duration_s, 'time')} is shorter than 10 drive "
                f"periods at every drive frequency up to {show(hi, 'frequency')} "
                f"(axes.frequency auto): give solver.duration >= {show(10 / hi, 'time')}")
        from contact.options import DEFAULT_DT_S

        steps = s.duration_s / DEFAULT_DT_S  # the default step is at most 100 ns
    top = limits.work_bound(limits.MAX_STEPS)
    if steps > top:
        raise ValueError(f"{where}solver.duration / solver.dt is at least {steps:.3g} time "
                         f"steps per drive point, above the limit {top:.3g}; shorten "
                         f"solver.duration or raise solver.dt ({limits.more_work_hint()})")


MAX_STUDY_BYTES = 1_000_000
"""Largest study file (bytes). A study is a few kB of TOML; the bound keeps ``/dev/zero``
given as the study from being read until memory runs out."""


def read_study_text(path: Path) -> str:
    """The text of the study file ``path``, refused unless it is a regular file of at most
    :data:`MAX_STUDY_BYTES` (read boundedly: :func:`fem.small_file.read_small_text`).

    Raises
    ------
    ValueError
        For a path that is not a regular file, a file above the cap, or text that is not
        UTF-8: one line naming the file.
    OSError
        If the file does not exist or cannot be opened.
    """
    from fem.small_file import FileTooLarge, NotRegularFile, read_small_text

    try:
        return read_small_text(path, MAX_STUDY_BYTES)
    except FileNotFoundError:  # a dangling link said "cannot use dangling: No such file"
        link = " (a symbolic link to a missing file)" if path.is_symlink() else ""
        raise ValueError(f"{path}: no such study file{link}") from None
    except NotRegularFile as exc:
        raise ValueError(f"{path}: is {exc.what}, not a study file; give a regular TOML file "
                         f"of at most {MAX_STUDY_BYTES / 1e6:g} MB") from None
    except FileTooLarge as exc:
        raise ValueError(f"{path}: {exc.size} bytes is above the "
                         f"{MAX_STUDY_BYTES / 1e6:g} MB a study file may have (a study is a few "
                         "kB of TOML): is it the study file?") from None
    except UnicodeDecodeError as exc:  # the message did not name the file
        raise ValueError(f"{path}: not UTF-8 text (byte {exc.start}: {exc.reason}); a study "
                         "file is TOML") from None


def load_study(path: str | Path) -> Study:
    """Read and check a study TOML file.

    Raises
    ------
    ValueError
        For a bad file: one line naming the file and the key; for a path that is not a
        regular file or a file above :data:`MAX_STUDY_BYTES`, one line naming the file.
    OSError
        If the file cannot be read.
    """
    path = Path(path)
    text = read_study_text(path)
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not valid TOML ({exc})") from None
    if not doc:  # an empty file (or only comments) ran the whole default study silently
        raise ValueError(f"{path}: the study file is empty; give at least its [axes] (see "
                         "examples/studies/length_width.toml)")
    return study_from_dict(doc, str(path))
