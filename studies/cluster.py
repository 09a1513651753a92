"""The dask cluster a study runs on: a LocalCluster of processes, or a running scheduler.

:func:`study_client` gives the client for one run: the caller's, or one it makes with
:func:`connect` (a new :func:`local_cluster`, or ``--scheduler`` / ``--scheduler-file``)
and closes again. Another's scheduler and workers are checked to run this lusm version
before any task.
"""

from __future__ import annotations

import json
import logging
import os
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

DEFAULT_WORKERS = 2
"""Processes of the default LocalCluster (this project's machines have 2 cores)."""


BLAS_ENV = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


CONNECT_TIMEOUT = "10s"
"""How long to wait for an existing scheduler."""


CONNECT_DEADLINE_S = 15.0
"""Wall-clock bound (s) on connecting to it: dask's own timeout does not cover a listener
that accepts and never answers (it would wait past 45 s)."""


MAX_SCHEDULER_FILE_BYTES = 1_000_000
"""Largest ``--scheduler-file`` read (a dask scheduler file is a few hundred bytes)."""


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


def _check_scheduler_file(path: str) -> None:
    """Refuse a ``--scheduler-file`` that is not the JSON a dask scheduler writes (an object
    with its ``address``), naming the option, before dask reads it as one (a study file
    given there would fail inside dask with an AssertionError)."""
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
    if scheduler:
        check_port(scheduler)
    if scheduler and scheduler_file:
        raise ValueError("--scheduler and --scheduler-file exclude each other; give one")
    if scheduler_file and not Path(scheduler_file).is_file():
        # a folder or a device exists: say what it is instead
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


def check_port(address: str) -> None:
    """Refuse at once a ``--scheduler`` address whose port no TCP connection can have
    (``tcp://127.0.0.1:99999`` waited :data:`CONNECT_TIMEOUT` and said it timed out).

    Raises
    ------
    ValueError
        Naming ``--scheduler`` and the range of ports.
    """
    import re

    m = re.search(r":(\d+)/?$", address.strip())
    if m and not 1 <= int(m.group(1)) <= 65535:
        raise ValueError(f"--scheduler {address}: port {m.group(1)} is not a TCP port; give "
                         "one in [1, 65535] (a dask scheduler listens on 8786 by default)")


def process_version() -> str:
    """The lusm version of the process this runs in (:func:`studies.task.package_version`,
    looked up when called): this client's, and, run there by :func:`check_scheduler` and
    :func:`check_workers` (pickled by reference), the scheduler's and each worker's."""
    from studies import task

    return task.package_version()


def check_scheduler(client, option: str = "--scheduler") -> None:
    """Refuse a scheduler that cannot import lusm or runs another version than this client.

    The scheduler unpickles every task (its function is :func:`compute_geometry`, pickled
    by reference), so without lusm the first submission fails with dask's "Error during
    deserialization of the task graph". Asked once before any task
    (``client.run_on_scheduler`` of the package version), it is one line naming ``option``.
    """
    try:
        version = client.run_on_scheduler(process_version)
    except Exception as exc:  # noqa: BLE001 - ModuleNotFoundError on the scheduler, travelling
        # back (or whatever else stops it from running lusm's function): its fault, not ours
        text = str(exc).splitlines()[0] if str(exc) else ""
        raise ValueError(f"{option}: the dask scheduler cannot run lusm ({type(exc).__name__}: "
                         f"{text[:200]}); install lusm on the scheduler too (it unpickles "
                         "every task), at this client's version") from None
    if version != process_version():
        raise ValueError(f"{option}: the dask scheduler runs lusm {version}, this client "
                         f"{process_version()}; install the same version everywhere")


def check_workers(client, option: str = "--scheduler", gmsh: bool = False) -> None:
    """Refuse workers that cannot import lusm or run another version than this client, and,
    with ``gmsh`` (a study of a parametric stator file), workers without gmsh (each task
    would fail on its mesh after the study started)."""
    try:
        versions = client.run(process_version)
    except Exception as exc:  # ModuleNotFoundError on the worker, travelling back
        raise ValueError(f"{option}: the workers cannot run lusm ({type(exc).__name__}: "
                         f"{str(exc).splitlines()[0] if str(exc) else ''}); install lusm "
                         "on every worker") from None
    mine = process_version()
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


@contextmanager
def study_client(client=None, scheduler: str | None = None, scheduler_file: str | None = None,
                 workers: int = DEFAULT_WORKERS, gmsh: bool = False) -> Iterator[Any]:
    """The client one run computes on: ``client`` as it is (the caller's, left open), or one
    made by :func:`connect` and closed, with the LocalCluster it started, when the run ends
    however it ends. On someone else's scheduler, the scheduler and the workers are checked
    first (:func:`check_scheduler`, :func:`check_workers`; gmsh too with ``gmsh``)."""
    if client is not None:
        yield client
        return
    client, cluster = connect(scheduler, scheduler_file, workers)
    try:
        with _quiet_client_logs():
            if cluster is None:  # someone else's cluster: same lusm as ours?
                option = "--scheduler" if scheduler else "--scheduler-file"
                check_scheduler(client, option)
                check_workers(client, option, gmsh=gmsh)
            yield client
    finally:
        with _quiet_client_logs():
            client.close()
            if cluster is not None:
                cluster.close()


