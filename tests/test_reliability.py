"""How every ``lusm`` command ends: work bounds, warnings, valid JSON, exit codes 1, 2 and 130,
signals, the library's refusals said in the options' terms, exports built aside, unreadable
inputs. The bad-input tables of each command are in ``tests/test_bad_input.py``."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from bounds import ParameterError, Words
from contact.errors import ChatteringError
from lusm.cli import main
from tests.conftest import ROOT


def test_work_bounds_can_be_raised_on_purpose(monkeypatch, capsys):
    # 2.5e7 steps: above the default bound, allowed with LUSM_MAX_WORK=2 (checked, not run)
    from lusm.options import check_run_size

    with pytest.raises(ValueError, match="LUSM_MAX_WORK"):
        check_run_size(0.05, 2e-9, 40e3)
    monkeypatch.setenv("LUSM_MAX_WORK", "2")
    assert check_run_size(0.05, 2e-9, 40e3) == 25_000_000
    # a bad factor is the variable's fault, even when an option's bound would have used it
    # first (it was blamed on --refine), and a huge one is refused, not an OverflowError
    for value in ["lots", "0", "1e308", "inf"]:
        monkeypatch.setenv("LUSM_MAX_WORK", value)
        for argv in (["params"], ["modes", "--refine", "3"]):
            assert main(argv) == 2
            err = capsys.readouterr().err.strip()
            assert err.startswith("lusm: error: LUSM_MAX_WORK must be a number in "
                                  "[1, 1000000]"), err
            assert len(err.splitlines()) == 1 and repr(value) in err


def test_warnings_where_the_model_stops_meaning_anything(capsys):
    from lusm.options import check_plate_mm, warn_drive

    check_plate_mm(30.0, 7.5, 20.0, 0.5, three_d=True)  # the 3D model has no such limit
    warn_drive(0.0, 0.0, load_N=0.1)  # the load pushes the slider: it moves
    assert capsys.readouterr().err == ""
    check_plate_mm(30.0, 7.5, 20.0, 0.5)
    warn_drive(900.0, 300.0)
    warn_drive(0.0, 0.0)
    err = capsys.readouterr().err
    assert "plane-stress" in err and "--thickness-mm 20" in err
    assert "--voltage 900" in err and "--preload 300" in err
    assert "nothing moves" in err


def test_json_is_valid_without_infinity(capsys):
    import json

    from lusm.options import print_json

    print_json({"a": float("inf"), "b": [float("nan"), 1.0], "c": np.float64(2.0)})
    text = capsys.readouterr().out
    assert json.loads(text) == {"a": None, "b": [None, 1.0], "c": 2.0}


def test_an_unexpected_error_is_one_line_exit_1(monkeypatch, capsys):
    import lusm.commands.params as cmd

    def boom(args):
        raise ZeroDivisionError("division by zero")

    monkeypatch.setattr(cmd, "run", boom)  # a bug in a command
    assert main(["params"]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "ZeroDivisionError" in err and "please report" in err and "LUSM_DEBUG" in err


@pytest.mark.slow
def test_sigterm_removes_the_staging_folder(tmp_path):
    out = tmp_path / "r"
    proc = subprocess.Popen([sys.executable, "-m", "lusm.cli", "report", "--quick",
                             "--no-progress", "--out", str(out)], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not list(tmp_path.glob(".*partial*")):
        time.sleep(0.05)
    assert list(tmp_path.glob(".*partial*")), "the report did not start staging"
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err
    assert list(tmp_path.iterdir()) == []  # no staging folder, no half report


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_python_swallows_still_stops_the_command(signum, monkeypatch, tmp_path,
                                                           capsys):
    # A handler that runs inside a __del__ or weakref callback (importlib's module locks have
    # one) cannot propagate its exception: Python prints "Exception ignored" and carries on.
    import lusm.commands.params as cmd
    from lusm.output_set import output_set

    class SignalOnCollect:
        def __del__(self):
            signal.raise_signal(signum)

    def command(args):
        with output_set(tmp_path / "out") as stage:
            (stage / "a.png").write_bytes(b"x")
            obj = SignalOnCollect()
            del obj  # the signal's exception is swallowed here
            (stage / "b.png").write_bytes(b"y")  # so the command goes on

    monkeypatch.setattr(cmd, "run", command)
    assert main(["params"]) == 130
    err = capsys.readouterr().err  # Python's own "Exception ignored" report, then the line
    assert err.strip().splitlines()[-1] == "lusm params: interrupted"
    assert list(tmp_path.iterdir()) == []  # nothing moved in, no staging folder left
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
def test_an_error_caused_by_a_signal_is_the_interruption(monkeypatch, tmp_path, capsys):
    # a signal landing inside a numba call comes back from the dispatcher as "SystemError:
    # ... returned a result with an exception set" (seen with Ctrl-C in lusm characteristic):
    # the command must end as interrupted (130), not as an internal error (1)
    import lusm.commands.params as cmd
    from lusm.output_set import output_set

    class SignalOnCollect:
        def __del__(self):
            signal.raise_signal(signal.SIGTERM)

    def command(args):
        with output_set(tmp_path / "out") as stage:
            (stage / "a.png").write_bytes(b"x")
            obj = SignalOnCollect()
            del obj
            raise SystemError("CPUDispatcher(...) returned a result with an exception set")

    monkeypatch.setattr(cmd, "run", command)
    assert main(["params"]) == 130
    assert capsys.readouterr().err.strip().splitlines()[-1] == "lusm params: interrupted"
    assert list(tmp_path.iterdir()) == []


def test_debug_env_shows_the_traceback():
    env = {**os.environ, "LUSM_DEBUG": "1"}
    proc = subprocess.run([sys.executable, "-m", "lusm.cli", "simulate", "--voltage",
                           "200", "--preload", "14", "--dt", "1e-13"], cwd=ROOT,
                          capture_output=True, text=True, env=env, timeout=120)
    assert proc.returncode != 0 and "Traceback" in proc.stderr


def test_library_errors_are_mapped_to_the_option_that_sets_them():
    from fem.geometry import PlateStator
    from lusm.errors import LusmError, user_error

    with pytest.raises(ParameterError) as info:  # a ValueError still, for library callers
        PlateStator(length_m=-1.0)
    e = user_error(info.value)
    assert isinstance(e, LusmError) and e.option == "--length-mm"
    assert str(e) == "--length-mm must be in (0, 10000] mm, got -1000"  # the option's mm
    e = user_error(FileNotFoundError(2, "No such file or directory", "/x/y.png"))
    assert str(e) == "cannot use /x/y.png: No such file or directory"
    e = user_error(UnicodeDecodeError("utf-8", b"\xff", 0, 1, "invalid start byte"))
    assert "UTF-8" in str(e) and "byte 0" in str(e)


def test_a_parameter_error_pickles_with_its_fields():
    """A dask worker's refusal reaches the client whole: its class, message and fields."""
    import pickle

    exc = ParameterError("dt_s", 1e-7, 0.0, 8.5e-10, "s", low_open=True, reason="r")
    back = pickle.loads(pickle.dumps(exc))
    assert type(back) is ParameterError and str(back) == str(exc)
    assert (back.name, back.value, back.high, back.low_open) == ("dt_s", 1e-7, 8.5e-10, True)


