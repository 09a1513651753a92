"""Scaling of ``lusm explore`` on this machine: points/s with 1 and 2 workers, task cost,
scheduler overhead per task, bytes moved; and the 1- and 2-worker datasets compared bit for bit.

Run::

    python benchmarks/explore_scaling.py            # ~1-2 min on 2 cores
    python benchmarks/explore_scaling.py --json     # the same figures as JSON

The study is the one of ``examples/studies/length_width.toml`` widened to 4 x 4 plates and
2 voltages x 2 preloads (16 tasks x 4 drive points). Workers are warmed (imports, numba
cache) before the clock starts, so the figures are the steady rate of a long study.
"""

from __future__ import annotations

import argparse
import json
import pickle
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

STUDY = {
    "outputs": ["f_L1_short", "f_L1_open", "f_B2_short", "f_B2_open", "k_eff", "split",
                "no_load_velocity", "motion_class"],
    "study": {"name": "explore scaling benchmark"},
    "axes": {
        "length": {"start": "27 mm", "stop": "33 mm", "num": 4},
        "width": {"start": "6.5 mm", "stop": "8.5 mm", "num": 4},
        "voltage": ["200 V", "300 V"],
        "preload": ["6 N", "10 N"],
    },
    # transient drive points of 5 ms (the steady engine, the study default, costs seconds at
    # creep points and would measure the motor model, not the distribution); the FE mesh is
    # the study's default (fe_refine 4, the single-point commands')
    "solver": {"fe_order": 2, "duration": "5 ms", "dt": "100 ns", "method": "event"},
}


def _noop(i):
    return i


def _warm(study):
    """Import the stack and load the numba cache in this process, on a plate outside the
    study (so that no FE solve of the study is cached before the clock starts)."""
    from studies.study import study_from_dict
    from studies.task import compute_geometry

    warm = {**STUDY, "axes": {**STUDY["axes"], "length": "25 mm", "width": "6 mm"}}
    compute_geometry(study_from_dict(warm), 0)
    return True


def _timed(study, i):
    from studies.task import compute_geometry

    return float(compute_geometry(study, i)["task_time_s"])


def _drive_point_times(study, indices) -> list[float]:
    """Wall time (s) of each drive point of the geometries ``indices``, timed directly: the
    one call a task makes per point (:func:`studies.task.motor_answers`), on the
    plate's parameter set at its auto frequency, in this process. (The figure had been the
    median full task minus the median FE-only task of other plates, over the points: two
    medians of different plates, whose difference is not a point's cost.)"""
    from threadpoolctl import threadpool_limits

    from contact.drive import auto_frequency
    from fem.geometry import PlateStator
    from fem.mesh_settings import MeshSettings
    from rom.from_fem import fem_params
    from studies.task import Drive, geometry_of, motor_answers

    s = study.solver
    times = []
    with threadpool_limits(limits=1):  # as in a task
        for i in indices:
            g = geometry_of(study, i)
            stator = PlateStator(length_m=g["length"], width_m=g["width"],
                                 thickness_m=g["thickness"], electrode_gap_m=g["gap"])
            params = fem_params(stator, g["material"],
                                MeshSettings(s.fe_order, s.fe_refine))
            f = auto_frequency(params)
            for v in study.axes["voltage"]:
                for p in study.axes["preload"]:
                    t0 = time.perf_counter()
                    motor_answers(params, Drive(v, p, f, study.axes["load"]), s)
                    times.append(time.perf_counter() - t0)
    return times


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--json", action="store_true")
    args = p.parse_args()

    from studies.study import study_from_dict

    study = study_from_dict(STUDY)
    import h5netcdf  # noqa: F401 - the client's imports are not part of the study's time
    import xarray as xr

    _warm(study)
    figures = _in_process_figures(study)
    datasets = {}
    with tempfile.TemporaryDirectory() as tmp:
        for n in (1, 2):
            figures[f"workers_{n}"], datasets[n] = _cluster_figures(study, n, Path(tmp))
    try:
        xr.testing.assert_identical(datasets[1], datasets[2])
        figures["bit_identical_1_vs_2_workers"] = True
    except AssertionError:
        figures["bit_identical_1_vs_2_workers"] = False
    w1, w2 = figures["workers_1"], figures["workers_2"]
    figures["speedup_2_over_1"] = w2["points_per_s"] / w1["points_per_s"]
    if args.json:
        print(json.dumps(figures, indent=2))
        return
    _print_figures(figures, study)