@contextmanager
def _quiet_client_logs() -> Iterator[None]:
    """Meanwhile, the ``distributed`` loggers of this process say nothing below CRITICAL: a
    scheduler that goes away makes the client log its failed reconnections with their
    tracebacks, where the study says the loss in one line
    (:class:`ClusterLostError`)."""
    log = logging.getLogger("distributed")
    before = log.level
    log.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        log.setLevel(before)


WORKER_TIMEOUT_S = 300.0
"""Default of how long (s) a study waits for a cluster that has no worker left (an external
scheduler whose workers died) before it stops with its parts kept."""

WORKER_NOTICE_S = 30.0
"""Seconds without a worker after which the wait is said (half the bound when that is
shorter)."""

POLL_S = 0.01
"""Seconds between two looks for a finished task (a lock and a length: free at this rate);
the cluster itself is looked at once a second. A batch of an optimisation waits this long at
most after its last task ends, so it is short beside a task's fraction of a second."""


class ClusterLostError(ValueError):
    """The cluster went away mid-study: its scheduler, or every worker for longer than the
    bound. The finished parts (explore's geometries, optimize's designs) are kept for
    ``--resume``.

    Attributes
    ----------
    where : str
        The option that named the cluster (``--scheduler``), or "the local cluster".
    """

    def __init__(self, message: str, where: str) -> None:
        super().__init__(message)
        self.where = where


class ClusterWaitWarning(UserWarning):
    """The cluster has had no worker for a while; the study waits for one."""


def cluster_where(scheduler: str | None, scheduler_file: str | None) -> str:
    """The option naming a run's cluster with its value (``--scheduler tcp://...``), or
    "the local cluster": what :class:`ClusterWatch`'s errors name."""
    return (f"--scheduler {scheduler}" if scheduler else
            f"--scheduler-file {scheduler_file}" if scheduler_file else "the local cluster")


class ClusterWatch:
    """The study's look at its cluster while it waits for a task: the scheduler still
    connected, and a worker there (or back within ``timeout_s``).

    Parameters
    ----------
    where : str
        The option naming the cluster and its value (``--scheduler tcp://...``), or
        "the local cluster": what the errors name.
    timeout_s : float
        The longest time (s) without a worker.
    """

    def __init__(self, where: str, timeout_s: float) -> None:
        self.where = where
        self.timeout_s = float(timeout_s)
        self.notice_s = min(WORKER_NOTICE_S, self.timeout_s / 2)

    def lost(self) -> ClusterLostError:
        """The error of a scheduler that went away."""
        return ClusterLostError(f"{self.where}: lost the connection to the dask scheduler "
                                "mid-study", self.where)

    def workers(self, client) -> int:
        """The cluster's workers now (a scheduler round trip)."""
        if client.status != "running":
            raise self.lost()
        try:
            return len(client.nthreads())
        except Exception as exc:  # noqa: BLE001 - the connection went while asking
            if client.status != "running":
                raise self.lost() from None
            raise exc

    def result(self, client, fut) -> Any:
        """``fut``'s result; a future cancelled because the scheduler went away is
        :meth:`lost`."""
        try:
            return fut.result()
        except Exception as exc:  # noqa: BLE001 - CancelledError, CommClosedError, ...
            if client.status != "running" or "connection-lost" in str(exc):
                raise self.lost() from None
            raise

    def wait(self, client, completed) -> None:
        """Return once ``completed`` has a finished task; meanwhile look at the cluster
        every second: a lost scheduler raises :meth:`lost`, no worker for
        :attr:`notice_s` is said once (:class:`ClusterWaitWarning`) and for
        :attr:`timeout_s` raises :class:`ClusterLostError`."""
        import warnings

        since, said, looked = None, False, 0.0
        while not completed.has_ready():
            now = time.monotonic()
            if now - looked >= 1.0 or client.status != "running":
                looked = now
                if self.workers(client) > 0:
                    since, said = None, False
                elif since is None:
                    since = now
            if since is not None and not said and now - since >= self.notice_s:
                said = True
                warnings.warn(ClusterWaitWarning(
                    f"no worker for {self.notice_s:g} s; waiting for the cluster to recover "
                    f"(Ctrl-C keeps the parts for --resume)"), stacklevel=2)
            if since is not None and now - since >= self.timeout_s:
                raise ClusterLostError(
                    f"{self.where}: no worker for {self.timeout_s:g} s (--worker-timeout-s); "
                    "the cluster did not recover", self.where)
            time.sleep(POLL_S)
