"""Design-space exploration on dask.distributed: one task per geometry, labelled results.

A :class:`studies.study.Study` spans geometry axes (length, width, thickness, gap,
material) and drive axes (frequency, voltage, preload, load). :func:`explore` submits one
task per geometry to a dask cluster (a :class:`distributed.LocalCluster` of processes by
default, or any running scheduler); each task (:func:`compute_geometry`) runs the 2D FE
modal solve once (:func:`fem.modes.plate_modes`), reduces it to a parameter set
(:func:`rom.from_fem.fem_params`, which reuses the cached solve) and evaluates every drive
point of that geometry (:func:`motor_answers`).

Nothing is lost:

* every finished geometry is written by the client, as it arrives, to one small ``.npz``
  file in ``<out>.parts/`` (written aside and renamed), so ``resume=True`` continues an
  interrupted study and the final dataset is the same as an uninterrupted run's;
* a worker process that dies mid-task loses nothing: the scheduler reruns its task elsewhere
  (``distributed.scheduler.allowed-failures``);
* results do not depend on the number of workers: each task is a pure function of the study
  and its geometry index, BLAS is held to one thread, ARPACK starts from a fixed vector.

The dataset (:func:`assemble`) has one dimension per axis, units in each variable's attrs and
provenance (package version, parameter-set source, solver settings, the study itself) in the
dataset's attrs; it is written to netCDF (h5netcdf engine) beside the target and renamed in.
"""

from __future__ import annotations

import json
import logging
import math
import os
import sys
import time
import uuid
import zipfile
from collections.abc import Callable
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from lusm.interrupts import checkpoint
from lusm.output_set import backup_name, staging
from studies.study import (
    AXIS_KIND,
    DRIVE_AXES,
    FEATURE_FIELDS,
    OUTPUTS,
    SI_UNIT,
    Study,
    plate_with,
)
from validation.summaries import motion_class

FE_SCALARS = ("f_L1_short", "f_L1_open", "f_B2_short", "f_B2_open", "k_eff_L1", "k_eff_B2",
              "split", "f_drive")
"""Per-geometry numbers of a part file (Hz, or 1 for k_eff)."""
MOTOR_ARRAYS = ("no_load_velocity", "stall_force", "peak_efficiency", "motion_class")
"""Per-drive-point answers without the load dimension."""
PARTS_SUFFIX = ".parts"
"""Folder ``<out>.parts`` next to the output holds one file per finished geometry."""
STUDY_FILE = "study.json"
"""The study a parts folder belongs to (resume refuses another)."""
DEFAULT_WORKERS = 2
"""Processes of the default LocalCluster (this project's machines have 2 cores)."""
BLAS_ENV = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
CONNECT_TIMEOUT = "10s"
"""How long to wait for an existing scheduler."""
CONNECT_DEADLINE_S = 15.0
"""Wall-clock bound (s) on connecting to it: dask's own timeout does not cover a listener
that accepts and never answers (it waited past 45 s)."""


def _within(fn: Callable[[], Any], seconds: float) -> Any:
    """``fn()``, or TimeoutError after ``seconds`` (s) of wall time; ``fn`` runs in a daemon
    thread, abandoned (not stopped) when it overruns."""
    import threading

    box: dict[str, Any] = {}

    def run() -> None:
        try:
            box["value"] = fn()
        except BaseException as exc:  # noqa: BLE001 - re-raised in the caller's thread
            box["error"] = exc

    worker = threading.Thread(target=run, daemon=True, name="lusm-connect")
    worker.start()
    worker.join(seconds)
    if worker.is_alive():
        raise TimeoutError(f"no answer within {seconds:g} s")
    if "error" in box:
        raise box["error"]
    return box["value"]