@pytest.mark.slow
def test_an_export_is_moved_in_complete(tmp_path, capsys):
    out = tmp_path / "new" / "m.vtu"
    assert main(["modes", "--refine", "2", "--export", str(out)]) == 0
    assert out.is_file() and sorted(p.name for p in out.parent.iterdir()) == ["m.vtu"]
    capsys.readouterr()
    assert main(["modes", "--refine", "2", "--export", str(out)]) == 2  # not overwritten
    assert "already exists" in capsys.readouterr().err
    first = out.read_bytes()
    assert main(["modes", "--refine", "2", "--export", str(out), "--force"]) == 0
    assert sorted(p.name for p in out.parent.iterdir()) == ["m.vtu", "m.vtu.bak-1"]
    assert (out.parent / "m.vtu.bak-1").read_bytes() == first  # --force keeps the old file


def test_an_export_with_a_long_file_name_is_written(tmp_path):
    # a 244-byte name, which the file system takes, failed after the solve: its staging
    # folder ".NAME-partial-XXXXXXXX" went over the 255-byte limit ("File name too long")
    out = tmp_path / ("f" * 240 + ".vtu")
    assert main(["modes", "--refine", "2", "--export", str(out)]) == 0
    assert out.is_file() and [p.name for p in tmp_path.iterdir()] == [out.name]


