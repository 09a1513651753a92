"""Design-space exploration on dask.distributed: one task per geometry, labelled results.

A :class:`studies.study.Study` spans geometry axes (length, width, thickness, gap,
material) and drive axes (frequency, voltage, preload, load). :func:`explore` submits one
task per geometry (:func:`studies.task.compute_geometry`) to a dask cluster
(:mod:`studies.cluster`: a LocalCluster of processes by default, or any running scheduler),
keeping a bounded window of tasks in flight.

Nothing is lost:

* every finished geometry is written by the client, as it arrives, to its part file
  (:mod:`studies.parts`), so ``resume=True`` continues an interrupted study and the final
  dataset is the same as an uninterrupted run's;
* a worker process that dies mid-task loses nothing: the scheduler reruns its task elsewhere
  (``distributed.scheduler.allowed-failures``);
* results do not depend on the number of workers: each task is a pure function of the study
  and its geometry index.

Once every geometry is in, the parts become one labelled dataset (:mod:`studies.dataset`)
and the parts folder goes.
"""

from __future__ import annotations

import os
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from bounds import short_reason
from lusm.interrupts import checkpoint
from studies.cluster import (
    DEFAULT_WORKERS,
    WORKER_TIMEOUT_S,
    ClusterWatch,
    cluster_where,
    study_client,
)
from studies.dataset import assemble, check_out, is_complete, write_dataset
from studies.parts import open_parts, remove_parts, write_part
from studies.progress import progress_bar
from studies.study import Study
from studies.task import (
    TASK_EXTRAS,
    WARNING_SEPARATOR,
    compute_geometry,
    has_results,
    package_version,
)


@dataclass
class ExploreResult:
    """What :func:`explore` did.

    Attributes
    ----------
    path : Path
        The written dataset.
    geometries, drive_points : int
        FE solves and drive points of the study (per geometry).
    computed, reused : int
        Geometries computed in this run and taken from an earlier, interrupted run.
    wall_time_s : float
    task_times_s : list of float
        Wall time of each computed task, measured in the task (s).
    result_bytes : int
        Bytes of the task results sent back to the client (pickled).
    workers : int
        Workers of the cluster when the study started.
    write_time_s : float
        Assembling and writing the dataset at the end (s).
    part_write_time_s : float
        The client's time writing part files, all parts together (s).
    figures : list of str
    warnings : list of str
        The distinct warnings of the dataset's geometries (each geometry's ``warnings``,
        raised on the workers, in geometry order; the caller says them: on the workers they
        print as raw Python warnings with a source line).
    already_complete : bool
        ``resume=True`` found this study's complete dataset at ``out``; nothing was run.
    """

    path: Path
    geometries: int
    drive_points: int
    computed: int = 0
    reused: int = 0
    wall_time_s: float = 0.0
    task_times_s: list[float] = field(default_factory=list)
    result_bytes: int = 0
    workers: int = 0
    write_time_s: float = 0.0
    part_write_time_s: float = 0.0
    figures: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    already_complete: bool = False

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready summary."""
        t = self.task_times_s
        return {"out": str(self.path), "geometries": self.geometries,
                "drive_points_per_geometry": self.drive_points,
                "points": self.geometries * self.drive_points, "computed": self.computed,
                "reused": self.reused, "workers": self.workers,
                "wall_time_s": self.wall_time_s,
                "task_time_mean_s": float(np.mean(t)) if t else None,
                "result_bytes": self.result_bytes, "figures": self.figures,
                "warnings": self.warnings, "already_complete": self.already_complete}


IN_FLIGHT_PER_WORKER = 4
"""Geometry tasks kept submitted per worker (at least :data:`MIN_IN_FLIGHT`): enough to keep
each worker busy while the client writes parts, few enough that the client's memory does not
grow with the study."""


MIN_IN_FLIGHT = 16
"""The smallest window of geometry tasks in flight (:func:`in_flight`)."""

WINDOW_RECHECK = 8
"""Completed tasks between two counts of the cluster's workers (a scheduler round trip)."""

