"""The ``[optimize]`` table of a study file: design variables, objectives, constraints, budget.

An optimisation study is an explore study (:mod:`studies.study`) with one more table::

    [optimize]
    evaluations = 40                 # the budget: designs evaluated
    wall_time = "20 min"             # optional: no new batch starts after it
    seed = 1

    [optimize.variables]             # explore's axis names, each a range with its units
    length = { min = "33 mm", max = "39 mm" }
    width = { min = "8.5 mm", max = "10.5 mm", step = "0.01 mm" }
    material = ["pzt8", "paper"]     # a choice

    [[optimize.objectives]]
    output = "peak_power"            # an output, or a ratio "stall_force / volume"
    goal = "maximize"
    at = { voltage = "300 V" }       # optional: one operating point of the study's axes

    [optimize.constraints]
    split = "0.5 %"                  # |f_B2 - f_L1| / f_L1 (or "300 Hz": |f_B2 - f_L1|)
                                     # or "tuned": each design's width tuned to L1 = B2
    tune = { variable = "width", min = "9 mm", max = "10.5 mm" }   # with "tuned" (optional)
    frequency = { min = "40 kHz", max = "55 kHz" }   # the drive frequency
    volume = { max = "1100 mm3" }    # the plate's length x width x thickness
    stall_force = { min = "1.5 N" }  # any output of OBJECTIVE_UNITS, its own units
    limits = true                    # the ceramic's limits: limit_ratio <= 1

Every evaluation is one plate of the study (:func:`studies.task.compute_geometry` of a
one-geometry study whose axes are the design's values): the same computation as the grid
point of ``lusm explore`` at those values. An objective over several operating points (the
study's voltages, preloads) is their worst case unless ``at`` picks one.

Mistakes raise ``ValueError`` with one line naming the key (``optimize.variables.length``).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import re
from dataclasses import dataclass, field
from typing import Any

from studies.study import (
    AXIS_KIND,
    FEATURE_AXES,
    UNITS,
    Study,
    check_range,
    parse_quantity,
    study_from_dict,
)

NUMERIC_VARIABLES = ("length", "width", "thickness", "gap", "tip_length", "tip_width",
                     "chamfer", "frequency")
"""Design variables with a range (explore's axis names, in SI: m, Hz)."""
VARIABLES = (*NUMERIC_VARIABLES, "material")
"""Every design variable; ``material`` is a choice among names."""

OBJECTIVE_UNITS: dict[str, str] = {
    "f_L1_short": "Hz", "f_L1_open": "Hz", "f_B2_short": "Hz", "f_B2_open": "Hz",
    "k_eff_L1": "1", "k_eff_B2": "1", "split": "Hz", "f_drive": "Hz",
    "no_load_velocity": "m/s", "stall_force": "N", "peak_efficiency": "1",
    "peak_power": "W", "limit_ratio": "1", "velocity": "m/s", "volume": "m^3",
}
"""What an objective or a bound may name, with its SI unit: the plate's FE outputs, the
motor's answers at each operating point, and the plate's volume."""
MOTOR_NAMES = ("no_load_velocity", "stall_force", "peak_efficiency", "peak_power",
               "limit_ratio", "velocity")
"""Names with one value per operating point (the others have one per plate)."""

VALUE_UNITS: dict[str, dict[str, float]] = {
    "Hz": UNITS["frequency"], "N": UNITS["force"], "m/s": {"m/s": 1.0, "mm/s": 1e-3},
    "W": {"W": 1.0, "mW": 1e-3}, "m^3": {"m3": 1.0, "cm3": 1e-6, "mm3": 1e-9},
    "1": {"1": 1.0, "%": 1e-2},
}
"""Units a bound may be written in, by the SI unit of its output."""
TIME_UNITS = {"s": 1.0, "min": 60.0, "h": 3600.0}

MAX_EVALUATIONS = 100_000
"""Largest budget of one optimisation (designs; as explore's geometry bound)."""
DEFAULT_STARTUP = 10
"""Random designs before the sampler models the history (optuna's TPE default)."""

_VALUE = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z0-9/%^]*)\s*$")


@dataclass(frozen=True)
class Variable:
    """One design variable.

    Attributes
    ----------
    name : str
        Explore's axis name (``length``, ..., ``material``).
    low, high : float
        Bounds in SI units (m or Hz); NaN for ``material``.
    step : float or None
        Grid of the values (SI), or None: continuous.
    choices : tuple of str
        The materials of a ``material`` variable.
    """

    name: str
    low: float = math.nan
    high: float = math.nan
    step: float | None = None
    choices: tuple[str, ...] = ()


