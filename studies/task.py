"""One geometry of a study: the task a dask worker runs.

:func:`compute_geometry` runs the 2D FE modal solve of one plate once
(:func:`fem.modes.plate_modes`), reduces it to a parameter set (:func:`rom.from_fem.fem_params`,
which reuses the cached solve) and evaluates every drive point of that geometry
(:func:`motor_answers`). It is a pure function of the study and the geometry index (BLAS held
to one thread, ARPACK from a fixed start vector), so its result does not depend on the worker
or on the number of workers.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from bounds import said_in, short_reason
from fem.mesh_settings import MeshSettings
from studies.study import FEATURE_FIELDS, Study, plate_with
from validation.summaries import motion_class

FE_SCALARS = ("f_L1_short", "f_L1_open", "f_B2_short", "f_B2_open", "k_eff_L1", "k_eff_B2",
              "split", "f_drive")
"""Per-geometry numbers of a part file (Hz, or 1 for k_eff)."""


MOTOR_ARRAYS = ("no_load_velocity", "stall_force", "peak_efficiency", "peak_power",
                "limit_ratio", "motion_class")
"""Per-drive-point answers without the load dimension."""


TASK_EXTRAS = ("task_time_s", "lusm_version")
"""What a task returns beside the geometry's outputs (not written into its part)."""

WARNING_SEPARATOR = "\n"
"""Between two warnings in a geometry's ``warnings`` (each is one line)."""

STUDY_FORMS = {"ultrasonic_friction": "set {name} = false in the study's [solver]"}
"""A library warning's setting (:class:`bounds.Words`) as the study file's key that makes
it: the unsettled-A_N warning's remedy is the ``[solver]`` key, not the single-point
commands' ``--no-ultrasonic-friction``."""

POINT_OK = "ok"
"""The ``point_status`` of a drive point that computed."""


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


def geometry_of(study: Study, index: int) -> dict[str, Any]:
    """Axis values (SI, material name) of geometry ``index`` (C order over the axes)."""
    idx = np.unravel_index(index, study.geometry_shape)
    return {a: study.axes[a][int(i)] for a, i in zip(study.geometry_axes, idx, strict=True)}


def _motor_shape(study: Study) -> tuple[int, ...]:
    return tuple(len(study.axes[a]) for a in study.drive_dims if a != "load")


