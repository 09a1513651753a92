"""``split = "tuned"``: each design's width (or length) tuned to L1 = B2 before its evaluation.

The tune runs on the worker, before the plate's evaluation: :func:`fe_tuner` solves the tuned
variable with :func:`fem.tuning.tune_plate` (the other plate dimension held, as ``lusm tune
--fix length``), from the study's own value, with the study's FE settings, so the evaluated
plate is the tuned one and every design sits on the L1 = B2 ridge. The search then runs over
the remaining variables. A design the tuner cannot tune (no crossing), or tunes outside the
tune's range, is not evaluated: it is infeasible by its ``tuned`` constraint value.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from fem.tuning import DEFAULT_REL_TOL, UNTUNED_FACTOR
from studies.optimize.problem import Tune

TUNED_SPLIT = UNTUNED_FACTOR * DEFAULT_REL_TOL
"""Largest ``|f_B2 - f_L1| / f_L1`` of a tuned design (-): what :func:`fem.tuning.tune_plate`
itself calls tuned at the tolerance :func:`fe_tuner` tunes to (1e-4)."""
UNTUNABLE = 1.0
"""The ``tuned`` constraint value of a design the tuner found no crossing for (> 0)."""

Tuner = Callable[[Any, str], float]
"""``tuner(study, variable) -> value`` (m): the ``variable`` of the one-geometry ``study`` at
which L1 = B2; raises ``ValueError`` where there is none."""


def tuned_key(variable: str) -> str:
    """The output holding the tuned value (``tuned_width``, m)."""
    return f"tuned_{variable}"


def fe_tuner(study, variable: str, start_aspect: float | None = None) -> float:
    """The ``variable`` (m) at which L1 = B2 for the plate of ``study`` (its one geometry):
    :func:`fem.tuning.tune_plate` with the other dimension held, starting from the
    width-over-length ``start_aspect`` (:func:`_start`; None: the study's value), at the
    study's FE order and refinement (the mesh the evaluation solves)."""
    import warnings

    from fem.mesh_settings import MeshSettings
    from fem.model import GapValidityWarning
    from fem.tuning import tune_plate
    from studies.task import geometry_of, plate_of

    stator, material = plate_of(study, geometry_of(study, 0))
    held = "length" if variable == "width" else "width"
    with warnings.catch_warnings():  # the evaluation of the tuned plate says its own
        warnings.simplefilter("ignore", GapValidityWarning)
        d = tune_plate(fix=held, material=material, start=_start(stator, held, start_aspect),
                       mesh=MeshSettings(study.solver.fe_order, study.solver.fe_refine))
    return float(d.stator.width_m if variable == "width" else d.stator.length_m)


def start_aspect(study) -> float | None:
    """The width over length of the study's own plate (its stator file's, or its single
    axis values), where the tunes start (:func:`fe_tuner`); None where it has none."""
    if study.stator is not None:
        return study.stator.stator.width_m / study.stator.stator.length_m
    width, length = study.axes["width"], study.axes["length"]
    return width[0] / length[0] if len(width) == len(length) == 1 else None


def _start(stator, held: str, aspect: float | None):
    """The tune's start: ``stator`` with the tuned dimension at the width-over-length
    ``aspect`` of the held one (the study's own plate's: a tuned plate's aspect changes little
    with its size, so the tune starts next to the crossing), or as it is (``aspect`` None)."""
    from studies.study import plate_with

    if aspect is None:
        return stator
    if held == "length":
        return plate_with(stator, {"width_m": aspect * stator.length_m})
    return plate_with(stator, {"length_m": stator.width_m / aspect})


def tuned_evaluation(evaluate: Callable, tuner: Tuner, tune: Tune, study, index: int) -> dict:
    """Tune ``study``'s plate (:class:`Tune`), then ``evaluate(tuned study, index)``; the
    outputs carry the tuned value (:func:`tuned_key`). A plate not tunable within the tune's
    range is not evaluated: NaN outputs, its reason in ``status``."""
    from studies.task import empty_outputs, plate_failed

    v = tune.variable
    try:
        value, reason = tuner(study, v), ""
    except (ValueError, RuntimeError, ArithmeticError) as exc:
        value, reason = math.nan, f"tune: the {v} has no L1 = B2 crossing ({exc})"
    if math.isfinite(value) and not _within(value, tune):
        reason = (f"tune: the {v} {value * 1e3:.4g} mm tuned to L1 = B2 lies outside "
                  f"[{tune.low * 1e3:g}, {tune.high * 1e3:g}] mm")
    if reason:
        out = plate_failed(study, empty_outputs(study), reason, "the plate could not be tuned")
    else:
        out = evaluate(replace(study, axes={**study.axes, v: (value,)}), index)
    out[tuned_key(v)] = np.array(value)
    return out


def _within(value: float, tune: Tune) -> bool:
    return not (value < tune.low or value > tune.high)  # a NaN side bounds nothing


def tune_constraint(tune: Tune, outputs: dict[str, np.ndarray]) -> float:
    """The ``tuned`` constraint value (<= 0 met): the tuned value's excess over its range
    (relative to the bound), and the evaluated plate's ``|split| / f_L1`` over
    :data:`TUNED_SPLIT`, the larger; :data:`UNTUNABLE` when no crossing was found."""
    value = float(outputs[tuned_key(tune.variable)])
    if not math.isfinite(value):
        return UNTUNABLE
    parts = []
    if math.isfinite(tune.low):
        parts.append((tune.low - value) / tune.low)
    if math.isfinite(tune.high):
        parts.append((value - tune.high) / tune.high)
    split = abs(float(outputs["split"])) / float(outputs["f_L1_short"]) - TUNED_SPLIT
    if math.isfinite(split):
        parts.append(split)
    return max(parts) if parts else math.nan


def tuned_design(tune: Tune | None, design: dict[str, Any],
                 outputs: dict[str, np.ndarray]) -> dict[str, Any]:
    """``design`` with its tuned value (the plate evaluated), as the search's variables."""
    if tune is None:
        return design
    return {**design, tune.variable: float(outputs[tuned_key(tune.variable)])}