@dataclass(frozen=True)
class Drive:
    """The drive points of one (frequency, voltage, preload) triple.

    Attributes
    ----------
    voltage_V, preload_N, frequency_Hz : float
    loads_N : tuple of float
        Loads (N) at which the velocity is wanted.
    """

    voltage_V: float
    preload_N: float
    frequency_Hz: float
    loads_N: tuple[float, ...]


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
        The distinct warnings the computed tasks raised on their workers (the caller says
        them; they printed on the workers' stderr as raw Python warnings with a source line).
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


# --- one geometry ---------------------------------------------------------------------------

def geometry_of(study: Study, index: int) -> dict[str, Any]:
    """Axis values (SI, material name) of geometry ``index`` (C order over the axes)."""
    idx = np.unravel_index(index, study.geometry_shape)
    return {a: study.axes[a][int(i)] for a, i in zip(study.geometry_axes, idx, strict=True)}


def _motor_shape(study: Study) -> tuple[int, ...]:
    return tuple(len(study.axes[a]) for a in study.drive_dims if a != "load")


def motor_answers(params, drive: Drive, solver) -> dict[str, Any]:
    """The motor's answer at one drive triple: the ONE place the contact model is called.

    Returns ``no_load_velocity`` (m/s), ``stall_force`` (N), ``peak_efficiency`` (-),
    ``motion_class`` (str) and ``velocity`` (m/s, one per load of ``drive.loads_N``). The
    coupling is :func:`contact.model.default_coupling`'s: work-consistent for these FE sets.

    ``solver.method == "steady"``: the steady state from rest (:func:`contact.steady.engine.
    steady_state`, at ``solver.accuracy``) and the speed-thrust characteristic (21 loads from 0 to
    the stall force for the peak efficiency; a second one only for the study's loads that are
    not among those 21). A transient method
    gives the no-load velocity and motion class of a run from rest; the loaded answers are
    then NaN.
    """
    from contact.model import default_coupling

    coupling = default_coupling(params)[0]  # consistent: a study's sets are FE sets
    if solver.method == "steady":
        from contact.characteristic import characteristic
        from contact.steady.engine import steady_state

        acc = solver.accuracy  # the CLI's default level, exact, unless the study says fast
        uf, rest = solver.ultrasonic_friction, solver.rest
        res = steady_state(params, drive.voltage_V, drive.preload_N,
                           frequency_Hz=drive.frequency_Hz, coupling=coupling, accuracy=acc,
                           ultrasonic_friction=uf, rest=rest)
        curve = characteristic(params, drive.voltage_V, drive.preload_N, None,
                               frequency_Hz=drive.frequency_Hz, coupling=coupling,
                               accuracy=acc, ultrasonic_friction=uf, rest=rest)
        # a load on the 21-load curve (0 N always is) has its velocity there: the same
        # start from rest; only the others cost a second characteristic
        at = {float(f): float(v) for f, v in zip(curve.load_N, curve.velocity_m_s,
                                                  strict=True)}
        missing = [f for f in drive.loads_N if float(f) not in at]
        if missing:
            loaded = characteristic(params, drive.voltage_V, drive.preload_N, missing,
                                    frequency_Hz=drive.frequency_Hz, coupling=coupling,
                                    accuracy=acc, ultrasonic_friction=uf, rest=rest)
            at.update(zip(map(float, loaded.load_N), map(float, loaded.velocity_m_s),
                          strict=True))
        eff = np.asarray(curve.efficiency, dtype=float)
        motion = motion_class(res.from_rest, res.velocity_m_s)
        return {"no_load_velocity": float(res.velocity_m_s),
                "stall_force": float(curve.stall_force_N),
                "peak_efficiency": float(np.nanmax(eff)) if np.isfinite(eff).any() else math.nan,
                "motion_class": motion,
                "velocity": np.array([at[float(f)] for f in drive.loads_N], dtype=float)}
    from contact.simulate import simulate

    # lusm simulate's step: the study's dt, else the period-dividing default
    r = simulate(params, drive.voltage_V, drive.preload_N, drive.frequency_Hz,
                 method=solver.method, duration_s=solver.duration_s,
                 dt_s=solver.step_s(drive.frequency_Hz), max_trace_points=2000,
                 coupling=coupling, ultrasonic_friction=solver.ultrasonic_friction)
    v0 = float(r.steady.velocity_m_s)
    velocity = np.array([v0 if load == 0.0 else math.nan for load in drive.loads_N])
    return {"no_load_velocity": v0, "stall_force": math.nan, "peak_efficiency": math.nan,
            "motion_class": r.steady.motion, "velocity": velocity,
            "settled": bool(r.steady.settled)}


def compute_geometry(study: Study, index: int) -> dict[str, np.ndarray]:
    """Everything the study wants of geometry ``index``: one FE solve, all drive points.

    A pure function of its arguments (BLAS held to one thread), so the same on any worker.
    A geometry whose FE solve or reduction fails gets NaN and its message in ``status``;
    a drive point whose run fails gets NaN and the motion class ``"failed"``.
    """
    import warnings

    from threadpoolctl import threadpool_limits

    t0 = time.perf_counter()
    _thread_lock_for_bars()
    # the filters stay the worker's own ("always" recorded ResourceWarnings too, whose
    # sources a record keeps alive: a semaphore then leaked at the interrupted shutdown)
    with threadpool_limits(limits=1), warnings.catch_warnings(record=True) as caught:
        out = _compute(study, index)
    out["task_time_s"] = np.array(time.perf_counter() - t0)
    out["warnings"] = np.array(sorted({" ".join(str(w.message).split()) for w in caught}),
                               dtype=str)
    out["lusm_version"] = np.array(_version())  # the client compares it with its own
    return out


def _thread_lock_for_bars() -> None:
    """Give tqdm a thread lock in this process before any bar is made.

    tqdm makes a multiprocessing RLock, a named POSIX semaphore registered with the
    client's resource_tracker, with the first bar, even a disabled one (those of
    :func:`contact.characteristic.characteristic`). A worker process that does not exit
    by itself never unlinks it: the nanny terminates a worker busy in a task when a Ctrl-C
    or SIGTERM closes the cluster, and a crashed worker is gone. The tracker then printed
    "resource_tracker: There appear to be N leaked semaphore objects" on the client's
    stderr after the run, even after one that ended with exit 0. A worker's bars are never
    shown and its tasks run one at a time in one thread, so a thread lock is enough.
    """
    import threading

    from tqdm import tqdm

    if "_lock" not in vars(tqdm):  # not made yet: tqdm.get_lock would make the semaphore
        tqdm.set_lock(threading.RLock())


def plate_of(study: Study, g: dict[str, Any]):
    """The stator and material of one geometry's axis values ``g`` (:func:`geometry_of`): the
    paper's plain plate, or the study's stator file with its plate's dimensions replaced
    (tip, chamfers, holes, electrodes and points kept, as ``lusm sweep --geometry``)."""
    from fem.geometry import PlateStator

    dims = {"length_m": g["length"], "width_m": g["width"], "thickness_m": g["thickness"],
            "electrode_gap_m": g["gap"]}
    dims.update({f: g[a] for a, f in FEATURE_FIELDS.items() if a in g})
    if study.stator is None:
        return PlateStator(**dims), g["material"]
    # the file's own plate where the axes keep it (and its own mesh: no gap, NaN)
    return plate_with(study.stator.stator, dims), study.stator.material


def _compute(study: Study, index: int) -> dict[str, np.ndarray]:
    from fem.modes import plate_modes
    from rom.from_fem import fem_params, fem_params_from_design

    g = geometry_of(study, index)
    s = study.solver
    out = _empty_outputs(study)
    stage = "FE"  # what failed, for the status: the plate's FE solve or its parameter set
    try:
        stator, material = plate_of(study, g)
        modes = plate_modes(stator, material, s.fe_order, s.fe_refine)
        for m in ("L1", "B2"):
            mode = getattr(modes, m)
            out[f"f_{m}_short"] = np.array(mode.f_short_Hz)
            out[f"f_{m}_open"] = np.array(mode.f_open_Hz)
            out[f"k_eff_{m}"] = np.array(mode.k_eff)
        out["split"] = np.array(modes.B2.f_short_Hz - modes.L1.f_short_Hz)
        if not study.needs_motor:
            return out
        # the modal reduction, the file's damping fit and motor tables, the auto frequency
        # (a fit to Table 2's amplitudes that a varied plate cannot match was an "FE:" failure)
        stage = "parameter set"
        if study.stator is None:
            params = fem_params(stator, material, order=s.fe_order, refine=s.fe_refine)
        else:  # the file's damping and motor tables too, as the single-point commands
            params = fem_params_from_design(study.stator, stator, order=s.fe_order,
                                            refine=s.fe_refine)
        if study.auto_frequency:
            from contact.drive import auto_frequency

            stage = "drive frequency"
            out["f_drive"] = np.array(auto_frequency(params))
    except (ValueError, RuntimeError, ArithmeticError) as exc:  # failure of this plate
        from lusm.errors import short_reason  # a list of 32 frequencies: its range

        out["status"] = np.array(short_reason(f"{stage}: {type(exc).__name__}: {exc}")[:300])
        if study.needs_motor:  # every drive point of the plate failed with it (it read '')
            out["motion_class"][...] = "failed"
        return out
    freqs = [float(out["f_drive"])] if study.auto_frequency else study.axes["frequency"]
    failures, unsettled = [], []
    # what the single-point commands refuse before they run, said in the study's keys
    # (it was the library's 'duration_s ... 9.999999999999999e-06', once per point)
    reasons = [_drive_problem(study, params, f) for f in freqs]
    # the work of the plate's runs, known only now: refused before any of them
    work = _plate_work_problem(study, params, [f for f, r in zip(freqs, reasons, strict=True)
                                               if r is None])
    for k, f in enumerate(freqs):
        reason = reasons[k] or work
        for i, v in enumerate(study.axes["voltage"]):
            for j, p in enumerate(study.axes["preload"]):
                at = (i, j) if study.auto_frequency else (k, i, j)
                if reason is not None:
                    out["motion_class"][at] = "failed"
                    failures.append(reason)
                    continue
                try:
                    ans = motor_answers(params, Drive(v, p, f, study.axes["load"]), s)
                except (ValueError, RuntimeError) as exc:  # chattering, too large a step
                    out["motion_class"][at] = "failed"
                    failures.append(f"{v:g} V, {p:g} N, {f:.6g} Hz: {exc}".splitlines()[0])
                    continue
                for name in MOTOR_ARRAYS:
                    out[name][at] = ans[name]
                out["velocity"][at] = ans["velocity"]
                if not ans.get("settled", True):
                    unsettled.append(f"{v:g} V, {p:g} N, {f:.6g} Hz")
    if failures:
        # one reason for all (the plate's: _drive_problem, _plate_work_problem), whole: the
        # work reason with its remedies is some 280 characters
        same = len(set(failures)) == 1
        out["status"] = np.array(f"{len(failures)} drive point(s) failed"
                                 f"{': ' if same else '; first: '}{failures[0]}"[:400])
    elif unsettled:  # a transient's velocity where it stopped, not the steady one
        out["status"] = np.array(
            f"{len(unsettled)} drive point(s) not settled within solver.duration "
            f"{s.duration_s:g} s (their velocity is where the run stopped; a longer duration "
            f"or method = \"steady\"); first: {unsettled[0]}"[:300])
    return out


def _drive_problem(study: Study, params, frequency_Hz: float) -> str | None:
    """Why no drive point of this plate can run at ``frequency_Hz`` (Hz), in the study's keys
    and units, or None: a transient's step and length (:func:`studies.study.
    transient_problem`, as ``lusm simulate`` checks them), or a frequency too far below the
    plate's fastest mode for the steady engine (as ``lusm characteristic`` checks it; that
    mode is the FE set's, so it is known only here)."""
    from studies.study import transient_problem

    at = _frequency_named(study, frequency_Hz) + (" of this plate" if study.auto_frequency
                                                 else "")
    if study.solver.method != "steady":
        return transient_problem(study.solver, frequency_Hz, at)
    from contact.model import default_coupling
    from contact.steady.slow import MAX_STEPS_PER_PERIOD, lowest_frequency_Hz, steps_per_period

    coupling = default_coupling(params)[0]
    n = steps_per_period(params, frequency_Hz, coupling)
    if n > MAX_STEPS_PER_PERIOD:
        # the bound in Hz, as lusm characteristic / map / simulate --steady say it
        lowest = lowest_frequency_Hz(params, coupling)
        return (f"{at} is too far below this plate's fastest mode for the "
                f"steady engine (solver.method = \"steady\"), which takes {lowest:g} Hz and "
                f"up on it ({n} steps per drive period, above {MAX_STEPS_PER_PERIOD}); give a "
                "higher axes.frequency or a transient solver.method")
    return None


def _frequency_named(study: Study, frequency_Hz: float) -> str:
    """A drive frequency (Hz) in the study's terms: its axis value, or the auto rule's."""
    from studies.study import show

    shown = show(frequency_Hz, "frequency")
    return (f"the auto drive frequency {shown}" if study.auto_frequency
            else f"axes.frequency {shown}")


def _plate_work_problem(study: Study, params, freqs: list[float]) -> str | None:
    """Why this plate's drive points at ``freqs`` (Hz) are more contact work than the study
    may have, or None: the study's bound (:func:`studies.study.contact_work_problem`) with
    every geometry taken as costly as this one. What the study's reading could not know: the
    steady engine's steps per drive period on this plate's FE set
    (:func:`contact.steady.slow.steps_per_period`, 25 at 40 kHz, 416 at 1 kHz on a 28 x 7.5 mm
    plate at fe_refine 1), and a transient's default step at an auto frequency."""
    from studies.study import contact_work_problem, steady_solves

    if not freqs:
        return None
    s = study.solver
    per_f = len(study.axes["voltage"]) * len(study.axes["preload"])  # runs per frequency
    if s.method == "steady":
        from contact.model import default_coupling
        from contact.steady.slow import steps_per_period

        coupling = default_coupling(params)[0]
        n = [steps_per_period(params, f, coupling) for f in freqs]
        k = steady_solves(study)
        at = _frequency_named(study, freqs[int(np.argmax(n))])
        detail = (f"{per_f * len(freqs)} drive points x {k} steady solves x "
                  + (f"{n[0]} steps per drive period (this plate's, at {at})" if len(n) == 1
                     else f"{sum(n) / len(n):.4g} steps per drive period (this plate's mean; "
                     f"{max(n)} at {at})"))
        return contact_work_problem(study, per_f * k * sum(n), detail)
    steps = [s.duration_s / s.step_s(f) for f in freqs]
    detail = (f"{per_f * len(freqs)} drive points x {sum(steps) / len(steps):.3g} steps each "
              "(this plate's)")
    return contact_work_problem(study, per_f * sum(steps), detail)


def _empty_outputs(study: Study) -> dict[str, np.ndarray]:
    """A geometry's outputs before it is computed: NaN, ``""`` and status ``"ok"``, in the
    shapes a part must have."""
    mshape = _motor_shape(study)
    n_load = len(study.axes["load"])
    out: dict[str, np.ndarray] = {k: np.array(math.nan) for k in FE_SCALARS}
    for k in MOTOR_ARRAYS[:-1]:
        out[k] = np.full(mshape, math.nan)
    out["motion_class"] = np.full(mshape, "", dtype="<U32")
    out["velocity"] = np.full((*mshape, n_load), math.nan)
    out["status"] = np.array("ok")
    return out


# --- parts: one file per finished geometry ---------------------------------------------------

def parts_folder(out: Path) -> Path:
    """The folder of per-geometry files of an output ``out``."""
    return out.with_name(out.name + PARTS_SUFFIX)


TASK_EXTRAS = ("task_time_s", "lusm_version", "warnings")
"""What a task returns beside the geometry's outputs (not written into its part)."""


def _part_path(folder: Path, index: int) -> Path:
    return folder / f"g{index:07d}.npz"


def _write_part(folder: Path, index: int, data: dict[str, np.ndarray]) -> None:
    final = _part_path(folder, index)
    tmp = folder / f".{final.name}-{uuid.uuid4().hex[:8]}"
    with open(tmp, "wb") as fh:
        np.savez(fh, **{k: v for k, v in data.items() if k not in TASK_EXTRAS})
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, final)  # a part is there complete or not at all


