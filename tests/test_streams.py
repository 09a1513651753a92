"""The standard streams a shell hands ``lusm`` (issue 42): a closed or full standard output
or error is one clear line on the stream that still works, or exit code 2 alone; never a
warning in the middle of ``--json``."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from lusm.cli import main

WARNS = ["params", "--source", "beam", "--material", "paper", "--json"]
"""A command that warns (--material has no effect on the beam) and prints JSON, in
milliseconds."""


def test_a_closed_stderr_keeps_the_warnings_out_of_the_json(monkeypatch, capsys):
    monkeypatch.setattr(sys, "stderr", None)  # what Python makes of 2>&-
    assert main(WARNS) == 0
    out = capsys.readouterr().out
    json.loads(out)  # no warning line inside it
    assert "warning" not in out


def test_a_closed_stdout_is_refused_in_one_line_before_any_work(monkeypatch, capsys):
    monkeypatch.setattr(sys, "stdout", None)  # what Python makes of >&-
    assert main(["modes", "--json", "--refine", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("lusm modes: error: standard output is "
                                                   "closed"), err


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_a_full_stdout_is_named_as_standard_output(monkeypatch, capsys):
    with open("/dev/full", "w") as full:
        monkeypatch.setattr(sys, "stdout", full)
        assert main(["params", "--json"]) == 2
        monkeypatch.undo()
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(
        "lusm params: error: cannot write standard output: No space left on device"), err


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_a_full_stderr_leaves_the_exit_code_alone(monkeypatch, capsys):
    full = open("/dev/full", "w", buffering=1)  # noqa: SIM115 - closed below, failing
    monkeypatch.setattr(sys, "stderr", full)
    assert main(WARNS) == 0  # its warning's write fails: not an error of the command
    assert main(["params", "--source", "beam", "--no-such-option"]) == 2
    monkeypatch.undo()
    with pytest.raises(OSError):
        full.close()  # what it still holds cannot be written
    json.loads(capsys.readouterr().out)


@pytest.mark.skipif(os.name != "posix", reason="needs a POSIX shell")
def test_closed_descriptors_from_a_shell(tmp_path):
    """The real thing: descriptors closed by the shell (a file the command opened had taken
    number 2, and Python's stderr was None)."""
    lusm = [sys.executable, "-m", "lusm"]
    cmd = " ".join(lusm)
    run = subprocess.run(["sh", "-c", f"{cmd} {' '.join(WARNS)} 2>&-"], capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 0 and json.loads(run.stdout), run
    run = subprocess.run(["sh", "-c", f"{cmd} params --json >&-"], capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 2 and "standard output is closed" in run.stderr, run
