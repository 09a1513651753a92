"""The result dataset of an optimisation: one row per evaluated design, labelled, with units.

Dimension ``trial`` (the evaluation number, optuna's trial number); the design's values
(``length``, ...: explore's names and units), the plate's outputs as explore's dataset has
them (the motor answers over the study's drive axes), each objective
(``objective_<name>``), each constraint's value (``constraint_<name>``: <= 0 met, relative
to its bound), ``feasible`` and ``best`` (the best design, or the Pareto front of several
objectives, among the feasible ones).
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from studies.optimize.metrics import constraint_names, evaluation_metrics
from studies.optimize.problem import Problem, trial_study
from studies.optimize.store import Store
from studies.optimize.tuned import tuned_key


@dataclass(frozen=True)
class OptimizeResult:
    """What an optimisation found.

    Attributes
    ----------
    path : Path
        The result dataset (netCDF), one row per evaluation.
    evaluations : int
        Designs evaluated in all (this run and the earlier ones it resumed).
    computed, reused : int
        Designs this run evaluated, and those taken from an earlier run's parts.
    feasible : int
        Evaluations that met every constraint (and computed).
    best : tuple of int
        Trial numbers of the best feasible designs: one for one objective, the Pareto front
        for several; empty when no design is feasible.
    objectives : tuple of str
        The objectives' labels (``peak_power``; units in the dataset).
    workers, batch : int
        The cluster's workers and the designs asked at once.
    wall_time_s : float
        This run's wall time (s).
    stopped_by : str
        ``"evaluations"`` (the budget) or ``"wall_time"``.
    already_complete : bool
        ``--resume`` found the finished dataset and changed nothing.
    warnings : tuple of str
    """

    path: Path
    evaluations: int
    computed: int
    reused: int
    feasible: int
    best: tuple[int, ...]
    objectives: tuple[str, ...]
    workers: int = 0
    batch: int = 0
    wall_time_s: float = 0.0
    stopped_by: str = "evaluations"
    already_complete: bool = False
    warnings: tuple[str, ...] = field(default=())

    @property
    def infeasible_everywhere(self) -> bool:
        """True when no evaluated design met the constraints: there is no optimum."""
        return not self.best


def objective_variable(label: str) -> str:
    """The dataset variable of an objective (``stall_force / volume`` ->
    ``objective_stall_force_per_volume``)."""
    return "objective_" + re.sub(r"\s*/\s*", "_per_", label)


def metrics_table(problem: Problem, records: list) -> tuple[np.ndarray, np.ndarray]:
    """The objectives ``(n, k)`` and constraint values ``(n, m)`` of ``records`` (SI)."""
    values, cons = [], []
    for r in records:
        v, c = evaluation_metrics(problem, r.outputs, r.design, trial_study(problem, r.design))
        values.append(v)
        cons.append(c)
    n = len(records)
    return (np.array(values, dtype=float).reshape(n, len(problem.objectives)),
            np.array(cons, dtype=float).reshape(n, len(constraint_names(problem))))


def feasible_mask(values: np.ndarray, cons: np.ndarray) -> np.ndarray:
    """Designs whose objectives computed and whose constraint values are all <= 0."""
    return np.isfinite(values).all(axis=1) & np.all(cons <= 0.0, axis=1)


def best_trials(problem: Problem, values: np.ndarray, feasible: np.ndarray) -> list[int]:
    """Row indices of the best feasible designs: the best one for one objective (the first
    of equals), the non-dominated ones (Pareto front) for several."""
    sign = np.array([-1.0 if o.maximize else 1.0 for o in problem.objectives])
    rows = np.flatnonzero(feasible)
    if rows.size == 0:
        return []
    loss = values[rows] * sign  # minimised
    if loss.shape[1] == 1:
        return [int(rows[int(np.argmin(loss[:, 0]))])]
    front = []
    for i, a in enumerate(loss):
        dominated = np.any(np.all(loss <= a, axis=1) & np.any(loss < a, axis=1))
        if not dominated:
            front.append(int(rows[i]))
    return front


def assemble(problem: Problem, records: list):
    """The labelled :class:`xarray.Dataset` of the evaluations ``records`` (trial order)."""
    import xarray as xr

    from studies.dataset import AXIS_NAMES, provenance

    study = problem.study
    values, cons = metrics_table(problem, records)
    feasible = feasible_mask(values, cons)
    best = best_trials(problem, values, feasible)
    trials = np.array([r.trial for r in records], dtype=int)
    data = {}
    for v in problem.variables:
        column = [r.design[v.name] for r in records]
        if v.name == "material":
            data[v.name] = ("trial", np.array(column, dtype=object),
                            {"long_name": "stator material (design variable)"})
        else:
            unit = "m" if v.name != "frequency" else "Hz"
            data[v.name] = ("trial", np.array(column, dtype=float),
                            {"units": unit, "long_name": f"{AXIS_NAMES[v.name]} (design "
                             f"variable, in [{v.low:g}, {v.high:g}] {unit})"})
    if problem.tune is not None:
        v = problem.tune.variable
        held = "length" if v == "width" else "width"
        data[tuned_key(v)] = ("trial", np.array([float(r.outputs[tuned_key(v)]) for r in
                                                 records]), {
            "units": "m", "long_name": f"{AXIS_NAMES[v]} tuned until L1 = B2 (the {held} "
            "held; fem.tuning.tune_plate), the plate evaluated; NaN: no crossing"})
    data.update(_outputs(problem, records))
    for k, o in enumerate(problem.objectives):
        data[objective_variable(o.label)] = (
            "trial", values[:, k], {"units": o.unit, "long_name": f"objective: {o.label}, "
                                    f"{'maximised' if o.maximize else 'minimised'}"
                                    + (f" at {o.at}" if o.at else " (worst operating point)")})
    for k, name in enumerate(constraint_names(problem)):
        data[f"constraint_{name}"] = ("trial", cons[:, k], {
            "units": "1", "long_name": f"constraint {name}: excess over its bound, relative "
            "to it (<= 0: met)"})
    data["feasible"] = ("trial", feasible.astype(np.int8), {
        "long_name": "1: computed and every constraint met"})
    marks = np.zeros(len(records), dtype=np.int8)
    marks[best] = 1
    data["best"] = ("trial", marks, {"long_name": "1: the best feasible design (one "
                                     "objective) or on the Pareto front (several)"})
    coords = {"trial": ("trial", trials, {"long_name": "evaluation number (optuna trial)"})}
    for a in study.drive_dims:
        if a == "frequency":
            continue
        coords[a] = (a, np.array(study.axes[a], dtype=float),
                     {"units": {"voltage": "V"}.get(a, "N"), "long_name": AXIS_NAMES[a]})
    attrs = provenance(study)
    attrs["title"] = f"lusm optimize: {study.name}"
    attrs.update({"optimize": problem.text, "optimize_fingerprint": problem.fingerprint,
                  "sampler": sampler_text(problem),
                  "best_trials": json.dumps([int(trials[i]) for i in best])})
    return xr.Dataset(data, coords=coords, attrs=attrs)


def sampler_text(problem: Problem) -> str:
    """How the designs were chosen, for the dataset's attributes."""
    import optuna

    return (f"optuna {optuna.__version__} TPESampler (multivariate, constant liar, "
            f"{problem.startup} random designs first), seed {problem.seed}, a fresh sampler "
            "per batch seeded with (seed, batch) and given every earlier evaluation")