def _read_part(folder: Path, index: int,
               template: dict[str, np.ndarray] | None = None) -> dict[str, np.ndarray] | None:
    """A part as written, or None (computed again) when it is missing, torn, or its arrays
    are not those of ``template`` (:func:`_empty_outputs`: the same names, shapes and
    kinds; a part without ``velocity`` ended a finished study with an internal error)."""
    try:
        with np.load(_part_path(folder, index), allow_pickle=False) as z:
            part = {k: z[k] for k in z.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile):  # missing or torn: computed
        return None  # again (a truncated part was an internal error of --resume)
    if template is not None and (
            set(part) != set(template)
            or any(part[k].shape != v.shape or part[k].dtype.kind != v.dtype.kind
                   for k, v in template.items())):
        return None
    return part


def _open_parts(study: Study, out: Path, resume: bool):
    """The parts folder of ``out`` (made, or checked as this study's), its finished parts by
    geometry, whether this call made it, and the run's lock on it (:func:`_lock_parts`),
    taken before any part is read."""
    folder = parts_folder(out)
    template = _empty_outputs(study)
    if not folder.exists():
        stamp = {"fingerprint": study.fingerprint, "study": json.loads(study.text),
                 "lusm_version": _version()}
        try:
            folder.mkdir(parents=True)
            (folder / STUDY_FILE).write_text(json.dumps(stamp, indent=1))
        except OSError as exc:  # /sys/x.nc: named by its option, not only by its path
            raise ValueError(f"--out {out}: cannot write its parts folder {folder} "
                             f"({exc.strerror or exc})") from None
        return folder, {}, True, _lock_parts(folder, out)
    if not (folder / STUDY_FILE).is_file():  # not ours: nothing is written into it
        option = "--resume" if resume else f"--out {out}"
        raise ValueError(f"{option}: {folder} has no {STUDY_FILE}, so it is not the parts "
                         "folder of a lusm explore run (a finished run leaves only files "
                         "that are not its own there); move it away or choose another --out")
    lock = _lock_parts(folder, out)  # a live run's folder is refused before anything is said
    old = _stamp_of(folder)
    why = _not_this_runs(study, folder, old, "--resume" if resume else f"--out {out}")
    if why is None and not resume:
        why = _not_resumed(study, out, folder, template)
    if why is not None:
        lock.release()
        raise ValueError(why)
    return folder, _finished_parts(study, folder, template), False, lock


def _stamp_of(folder: Path) -> dict:
    """The ``study.json`` of a parts folder ({} when unreadable)."""
    try:
        old = json.loads((folder / STUDY_FILE).read_text())
    except (OSError, ValueError):
        return {}
    return old if isinstance(old, dict) else {}


def _finished_parts(study: Study, folder: Path, template) -> dict[int, dict]:
    """The readable, well-formed parts in ``folder`` by geometry."""
    done = {}
    for i in range(study.n_geometries):
        if _part_path(folder, i).exists():
            part = _read_part(folder, i, template)
            if part is not None:
                done[i] = part
    return done


def _not_this_runs(study: Study, folder: Path, old: dict, option: str) -> str | None:
    """Why the parts in ``folder`` (whose ``study.json`` is ``old``) cannot go into this run's
    dataset, naming ``option``: another lusm version's (said first: it may read the same file
    as another study) or another study's; None when they can."""
    if old.get("lusm_version") != _version():
        return (f"{option}: {folder} was computed by lusm {old.get('lusm_version', 'unknown')} "
                f"(this is lusm {_version()}); resuming would mix both in one dataset; remove "
                "that folder to start over")
    if old.get("fingerprint") != study.fingerprint:
        return (f"{option}: {folder} holds the parts of another study (the study file or its "
                "study.stator file changed); remove that folder, or restore the study")
    return None