@pytest.mark.parametrize("exc, code, words", [
    (ChatteringError("contact chattering: more switches than allowed within one step",
                     step_remedy=True), 2, ["error: contact chattering", "smaller --dt"]),
    (ChatteringError("contact chattering in the full-model shooting"), 2,
     ["error: contact chattering in the full-model shooting"]),
    (RuntimeError("f(a) and f(b) must have different signs"), 1,
     ["RuntimeError", "please report"]),
])
def test_the_kernels_refusal_is_bad_input_but_other_runtime_errors_are_bugs(
        exc, code, words, monkeypatch, capsys):
    # the kernel's chattering is a property of the operating point (exit 2, one line); any
    # other RuntimeError from the library (a SciPy root finder giving up) is not the user's
    import contact.simulate

    def refuse(*args, **kwargs):
        raise exc

    monkeypatch.setattr(contact.simulate, "simulate", refuse)
    assert main(["simulate", "--voltage", "200", "--preload", "14"]) == code
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and all(w in err for w in words), err
    assert "max_events_per_step" not in err and "dt_s" not in err  # the CLI's words only


@pytest.mark.parametrize("exc, code, last", [
    (KeyboardInterrupt(), 130, "lusm params: interrupted"),
    (ParameterError("voltage_V", float("nan"), 0.0, None, "V"), 2,
     "lusm params: error: --voltage must be a finite number >= 0 V, got nan"),
])
def test_the_last_line_is_its_own_after_an_open_progress_bar(exc, code, last, monkeypatch,
                                                             capsys):
    # a bar left open by an interrupted loop has no line end: the command's one line was
    # printed after its text (seen with Ctrl-C during lusm map)
    from tqdm import tqdm

    import lusm.commands.params as cmd

    def command(args):
        bar = tqdm(total=10, desc="work", file=sys.stderr)
        bar.update(3)
        raise exc

    monkeypatch.setattr(cmd, "run", command)
    assert main(["params"]) == code
    err = capsys.readouterr().err
    assert err.endswith("\n") and err.splitlines()[-1] == last


def test_a_ctrl_c_before_the_command_starts_is_one_line(monkeypatch, capsys):
    # Ctrl-C during the first fraction of a second (imports, the BLAS probe, parsing) printed
    # a KeyboardInterrupt traceback: it is the same interruption as later on
    import lusm.cli as cli

    def interrupted():
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "build_parser", interrupted)
    assert main(["params"]) == 130
    assert capsys.readouterr().err.strip() == "lusm params: interrupted"


