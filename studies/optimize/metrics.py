"""An evaluation's objectives and constraint values, from the outputs of its plate.

The outputs are those of :func:`studies.task.compute_geometry` (or of an evaluator that
gives the same arrays): per plate scalars (``split``, ``f_L1_short``, ...) and per
operating point arrays (``no_load_velocity``, ...; dimensions the study's drive axes, the
fixed ``frequency`` first, then ``voltage``, ``preload``, and ``load`` for ``velocity``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from studies.optimize.problem import MOTOR_NAMES, Bound, Objective, Problem
from studies.optimize.tuned import tune_constraint, tuned_design


def volume_m3(design: dict[str, Any], study) -> float:
    """The plate's volume (m^3): length x width x thickness (the tip and chamfers aside), the
    design's values where it has them, else the study's single axis values."""
    size = [design.get(a, study.axes[a][0]) for a in ("length", "width", "thickness")]
    return float(np.prod(size))


def named_values(name: str, outputs: dict[str, np.ndarray], design: dict[str, Any], study,
                 at: dict[str, float]) -> np.ndarray:
    """The values of ``name`` (SI) at the operating points ``at`` selects (all of them where
    it selects none): one value for a plate quantity, an array for a motor answer."""
    if name == "volume":
        return np.array(volume_m3(design, study))
    if name not in MOTOR_NAMES:
        return np.asarray(outputs[name], dtype=float)
    values = np.asarray(outputs[name], dtype=float)
    dims = [a for a in study.drive_dims if a != "load"] + (["load"] if name == "velocity"
                                                           else [])
    index = tuple(study.axes[a].index(at[a]) if a in at else slice(None) for a in dims)
    return values[index]


def objective_value(obj: Objective, outputs: dict[str, np.ndarray], design: dict[str, Any],
                    study) -> float:
    """The objective (SI): its ratio at each selected operating point, their worst case
    (the lowest for a maximised one, the highest for a minimised one); NaN when any is."""
    top = named_values(obj.numerator, outputs, design, study, obj.at)
    value = top
    if obj.denominator is not None:
        bottom = named_values(obj.denominator, outputs, design, study, obj.at)
        with np.errstate(divide="ignore", invalid="ignore"):
            value = top / bottom
    value = np.asarray(value, dtype=float)
    if value.size == 0 or not np.isfinite(value).all():
        return math.nan
    return float(value.min() if obj.maximize else value.max())


def _excess(value: float, bound: float) -> float:
    """How far ``value`` lies above ``bound``, relative to it (<= 0: within)."""
    return (value - bound) / abs(bound) if bound != 0 else value - bound


def constraint_values(bound: Bound, outputs: dict[str, np.ndarray], design: dict[str, Any],
                      study) -> list[float]:
    """The constraint's values (<= 0 feasible, relative to the bound; one per side it has),
    the worst over every operating point; NaN where the output is."""
    if bound.name == "split":
        split = abs(float(outputs["split"]))
        if bound.relative:
            return [split / float(outputs["f_L1_short"]) - bound.high]
        return [_excess(split, bound.high)]
    values = np.asarray(named_values(bound.name, outputs, design, study, {}), dtype=float)
    if values.size == 0 or not np.isfinite(values).all():
        return [math.nan] * (int(np.isfinite(bound.low)) + int(np.isfinite(bound.high)))
    out = []
    if np.isfinite(bound.low):
        out.append(max(-_excess(float(v), bound.low) for v in values.ravel()))
    if np.isfinite(bound.high):
        out.append(max(_excess(float(v), bound.high) for v in values.ravel()))
    return out


def constraint_names(problem: Problem) -> list[str]:
    """One name per constraint value (:func:`evaluation_metrics`'s order)."""
    names = []
    for b in problem.bounds:
        if b.name == "split":
            names.append("split_max")
            continue
        if np.isfinite(b.low):
            names.append(f"{b.name}_min")
        if np.isfinite(b.high):
            names.append(f"{b.name}_max")
    if problem.tune is not None:
        names.append("tuned")
    return names


def evaluation_metrics(problem: Problem, outputs: dict[str, np.ndarray],
                       design: dict[str, Any], study) -> tuple[list[float], list[float]]:
    """The objectives (SI, as their goals give them) and constraint values (<= 0 feasible) of
    one evaluation of the one-geometry ``study`` of ``design`` (with ``split = "tuned"``,
    the design's tuned value taken from its outputs, and its ``tuned`` constraint last)."""
    design = tuned_design(problem.tune, design, outputs)
    values = [objective_value(o, outputs, design, study) for o in problem.objectives]
    cons = [c for b in problem.bounds for c in constraint_values(b, outputs, design, study)]
    if problem.tune is not None:
        cons.append(tune_constraint(problem.tune, outputs))
    return values, cons