def _not_resumed(study: Study, out: Path, folder: Path, template) -> str:
    """Why a run without ``--resume`` does not start over this study's parts folder, and what
    to do: every geometry computed (the dataset not written: an interrupt or a failed write
    at the end), a finished run in which none computed fully, or an unfinished run."""
    if not all(_part_path(folder, i).exists() for i in range(study.n_geometries)):
        return (f"--out {out}: {folder} holds an unfinished run; pass --resume to continue "
                "it, or remove that folder to start over")
    parts = _finished_parts(study, folder, template)
    if len(parts) == study.n_geometries and not any(
            computed_fully(str(p["status"])) for p in parts.values()):
        return (f"--out {out}: {folder} holds a finished run in which no geometry computed "
                "fully (each part's reason in its 'status'; --resume says the first again); "
                "remove that folder to run a corrected study")
    return (f"--out {out}: {folder} holds every geometry of this study, computed (the dataset "
            "was not written); pass --resume to write it, or remove that folder to start over")


LOCK_FILE = ".lock"
"""The file of a parts folder a running ``explore`` holds locked (:mod:`filelock`)."""


class PartsBusyError(ValueError):
    """Another ``explore`` holds the lock of the parts folder: this run is refused before any
    work, and the parts there are that run's, not this one's."""


def _lock_parts(folder: Path, out: Path):
    """Hold ``folder``'s lock for this run (a :class:`filelock.FileLock`, released by the
    caller; the system releases it when the process ends, however it ends), or refuse: two
    runs on one parts folder would both compute every geometry left."""
    from filelock import FileLock, Timeout

    lock = FileLock(folder / LOCK_FILE)
    try:
        lock.acquire(timeout=0)
    except Timeout:
        raise PartsBusyError(f"--out {out}: another lusm explore is running on {folder}; "
                             "wait for it to finish, or choose another --out") from None
    except OSError as exc:  # a read-only folder, or one a finishing run just removed
        raise ValueError(f"--out {out}: cannot lock its parts folder {folder} "
                         f"({exc.strerror or exc})") from None
    return lock


def _remove_parts(folder: Path, n: int, made: list[Path] = ()) -> None:
    """Remove the files this module wrote, then the folder if nothing else is in it, then
    the folders ``made`` above it (deepest first) that are still empty."""
    for i in range(n):
        _part_path(folder, i).unlink(missing_ok=True)
    (folder / STUDY_FILE).unlink(missing_ok=True)
    (folder / LOCK_FILE).unlink(missing_ok=True)
    for stray in folder.glob(".g*.npz-*"):  # torn temporaries of ours
        stray.unlink(missing_ok=True)
    for f in (folder, *made):
        try:
            f.rmdir()
        except OSError:
            break  # something of the user's is in it (or it is gone): left alone


# --- the dataset ------------------------------------------------------------------------------

def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("lusm")
    except PackageNotFoundError:  # pragma: no cover - running from a bare checkout
        return "unknown"


def assemble(study: Study, parts: dict[int, dict[str, np.ndarray]]):
    """The labelled :class:`xarray.Dataset` of a study from its per-geometry parts.

    Dimensions: the geometry axes, then the drive axes (``frequency`` only when fixed);
    coordinates in SI units (``units`` attrs); variables as asked by ``study.outputs``.
    """
    import xarray as xr

    gdims = list(study.geometry_axes)
    mdims = [a for a in study.drive_dims if a != "load"]
    gshape = study.geometry_shape
    n = study.n_geometries
    missing = [i for i in range(n) if i not in parts]
    if missing:
        raise ValueError(f"{len(missing)} geometries are missing (first: {missing[0]})")

    def stack(name: str) -> np.ndarray:
        arrs = [parts[i][name] for i in range(n)]
        return np.stack(arrs).reshape(gshape + arrs[0].shape)

    coords = {}
    for a in study.geometry_axes + DRIVE_AXES:
        if a not in gdims + list(study.drive_dims) and a != "frequency":
            continue
        if a in DRIVE_AXES and not study.needs_motor:  # an FE-only study drives nothing
            continue
        if a == "frequency" and study.auto_frequency:
            continue
        if a == "material":
            coords[a] = (a, np.array(study.axes[a], dtype=object),
                         {"long_name": "stator material"})
        else:
            coords[a] = (a, np.array(study.axes[a], dtype=float),
                         {"units": SI_UNIT[AXIS_KIND[a]], "long_name": _AXIS_NAMES[a]})
    data_vars = {}

    def add(name: str, dims: list[str], values: np.ndarray, units: str, long_name: str):
        attrs = {"long_name": long_name}
        if units:
            attrs["units"] = units
        data_vars[name] = (dims, values, attrs)

    for o in study.outputs:
        unit, meaning = OUTPUTS[o]
        if o == "k_eff":
            for m in ("L1", "B2"):
                # one mode each (it read "L1 effective ... coupling factor of L1 and B2")
                add(f"k_eff_{m}", gdims, stack(f"k_eff_{m}"), unit,
                    f"effective electromechanical coupling factor of {m}")
        elif o in ("f_L1_short", "f_L1_open", "f_B2_short", "f_B2_open", "split"):
            add(o, gdims, stack(o), unit, meaning)
        elif o == "velocity":
            add(o, gdims + mdims + ["load"], stack(o), unit, meaning)
        elif o == "motion_class":
            add(o, gdims + mdims, stack(o).astype(object), unit, meaning)
        else:
            add(o, gdims + mdims, stack(o), unit, meaning)
    if study.needs_motor and study.auto_frequency:
        add("f_drive", gdims, stack("f_drive"), "Hz",
            "drive frequency (auto: largest product of the free tip amplitudes, "
            "contact.drive.auto_frequency)")
    add("status", gdims, stack("status").astype(object), "",
        "'ok', or why the geometry or some of its drive points failed")
    s = study.solver
    attrs = {
        "title": f"lusm explore: {study.name}",
        "lusm_version": _version(),
        "study_source": study.source,
        "study": study.text,
        "study_fingerprint": study.fingerprint,
        "parameter_set_source": _parameter_set_source(study),
        "fe_solver": f"fem.modes.plate_modes, order {s.fe_order}, {_mesh_text(study)}, "
                     "shift-invert eigsh with a fixed start vector",
        "motor_solver": (
            f"contact.steady.steady_state and contact.characteristic.characteristic, "
            f"accuracy={s.accuracy}" + (f", rest={s.rest}" if s.accuracy == "exact" else "")
            + " (solver.duration and solver.dt unused)"
            if s.method == "steady" else
            f"contact.simulate.simulate method={s.method}, duration_s={s.duration_s:g}, "
            + (f"dt_s={s.dt_s:g}" if s.dt_s is not None else
               "dt_s=the largest step up to 1e-07 s dividing the drive period "
               "(lusm.options.time_step_s, as lusm simulate)")
            + ", from rest (a point that did not settle is named in status); "
            "stall_force, peak_efficiency and loaded velocity need method = \"steady\" (NaN)"),
        "frequency_rule": "auto" if study.auto_frequency else "fixed (coordinate frequency)",
        "coupling": "consistent (auto: the work-consistent tangential coupling of every set "
                    "that is not Table 2's, contact.model.default_coupling; docs/contact.md "
                    "2.3.1)",
        "friction": ("Eq. 11 ultrasonic friction reduction (mu_d,eff)"
                     if s.ultrasonic_friction else "constant mu_d (solver.ultrasonic_friction "
                     "= false)"),
    }
    if study.needs_motor:
        attrs["damping"] = damping_text(study)
    if study.stator is not None:
        d = study.stator
        stamp = json.loads(study.text)["stator"]
        attrs["stator_file"] = stamp["file"]
        attrs["stator_name"] = d.name
        attrs["stator_sha256"] = stamp["sha256"]
        if d.mesh_path is not None:
            attrs["stator_mesh_file"] = os.path.abspath(d.mesh_path)
    if not study.needs_motor:  # FE outputs only: no contact model ran
        for k in ("motor_solver", "frequency_rule", "coupling", "friction"):
            del attrs[k]
        attrs["parameter_set_source"] = "none: FE outputs only"
    # the study's path (and the name it gives by default) may hold bytes that are not UTF-8
    attrs = {k: storable_text(v) for k, v in attrs.items()}
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _mesh_text(study: Study) -> str:
    """The FE mesh of the study's plates, in words: ``refine N``, or a stator file's own."""
    d = study.stator
    if d is not None and d.mesh_path is not None:
        return f"the stator file's mesh {d.mesh_path}"
    from fem.meshing.meshed_stator import has_planform

    if d is not None and has_planform(d.stator):
        return "gmsh at the stator file's [mesh] size_mm (solver.fe_refine unused)"
    return f"refine {study.solver.fe_refine}"