@dataclass(frozen=True)
class Objective:
    """One objective: ``numerator`` (over ``denominator``) at the operating point ``at``.

    Attributes
    ----------
    numerator, denominator : str
        Keys of :data:`OBJECTIVE_UNITS`; ``denominator`` None for a plain output.
    maximize : bool
    at : dict
        Drive axis -> value (SI) selecting one operating point; the others' worst case.
    """

    numerator: str
    denominator: str | None
    maximize: bool
    at: dict[str, float] = field(default_factory=dict)

    @property
    def label(self) -> str:
        """The objective as the study writes it (``stall_force / volume``)."""
        return self.numerator + (f" / {self.denominator}" if self.denominator else "")

    @property
    def unit(self) -> str:
        """Its SI unit."""
        top = OBJECTIVE_UNITS[self.numerator]
        if self.denominator is None:
            return top
        bottom = OBJECTIVE_UNITS[self.denominator]
        return top if bottom == "1" else f"{top}/({bottom})"


@dataclass(frozen=True)
class Bound:
    """A constraint ``low <= value <= high`` on an output (SI; NaN: no such side), or the
    split's ``|split| <= high`` (``relative``: over f_L1_short)."""

    name: str
    low: float = math.nan
    high: float = math.nan
    relative: bool = False


TUNE_VARIABLES = ("width", "length")
"""What ``split = "tuned"`` may tune (the other one is held, as ``lusm tune --fix``)."""


@dataclass(frozen=True)
class Tune:
    """``split = "tuned"``: each design's ``variable`` solved for L1 = B2 before its evaluation.

    Attributes
    ----------
    variable : str
        ``width`` (the length held, the default) or ``length`` (the width held).
    low, high : float
        The tuned value's allowed range (m; NaN: no such side): a design tuned outside it,
        or not tunable at all, is infeasible.
    """

    variable: str = "width"
    low: float = math.nan
    high: float = math.nan


@dataclass(frozen=True)
class Problem:
    """An optimisation study: the explore study its evaluations are plates of, and the search.

    Attributes
    ----------
    study : Study
        The study whose variable axes hold each variable's two bounds (checked as explore
        checks them); an evaluation replaces them by the design's values.
    variables : tuple of Variable
    objectives : tuple of Objective
    bounds : tuple of Bound
    evaluations : int
        The budget (designs).
    wall_time_s : float or None
        No new batch starts after this wall time (s).
    seed : int
    startup : int
        Random designs before the sampler models the history.
    text : str
        The canonical optimize table (JSON), part of :attr:`fingerprint`.
    tune : Tune or None
        ``split = "tuned"``: the inner tune of each design (:mod:`studies.optimize.tuned`).
    """

    study: Study
    variables: tuple[Variable, ...]
    objectives: tuple[Objective, ...]
    bounds: tuple[Bound, ...]
    evaluations: int
    wall_time_s: float | None
    seed: int
    startup: int
    text: str = ""
    tune: Tune | None = None

    @property
    def fingerprint(self) -> str:
        """SHA-256 of the study and the search (budget and wall time aside: a resumed run
        may have more): what a resumed run compares."""
        doc = json.loads(self.text)
        for k in ("evaluations", "wall_time"):
            doc.pop(k, None)
        return hashlib.sha256((self.study.fingerprint + json.dumps(doc, sort_keys=True))
                              .encode()).hexdigest()


def parse_value(value: Any, unit: str, key: str) -> float:
    """A bound such as ``"1.5 N"``, ``"0.5 %"`` or ``"1100 mm3"`` in the SI ``unit``."""
    allowed = VALUE_UNITS[unit]
    if isinstance(value, bool) or not isinstance(value, str):
        raise ValueError(f"{key} must be a string with its unit ({', '.join(allowed)}), got "
                         f"{value!r}")
    m = _VALUE.match(value)
    if m is None or m.group(2) not in allowed:
        raise ValueError(f"{key} must be a number with a unit among {', '.join(allowed)}, got "
                         f"{value!r}")
    out = float(m.group(1)) * allowed[m.group(2)]
    if not math.isfinite(out):
        raise ValueError(f"{key} must be finite, got {value!r}")
    return out