def motor_answers(params, drive: Drive, solver) -> dict[str, Any]:
    """The motor's answer at one drive triple: the ONE place the contact model is called.

    Returns ``no_load_velocity`` (m/s), ``stall_force`` (N), ``peak_efficiency`` (-),
    ``peak_power`` (W, the largest v F of the 21-load characteristic), ``limit_ratio`` (-,
    :func:`limit_ratio` of the unloaded steady state), ``motion_class`` (str) and
    ``velocity`` (m/s, one per load of ``drive.loads_N``). The
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
        power = np.asarray(curve.load_N, dtype=float) * np.asarray(curve.velocity_m_s,
                                                                   dtype=float)
        motion = motion_class(res.from_rest, res.velocity_m_s)
        return {"no_load_velocity": float(res.velocity_m_s),
                "stall_force": float(curve.stall_force_N),
                "peak_efficiency": float(np.nanmax(eff)) if np.isfinite(eff).any() else math.nan,
                "peak_power": float(np.nanmax(power)) if np.isfinite(power).any() else math.nan,
                "limit_ratio": limit_ratio(params, drive, res.from_rest),
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
            "peak_power": math.nan, "limit_ratio": math.nan,
            "motion_class": r.steady.motion, "velocity": velocity,
            "settled": bool(r.steady.settled)}


def limit_ratio(params, drive: Drive, branch) -> float:
    """The largest of the unloaded steady state's vibration velocity, stress, drive field
    and heat density over the material's limit for it (-; above 1: beyond a limit;
    :func:`contact.operating_limits.operating_limits`), NaN without shape data or limits."""
    from contact.operating_limits import QUANTITIES, operating_limits

    lim = operating_limits(params, drive.voltage_V, drive.frequency_Hz, branch)
    if lim is None:
        return math.nan
    ratios = [lim.ratio(q) for q in QUANTITIES]
    finite = [r for r in ratios if math.isfinite(r)]
    return max(finite) if finite else math.nan


def compute_geometry(study: Study, index: int) -> dict[str, np.ndarray]:
    """Everything the study wants of geometry ``index``: one FE solve, all drive points.

    A pure function of its arguments (BLAS held to one thread), so the same on any worker.
    A geometry whose FE solve or reduction fails gets NaN and its message in ``status``;
    a drive point whose run fails gets NaN, the motion class ``"failed"`` and its reason in
    ``point_status`` (the others compute). The warnings raised meanwhile (one line each,
    :data:`WARNING_SEPARATOR` between them) are the geometry's ``warnings``.
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
    out["warnings"] = np.array(WARNING_SEPARATOR.join(
        sorted({" ".join(said_in(w.message, STUDY_FORMS).split()) for w in caught})))
    out["lusm_version"] = np.array(package_version())  # the client compares it with its own
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

    g = geometry_of(study, index)
    s = study.solver
    out = empty_outputs(study)
    stage = "FE"  # what failed, for the status: the plate's FE solve or its parameter set
    try:
        stator, material = plate_of(study, g)
        mesh = MeshSettings(s.fe_order, s.fe_refine)
        modes = plate_modes(stator, material, mesh)
        for m in ("L1", "B2"):
            mode = getattr(modes, m)
            out[f"f_{m}_short"] = np.array(mode.f_short_Hz)
            out[f"f_{m}_open"] = np.array(mode.f_open_Hz)
            out[f"k_eff_{m}"] = np.array(mode.k_eff)
        out["split"] = np.array(modes.B2.f_short_Hz - modes.L1.f_short_Hz)
        if not study.needs_motor:
            return out
        # the modal reduction, the file's damping fit and motor tables, the auto frequency
        # (a fit to Table 2's amplitudes that a varied plate cannot match is not an FE failure)
        stage = "parameter set"
        params = _params_of(study, stator, material, mesh)
        if study.auto_frequency:
            from contact.drive import auto_frequency

            stage = "drive frequency"
            out["f_drive"] = np.array(auto_frequency(params))
    except (ValueError, RuntimeError, ArithmeticError) as exc:  # failure of this plate
        # short_reason: a list of 32 frequencies is said as its range
        return plate_failed(study, out, short_reason(f"{stage}: {type(exc).__name__}: {exc}"),
                            f"the plate's {stage} failed")
    _warn_unexcited(study, stator, params)
    freqs = [float(out["f_drive"])] if study.auto_frequency else study.axes["frequency"]
    if s.settle:  # this plate's run length: its settling time, as lusm simulate's default
        study = _settled_study(study, params, freqs)
        s = study.solver
        out["duration"] = np.array(s.duration_s)
    failures, unsettled = [], []
    # what the single-point commands refuse before they run, said once per plate in the
    # study's keys (not in the library's, 'duration_s ... 9.999999999999999e-06')
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
                    _point_failed(out, at, reason)
                    failures.append(reason)
                    continue
                try:
                    ans = motor_answers(params, Drive(v, p, f, study.axes["load"]), s)
                except (ValueError, RuntimeError) as exc:  # chattering, too large a step
                    _point_failed(out, at, str(exc).splitlines()[0])
                    failures.append(f"{v:g} V, {p:g} N, {f:.6g} Hz: {exc}".splitlines()[0])
                    continue
                for name in MOTOR_ARRAYS:
                    out[name][at] = ans[name]
                out["velocity"][at] = ans["velocity"]
                out["point_status"][at] = POINT_OK
                if not ans.get("settled", True):
                    out["point_status"][at] = (f"not settled within solver.duration "
                                               f"{s.duration_s:g} s")
                    unsettled.append(f"{v:g} V, {p:g} N, {f:.6g} Hz")
    _plate_status(out, failures, unsettled, s.duration_s)
    return out


def _params_of(study: Study, stator, material, mesh: MeshSettings):
    """The plate's reduced parameter set: a plain plate damped by its material's ``Q_m``
    with the mount's (as ``lusm simulate``'s plate options), a stator file's plate with the
    file's damping and motor tables (as the single-point commands on the file)."""
    from rom.from_fem import fem_params, fem_params_from_design

    if study.stator is None:
        from fem.material import get_material
        from validation.summaries import plate_damping

        ratios = plate_damping(get_material(material), "fem")[0]
        return fem_params(stator, material, mesh, damping_ratios=ratios)
    return fem_params_from_design(study.stator, stator, mesh=mesh)


def _settled_study(study: Study, params, freqs: list[float]) -> Study:
    """``study`` with the plate's own transient length: ``lusm simulate``'s default
    (:func:`contact.drive.default_duration_s`) over the plate's drive points at ``freqs``
    (Hz), at least the study's ``duration_s``, cut to the step bound
    (:func:`studies.study.transient_top_s`) with a warning that suggests the steady engine."""
    import warnings
    from dataclasses import replace

    from contact.drive import default_duration_s
    from studies.study import show, transient_top_s

    s = study.solver
    drives = [(v, p, f) for f in freqs for v in study.axes["voltage"]
              for p in study.axes["preload"]]
    top = min(transient_top_s(s, f) for f in freqs)
    duration, settle = default_duration_s(params, drives, top)
    if settle > duration:
        warnings.warn(f"solver.duration: this plate settles in about {show(settle, 'time')}, "
                      f"above the {show(duration, 'time')} the step bound allows; it runs "
                      f"{show(duration, 'time')}, which may not settle: method = \"steady\" "
                      "finds the steady state directly", stacklevel=2)
    return replace(study, solver=replace(s, duration_s=duration))