def damping_text(study: Study) -> str:
    """The modal damping of the study's parameter sets, in words (every answer with a
    velocity depends on it): Table 2's ratios, borrowed by the FE reduction, or the stator
    file's ``[damping]``."""
    from rom import table2

    t2 = table2()
    borrowed = (f"Table 2's ratios zeta_L1 = {t2.zeta_L1:.4g}, zeta_B2 = {t2.zeta_B2:.4g} "
                "(borrowed: the FE reduction has no damping of its own)")
    d = study.stator
    if d is None:
        return borrowed
    # the values first: a figure's title shortens the end, where the path is
    from rom.from_fem import design_damping

    ratios = design_damping(d)  # the file's ratios, Q_m's, or Table 2's by name
    if ratios is not None:
        z1, z2 = ratios
        return (f"zeta_L1 = {z1:.4g}, zeta_B2 = {z2:.4g} ({d.damping_origin}), from stator "
                f"file {d.path}")
    if d.damping_origin:  # fitted per plate, or Table 2's by name
        return f"{d.damping_origin}, from stator file {d.path}"
    return f"{borrowed}; stator file {d.path} has no [damping]"


def _parameter_set_source(study: Study) -> str:
    """How each geometry's parameter set is built, for the dataset's attributes."""
    s = study.solver
    fe = (f"FE modal reduction per geometry (rom.from_fem.fem_params: scikit-fem plane stress, "
          f"order {s.fe_order}, {_mesh_text(study)}")
    d = study.stator
    if d is None:
        return (f"{fe}); contact, slider, friction and damping constants from rom.table2 "
                "(Li, Yao & Wu 2016, Table 2)")
    motor = ("; " + ", ".join(f"{where} from the file" for where in d.motor_keys().values())
             if d.motor else "")
    return (f"{fe}) of stator file {d.path} ({d.name}), its plate dimensions from the "
            f"geometry axes; damping {damping_text(study)}{motor}; the other contact, slider "
            "and friction constants from rom.table2 (Li, Yao & Wu 2016, Table 2)")


def storable_text(text: str) -> str:
    """``text`` as a netCDF attribute can hold it (UTF-8): a file name's bytes that are not
    UTF-8, which Python keeps as lone surrogates (``'st\\udcfe.toml'``), written as
    ``\\xNN`` (``'st\\xfe.toml'``), so the path stays readable and exact. The write failed
    on them with "'utf-8' codec can't encode character '\\udcfe'" after every geometry of the
    study had been computed (and again under --resume)."""
    try:
        raw = os.fsencode(text)  # a path's undecodable bytes back as they were
    except UnicodeEncodeError:  # a lone surrogate no file name decodes to
        raw = text.encode("utf-8", "backslashreplace")
    return raw.decode("utf-8", "backslashreplace")


_AXIS_NAMES = {"length": "plate length", "width": "plate width",
               "thickness": "plate thickness", "gap": "electrode gap",
               "tip_length": "contact tip length", "tip_width": "contact tip width",
               "chamfer": "corner chamfer leg",
               "frequency": "drive frequency", "voltage": "drive amplitude V0",
               "preload": "preload F_P", "load": "load (braking force) on the slider"}


def write_dataset(ds, out: Path, force: bool = False) -> None:
    """Write ``ds`` to netCDF aside and rename it onto ``out``.

    A file already at ``out`` is refused unless ``force``; with ``force`` it is kept as
    ``out.bak-N``, never deleted. HDF5 builds the file in memory and this process writes its
    bytes (as many as the file has), so a disk that refuses them (full, or a file size limit)
    is an ``OSError`` of an ordinary write, not a failure inside h5py's close (which crashes
    the process at exit).

    Raises
    ------
    ValueError
        If ``out`` is refused (:func:`check_out`) or the dataset cannot be written there:
        one line naming ``--out`` and the system's reason; no staging file is left.
    """
    import dask

    out = Path(out)
    check_out(out, force)
    # memory only: nothing of HDF5 touches the disk. xarray locks the target on the active
    # dask scheduler; with a distributed Client alive in this process that is a
    # distributed.Lock named by the in-memory buffer, which the scheduler refused ("Semaphore
    # or Lock <_io.BytesIO ...> not known"). The dataset is NumPy, not dask: no scheduler runs
    with dask.config.set(scheduler="synchronous"):
        data = ds.to_netcdf(engine="h5netcdf")
    out.parent.mkdir(parents=True, exist_ok=True)
    with staging(out.parent, out.name, "--out", out) as stage:
        tmp = stage / out.name
        try:
            with open(tmp, "xb") as fh:  # closed (and its error raised) before the removal
                fh.write(data)
                fh.flush()
                os.fsync(fh.fileno())
        except OSError as exc:
            raise ValueError(f"--out {out}: cannot write the dataset "
                             f"({exc.strerror or exc}; {len(data)} bytes)") from None
        checkpoint()  # a Ctrl-C / SIGTERM that Python swallowed: nothing is moved in
        if os.path.lexists(out):  # a link (dangling or not) itself, not its file
            os.replace(out, backup_name(out))
        os.replace(tmp, out)


def is_complete(study: Study, out: str | Path) -> bool:
    """Whether ``out`` holds the finished dataset of ``study``: a dataset carrying its
    fingerprint and no parts folder beside it (what a run that finished leaves)."""
    out = Path(out)
    if not out.is_file() or parts_folder(out).exists():
        return False
    try:
        ds = open_result(out)
    except (OSError, ValueError):  # not a dataset: check_out refuses it as the user's file
        return False
    return ds.attrs.get("study_fingerprint") == study.fingerprint


def check_out(out: Path, force: bool) -> None:
    """Refuse, before any work, an output the dataset could not be written to."""
    if not str(out).strip():
        raise ValueError(f"--out must name a netCDF file (.nc, .nc4 or .h5), got {str(out)!r}")
    out = Path(out)
    if out.suffix.lower() not in (".nc", ".nc4", ".h5"):
        zarr = "; zarr stores are not supported yet" if out.suffix.lower() == ".zarr" else ""
        raise ValueError(f"--out {out}: name a netCDF file (.nc, .nc4 or .h5){zarr}")
    if out.is_dir():
        raise ValueError(f"--out {out} is a folder; name a .nc file")
    if out.exists() and not force:
        raise ValueError(f"--out {out} exists; choose a new name or pass --force (the old "
                         "file is kept as a .bak file)")
    if out.is_symlink() and not out.exists() and not force:
        # a link to nowhere is the user's too: the dataset was renamed over it, silently
        raise ValueError(f"--out {out} exists, a symbolic link to {os.readlink(out)}, which "
                         "does not exist; choose a new name or pass --force (the link is kept "
                         "as a .bak file)")
    existing = next((p for p in [out.parent, *out.parent.parents] if p.exists()), Path.cwd())
    if not existing.is_dir() or not os.access(existing, os.W_OK | os.X_OK):
        raise ValueError(f"--out {out}: {existing} is not a writable folder")


# --- the cluster -------------------------------------------------------------------------------

def worker_env() -> dict[str, str]:
    """Environment of LocalCluster workers: one BLAS thread, the client's numba cache."""
    env = {k: "1" for k in BLAS_ENV}
    for k in ("NUMBA_CACHE_DIR", "PYTHONPATH", "LUSM_MAX_WORK"):
        if os.environ.get(k):
            env[k] = os.environ[k]
    return env