def in_flight(workers: int, tasks: int) -> int:
    """Tasks to keep submitted on ``workers`` workers out of ``tasks`` left."""
    return min(tasks, max(MIN_IN_FLIGHT, IN_FLIGHT_PER_WORKER * max(workers, 1)))


def explore(
    study: Study,
    out: str | Path,
    *,
    client=None,
    scheduler: str | None = None,
    scheduler_file: str | None = None,
    workers: int = DEFAULT_WORKERS,
    resume: bool = False,
    force: bool = False,
    progress: bool = True,
    on_part: Callable[[int], None] | None = None,
    worker_timeout_s: float = WORKER_TIMEOUT_S,
) -> ExploreResult:
    """Run a study on dask.distributed and write its dataset to ``out`` (netCDF).

    Parameters
    ----------
    study : Study
    out : path
        The ``.nc`` file to write; its parts go to ``<out>.parts/`` meanwhile.
    client : distributed.Client, optional
        Use this client (and its cluster); otherwise :func:`studies.cluster.connect` with
        ``scheduler``, ``scheduler_file`` or a LocalCluster of ``workers`` processes, closed
        at the end.
    resume : bool
        Continue from the parts of an interrupted run of the same study; on a study whose
        dataset ``out`` is already complete, return at once and leave it as it is.
    force : bool
        Replace an existing ``out`` (kept as ``out.bak-N``).
    progress : bool
        Show a tqdm progress bar on stderr (geometries done).
    on_part : callable, optional
        Called with the geometry index after each part is written (tests interrupt here).
    worker_timeout_s : float
        How long (s) to wait for a cluster with no worker left; the wait is said
        (:class:`ClusterWaitWarning`) after :data:`WORKER_NOTICE_S`.

    Raises
    ------
    ClusterLostError
        The scheduler went away, or no worker came back within ``worker_timeout_s``; the
        finished geometries stay in the parts folder for ``resume=True``.

    Returns
    -------
    ExploreResult
    """
    out = Path(out)
    # an FE-only study drives nothing (no drive point per geometry)
    points = study.n_drive_points if study.needs_motor else 0
    if resume and is_complete(study, out):  # resuming a finished study changes nothing
        return ExploreResult(out, study.n_geometries, points, reused=study.n_geometries,
                             already_complete=True)
    check_out(out, force)
    t0 = time.perf_counter()
    # folders above --out that this run makes: removed again, if still empty, when it stops
    # before computing anything
    made = [p for p in Path(os.path.abspath(out)).parents if not p.exists()]
    folder, parts, created, lock = open_parts(study, out, resume)
    try:
        result = ExploreResult(out, study.n_geometries, points, reused=len(parts))
        todo = [i for i in range(study.n_geometries) if i not in parts]
        if todo:
            cluster = (client, scheduler, scheduler_file, workers, worker_timeout_s)
            try:
                _compute_on_cluster(cluster, study, todo, folder, parts, result, progress,
                                    on_part)
            except BaseException:
                if created and result.computed == 0:  # nothing was computed: leave no trace
                    remove_parts(folder, study.n_geometries, made)
                raise
        _refuse_if_nothing_computed(study, parts, folder, created)
        result.warnings = geometry_warnings(parts)
        _write_result(study, parts, out, folder, force, result)
        result.wall_time_s = time.perf_counter() - t0
        return result
    finally:
        lock.release()  # its file went with the folder once the dataset is in


def _compute_on_cluster(cluster: tuple, study: Study, todo: list[int], folder: Path,
                        parts: dict[int, dict], result: ExploreResult, progress: bool,
                        on_part: Callable[[int], None] | None) -> None:
    """Open the study's client from ``cluster`` (``client, scheduler, scheduler_file,
    workers, worker_timeout_s`` of :func:`explore`) and compute the geometries ``todo``
    on it (:func:`_compute_all`)."""
    client, scheduler, scheduler_file, workers, worker_timeout_s = cluster
    # no more local processes than geometries to compute (idle ones cost memory)
    with study_client(client, scheduler, scheduler_file, max(1, min(workers, len(todo))),
                      gmsh=study.meshed_by_gmsh) as running:
        watch = ClusterWatch(cluster_where(scheduler, scheduler_file), worker_timeout_s)
        _compute_all(running, study, todo, folder, parts, result, watch, progress, on_part)