def load_problem(path) -> Problem:
    """Read a study file with an ``[optimize]`` table (:func:`problem_from_dict`)."""
    import tomllib
    from pathlib import Path

    from studies.study import read_study_text

    path = Path(path)
    try:
        doc = tomllib.loads(read_study_text(path))
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not valid TOML ({exc})") from None
    return problem_from_dict(doc, str(path))


def problem_from_dict(doc: dict, source: str = "<dict>") -> Problem:
    """Check a study document with an ``[optimize]`` table and build the :class:`Problem`.

    Raises
    ------
    ValueError
        One line naming the key (``optimize.variables.length``, ``optimize.evaluations``).
    """
    where = "" if source == "<dict>" else f"{source}: "
    doc = dict(doc)
    raw = doc.pop("optimize", None)
    if not isinstance(raw, dict):
        raise ValueError(f"{where}optimize must be a table ([optimize] with variables, "
                         "objectives and evaluations; docs/optimize.md)")
    unknown = sorted(set(raw) - {"variables", "objectives", "constraints", "evaluations",
                                 "wall_time", "seed", "startup"})
    if unknown:
        raise ValueError(f"{where}optimize.{unknown[0]} is not an optimize key; use variables, "
                         "objectives, constraints, evaluations, wall_time, seed and startup")
    variables = _variables(raw.get("variables"), doc, where)
    objectives = _objectives(raw.get("objectives"), where)
    bounds, tune = _bounds(raw.get("constraints", {}), where)
    evaluations = _integer(raw.get("evaluations"), f"{where}optimize.evaluations", 1,
                           MAX_EVALUATIONS)
    seed = _integer(raw.get("seed", 0), f"{where}optimize.seed", 0, 2**31 - 1)
    startup = _integer(raw.get("startup", DEFAULT_STARTUP), f"{where}optimize.startup", 1,
                       MAX_EVALUATIONS)
    wall = None
    if "wall_time" in raw:
        wall = _time(raw["wall_time"], f"{where}optimize.wall_time")
    study = _study(doc, variables, objectives, bounds, source, where)
    _check_named(study, variables, objectives, bounds, where)
    if tune is not None:
        _check_tune(tune, study, variables, where)
    canonical = {"variables": [v.__dict__ for v in variables],
                 "objectives": [o.__dict__ for o in objectives],
                 "bounds": [b.__dict__ for b in bounds], "evaluations": evaluations,
                 "wall_time": wall, "seed": seed, "startup": startup}
    if tune is not None:  # only then: an untuned problem's fingerprint stays as it is
        canonical["tune"] = tune.__dict__
    return Problem(study, variables, objectives, bounds, evaluations, wall, seed, startup,
                   json.dumps(canonical, sort_keys=True, default=str), tune)


def _integer(value: Any, key: str, lo: int, hi: int) -> int:
    if value is None:
        raise ValueError(f"{key} is missing; give the number of designs to evaluate "
                         f"(an integer in [{lo}, {hi}])")
    if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
        raise ValueError(f"{key} must be an integer in [{lo}, {hi}], got {value!r}")
    return value


def _time(value: Any, key: str) -> float:
    m = _VALUE.match(value) if isinstance(value, str) else None
    if m is None or m.group(2) not in TIME_UNITS:
        raise ValueError(f"{key} must be a duration such as '10 min' (units: "
                         f"{', '.join(TIME_UNITS)}), got {value!r}")
    out = float(m.group(1)) * TIME_UNITS[m.group(2)]
    if not 0 < out <= 30 * 86400:
        raise ValueError(f"{key} must lie in (0 s, 30 days], got {value!r}")
    return out