def local_cluster(n_workers: int = DEFAULT_WORKERS):
    """A LocalCluster of ``n_workers`` processes with one thread each and no dashboard.

    The worker processes ignore SIGINT: a terminal's Ctrl-C goes to the whole process group,
    and each worker would print its own KeyboardInterrupt traceback while the client is
    already stopping them. They are spawned through a wrapper that ignores SIGINT before it
    executes Python (:func:`_workers_ignoring_sigint`). A Ctrl-C while the cluster starts is
    held, and raised once the start returns and the new cluster is closed.
    """
    from distributed import LocalCluster

    from contact.deferred_signals import deferred_signals

    def start():
        # the workers' own logs stay quiet: a task's failure comes back to the client as its
        # exception, and a heartbeat to the closed scheduler at shutdown is not news. No
        # dashboard; the scheduler's HTTP routes on a free local port, not the shared 8787
        return LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                            dashboard_address=None, silence_logs=logging.CRITICAL,
                            env=worker_env(),
                            scheduler_kwargs={"dashboard": False,
                                              "dashboard_address": "127.0.0.1:0"})

    cluster = None
    try:
        with _workers_ignoring_sigint(), deferred_signals():
            cluster = start()
    except BaseException:
        if cluster is not None:
            cluster.close()
        raise
    return cluster


_WRAPPER: list[str] = []
"""The spawn wrapper of :func:`_workers_ignoring_sigint`, once written (this process)."""


@contextmanager
def _workers_ignoring_sigint():
    """Meanwhile, multiprocessing spawns its children through a shell wrapper that ignores
    SIGINT and then executes this Python (``multiprocessing.set_executable``; the previous
    executable is restored after). The wrapper lives in a private temporary folder, removed
    at exit. POSIX only; elsewhere nothing changes."""
    import atexit
    import multiprocessing
    import multiprocessing.spawn
    import shlex
    import shutil
    import stat
    import tempfile

    if os.name != "posix" or not Path("/bin/sh").exists():
        yield
        return
    if not _WRAPPER:
        folder = tempfile.mkdtemp(prefix="lusm-spawn-")
        atexit.register(shutil.rmtree, folder, True)
        path = Path(folder) / "python-ignoring-sigint"
        path.write_text(f"#!/bin/sh\ntrap '' INT\nexec {shlex.quote(sys.executable)} \"$@\"\n")
        path.chmod(stat.S_IRWXU)
        _WRAPPER.append(str(path))
    before = multiprocessing.spawn.get_executable()
    multiprocessing.set_executable(_WRAPPER[0])
    try:
        yield
    finally:
        multiprocessing.set_executable(before)


IN_FLIGHT_PER_WORKER = 4
"""Geometry tasks kept submitted per worker (at least :data:`MIN_IN_FLIGHT`): enough to keep
each worker busy while the client writes parts, few enough that the client's memory does not
grow with the study."""
MIN_IN_FLIGHT = 16
WINDOW_RECHECK = 8
"""Completed tasks between two counts of the cluster's workers (a scheduler round trip)."""


def in_flight(workers: int, tasks: int) -> int:
    """Tasks to keep submitted on ``workers`` workers out of ``tasks`` left."""
    return min(tasks, max(MIN_IN_FLIGHT, IN_FLIGHT_PER_WORKER * max(workers, 1)))


MAX_SCHEDULER_FILE_BYTES = 1_000_000
"""Largest ``--scheduler-file`` read (a dask scheduler file is a few hundred bytes)."""


def _check_scheduler_file(path: str) -> None:
    """Refuse a ``--scheduler-file`` that is not the JSON a dask scheduler writes (an object
    with its ``address``): a study file given there had said "cannot connect to the dask
    scheduler (AssertionError)"."""
    what = (f"--scheduler-file {path} is not a dask scheduler file (the JSON object with an "
            "'address' that `dask scheduler --scheduler-file` writes)")
    try:
        if Path(path).stat().st_size > MAX_SCHEDULER_FILE_BYTES:
            raise ValueError(f"{what}: it is above {MAX_SCHEDULER_FILE_BYTES} bytes")
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else "not JSON"
        raise ValueError(f"{what}: {reason}") from None
    if not (isinstance(doc, dict) and isinstance(doc.get("address"), str) and doc["address"]):
        raise ValueError(f"{what}: it has no 'address'")


def connect(scheduler: str | None = None, scheduler_file: str | None = None,
            workers: int = DEFAULT_WORKERS):
    """A client to ``scheduler`` / ``scheduler_file``, or to a new LocalCluster.

    Returns ``(client, cluster)``; ``cluster`` is None for an existing scheduler.
    """
    from distributed import Client

    check_scheduler_names(scheduler, scheduler_file)
    if scheduler and scheduler_file:
        raise ValueError("--scheduler and --scheduler-file exclude each other; give one")
    if scheduler_file and not Path(scheduler_file).is_file():
        # a folder or a device had been told it "does not exist"
        kind = ("does not exist" if not Path(scheduler_file).exists() else
                "is a folder, not a dask scheduler file" if Path(scheduler_file).is_dir()
                else "is not a regular file, not a dask scheduler file")
        raise ValueError(f"--scheduler-file {scheduler_file} {kind}")
    if scheduler_file:
        _check_scheduler_file(scheduler_file)
    if scheduler or scheduler_file:
        option, where = ("--scheduler", scheduler) if scheduler else \
            ("--scheduler-file", scheduler_file)
        try:
            if scheduler:
                return _within(lambda: Client(scheduler, timeout=CONNECT_TIMEOUT),
                               CONNECT_DEADLINE_S), None
            return _within(lambda: Client(scheduler_file=scheduler_file,
                                          timeout=CONNECT_TIMEOUT), CONNECT_DEADLINE_S), None
        except Exception as exc:  # noqa: BLE001 - refused, timed out, bad address, or not
            # dask at all: an SSH banner read as a message length (MemoryError), a scheduler
            # file of '{}' (AssertionError); each is the address's fault, not lusm's
            text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise ValueError(f"{option} {where}: cannot connect to the dask scheduler "
                             f"({text[:200]})") from None
    cluster = local_cluster(workers)
    return Client(cluster), cluster


def package_version() -> str:
    """The lusm version of this process (run on the workers to compare with the client)."""
    return _version()


def check_scheduler_names(scheduler: str | None, scheduler_file: str | None) -> None:
    """Refuse an empty ``--scheduler`` or ``--scheduler-file``: ``''`` read as "no
    scheduler", and the study ran on a LocalCluster without a word (with ``--workers 1`` it
    also passed the check that forbids --workers with a scheduler).

    Raises
    ------
    ValueError
        Starting with the option's name.
    """
    for option, value, what in (("--scheduler", scheduler,
                                 "a dask scheduler address (tcp://HOST:8786)"),
                                ("--scheduler-file", scheduler_file, "a dask scheduler file")):
        if value is not None and not str(value).strip():
            raise ValueError(f"{option} must name {what}, got {value!r}")


def check_scheduler(client, option: str = "--scheduler") -> None:
    """Refuse a scheduler that cannot import lusm or runs another version than this client.

    The scheduler unpickles every task (its function is :func:`compute_geometry`, pickled
    by reference), so without lusm it failed the first submission with dask's "Error during
    deserialization of the task graph", an internal error here. Asked once before any task
    (``client.run_on_scheduler`` of the package version), it is one line naming ``option``.
    """
    try:
        version = client.run_on_scheduler(package_version)
    except Exception as exc:  # noqa: BLE001 - ModuleNotFoundError on the scheduler, travelling
        # back (or whatever else stops it from running lusm's function): its fault, not ours
        text = str(exc).splitlines()[0] if str(exc) else ""
        raise ValueError(f"{option}: the dask scheduler cannot run lusm ({type(exc).__name__}: "
                         f"{text[:200]}); install lusm on the scheduler too (it unpickles "
                         "every task), at this client's version") from None
    if version != _version():
        raise ValueError(f"{option}: the dask scheduler runs lusm {version}, this client "
                         f"{_version()}; install the same version everywhere")