def _plate_status(out: dict[str, np.ndarray], failures: list[str], unsettled: list[str],
                  duration_s: float) -> None:
    """Set a plate's ``status`` from its failed and its unsettled drive points."""
    if failures:
        # one reason for all (the plate's: _drive_problem, _plate_work_problem), whole: the
        # work reason with its remedies is some 280 characters
        same = len(set(failures)) == 1
        out["status"] = np.array(f"{len(failures)} drive point(s) failed"
                                 f"{': ' if same else '; first: '}{failures[0]}"[:400])
    elif unsettled:  # a transient's velocity where it stopped, not the steady one
        out["status"] = np.array(
            f"{len(unsettled)} drive point(s) not settled within solver.duration "
            f"{duration_s:g} s (their velocity is where the run stopped; a longer duration "
            f"or method = \"steady\"); first: {unsettled[0]}"[:300])


def _point_failed(out: dict[str, np.ndarray], at: tuple, reason: str) -> None:
    """Mark the drive point ``at`` failed, with ``reason`` in its ``point_status``."""
    out["motion_class"][at] = "failed"
    out["point_status"][at] = short_reason(f"failed: {reason}")[:POINT_STATUS_CHARS]


POINT_STATUS_CHARS = 300
"""Longest ``point_status`` kept (characters; the work reason with its remedies is ~280)."""


def _warn_unexcited(study: Study, stator, params) -> None:
    """Warn, as the single-point commands do, when the plate's drive excites no B2 (or no
    L1): the motor then gives no thrust, which a status "ok" with zero velocity hid."""
    import warnings

    from validation.summaries import unexcited_modes

    where = (f"study.stator {study.stator.path}: " if study.stator is not None else "")
    for text in unexcited_modes(params, stator.drive_electrodes):
        warnings.warn(where + text, stacklevel=2)


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
    plate at fe_refine 1), a transient's default step at an auto frequency, and, without a
    typed ``solver.duration``, a transient's run length: the plate's settling time
    (:func:`_settled_study` sets it before this check)."""
    from studies.study import contact_work_problem, show, steady_solves

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
    run = f"settling time {show(s.duration_s, 'time')}" if s.settle else ""
    detail = (f"{per_f * len(freqs)} drive points x {sum(steps) / len(steps):.3g} steps each "
              f"(this plate's{' ' if run else ''}{run})")
    return contact_work_problem(study, per_f * sum(steps), detail)


def empty_outputs(study: Study) -> dict[str, np.ndarray]:
    """A geometry's outputs before it is computed: NaN, ``""`` and status ``"ok"``, in the
    shapes a part must have."""
    mshape = _motor_shape(study)
    n_load = len(study.axes["load"])
    out: dict[str, np.ndarray] = {k: np.array(math.nan) for k in FE_SCALARS}
    for k in MOTOR_ARRAYS[:-1]:
        out[k] = np.full(mshape, math.nan)
    out["motion_class"] = np.full(mshape, "", dtype="<U32")
    out["velocity"] = np.full((*mshape, n_load), math.nan)
    out["point_status"] = np.full(mshape, "", dtype=f"<U{POINT_STATUS_CHARS}")
    out["status"] = np.array("ok")
    out["warnings"] = np.array("")
    if study.solver.settle:
        out["duration"] = np.array(math.nan)
    return out


def plate_failed(study: Study, out: dict[str, np.ndarray], status: str, why: str
                 ) -> dict[str, np.ndarray]:
    """``out`` of a plate that failed before its drive points: its ``status`` (the first
    line, at most 400 characters), and every drive point failed with it, ``why``."""
    out["status"] = np.array(status.splitlines()[0][:400])
    if study.needs_motor:
        out["motion_class"][...] = "failed"
        out["point_status"][...] = f"failed: {why} (see status)"
    return out


def has_results(part: dict[str, np.ndarray]) -> bool:
    """Whether a geometry's part holds any answer: it computed fully
    (:func:`computed_fully`), or some of its drive points did (``point_status``)."""
    if computed_fully(str(part["status"])):
        return True
    ps = np.asarray(part.get("point_status", ""), dtype=str)
    return bool(((ps == POINT_OK) | np.char.startswith(ps, "not settled")).any())


def computed_fully(status: str) -> bool:
    """Whether a geometry's ``status`` says it computed fully: ``"ok"``, or drive points a
    transient left unsettled (their velocity is where the run stopped: said, not refused)."""
    return status == "ok" or " not settled within " in status


def package_version() -> str:
    """The lusm version of this process: a task stamps its result with it, the client
    compares it with its own (and the scheduler's and the workers', run there)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("lusm")
    except PackageNotFoundError:  # pragma: no cover - running from a bare checkout
        return "unknown"
