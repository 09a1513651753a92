"""Scaling of ``lusm optimize`` on this machine: designs evaluated per second with 1 and 2
LocalCluster workers, and with 8 workers of a remote ``dask scheduler`` (a scheduler and a
``dask worker --nworkers 8`` started here on loopback, as `--scheduler` reaches one).

Run::

    nice -n 5 python benchmarks/optimize_scaling.py            # ~3-6 min on 2 loaded cores
    nice -n 5 python benchmarks/optimize_scaling.py --budget 16 --json

Each configuration runs the same problem (``PROBLEM``: the paper's plate, length x width,
the most k_eff_B2 with |split| <= 2 %; FE-only, so that an evaluation is the FE solve and
the modal reduction, about a second) for the same number of evaluations, in batches of its
workers. Workers are warmed (imports, numba cache, one FE solve outside the box) before the
clock starts. CPU time is that of this process and every process under it (the client, the
LocalCluster's workers, the scheduler and the 8 workers), from ``psutil``; the client's
own, and the sampler's wall time (``ask_batch``), say what the search adds to the
evaluations. On 2 cores, 8
workers cannot be faster than 2: the figure shows that the batches grow with the workers and
that the search completes on a remote cluster, not a speed-up.
"""

from __future__ import annotations

import argparse
import json
import os
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

PROBLEM = {
    "outputs": ["split", "k_eff"],
    "study": {"name": "optimize scaling benchmark"},
    "solver": {"fe_order": 2, "fe_refine": 2},
    "optimize": {"evaluations": 16, "seed": 0, "startup": 4,
                 "variables": {"length": {"min": "28 mm", "max": "32 mm"},
                               "width": {"min": "6.5 mm", "max": "8.5 mm"}},
                 "objectives": [{"output": "k_eff_B2", "goal": "maximize"}],
                 "constraints": {"split": "2 %"}},
}


def _warm() -> bool:
    """Import the stack and solve one plate outside the box, in the calling process."""
    from studies.study import study_from_dict
    from studies.task import compute_geometry

    study = {k: v for k, v in PROBLEM.items() if k != "optimize"}
    compute_geometry(study_from_dict({**study, "axes": {"length": "26 mm"}}), 0)
    return True


def _cpu_s() -> float:
    """CPU time (s, user + system) of this process and of every live process under it."""
    import psutil

    me = psutil.Process()
    total = 0.0
    for p in [me, *me.children(recursive=True)]:
        try:
            t = p.cpu_times()
            total += t.user + t.system
        except psutil.Error:
            pass
    return total


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _remote_cluster(n: int) -> tuple[str, list[subprocess.Popen]]:
    """A ``dask scheduler`` and a ``dask worker --nworkers n --nthreads 1`` on loopback,
    each in a session of its own; returns the address and the two processes."""
    from distributed import Client

    from studies.cluster import worker_env

    address = f"tcp://127.0.0.1:{_free_port()}"
    env = {**os.environ, **worker_env()}
    common = dict(stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                  start_new_session=True)
    procs = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler",
                               "--host", "127.0.0.1", "--port", address.rsplit(":", 1)[1],
                               "--no-dashboard"], **common)]
    procs.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker",
                                   address, "--nworkers", str(n), "--nthreads", "1",
                                   "--no-dashboard"], **common))
    with Client(address, timeout="60s") as client:
        client.wait_for_workers(n, timeout=180)
    return address, procs


def _stop(procs: list[subprocess.Popen]) -> None:
    import signal

    for p in reversed(procs):
        try:
            os.killpg(p.pid, signal.SIGTERM)
            p.wait(timeout=30)
        except (ProcessLookupError, subprocess.TimeoutExpired):
            os.killpg(p.pid, signal.SIGKILL)
            p.wait(timeout=30)