def check_workers(client, option: str = "--scheduler", gmsh: bool = False) -> None:
    """Refuse workers that cannot import lusm or run another version than this client, and,
    with ``gmsh`` (a study of a parametric stator file), workers without gmsh (each task
    failed on its mesh after the study had started)."""
    try:
        versions = client.run(package_version)
    except Exception as exc:  # ModuleNotFoundError on the worker, travelling back
        raise ValueError(f"{option}: the workers cannot run lusm ({type(exc).__name__}: "
                         f"{str(exc).splitlines()[0] if str(exc) else ''}); install lusm "
                         "on every worker") from None
    mine = _version()
    other = {w: v for w, v in versions.items() if v != mine}
    if other:
        w, v = next(iter(other.items()))
        raise ValueError(f"{option}: worker {w} runs lusm {v}, this client {mine}; install "
                         "the same version everywhere")
    if gmsh:
        from fem.meshing.parametric import gmsh_problem

        problems = {w: p for w, p in client.run(gmsh_problem).items() if p}
        if problems:
            w, p = next(iter(problems.items()))
            raise ValueError(f"{option}: worker {w} cannot mesh the study.stator's features: "
                             f"{p} (on every worker)")


# --- the study --------------------------------------------------------------------------------

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
) -> ExploreResult:
    """Run a study on dask.distributed and write its dataset to ``out`` (netCDF).

    Parameters
    ----------
    study : Study
    out : path
        The ``.nc`` file to write; its parts go to ``<out>.parts/`` meanwhile.
    client : distributed.Client, optional
        Use this client (and its cluster); otherwise :func:`connect` with ``scheduler``,
        ``scheduler_file`` or a LocalCluster of ``workers`` processes, closed at the end.
    resume : bool
        Continue from the parts of an interrupted run of the same study; on a study whose
        dataset ``out`` is already complete, return at once and leave it as it is.
    force : bool
        Replace an existing ``out`` (kept as ``out.bak-N``).
    progress : bool
        Show a tqdm progress bar on stderr (geometries done).
    on_part : callable, optional
        Called with the geometry index after each part is written (tests interrupt here).

    Returns
    -------
    ExploreResult
    """
    import pickle

    from distributed import as_completed

    out = Path(out)
    if resume and is_complete(study, out):  # resuming a finished study changes nothing
        return ExploreResult(out, study.n_geometries,
                             study.n_drive_points if study.needs_motor else 0,
                             reused=study.n_geometries, already_complete=True)
    check_out(out, force)
    t0 = time.perf_counter()
    # folders above --out that this run makes: removed again, if still empty, when it stops
    # before computing anything (an interrupted `--out new/sub/x.nc` left new/sub/ behind)
    made = [p for p in Path(os.path.abspath(out)).parents if not p.exists()]
    folder, parts, created, lock = _open_parts(study, out, resume)
    try:
        # an FE-only study drives nothing (its --json said one drive point per geometry)
        result = ExploreResult(out, study.n_geometries,
                               study.n_drive_points if study.needs_motor else 0, reused=len(parts))
        todo = [i for i in range(study.n_geometries) if i not in parts]
        own = None  # the client (and cluster) made here, closed here
        if todo:
            if client is None:
                try:
                    # no more local processes than geometries to compute (8 workers for 2
                    # tasks had started 330 MB of idle processes)
                    client, cluster = connect(scheduler, scheduler_file,
                                              max(1, min(workers, len(todo))))
                    own = (client, cluster)
                    if cluster is None:  # someone else's cluster: same lusm as ours?
                        option = "--scheduler" if scheduler else "--scheduler-file"
                        check_scheduler(client, option)
                        check_workers(client, option, gmsh=study.meshed_by_gmsh)
                except BaseException:
                    if own is not None:
                        own[0].close()
                    if created:  # nothing was computed: leave no trace
                        _remove_parts(folder, study.n_geometries, made)
                    raise
            try:
                # nthreads() lists every worker (scheduler_info() gives at most 5 on
                # some dask releases: a window sized from it starved a large cluster)
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

                # a bounded window of tasks in flight, topped up as each finishes (dask's
                # as_completed(...).add pattern): a future per geometry up front had grown
                # the client by 55 MB/s towards 100 000 of them before any part was written
                window = [submit_next() for _ in range(in_flight(result.workers, len(todo)))]
                bar = _bar(len(todo) + len(parts), len(parts), progress)
                try:
                    completed = as_completed(window)
                    for n_done, fut in enumerate(completed, start=1):
                        # topped up to the window of the workers there are now: workers
                        # that join later (an adaptive cluster) widen it
                        workers = (len(client.nthreads()) if n_done % WINDOW_RECHECK == 0
                                   else result.workers)
                        result.workers = max(result.workers, workers)
                        want = in_flight(workers, len(todo))
                        while len(live) - 1 < want:
                            nxt = submit_next()
                            if nxt is None:
                                break
                            completed.add(nxt)
                        data = fut.result()
                        i = index.pop(fut.key)
                        if str(data.get("lusm_version")) != _version():
                            # a worker that joined after check_workers, with other lusm
                            where = ("--scheduler" if scheduler else "--scheduler-file"
                                     if scheduler_file else "the local cluster")
                            raise ValueError(
                                f"{where}: a worker computed geometry {i} with lusm "
                                f"{data.get('lusm_version')}, this client {_version()}; "
                                "install the same version everywhere")
                        result.task_times_s.append(float(data["task_time_s"]))
                        result.warnings += [w for w in map(str, data.get("warnings", ()))
                                            if w not in result.warnings]
                        result.result_bytes += len(pickle.dumps(data, protocol=5))
                        tw = time.perf_counter()
                        _write_part(folder, i, data)
                        result.part_write_time_s += time.perf_counter() - tw
                        parts[i] = {k: v for k, v in data.items() if k not in TASK_EXTRAS}
                        result.computed += 1
                        bar.update(1)
                        live.discard(fut)
                        fut.release()
                        checkpoint()  # a swallowed Ctrl-C / SIGTERM: stop at the next geometry
                        if on_part is not None:
                            on_part(i)
                finally:
                    bar.close()
                    for f in live:
                        f.cancel()
            except BaseException:
                if created and result.computed == 0:  # nothing was computed: leave no trace
                    _remove_parts(folder, study.n_geometries, made)
                raise
            finally:
                if own is not None:
                    own[0].close()
                    if own[1] is not None:
                        own[1].close()
        _refuse_if_nothing_computed(study, parts, folder)
        t1 = time.perf_counter()
        ds = assemble(study, parts)
        from contact.deferred_signals import deferred_signals

        # the dataset and the removal of the parts are one step: a Ctrl-C between them left a
        # complete dataset beside a half-removed parts folder, and --resume and --force each
        # sent the user to the other; a signal now lands after both
        with deferred_signals():
            write_dataset(ds, out, force)
            _remove_parts(folder, study.n_geometries)
        result.write_time_s = time.perf_counter() - t1
        result.wall_time_s = time.perf_counter() - t0
        return result
    finally:
        lock.release()  # its file went with the folder once the dataset is in


def computed_fully(status: str) -> bool:
    """Whether a geometry's ``status`` says it computed fully: ``"ok"``, or drive points a
    transient left unsettled (their velocity is where the run stopped: said, not refused)."""
    return status == "ok" or " not settled within " in status


class NothingComputedError(ValueError):
    """No geometry of a study computed fully: no dataset is written, the parts are kept."""


def _refuse_if_nothing_computed(study: Study, parts: dict[int, dict], folder: Path) -> None:
    """Refuse to write a dataset of NaN: when no geometry computed fully, the parts (each
    with its reason in ``status``) stay in ``folder`` and nothing is written to ``--out`` (a
    dataset of NaN there made the corrected rerun refuse the existing file)."""
    from lusm.errors import short_reason

    status = [str(parts[i]["status"]) for i in sorted(parts)]
    if not status or any(computed_fully(x) for x in status):
        return
    raise NothingComputedError(
        f"no geometry of the study computed fully ({len(status)} of {study.n_geometries}); "
        f"first: {short_reason(status[0])}; no dataset was written, and "
        + ("the part (its reason in its 'status') is" if len(status) == 1 else
           f"the {len(status)} parts (each one's reason in its 'status') are")
        + f" kept in {folder}; remove that folder to run a corrected study")