def _variables(raw: Any, doc: dict, where: str) -> tuple[Variable, ...]:
    """The design variables, each checked: a known name, not also an axis, bounds in the
    axis's units and range, ascending."""
    key = f"{where}optimize.variables"
    if not isinstance(raw, dict) or not raw:
        raise ValueError(f"{key} must be a table of at least one variable, e.g. length = "
                         "{ min = \"33 mm\", max = \"39 mm\" }")
    axes = doc.get("axes", {}) if isinstance(doc.get("axes", {}), dict) else {}
    out = []
    for name, spec in raw.items():
        k = f"{key}.{name}"
        if name not in VARIABLES:
            raise ValueError(f"{k} is not a design variable; use one of {', '.join(VARIABLES)}")
        if name in axes:
            raise ValueError(f"{k} is also axes.{name}; a design variable is not an axis "
                             "(remove it from [axes])")
        if name == "material":
            out.append(_material(spec, k))
            continue
        study = doc.get("study", {})
        if name in FEATURE_AXES and not (isinstance(study, dict) and "stator" in study):
            raise ValueError(f"{k} varies a stator file's feature: it needs study.stator "
                             "naming a file with [tip], [chamfers] or [[holes]]")
        if not isinstance(spec, dict) or set(spec) - {"min", "max", "step"} or \
                not {"min", "max"} <= set(spec):
            raise ValueError(f"{k} must be a table {{ min = ..., max = ... }} (and optionally "
                             "step), each a quantity with its unit")
        kind = AXIS_KIND[name]
        lo = parse_quantity(spec["min"], kind, f"{k}.min")
        hi = parse_quantity(spec["max"], kind, f"{k}.max")
        if not lo < hi:
            raise ValueError(f"{k}: min {spec['min']!r} must be below max {spec['max']!r}")
        check_range(name, (lo, hi), k)
        step = None
        if "step" in spec:
            step = parse_quantity(spec["step"], kind, f"{k}.step")
            if not 0 < step <= hi - lo:
                raise ValueError(f"{k}.step must lie in (0, max - min], got {spec['step']!r}")
        out.append(Variable(name, lo, hi, step))
    return tuple(out)


def _material(spec: Any, key: str) -> Variable:
    from fem.material import MATERIAL_NAMES

    items = spec if isinstance(spec, list) else None
    if not items or len(items) < 2:
        raise ValueError(f"{key} must be a list of at least two materials among "
                         f"{', '.join(MATERIAL_NAMES)}")
    names = []
    for m in items:
        name = m.strip().lower().replace("-", "") if isinstance(m, str) else None
        if name not in MATERIAL_NAMES or name in names:
            raise ValueError(f"{key} must list distinct materials among "
                             f"{', '.join(MATERIAL_NAMES)}, got {m!r}")
        names.append(name)
    return Variable("material", choices=tuple(names))


def _objectives(raw: Any, where: str) -> tuple[Objective, ...]:
    key = f"{where}optimize.objectives"
    if isinstance(raw, dict):
        raw = [raw]
    if not isinstance(raw, list) or not raw:
        raise ValueError(f"{key} must be at least one table [[optimize.objectives]] with "
                         "output and goal")
    out = []
    for i, spec in enumerate(raw):
        k = f"{key}[{i}]"
        if not isinstance(spec, dict) or set(spec) - {"output", "goal", "at"}:
            raise ValueError(f"{k} must be a table with output, goal and optionally at")
        text = spec.get("output")
        parts = [p.strip() for p in text.split("/")] if isinstance(text, str) else []
        if not 1 <= len(parts) <= 2 or any(p not in OBJECTIVE_UNITS for p in parts):
            raise ValueError(f"{k}.output must name an output or a ratio of two ('a / b') "
                             f"among {', '.join(OBJECTIVE_UNITS)}, got {text!r}")
        goal = spec.get("goal")
        if goal not in ("maximize", "minimize"):
            raise ValueError(f"{k}.goal must be maximize or minimize, got {goal!r}")
        at = _at(spec.get("at", {}), f"{k}.at")
        out.append(Objective(parts[0], parts[1] if len(parts) == 2 else None,
                             goal == "maximize", at))
    if len({o.label for o in out}) < len(out):
        raise ValueError(f"{key} names one objective twice")
    return tuple(out)


def _at(raw: Any, key: str) -> dict[str, float]:
    kinds = {"voltage": "voltage", "preload": "force", "load": "force",
             "frequency": "frequency"}
    if not isinstance(raw, dict) or set(raw) - set(kinds):
        raise ValueError(f"{key} must be a table of drive axes ({', '.join(kinds)})")
    return {a: parse_quantity(v, kinds[a], f"{key}.{a}") for a, v in raw.items()}