def _run(problem, out: Path, budget: int, **cluster) -> dict:
    """One search of ``budget`` designs on ``cluster`` (optimize's keyword arguments): its
    rate, its CPU time (all processes, and the client alone), the sampler's share of the
    wall time (``ask_batch``, timed where the search calls it) and its failed designs."""
    import psutil

    import studies.optimize.search as search
    from studies.dataset import open_result
    from studies.optimize import optimize

    asked = search.ask_batch
    sampler = [0.0]

    def timed_ask(*a, **k):
        t = time.perf_counter()
        try:
            return asked(*a, **k)
        finally:
            sampler[0] += time.perf_counter() - t

    me = psutil.Process()
    search.ask_batch = timed_ask
    try:
        c0, m0, t0 = _cpu_s(), sum(me.cpu_times()[:2]), time.perf_counter()
        r = optimize(problem, out, budget=budget, **cluster)
        wall, cpu = time.perf_counter() - t0, _cpu_s() - c0
        client_cpu = sum(me.cpu_times()[:2]) - m0
    finally:
        search.ask_batch = asked
    status = open_result(r.path)["status"].values
    return {"workers": r.workers, "batch": r.batch, "evaluations": r.evaluations,
            "computed": r.computed, "failed": int(sum(str(x) != "ok" for x in status)),
            "feasible": r.feasible, "wall_s": wall, "designs_per_s": r.computed / wall,
            "cpu_s": cpu, "cpu_s_per_design": cpu / r.computed, "client_cpu_s": client_cpu,
            "sampler_s": sampler[0]}


def _evaluation_s(problem) -> float:
    """Wall time (s) of one design's evaluation in this process, the median of 3 designs
    of the box (its centre and two corners): the cost a worker pays per design."""
    import statistics

    from studies.optimize.problem import trial_study
    from studies.task import compute_geometry

    designs = [{"length": 30e-3, "width": 7.5e-3}, {"length": 28e-3, "width": 6.5e-3},
               {"length": 32e-3, "width": 8.5e-3}]
    times = []
    for d in designs:
        t = time.perf_counter()
        compute_geometry(trial_study(problem, d), 0)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--budget", type=int, default=16, help="designs per configuration")
    p.add_argument("--remote-workers", type=int, default=8)
    p.add_argument("--json", action="store_true")
    args = p.parse_args()

    from distributed import Client

    from studies.cluster import local_cluster
    from studies.optimize import problem_from_dict

    problem = problem_from_dict(PROBLEM)
    figures = {"load_before": os.getloadavg(), "cpus": os.cpu_count(), "budget": args.budget}
    _warm()
    figures["evaluation_in_process_s"] = _evaluation_s(problem)
    with tempfile.TemporaryDirectory() as tmp:
        for n in (1, 2):
            cluster = local_cluster(n)
            client = Client(cluster)
            try:
                client.run(_warm)
                figures[f"local_{n}"] = _run(problem, Path(tmp) / f"l{n}.nc", args.budget,
                                             client=client)
            finally:
                client.close()
                cluster.close()
        n = args.remote_workers
        address, procs = _remote_cluster(n)
        try:
            with Client(address) as client:
                client.run(_warm)
            # through --scheduler's path: the version checks, then the search
            figures[f"remote_{n}"] = _run(problem, Path(tmp) / f"r{n}.nc", args.budget,
                                          scheduler=address)
        finally:
            _stop(procs)
    figures["load_after"] = os.getloadavg()
    if args.json:
        print(json.dumps(figures, indent=2))
        return
    print(f"load average before {figures['load_before'][0]:.2f}, after "
          f"{figures['load_after'][0]:.2f} on {figures['cpus']} cores; {args.budget} designs "
          f"per configuration; one evaluation in-process "
          f"{figures['evaluation_in_process_s']:.2f} s")
    for key in ("local_1", "local_2", f"remote_{n}"):
        f = figures[key]
        print(f"{key}: {f['workers']} workers, batches of {f['batch']}: {f['computed']} designs "
              f"({f['failed']} failed, {f['feasible']} feasible) in {f['wall_s']:.1f} s, "
              f"{f['designs_per_s']:.3f} designs/s; CPU {f['cpu_s']:.1f} s "
              f"({f['cpu_s_per_design']:.2f} s/design; client {f['client_cpu_s']:.1f} s, "
              f"sampler {f['sampler_s']:.2f} s wall)")


if __name__ == "__main__":
    main()