def _bar(total: int, initial: int, enabled: bool):
    from tqdm import tqdm

    return tqdm(total=total, initial=initial, unit="geometry", file=sys.stderr,
                disable=(not enabled) or None, desc="lusm explore", leave=False)


def open_result(path: str | Path):
    """Read a dataset written by :func:`explore` (loaded into memory, file closed)."""
    import xarray as xr

    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()


# --- pictures ---------------------------------------------------------------------------------

MAP_VARIABLES = ("no_load_velocity", "stall_force", "split")
"""Variables drawn by :func:`design_maps`."""

PLOT_DIMS = ("length", "width", "thickness", "gap", "tip_length", "tip_width", "chamfer",
             "frequency", "voltage", "preload")
"""Numeric dimensions a study's figures are drawn over, in the order they are chosen (the
``material`` axis, a name, is drawn as :func:`drawn_materials` says)."""


def plot_dims(ds, name: str) -> tuple[str, ...]:
    """The numeric dimensions :func:`design_maps` draws variable ``name`` over: length x width
    where both vary (the design-space map), else the first two of :data:`PLOT_DIMS` along which
    it has at least two values (a map), else the first one (a curve); empty when none."""
    varied = [d for d in PLOT_DIMS if d in ds[name].dims and ds.sizes[d] >= 2]
    if "length" in varied and "width" in varied:
        return ("length", "width")
    return tuple(varied[:2])


def drawn_materials(ds, name: str) -> bool:
    """Whether :func:`design_maps` draws variable ``name`` for each value of the ``material``
    axis: when it has two or more. A map is then one panel per material, a curve one line per
    material, and a variable that varies along no numeric axis its values against the
    materials (figures had shown the first material only, and a study over materials alone
    drew nothing; found by exploratory testing)."""
    return "material" in ds[name].dims and ds.sizes["material"] >= 2


def drawable_maps(ds) -> list[str]:
    """The :data:`MAP_VARIABLES` :func:`design_maps` can draw: present, along at least one
    numeric axis of two values or more (:func:`plot_dims`) or two materials or more
    (:func:`drawn_materials`), not all NaN."""
    return [name for name in MAP_VARIABLES
            if name in ds and (plot_dims(ds, name) or drawn_materials(ds, name))
            and np.isfinite(ds[name].values.astype(float)).any()]


def _axis_scale(ds, dim: str) -> tuple[float, str]:
    """Factor and unit a coordinate is drawn in: mm for lengths, kHz for frequencies."""
    unit = ds[dim].attrs.get("units", "")
    return {"m": (1e3, "mm"), "Hz": (1e-3, "kHz")}.get(unit, (1.0, unit))


def design_maps(ds, folder: str | Path) -> list[Path]:
    """PNG figures of :data:`MAP_VARIABLES`, each over its dimensions of :func:`plot_dims`:
    maps over two (length x width for a design-space study), curves over one; with two
    materials or more (:func:`drawn_materials`), one map panel or one curve per material, or
    the values against the materials where no numeric axis varies; the other dimensions at
    their first value.

    Returns the written files (``{name}_{dim}[_{dim}][_material].png``); a variable that is
    absent, all NaN, or without a numeric axis of at least two values or two materials, gives
    none.
    """
    import textwrap

    from matplotlib.figure import Figure

    folder = Path(folder)
    written = []
    for name in drawable_maps(ds):
        dims = plot_dims(ds, name)
        per_material = drawn_materials(ds, name)
        drawn = dims + (("material",) if per_material else ())
        da = ds[name]
        fixed = {d: 0 for d in da.dims if d not in drawn}
        # ascending coordinates: a list axis may come in any order (a map of 9 cells drew 4);
        # the materials in the study's order
        da = da.isel(fixed).transpose(*drawn)
        if dims:
            da = da.sortby(list(dims))
        materials = [str(m) for m in ds["material"].values] if per_material else [None]
        where = ", ".join(_coord_text(ds, d) for d in fixed)
        panels = len(materials) if len(dims) == 2 else 1
        fig = Figure(figsize=(6.0 + 3.5 * (panels - 1), 4.5), layout="constrained")
        axes = fig.subplots(1, panels, sharex=True, sharey=True, squeeze=False)[0]
        if panels > 1:  # the panels' end ticks ("8.50" "6.50") had touched
            fig.get_layout_engine().set(wspace=0.08)
        scale, unit = (1e3, "mm/s") if name == "no_load_velocity" else \
            ((1e-3, "kHz") if name == "split" else (1.0, da.attrs.get("units", "")))
        label = f"{da.attrs.get('long_name', name)} ({unit})"
        # the values (drawn unit) of each material (of the only one)
        of = [(da if m is None else da.isel(material=k)).values.astype(float) * scale
              for k, m in enumerate(materials)]
        if dims:
            fy, uy = _axis_scale(ds, dims[0])
            ylabel = f"{ds[dims[0]].attrs.get('long_name', dims[0])} ({uy})"
        if len(dims) == 2:
            fx, ux = _axis_scale(ds, dims[1])
            finite = np.asarray(of)[np.isfinite(of)]  # one colour scale for the panels
            lo, hi = (finite.min(), finite.max()) if finite.size else (None, None)
            for k, ax in enumerate(axes):
                mesh = ax.pcolormesh(da[dims[1]].values * fx, da[dims[0]].values * fy, of[k],
                                     shading="nearest", cmap="viridis", vmin=lo, vmax=hi)
                ax.set_xlabel(f"{ds[dims[1]].attrs.get('long_name', dims[1])} ({ux})")
                if materials[k] is not None:
                    ax.set_title(f"material {materials[k]}", fontsize=8)
            axes[0].set_ylabel(ylabel)
            fig.colorbar(mesh, ax=list(axes), label=label)
        elif dims:  # one axis varies: the answer against it, a line per material
            ax = axes[0]
            for k, m in enumerate(materials):
                ax.plot(da[dims[0]].values * fy, of[k], "o-", label=m)
            if per_material:
                ax.legend(title="stator material", fontsize=8)
            ax.set_xlabel(ylabel)
            ax.set_ylabel(label)
            ax.grid(True, alpha=0.3)
        else:  # only the material varies: its values against the materials' names
            ax = axes[0]
            ax.plot(range(len(materials)), of, "o")
            ax.set_xticks(range(len(materials)), labels=materials)
            ax.set_xlim(-0.5, len(materials) - 0.5)
            ax.set_xlabel(ds["material"].attrs.get("long_name", "material"))
            ax.set_ylabel(label)
            ax.grid(True, alpha=0.3)
        lines = [name] + ([textwrap.fill(f"at {where}", 95)] if where else [])
        if name != "split" and "damping" in ds.attrs:  # a speed or force: say its damping
            lines.append(textwrap.fill(textwrap.shorten(f"damping {ds.attrs['damping']}",
                                                        190), 95))
        if panels > 1:
            fig.suptitle("\n".join(lines), fontsize=8)
        else:
            axes[0].set_title("\n".join(lines), fontsize=8)
        path = folder / f"{name}_{'_'.join(drawn)}.png"
        fig.savefig(path, dpi=120)
        written.append(path)
    return written


def _coord_text(ds, dim: str) -> str:
    v = ds[dim].values[0]
    if dim == "material":
        return f"material {v}"
    if dim == "gap" and math.isnan(v):  # a stator file's own mesh: its tagged electrodes
        return "gap of the stator's mesh"
    unit = ds[dim].attrs.get("units", "")
    if unit == "m":
        return f"{dim} {v * 1e3:g} mm"
    return f"{dim} {v:g} {unit}"