def _bounds(raw: Any, where: str) -> tuple[tuple[Bound, ...], Tune | None]:
    """The constraints' bounds, and the inner tune of ``split = "tuned"`` (else None)."""
    key = f"{where}optimize.constraints"
    if not isinstance(raw, dict):
        raise ValueError(f"{key} must be a table")
    tuned = raw.get("split") == "tuned"
    if "tune" in raw and not tuned:
        raise ValueError(f"{key}.tune names the variable an inner tune solves: it needs "
                         f"{key}.split = \"tuned\"")
    tune = _tune(raw.get("tune", "width"), f"{key}.tune") if tuned else None
    out = []
    for name, spec in raw.items():
        k = f"{key}.{name}"
        if name == "tune" or (name == "split" and tuned):
            continue
        if name == "limits":
            if spec is not True:
                raise ValueError(f"{k} must be true (every operating point within the "
                                 f"ceramic's limits) or left out, got {spec!r}")
            out.append(Bound("limit_ratio", high=1.0))
            continue
        if name == "split":
            if not isinstance(spec, str):
                raise ValueError(f"{k} must be a string: \"0.5 %\", \"300 Hz\" or \"tuned\", "
                                 f"got {spec!r}")
            unit = spec.strip().split()[-1] if isinstance(spec, str) and spec.strip() else ""
            relative = unit == "%"
            value = parse_value(spec, "1" if relative else "Hz", k)
            if not value >= 0:
                raise ValueError(f"{k} must be >= 0, got {spec!r}")
            out.append(Bound("split", high=value, relative=relative))
            continue
        target = "f_drive" if name == "frequency" else name
        if target not in OBJECTIVE_UNITS:
            raise ValueError(f"{k} is not a constraint; use split, frequency (the drive "
                             f"frequency), volume, limits or an output among "
                             f"{', '.join(OBJECTIVE_UNITS)}")
        if isinstance(spec, str):
            spec = {"max": spec}
        if not isinstance(spec, dict) or not spec or set(spec) - {"min", "max"}:
            raise ValueError(f"{k} must be a table {{ min = ..., max = ... }} (either or both)")
        lo = parse_value(spec["min"], OBJECTIVE_UNITS[target], f"{k}.min") \
            if "min" in spec else math.nan
        hi = parse_value(spec["max"], OBJECTIVE_UNITS[target], f"{k}.max") \
            if "max" in spec else math.nan
        if lo >= hi:
            raise ValueError(f"{k}: min {spec['min']!r} must be below max {spec['max']!r}")
        out.append(Bound(target, lo, hi))
    return tuple(out), tune


def _tune(spec: Any, key: str) -> Tune:
    """``tune = "width"`` or ``tune = { variable = "width", min = ..., max = ... }``."""
    if isinstance(spec, str):
        spec = {"variable": spec}
    if not isinstance(spec, dict) or set(spec) - {"variable", "min", "max"}:
        raise ValueError(f"{key} must be \"width\" or \"length\", or a table {{ variable = "
                         "\"width\", min = ..., max = ... }} (min and max optional)")
    name = spec.get("variable", "width")
    if name not in TUNE_VARIABLES:
        raise ValueError(f"{key} must name the tuned variable, width or length (the other "
                         f"one is held, as lusm tune --fix), got {name!r}")
    lo = parse_quantity(spec["min"], "length", f"{key}.min") if "min" in spec else math.nan
    hi = parse_quantity(spec["max"], "length", f"{key}.max") if "max" in spec else math.nan
    if lo >= hi:
        raise ValueError(f"{key}: min {spec['min']!r} must be below max {spec['max']!r}")
    given = tuple(x for x in (lo, hi) if not math.isnan(x))
    if given:
        check_range(name, given, key)
    return Tune(name, lo, hi)


def _study(doc: dict, variables, objectives, bounds, source: str, where: str) -> Study:
    """The explore study of the problem: each variable an axis of its two bounds, the outputs
    the objectives and bounds need added to the study's own."""
    doc = dict(doc)
    axes = dict(doc.get("axes", {})) if isinstance(doc.get("axes", {}), dict) else {}
    for v in variables:
        if v.name == "material":
            axes["material"] = list(v.choices)
        else:
            unit = "mm" if AXIS_KIND[v.name] == "length" else "Hz"
            scale = 1e3 if unit == "mm" else 1.0
            axes[v.name] = [f"{v.low * scale!r} {unit}", f"{v.high * scale!r} {unit}"]
    doc["axes"] = axes
    names = {o.numerator for o in objectives} | {o.denominator for o in objectives} | \
        {b.name for b in bounds}
    wanted = {"split" if n in ("split", "f_drive", "volume") else
              "k_eff" if n.startswith("k_eff") else n for n in names if n}
    wanted.discard("f_drive")
    wanted.discard("volume")
    if "peak_power" in wanted or "velocity" in wanted:
        wanted.add("stall_force")
    if "f_drive" in names:  # the auto drive frequency comes with the motor's answers
        wanted.add("no_load_velocity")
    own = doc.get("outputs", [])
    own = own if isinstance(own, list) else []
    doc["outputs"] = list(dict.fromkeys([*own, *sorted(wanted), "split", "f_L1_short"]))
    return study_from_dict(doc, source)