def _compute_all(client, study: Study, todo: list[int], folder: Path,
                 parts: dict[int, dict], result: ExploreResult, watch: ClusterWatch, progress: bool,
                 on_part: Callable[[int], None] | None) -> None:
    """Compute the geometries ``todo`` on ``client``, taking each part in as it arrives
    (:func:`_take_part`) with a bounded window of tasks in flight, topped up as each
    finishes (dask's ``as_completed(...).add`` pattern): a future per geometry up front
    would grow the client by 55 MB/s towards 100 000 of them before any part is written.
    While no task finishes, ``watch`` looks at the cluster (:meth:`ClusterWatch.wait`): a lost
    scheduler or a cluster without workers for too long ends the study, its parts kept.
    Tasks still in flight when this stops (an error, an interrupt) are cancelled."""
    from distributed import as_completed

    # nthreads() lists every worker (scheduler_info() gives at most 5 on some dask
    # releases: a window sized from it starves a large cluster)
    result.workers = len(client.nthreads())
    run = uuid.uuid4().hex[:8]  # keys of a cancelled earlier run may still be live
    live, index = set(), {}  # submitted and not yet taken in
    waiting = iter(todo)

    def submit_next():
        """Submit the next geometry, if any (returns its future or None)."""
        i = next(waiting, None)
        if i is None:
            return None
        fut = client.submit(compute_geometry, study, i, pure=False,
                            key=f"lusm-geometry-{study.fingerprint[:8]}-{run}-{i}")
        live.add(fut)
        index[fut.key] = i
        return fut

    window = [submit_next() for _ in range(in_flight(result.workers, len(todo)))]
    bar = progress_bar(len(todo) + len(parts), len(parts), progress, "geometry",
                       "lusm explore")
    try:
        completed = as_completed(window)
        n_done = 0
        while not completed.is_empty():
            watch.wait(client, completed)
            fut = next(completed)
            n_done += 1
            # topped up to the window of the workers there are now: workers that join later
            # (an adaptive cluster) widen it
            workers = (watch.workers(client) if n_done % WINDOW_RECHECK == 0
                       else result.workers)
            result.workers = max(result.workers, workers)
            want = in_flight(workers, len(todo))
            while len(live) - 1 < want:
                nxt = submit_next()
                if nxt is None:
                    break
                completed.add(nxt)
            data = watch.result(client, fut)
            i = index.pop(fut.key)
            _take_part(data, i, folder, parts, result, watch.where)
            bar.update(1)
            live.discard(fut)
            fut.release()
            checkpoint()  # a swallowed Ctrl-C / SIGTERM: stop at the next geometry
            if on_part is not None:
                on_part(i)
    finally:
        bar.close()
        if client.status == "running":  # a lost scheduler has nothing left to cancel
            for f in live:
                f.cancel()


def _take_part(data: dict[str, np.ndarray], index: int, folder: Path,
               parts: dict[int, dict], result: ExploreResult, where: str) -> None:
    """Take in the result ``data`` of geometry ``index``: check its lusm version, count its
    time, size and warnings, write its part file and keep its outputs in ``parts``."""
    import pickle

    if str(data.get("lusm_version")) != package_version():
        # a worker that joined after check_workers, with other lusm
        raise ValueError(f"{where}: a worker computed geometry {index} with lusm "
                         f"{data.get('lusm_version')}, this client {package_version()}; "
                         "install the same version everywhere")
    result.task_times_s.append(float(data["task_time_s"]))
    result.result_bytes += len(pickle.dumps(data, protocol=5))
    tw = time.perf_counter()
    write_part(folder, index, data)
    result.part_write_time_s += time.perf_counter() - tw
    parts[index] = {k: v for k, v in data.items() if k not in TASK_EXTRAS}
    result.computed += 1


