"""``lusm explore`` and ``lusm optimize`` on a real external cluster that goes away
mid-study: a ``dask scheduler`` and a ``dask worker`` started here on loopback (free ports)
and killed. A lost worker is waited for within ``--worker-timeout-s`` and said; a lost
scheduler is one line naming ``--scheduler``, exit code 2, with the command that resumes; the
finished parts are kept."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("distributed")

from lusm.cli import main  # noqa: E402
from studies.parts import parts_folder  # noqa: E402

STUDY = """\
outputs = ["f_L1_short"]
[study]
name = "lost cluster"
[axes]
length = { start = "28 mm", stop = "32 mm", num = 12 }
[solver]
fe_order = 1
fe_refine = 1
"""
"""Twelve FE-only plates of a fraction of a second each: the worker dies after the first."""

OPTIMIZE = """\
outputs = ["split"]
[study]
name = "lost cluster"
[solver]
fe_order = 1
fe_refine = 1
[optimize]
evaluations = 6
[optimize.variables]
length = { min = "28 mm", max = "32 mm" }
[[optimize.objectives]]
output = "k_eff_B2"
goal = "maximize"
"""
"""Six FE-only designs (batches of one on the one worker): the worker dies after the first."""


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _start(*args: str) -> subprocess.Popen:
    """A dask process in a session of its own (killed as a group: the worker's nanny and
    its worker), its output discarded."""
    return subprocess.Popen([sys.executable, "-m", *args], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)


def _kill(proc: subprocess.Popen) -> None:
    """SIGKILL the process group this test started, and reap its leader."""
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    proc.wait(timeout=30)


@pytest.fixture
def cluster():
    """``(address, scheduler process, worker process)`` of a fresh scheduler with one worker
    of one thread, killed at the end whatever the test did to them."""
    from distributed import Client

    address = f"tcp://127.0.0.1:{_free_port()}"
    scheduler = _start("distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port",
                       address.rsplit(":", 1)[1], "--no-dashboard")
    worker = None
    try:
        worker = _start("distributed.cli.dask_worker", address, "--nworkers", "1",
                        "--nthreads", "1", "--no-dashboard")
        with Client(address, timeout="30s") as client:
            client.wait_for_workers(1, timeout=60)
        yield address, scheduler, worker
    finally:
        for proc in (worker, scheduler):
            if proc is not None:
                _kill(proc)


def _run_killing(cluster, victim: str, tmp_path: Path, monkeypatch, capsys,
                 extra: tuple[str, ...] = (), command: str = "explore"
                 ) -> tuple[int, str, Path]:
    """Run ``lusm COMMAND`` (explore's study, or optimize's) on ``cluster`` and kill its
    ``victim`` ("worker" or "scheduler") once the first part is written; returns the exit
    code, stderr and the output path."""
    import studies.explore as E
    import studies.optimize.store as S

    writer = S if command == "optimize" else E  # the module whose write_part writes parts
    address, scheduler, worker = cluster
    study = tmp_path / "study.toml"
    study.write_text(OPTIMIZE if command == "optimize" else STUDY)
    out = tmp_path / "x.nc"
    write_part = writer.write_part

    def write_then_kill(folder, index, data):
        write_part(folder, index, data)
        proc = worker if victim == "worker" else scheduler
        if proc.poll() is None:
            _kill(proc)

    monkeypatch.setattr(writer, "write_part", write_then_kill)
    t0 = time.monotonic()
    rc = main([command, str(study), "--out", str(out), "--scheduler", address, *extra])
    assert time.monotonic() - t0 < 60
    return rc, capsys.readouterr().err, out


@pytest.mark.slow
def test_a_lost_worker_is_waited_for_within_the_bound_and_said(cluster, tmp_path,
                                                               monkeypatch, capsys):
    rc, err, out = _run_killing(cluster, "worker", tmp_path, monkeypatch, capsys,
                                ("--worker-timeout-s", "2"))
    lines = [ln for ln in err.splitlines() if ln.strip() and "lusm explore" in ln]
    assert rc == 2 and "Traceback" not in err, err
    assert "lusm explore: warning: no worker for 1 s; waiting for the cluster to recover " \
           "(Ctrl-C keeps the parts for --resume)" in lines, err
    assert lines[-1].startswith(f"lusm explore: error: --scheduler {cluster[0]}: no worker "
                                "for 2 s (--worker-timeout-s)"), err
    assert "--resume" in lines[-1] and "--worker-timeout-s 2" in lines[-1], err
    assert not out.exists() and list(parts_folder(out).glob("g*.npz"))


@pytest.mark.slow
def test_a_lost_scheduler_is_one_line_naming_the_option_and_the_resume(cluster, tmp_path,
                                                                      monkeypatch, capsys):
    rc, err, out = _run_killing(cluster, "scheduler", tmp_path, monkeypatch, capsys)
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert rc == 2 and "Traceback" not in err, err
    assert len(lines) == 1 and lines[0].startswith(
        f"lusm explore: error: --scheduler {cluster[0]}: lost the connection to the dask "
        "scheduler"), err
    assert f"--out {out} --scheduler {cluster[0]} --resume" in lines[0], err
    assert not out.exists() and list(parts_folder(out).glob("g*.npz"))


@pytest.mark.slow
def test_optimize_waits_for_a_lost_worker_within_the_bound(cluster, tmp_path, monkeypatch,
                                                           capsys):
    rc, err, out = _run_killing(cluster, "worker", tmp_path, monkeypatch, capsys,
                                ("--worker-timeout-s", "2", "--seed", "4"), "optimize")
    lines = [ln for ln in err.splitlines() if ln.strip() and "lusm optimize" in ln]
    assert rc == 2 and "Traceback" not in err, err
    assert "lusm optimize: warning: no worker for 1 s; waiting for the cluster to recover " \
           "(Ctrl-C keeps the parts for --resume)" in lines, err
    assert lines[-1].startswith(f"lusm optimize: error: --scheduler {cluster[0]}: no worker "
                                "for 2 s (--worker-timeout-s); the cluster did not recover; "
                                "1 evaluated design is kept in "), err
    assert lines[-1].endswith(f"--out {out} --scheduler {cluster[0]} --seed 4 "
                              "--worker-timeout-s 2 --resume"), err
    assert not out.exists() and len(list(parts_folder(out).glob("g*.npz"))) == 1


@pytest.mark.slow
@pytest.mark.benchmark  # the watcher explore's scheduler test checks, on its own cluster
def test_optimize_says_a_lost_scheduler_in_one_line_with_the_resume(cluster, tmp_path,
                                                                    monkeypatch, capsys):
    rc, err, out = _run_killing(cluster, "scheduler", tmp_path, monkeypatch, capsys,
                                command="optimize")
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert rc == 2 and "Traceback" not in err, err
    assert len(lines) == 1 and lines[0].startswith(
        f"lusm optimize: error: --scheduler {cluster[0]}: lost the connection to the dask "
        "scheduler"), err
    assert lines[0].endswith(f"--out {out} --scheduler {cluster[0]} --resume"), err
    assert not out.exists() and list(parts_folder(out).glob("g*.npz"))