def _check_named(study: Study, variables, objectives, bounds, where: str) -> None:
    """Refuse what no evaluation could give: a motor output with a transient solver, an
    ``at`` outside the study's axes, a frequency bound without a drive frequency to bound,
    a feature variable without a parametric stator."""
    feats = [v.name for v in variables if v.name in FEATURE_AXES]
    if feats and not study.meshed_by_gmsh:
        raise ValueError(f"{where}optimize.variables.{feats[0]} varies a stator file's feature: "
                         "it needs study.stator naming a file with [tip], [chamfers] or "
                         "[[holes]]")
    names = [o.numerator for o in objectives] + [o.denominator for o in objectives if
                                                o.denominator] + [b.name for b in bounds]
    loaded = [n for n in names if n in ("stall_force", "peak_efficiency", "peak_power",
                                         "limit_ratio", "velocity")]
    if loaded and study.solver.method != "steady":
        raise ValueError(f"{where}optimize: {loaded[0]} needs solver.method = \"steady\" (a "
                         "transient gives the no-load velocity only)")
    freq = any(v.name == "frequency" for v in variables)
    if "f_drive" in names and not (study.auto_frequency or freq):
        raise ValueError(f"{where}optimize.constraints.frequency bounds the drive frequency: "
                         "it needs axes.frequency = \"auto\" or a frequency variable")
    for i, o in enumerate(objectives):
        for a, value in o.at.items():
            if a == "frequency" and (study.auto_frequency or freq):
                raise ValueError(f"{where}optimize.objectives[{i}].at.frequency: the drive "
                                 "frequency is the design's (auto or a variable), not an "
                                 "operating point to pick")
            if a == "load" and o.numerator != "velocity" and o.denominator != "velocity":
                raise ValueError(f"{where}optimize.objectives[{i}].at.load picks the velocity "
                                 "at a load; the other answers have no load")
            if value not in study.axes[a]:
                raise ValueError(f"{where}optimize.objectives[{i}].at.{a} {value:g} is not "
                                 f"among axes.{a} ({', '.join(f'{x:g}' for x in study.axes[a])}"
                                 ")")


def _check_tune(tune: Tune, study: Study, variables, where: str) -> None:
    """Refuse an inner tune of a variable the search varies too, that the study's axes fix,
    or that a stator file with its own mesh cannot take (a study cannot rescale a mesh)."""
    key = f"{where}optimize.constraints.tune"
    v = tune.variable
    if any(x.name == v for x in variables):
        raise ValueError(f"{key}: {v} is tuned for L1 = B2 in each design, so it cannot also "
                         f"be a search variable; remove optimize.variables.{v}")
    if len(study.axes[v]) != 1:
        raise ValueError(f"{key}: {v} is tuned in each design; it cannot also be "
                         f"axes.{v} (remove it from [axes])")
    if study.stator is not None and study.stator.mesh_path is not None:
        raise ValueError(f"{key}: the {v} of study.stator {study.stator.path} cannot be tuned: "
                         f"it has its own mesh ({study.stator.mesh_path}), which a study cannot "
                         "rescale; give split a bound (\"0.5 %\") or a stator file without "
                         "[mesh] file")


def trial_study(problem: Problem, design: dict[str, Any]):
    """The one-geometry explore study of ``design`` (its axes the design's values): the same
    computation as the grid point of ``lusm explore`` at those values."""
    return dataclasses.replace(problem.study, axes=design_values(problem, design))



def design_values(problem: Problem, design: dict[str, Any]) -> dict[str, tuple]:
    """The axes of the one-geometry study of ``design`` (variable -> value, SI; the tuned
    value too where ``design`` has it, else the tune's start: the study's own)."""
    axes = dict(problem.study.axes)
    for v in problem.variables:
        axes[v.name] = (design[v.name],)
    if problem.tune is not None and problem.tune.variable in design:
        axes[problem.tune.variable] = (design[problem.tune.variable],)
    return axes


def with_seed(problem: Problem, seed: int) -> Problem:
    """``problem`` with the sampler's seed ``seed`` (``--seed``): another search, with its
    own fingerprint."""
    from dataclasses import replace

    doc = json.loads(problem.text)
    doc["seed"] = int(seed)
    return replace(problem, seed=int(seed), text=json.dumps(doc, sort_keys=True))