def _write_result(study: Study, parts: dict[int, dict], out: Path, folder: Path, force: bool,
                  result: ExploreResult) -> None:
    """Assemble the dataset, write it to ``out`` and remove the parts folder, as one step."""
    from contact.deferred_signals import deferred_signals

    t1 = time.perf_counter()
    ds = assemble(study, parts)
    # the dataset and the removal of the parts are one step: a Ctrl-C between them would
    # leave a complete dataset beside a half-removed parts folder, where --resume and
    # --force each send the user to the other; a signal lands after both
    with deferred_signals():
        write_dataset(ds, out, force)
        remove_parts(folder, study.n_geometries)
    result.write_time_s = time.perf_counter() - t1


class NothingComputedError(ValueError):
    """No geometry of a study computed fully: no dataset is written, the parts are kept."""


def geometry_warnings(parts: dict[int, dict]) -> list[str]:
    """The warnings of the geometries ``parts`` (their ``warnings``), once per kind, in
    geometry order: warnings that differ only in their numbers (a force factor per plate)
    are one kind, said by its first with the count of geometries that gave it."""
    first: dict[str, str] = {}
    count: dict[str, int] = {}
    for i in sorted(parts):
        kinds = set()
        for w in str(parts[i]["warnings"]).split(WARNING_SEPARATOR):
            kind = _kind(w)
            if w and kind not in kinds:
                kinds.add(kind)
                first.setdefault(kind, w)
                count[kind] = count.get(kind, 0) + 1
    return [first[k] + (f" ({count[k]} of {len(parts)} geometries; each one's in the "
                        "dataset's 'warnings')" if count[k] > 1 else "")
            for k in first]


def _kind(text: str) -> str:
    """``text`` with its numbers replaced by ``#``: one kind of message, whatever the plate."""
    import re

    return re.sub(r"[-+]?\d[\d.eE+-]*", "#", text)


def _refuse_if_nothing_computed(study: Study, parts: dict[int, dict], folder: Path,
                                created: bool) -> None:
    """Refuse to write a dataset of NaN: when no geometry has any answer (:func:`studies.
    task.has_results`), nothing is written to ``--out`` (a dataset of NaN there made the
    corrected rerun refuse the existing file). The parts (each with its reason in
    ``status``) stay in ``folder``, except where every plate failed for one reason of the
    study's stator file, said whole: those parts hold nothing more, and a folder made by this
    run (``created``) goes (:func:`_stator_failure`)."""
    status = [str(parts[i]["status"]) for i in sorted(parts)]
    if not status or any(has_results(p) for p in parts.values()):
        return
    stator = _stator_failure(study, status)
    if stator is not None and created:
        remove_parts(folder, study.n_geometries)
        raise NothingComputedError(f"{stator}; no dataset was written")
    raise NothingComputedError(
        f"no geometry of the study computed fully ({len(status)} of {study.n_geometries}); "
        f"first: {short_reason(status[0])}; no dataset was written, and "
        + ("the part (its reason in its 'status') is" if len(status) == 1 else
           f"the {len(status)} parts (each one's reason in its 'status') are")
        + f" kept in {folder}; remove that folder to run a corrected study")


def _stator_failure(study: Study, status: list[str]) -> str | None:
    """The one line of a study whose every plate failed at its FE solve or parameter set
    for the same reason, with a stator file: its fault (electrodes that touch, a tip on a
    node of a mode), named as ``study.stator FILE``; None otherwise."""
    if (study.stator is None or len(set(map(_kind, status))) != 1
            or len(status) != study.n_geometries):
        return None
    stage, _, reason = status[0].partition(": ")
    if stage not in ("FE", "parameter set"):
        return None
    kind, _, text = reason.partition(": ")
    return (f"study.stator {study.stator.path}: {short_reason(text or kind)} (every plate of "
            f"the study, {len(status)} of {len(status)}, at its {stage})")