def test_library_warnings_are_one_line_naming_the_command(capsys):
    # the 2D model's validity warning came out in Python's form: the library's file and line,
    # the warning's class, then the statement that raised it
    from fem.model import clear_model_cache

    clear_model_cache()  # the warning comes with the model's assembly (test_beam's is cached)
    assert main(["params", "--source", "fem", "--gap-mm", "2"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert err and all(line.startswith("lusm params: warning: ") for line in err), err
    assert any("electrode gap 2 mm exceeds thickness/6" in line for line in err)
    assert not any("GapValidityWarning" in line or ".py:" in line for line in err)


def test_an_export_into_a_folder_it_cannot_write_names_the_users_file(tmp_path, monkeypatch,
                                                                      capsys):
    # the message named the staging folder's random name (".m.vtu-partial-xxxx")
    real_mkdir = os.mkdir

    def denied(path, *args, **kwargs):  # only the staging folder: its parent is made first
        if os.path.basename(path).startswith(".m.vtu-partial-"):
            raise PermissionError(13, "Permission denied", path)
        return real_mkdir(path, *args, **kwargs)

    monkeypatch.setattr(os, "mkdir", denied)
    out = tmp_path / "ro" / "m.vtu"
    assert main(["modes", "--refine", "2", "--export", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"lusm modes: error: --export {out}: cannot write there (Permission denied)"


@pytest.mark.slow
def test_an_export_that_cannot_be_written_whole_is_refused_and_leaves_nothing(tmp_path):
    """Under a file-size limit meshio's XDMF writer lost its HDF5 writes in h5py's
    finalizers: tracebacks, "wrote m.xdmf", exit 0, and a truncated m.h5 moved in that meshio
    cannot read. The limit is set in the child (Python ignores SIGXFSZ: writes fail EFBIG)."""
    out = tmp_path / "x" / "m.xdmf"
    code = ("import resource; resource.setrlimit(resource.RLIMIT_FSIZE, (30720, 30720)); "
            "from lusm.cli import main; raise SystemExit(main(['modes', '--refine', '2', "
            f"'--export', {str(out)!r}]))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       cwd=ROOT, timeout=300)
    assert r.returncode == 2, r.stderr
    assert r.stderr.strip().splitlines() == [
        f"lusm modes: error: --export: cannot write {out} whole (File too large)"]
    assert not out.parent.exists() or list(out.parent.iterdir()) == []


def test_an_export_into_a_folder_it_cannot_write_is_refused_before_the_solve(tmp_path,
                                                                             monkeypatch,
                                                                             capsys):
    # it was refused only after the FE solve (30 s of a 3D model)
    import fem.modes

    def no_solve(*args, **kwargs):
        raise AssertionError("solved before checking the export's folder")

    monkeypatch.setattr(fem.modes, "plate_modes", no_solve)
    monkeypatch.setattr(os, "access", lambda path, mode: False)
    out = tmp_path / "m.vtu"
    assert main(["modes", "--export", str(out)]) == 2
    assert capsys.readouterr().err.strip() == (
        f"lusm modes: error: --export {out}: cannot write into {tmp_path} (permission denied)")


def test_a_report_that_cannot_be_written_names_its_folder(tmp_path, monkeypatch, capsys):
    """A file-size limit while the report's set was written said "cannot use: File too
    large", naming neither --out nor the folder (the other commands say both)."""
    import errno

    import validation.report

    def full(out, **kwargs):
        raise OSError(errno.EFBIG, os.strerror(errno.EFBIG))

    monkeypatch.setattr(validation.report, "write_report", full)
    out = tmp_path / "r"
    assert main(["report", "--out", str(out)]) == 2
    assert capsys.readouterr().err.strip() == (
        f"lusm report: error: --out {out}: cannot write (File too large)")


@pytest.mark.parametrize("exc, said", [
    # the range in the option's units, the library's reason after it
    (ParameterError("frequency_Hz", 1.0, 2e4, None, "Hz", reason="the fastest mode"),
     "--frequency must be >= 20000 Hz, got 1 (the fastest mode)"),
    (ParameterError("dt_s", 1e-7, 0.0, 8.5e-10, "s", low_open=True),
     "--dt must be in (0, 8.5e-10] s, got 1e-07"),
    (ParameterError("electrode_gap_m", 0.01, 0.0, 0.0075, "m", high_open=True),
     "--gap-mm must be in [0, 7.5) mm, got 10"),
    (ParameterError("voltage_V", float("nan"), 0.0, None, "V"),
     "--voltage must be a finite number >= 0 V, got nan"),
    # no range (a work bound): the library's words after the option, its assignment named
    (ParameterError("refine", 8, message=Words("{refine}", refine="8") + " makes 3e+04 elements"),
     "--refine 8 makes 3e+04 elements"),
    (ParameterError("layers", 9, message="too many bricks"), "--layers: too many bricks"),
    # a parameter no option sets, and a plain ValueError: the library's line
    (ParameterError("mu_d", 2.0, 0.0, 1.0), "mu_d must be in [0, 1], got 2.0"),
    (ValueError(Words("{load_N}: no steady state from rest", load_N="50 N")),
     "--load-N 50 N: no steady state from rest"),
    (ValueError("check the plate and --refine"), "check the plate and --refine"),
])
def test_library_refusals_are_said_with_the_options_the_user_typed(exc, said):
    from lusm.errors import user_error

    assert str(user_error(exc)) == said


@pytest.mark.parametrize("argv, option", [
    (["modes", "--geometry", ""], "--geometry"), (["params", "--geometry", ""], "--geometry"),
    (["modes", "--export", ""], "--export"),
    (["simulate", "--voltage", "200", "--preload", "14", "--params", ""], "--params"),
])
def test_an_empty_path_is_refused_not_read_as_not_given(argv, option, capsys):
    # "" ran the default plate (and --export "" wrote nothing) with exit 0
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert f"{option} must name" in err and len(err.splitlines()) == 1


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs named pipes")
@pytest.mark.parametrize(("option", "argv", "said"), [
    ("--geometry", ["modes", "--geometry"], "is a FIFO (named pipe), not a TOML file"),
    ("--params", ["simulate", "--voltage", "200", "--preload", "14", "--params"],
     "not a regular file (a FIFO (named pipe))"),
])
def test_a_named_pipe_given_as_an_input_file_is_refused_at_once(tmp_path, capsys, option,
                                                                 argv, said):
    # a stator file named by a FIFO was "stator file not found" (it exists); the one reader
    # of small input files (fem.small_file) opens nothing that could block and says what the
    # path is. A writer is never attached: a reader that opened the pipe would wait for ever
    fifo = tmp_path / "in.toml"
    os.mkfifo(fifo)
    assert main([*argv, str(fifo)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and option in err[0] and said in err[0]


def test_the_small_file_reader_checks_what_it_reads_not_only_the_size_reported(tmp_path):
    # /proc files report size 0 and yield more: the cap holds on the bytes read
    from fem.small_file import FileTooLarge, read_small_text

    proc = Path("/proc/self/maps")
    if not proc.exists() or proc.stat().st_size != 0:
        pytest.skip("needs a file whose reported size is 0 and whose content is not")
    with pytest.raises(FileTooLarge):
        read_small_text(proc, 10)
    (tmp_path / "ok.toml").write_bytes("\ufeffname = 'x'\n".encode())
    assert read_small_text(tmp_path / "ok.toml", 100) == "name = 'x'\n"


@pytest.mark.slow
def test_a_ctrl_c_after_the_command_is_done_is_ignored():
    # a Ctrl-C during the interpreter's shutdown, right after lusm modes or lusm render had
    # printed their last line, printed a KeyboardInterrupt traceback from threading._shutdown
    # and exited 0: once the command is done, SIGINT is ignored to the end of the process
    code = ("import signal, sys\n"
            "from lusm.cli import main\n"
            "sys.argv = ['lusm', 'params', '--json']\n"
            "rc = main()\n"
            "print(signal.getsignal(signal.SIGINT) is signal.SIG_IGN)\n"
            "sys.exit(rc)\n")
    run = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 0 and run.stdout.strip().splitlines()[-1] == "True"


_ENDED = [["params", "--json"], ["simulate", "--voltage", "-1"]]
"""A command that ends 0 (with its output on stdout) and one refused (2)."""


def _after_main(argv: list[str], then: str) -> subprocess.CompletedProcess:
    """A Python process that runs ``lusm ARGV`` through ``main()``, then the code ``then``
    (with ``os``, ``signal``, ``subprocess``, ``sys``, ``time``, ``atexit`` imported), then
    exits with the command's code."""
    code = ("import atexit, os, signal, subprocess, sys, time\n"
            "from lusm.cli import main\n"
            f"sys.argv = ['lusm', *{argv!r}]\n"
            "rc = main()\n" + then + "sys.exit(rc)\n")
    return subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)


@pytest.mark.parametrize("argv", _ENDED)
def test_a_sigterm_after_the_command_has_ended_keeps_its_exit_code(argv):
    """A SIGTERM landing after the command had moved its output in and printed its last
    line killed the process with exit 143 and no word (3 of 30 late SIGTERMs to lusm
    simulate --plot; exploratory testing): the command's end is said, and its exit code
    (0 done, 2 refused) stays, with what it printed. Here the signal is sent after main()
    returned, where the interpreter's shutdown would run: it ends the process there."""
    import json

    run = _after_main(argv, "os.kill(os.getpid(), signal.SIGTERM)\n"
                            "print('still here')\n")
    assert run.returncode == (0 if argv[0] == "params" else 2), run.stderr
    assert "still here" not in run.stdout  # ended by the signal, not by running on
    if argv[0] == "params":  # its JSON, still in Python's buffer at the signal, is kept
        assert json.loads(run.stdout)
    else:
        assert "lusm simulate: error: " in run.stderr


@pytest.mark.parametrize("argv", _ENDED)
@pytest.mark.slow
def test_a_sigterm_ends_a_hung_clean_up_with_the_commands_exit_code(argv):
    """Once the command had ended SIGTERM was ignored to the process's exit, so a clean-up
    that hung (explore's cluster shutdown, an exit hook) could be stopped by SIGKILL alone
    (review). Here an exit hook hangs and a child process sends SIGTERM: the process ends
    at once, with the command's exit code."""
    code = ("def hang():\n"
            "    subprocess.Popen([sys.executable, '-c', 'import os, signal, time; '\n"
            "                      f'time.sleep(0.5); os.kill({os.getpid()}, signal.SIGTERM)'])\n"
            "    print('clean-up hangs', file=sys.stderr, flush=True)\n"
            "    time.sleep(600)\n"
            "    print('clean-up done', file=sys.stderr)\n"
            "atexit.register(hang)\n")
    # the hook sleeps 600 s: a SIGTERM that does not end it fails here, by the timeout
    run = _after_main(argv, code)
    assert run.returncode == (0 if argv[0] == "params" else 2), run.stderr
    assert "clean-up hangs" in run.stderr and "clean-up done" not in run.stderr


def test_unreadable_inputs_are_named_as_such(tmp_path, capsys):
    # a dangling study link said "cannot use dangling: No such file or directory"; a
    # non-UTF-8 --params file quoted Python's codec message
    link = tmp_path / "study.toml"
    link.symlink_to(tmp_path / "missing.toml")
    assert main(["explore", str(link), "--out", str(tmp_path / "o.nc")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no such study file (a symbolic link to a missing file)" in err[0]
    bad = tmp_path / "p.json"
    bad.write_bytes(b"\xff\xfe{}")
    assert main(["simulate", "--voltage", "200", "--preload", "14", "--params", str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--params" in err[0] and "not UTF-8 text (byte 0" in err[0]
    assert "codec" not in err[0]


def test_an_export_path_ending_in_a_separator_names_a_folder(tmp_path, capsys):
    """``--export out/dd.vtu/`` names a folder: it had been written as the file dd.vtu (the
    trailing separator is dropped by pathlib). It is refused before any work, and nothing is
    made."""
    target = tmp_path / "out" / "dd.vtu"
    for tail in ("/", "/."):  # pathlib drops a trailing '.' as well (review)
        assert main(["modes", "--refine", "1", "--export", f"{target}{tail}"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--export" in err[0] and "is a folder" in err[0]
        assert not (tmp_path / "out").exists()
