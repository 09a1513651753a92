"""The search: optuna's TPE sampler asked in batches, the designs evaluated on dask.

Each batch is as many designs as the cluster has workers. The sampler of batch ``b`` is a
fresh :class:`optuna.samplers.TPESampler` seeded with ``(seed, b)``, given every evaluation
of the batches before it (:func:`ask_batch`): the designs a batch asks for depend only on the
seed and on what was evaluated before, so a run resumed from its parts asks for the same
designs as the uninterrupted run, and gives the same result.
"""

from __future__ import annotations

import math
import time
import uuid
import warnings
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from studies.cluster import WORKER_TIMEOUT_S, ClusterWatch, cluster_where
from studies.optimize.metrics import evaluation_metrics
from studies.optimize.problem import Problem, trial_study
from studies.optimize.result import OptimizeResult, is_complete_file, write_result
from studies.optimize.store import Record, Store
from studies.optimize.tuned import Tuner, fe_tuner, start_aspect, tuned_evaluation
from studies.progress import progress_bar
from studies.task import TASK_EXTRAS

Evaluator = Callable[[Any, int], dict]
"""``evaluate(study, 0) -> outputs``: :func:`studies.task.compute_geometry` by default; a
test gives an analytic function of the same arrays."""


def _distributions(problem: Problem) -> dict:
    from optuna.distributions import CategoricalDistribution, FloatDistribution

    out = {}
    for v in problem.variables:
        if v.name == "material":
            out[v.name] = CategoricalDistribution(v.choices)
        else:
            out[v.name] = FloatDistribution(v.low, v.high, step=v.step)
    return out


def _frozen(problem: Problem, record: Record, dists: dict):
    """``record`` as an optuna trial: complete with its objectives and constraint values,
    failed where an objective could not be computed."""
    from optuna.trial import TrialState, create_trial

    values, cons = evaluation_metrics(problem, record.outputs, record.design,
                                      trial_study(problem, record.design))
    params = {v.name: record.design[v.name] for v in problem.variables}
    if problem.tune is not None and cons[-1] > 0 and not all(map(math.isfinite, values)):
        # not tunable (not evaluated): infeasible by its tune alone; TPE ranks an infeasible
        # trial by its constraint values only, so its objectives are placeholders
        values = [0.0] * len(values)
        cons = [c if math.isfinite(c) else 0.0 for c in cons]
    if not all(math.isfinite(x) for x in values + cons):
        return create_trial(state=TrialState.FAIL, params=params, distributions=dists)
    return create_trial(values=values, params=params, distributions=dists,
                        constraints={str(i): c for i, c in enumerate(cons)} if cons else None)