def _outputs(problem: Problem, records: list) -> dict[str, tuple]:
    """The plate's outputs, stacked over the trials, as explore's dataset labels them."""
    from studies.study import OUTPUTS

    study = problem.study
    mdims = [a for a in study.drive_dims if a not in ("load", "frequency")]
    squeeze = "frequency" in study.drive_dims  # a design's own frequency: one value
    out = {}

    def stack(name: str) -> np.ndarray:
        arr = np.stack([np.asarray(r.outputs[name]) for r in records])
        return arr[:, 0] if squeeze and arr.ndim > 1 else arr

    for o in study.outputs:
        unit, meaning = OUTPUTS[o]
        attrs = {"long_name": meaning, **({"units": unit} if unit else {})}
        if o == "k_eff":
            for m in ("L1", "B2"):
                out[f"k_eff_{m}"] = ("trial", stack(f"k_eff_{m}"), {
                    "units": "1", "long_name": f"effective electromechanical coupling factor "
                    f"of {m}"})
        elif o in ("f_L1_short", "f_L1_open", "f_B2_short", "f_B2_open", "split"):
            out[o] = ("trial", stack(o), attrs)
        elif o == "velocity":
            out[o] = (["trial", *mdims, "load"], stack(o), attrs)
        elif o == "motion_class":
            out[o] = (["trial", *mdims], stack(o).astype(object), attrs)
        else:
            out[o] = (["trial", *mdims], stack(o), attrs)
    if study.needs_motor and study.auto_frequency:
        out["f_drive"] = ("trial", stack("f_drive"), {
            "units": "Hz", "long_name": "drive frequency (auto: contact.drive.auto_frequency)"})
    for name in ("status", "warnings"):
        out[name] = ("trial", stack(name).astype(object), {
            "long_name": "'ok', or why the plate or some drive points failed"
            if name == "status" else "what the plate's computation warned"})
    return out