def _in_process_figures(study) -> dict:
    """The study's size, one task and its FE part timed in this process, and one drive point
    of the study (5 ms) and of ``lusm simulate`` (50 ms)."""
    from contact.drive import auto_frequency
    from contact.simulate import simulate
    from fem.geometry import PlateStator
    from fem.modes import clear_caches
    from rom.from_fem import fem_params
    from studies.study import study_from_dict

    # a task and the FE part of it alone (an FE-only study), on the same plates, one after
    # the other so that the shared machine's load drifts little between them; the FE
    # caches (the model, the modes, the gap's cross-section) are emptied before each, so
    # that both solve everything (on other plates the FE part can be half the task on one
    # run and 0.9 of it on the next)
    fe_only = study_from_dict({**STUDY, "outputs": ["f_L1_short", "split"]})
    t, t_fe = [], []
    for i in range(1, 5):
        for which, times in ((fe_only, t_fe), (study, t)):
            clear_caches()
            times.append(_timed(which, i))
    # one drive point of the study (5 ms), timed directly on the plates of the tasks above
    point_5ms = statistics.median(_drive_point_times(study, range(1, 5)))
    # one drive point as the default `lusm simulate` runs it (50 ms, its default step), for
    # the estimate
    params = fem_params(PlateStator(), "pzt8")  # lusm simulate --source fem's set
    f = auto_frequency(params)
    simulate(params, 200, 6, f, duration_s=5e-3)
    reps = []
    for _ in range(5):  # the shared machine makes single runs vary by up to 10x: best of 5
        t0 = time.perf_counter()
        simulate(params, 200, 6, f, duration_s=0.05)
        reps.append(time.perf_counter() - t0)
    return {"tasks": study.n_geometries, "points": study.n_geometries * study.n_drive_points,
            "drive_point_5ms_s": point_5ms,
            "drive_point_50ms_s": min(reps),
            "drive_point_50ms_worst_of_5_s": max(reps),
            "drive_points_per_task": study.n_drive_points,
            "task_time_in_process_s": statistics.median(t),
            "fe_part_of_task_s": statistics.median(t_fe),
            "study_argument_bytes": len(pickle.dumps(study, protocol=5))}


def _cluster_figures(study, n: int, tmp: Path) -> tuple[dict, object]:
    """The study run on a LocalCluster of ``n`` workers: its throughput and overheads, and
    its dataset."""
    from distributed import Client

    from studies.cluster import local_cluster
    from studies.dataset import open_result
    from studies.explore import explore

    n_tasks, n_points = study.n_geometries, study.n_geometries * study.n_drive_points
    cluster = local_cluster(n)
    client = Client(cluster)
    try:
        client.run(_warm, study)
        t0 = time.perf_counter()
        client.gather(client.map(_noop, range(1000), pure=False))
        noop_per_task = (time.perf_counter() - t0) / 1000
        out = tmp / f"w{n}.nc"
        r = explore(study, out, client=client, progress=False)
        dataset = open_result(out)
    finally:
        client.close()
        cluster.close()
    busy = sum(r.task_times_s)
    return {
        "wall_s": r.wall_time_s,
        "points_per_s": n_points / r.wall_time_s,
        "tasks_per_s": n_tasks / r.wall_time_s,
        "task_time_mean_s": busy / n_tasks,
        # wall time the workers were not running a task, per task (includes the client's
        # part writes and the final dataset write)
        "overhead_per_task_s": max(0.0, (r.wall_time_s * n - busy) / n_tasks),
        "final_write_s": r.write_time_s,
        "part_write_per_task_s": r.part_write_time_s / n_tasks,
        "noop_round_trip_per_task_s": noop_per_task,
        "result_bytes_per_task": r.result_bytes / n_tasks,
    }, dataset


def _print_figures(figures: dict, study) -> None:
    """The figures of :func:`main` for a reader."""
    print(f"study: {figures['tasks']} tasks (geometries) x {study.n_drive_points} drive points")
    print(f"one task in-process: {figures['task_time_in_process_s'] * 1e3:.1f} ms "
          f"(FE solve alone {figures['fe_part_of_task_s'] * 1e3:.1f} ms; a 5 ms drive point "
          f"{figures['drive_point_5ms_s'] * 1e3:.1f} ms; a 50 ms drive point as lusm simulate "
          f"runs it {figures['drive_point_50ms_s'] * 1e3:.1f} ms, best of 5; worst "
          f"{figures['drive_point_50ms_worst_of_5_s'] * 1e3:.1f} ms)")
    print(f"study argument {figures['study_argument_bytes']} B per task")
    for n in (1, 2):
        w = figures[f"workers_{n}"]
        print(f"{n} worker(s): {w['points_per_s']:.1f} points/s, {w['tasks_per_s']:.2f} tasks/s,"
              f" task {w['task_time_mean_s'] * 1e3:.1f} ms, overhead "
              f"{w['overhead_per_task_s'] * 1e3:.1f} ms/task, no-op round trip "
              f"{w['noop_round_trip_per_task_s'] * 1e3:.2f} ms/task, result "
              f"{w['result_bytes_per_task']:.0f} B/task; part write "
              f"{w['part_write_per_task_s'] * 1e3:.2f} ms/task; final dataset write "
              f"{w['final_write_s'] * 1e3:.0f} ms")
    print(f"speed-up 2 over 1 worker: {figures['speedup_2_over_1']:.2f}; datasets bit-identical: "
          f"{figures['bit_identical_1_vs_2_workers']}")

if __name__ == "__main__":
    main()