def ask_batch(problem: Problem, history: list[Record], index: int, size: int,
              frozen: dict[int, Any] | None = None) -> list[dict]:
    """The ``size`` designs of batch ``index``: a TPE sampler seeded with ``(seed, index)``
    given the evaluations ``history`` (every batch before this one), asked ``size`` times
    (constant liar: the designs of one batch spread out). ``frozen`` keeps each record's
    optuna trial by trial number between batches (its metrics computed once)."""
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    seed = int(np.random.SeedSequence([problem.seed, index]).generate_state(1)[0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        sampler = optuna.samplers.TPESampler(seed=seed, n_startup_trials=problem.startup,
                                             multivariate=True, constant_liar=True)
        study = optuna.create_study(
            sampler=sampler,
            directions=["maximize" if o.maximize else "minimize" for o in problem.objectives])
        dists = _distributions(problem)
        frozen = {} if frozen is None else frozen
        for r in history:
            if r.trial not in frozen:
                frozen[r.trial] = _frozen(problem, r, dists)
        study.add_trials([frozen[r.trial] for r in history])
        return [_plain(study.ask(dists).params) for _ in range(size)]


def _plain(params: dict) -> dict:
    """Optuna's values as plain Python (a float, a material's name)."""
    return {k: (v if isinstance(v, str) else float(v)) for k, v in params.items()}


def _task(problem: Problem, evaluate: Evaluator, tuner: Tuner | None) -> tuple:
    """The function a worker runs on ``(study, 0)``, and its leading arguments: ``evaluate``,
    or with ``split = "tuned"`` the tune then ``evaluate``
    (:func:`studies.optimize.tuned.tuned_evaluation`)."""
    if problem.tune is None:
        return (evaluate,)
    if tuner is None:
        from functools import partial

        tuner = partial(fe_tuner, start_aspect=start_aspect(problem.study))
    return (tuned_evaluation, evaluate, tuner, problem.tune)


def run_batches(client, problem: Problem, store: Store, evaluate: Evaluator, budget: int,
                wall_time_s: float | None, on_trial: Callable[[int], None] | None,
                progress: bool, watch: ClusterWatch, tuner: Tuner | None = None
                ) -> tuple[int, str]:
    """Evaluate batches of designs until ``budget`` designs have been, or ``wall_time_s``
    (s) has passed; returns the designs this run evaluated and what stopped it. While no
    evaluation finishes, ``watch`` looks at the cluster (explore's
    :meth:`studies.cluster.ClusterWatch.wait`): a lost scheduler, or no worker for longer
    than its bound, raises :class:`studies.cluster.ClusterLostError`, the parts kept."""
    from distributed import as_completed

    from lusm.interrupts import checkpoint

    t0, computed, batch = time.monotonic(), 0, store.batch
    run = uuid.uuid4().hex[:8]
    bar = progress_bar(budget, len(store.records), progress, "design", "lusm optimize")
    submitted: dict[str, tuple] = {}  # in flight: key -> (future, trial, design)
    frozen: dict[int, Any] = {}  # the optuna trial of each stored evaluation
    task = _task(problem, evaluate, tuner)
    try:
        for b in range((budget + batch - 1) // batch):
            first, size = b * batch, min(batch, budget - b * batch)
            have = [t for t in range(first, first + size) if t in store.records]
            if len(have) == size:
                continue
            if wall_time_s is not None and time.monotonic() - t0 > wall_time_s and not have:
                return computed, "wall_time"
            history = [store.records[t] for t in sorted(store.records) if t < first]
            designs = ask_batch(problem, history, b, size, frozen)
            for j, design in enumerate(designs):
                t = first + j
                if t in store.records and store.records[t].design == design:
                    continue
                fut = client.submit(*task, trial_study(problem, design), 0, pure=False,
                                    key=f"lusm-optimize-{run}-{t}")
                submitted[fut.key] = (fut, t, design)
            completed = as_completed([f for f, _, _ in submitted.values()])
            while not completed.is_empty():
                watch.wait(client, completed)
                fut = next(completed)
                _, t, design = submitted.pop(fut.key)
                data = watch.result(client, fut)
                outputs = {k: v for k, v in data.items() if k not in TASK_EXTRAS}
                store.add(Record(t, design, outputs))
                computed += 1
                bar.update(1)
                checkpoint()
                if on_trial is not None:
                    on_trial(t)
    finally:
        bar.close()
        if client.status == "running":
            for fut, _, _ in submitted.values():
                fut.cancel()
    return computed, "evaluations"


def optimize(problem: Problem, out: str | Path, *, client=None, scheduler: str | None = None,
             scheduler_file: str | None = None, workers: int = 2, budget: int | None = None,
             resume: bool = False, force: bool = False, evaluate: Evaluator | None = None,
             progress: bool = False, on_trial: Callable[[int], None] | None = None,
             worker_timeout_s: float = WORKER_TIMEOUT_S, tuner: Tuner | None = None
             ) -> OptimizeResult:
    """Search the design space of ``problem`` for its best designs; write one dataset row per
    evaluation to ``out``.

    Parameters
    ----------
    problem : Problem
        The study and its ``[optimize]`` table (:func:`studies.optimize.problem.load_problem`).
    out : str or Path
        The netCDF dataset to write (refused if it exists, unless ``force``: then kept as
        ``out.bak-N``). The evaluations are kept in ``out.parts/`` meanwhile.
    client, scheduler, scheduler_file, workers
        The cluster (:func:`studies.cluster.study_client`): the caller's client, an existing
        scheduler, or a LocalCluster of ``workers`` processes.
    budget : int, optional
        Designs to evaluate (default: the study's ``optimize.evaluations``).
    resume : bool
        Continue from the parts of an interrupted run (the same designs are asked again, the
        evaluated ones are not computed again).
    force : bool
    evaluate : callable, optional
        ``evaluate(study, 0) -> outputs`` run on the workers (default
        :func:`studies.task.compute_geometry`).
    progress : bool
        A progress bar on stderr.
    on_trial : callable, optional
        Called with the trial number after each evaluation is stored (tests interrupt here).
    worker_timeout_s : float
        How long (s) to wait for a cluster with no worker left, as explore waits
        (:class:`studies.cluster.ClusterWatch`).
    tuner : callable, optional
        With ``split = "tuned"``: ``tuner(study, variable) -> value`` (m) run on the workers
        before ``evaluate`` (default :func:`studies.optimize.tuned.fe_tuner`, from the
        study's own plate's aspect).

    Raises
    ------
    studies.cluster.ClusterLostError
        From :class:`studies.cluster.ClusterWatch` (scheduler gone, or no worker back within
        ``worker_timeout_s``); the evaluated designs stay in the parts folder for
        ``resume=True``.

    Returns
    -------
    OptimizeResult
    """
    from studies.cluster import study_client
    from studies.dataset import check_out
    from studies.task import compute_geometry

    out = Path(out)
    budget = problem.evaluations if budget is None else int(budget)
    if resume and is_complete_file(out, problem.fingerprint):
        from studies.optimize.result import result_of_file

        return result_of_file(problem, out)
    check_out(out, force)
    t0 = time.perf_counter()
    with Store(problem, out, resume) as store:
        reused = len(store.records)
        watch = ClusterWatch(cluster_where(scheduler, scheduler_file), worker_timeout_s)
        with study_client(client, scheduler, scheduler_file, workers,
                          gmsh=problem.study.meshed_by_gmsh) as running:
            n_workers = max(1, len(running.nthreads()))
            store.set_batch(n_workers)
            computed, stopped = run_batches(running, problem, store, evaluate or
                                            compute_geometry, budget, problem.wall_time_s,
                                            on_trial, progress, watch, tuner)
        result = write_result(problem, store, out, force)
    return replace(result, computed=computed, reused=reused, workers=n_workers,
                   batch=store.batch, wall_time_s=time.perf_counter() - t0,
                   stopped_by=stopped)