def write_result(problem: Problem, store: Store, out: Path, force: bool):
    """Write the dataset of every evaluation in ``store`` to ``out``, then remove the parts
    (one step: a signal lands after both); returns the :class:`OptimizeResult`."""
    from contact.deferred_signals import deferred_signals
    from studies.dataset import write_dataset

    records = [store.records[t] for t in sorted(store.records)]
    if not records:
        raise ValueError(f"--out {out}: no design was evaluated (the wall time ran out "
                         "before the first batch); no dataset was written")
    ds = assemble(problem, records)
    with deferred_signals():
        write_dataset(ds, out, force)
        store.close()
        store.remove()
    return result_of_dataset(problem, ds, out)


def result_of_dataset(problem: Problem, ds, out: Path):
    """The :class:`OptimizeResult` a dataset holds."""
    return OptimizeResult(Path(out), int(ds.sizes["trial"]), 0, 0,
                          int(ds["feasible"].values.sum()),
                          tuple(json.loads(ds.attrs["best_trials"])),
                          tuple(o.label for o in problem.objectives))


def is_complete_file(out: Path, fingerprint: str) -> bool:
    """Whether ``out`` is the finished dataset of the problem ``fingerprint`` (and no parts
    folder is beside it)."""
    from studies.dataset import open_result
    from studies.parts import parts_folder

    out = Path(out)
    if not out.is_file() or parts_folder(out).exists():
        return False
    try:
        ds = open_result(out)
    except (OSError, ValueError):
        return False
    return ds.attrs.get("optimize_fingerprint") == fingerprint


def result_of_file(problem: Problem, out: Path):
    """The result of a finished run's dataset, changed in nothing (``--resume`` on it)."""
    from dataclasses import replace

    from studies.dataset import open_result

    return replace(result_of_dataset(problem, open_result(out), out), already_complete=True)


def row_design(problem: Problem, ds, row: int) -> dict:
    """The design of row ``row`` (SI, the material's name), its tuned value included (with
    ``split = "tuned"``): the plate that was evaluated."""
    design = {v.name: (str(ds[v.name].values[row]) if v.name == "material"
                       else float(ds[v.name].values[row])) for v in problem.variables}
    if problem.tune is not None:
        design[problem.tune.variable] = float(ds[tuned_key(problem.tune.variable)].values[row])
    return design


def best_row(ds) -> int | None:
    """The row of the best design (the first of the front), None when none is feasible."""
    rows = np.flatnonzero(ds["best"].values)
    return int(rows[0]) if rows.size else None
