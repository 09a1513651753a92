"""Output sets never delete or overwrite a file lusm did not write, and never half-write."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from lusm.output_set import MARKER, OutputError, output_set
from tests.conftest import ROOT


def _write(stage: Path, files: dict[str, str]) -> None:
    for rel, text in files.items():
        (stage / rel).parent.mkdir(parents=True, exist_ok=True)
        (stage / rel).write_text(text)


def _snapshot(folder: Path) -> dict[str, str]:
    return {p.relative_to(folder).as_posix(): p.read_text()
            for p in folder.rglob("*") if p.is_file() and p.name != MARKER}


def test_new_folder_gets_the_set_and_a_marker(tmp_path):
    out = tmp_path / "a" / "b"
    with output_set(out, "report") as stage:
        _write(stage, {"index.md": "1", "figures/f.png": "x"})
    assert _snapshot(out) == {"index.md": "1", "figures/f.png": "x"}
    assert (out / MARKER).exists()
    assert [p.name for p in tmp_path.rglob(".*partial*")] == []


def test_a_report_replaces_only_its_own_files(tmp_path):
    out = tmp_path / "r"
    with output_set(out, "report") as stage:
        _write(stage, {"index.md": "old", "figures/old.png": "o", "figures/keep.png": "k"})
    (out / "figures" / "mine.txt").write_text("user")  # the user's file inside a report
    (out / "notes.md").write_text("user notes")
    with output_set(out, "report") as stage:
        _write(stage, {"index.md": "new", "figures/keep.png": "k2"})
    # the earlier set's figure the new one does not write is kept, not deleted
    assert _snapshot(out) == {"index.md": "new", "figures/keep.png": "k2",
                              "figures/old.png": "o",
                              "figures/mine.txt": "user", "notes.md": "user notes"}


def test_an_earlier_sets_file_stays_lusms_to_replace(tmp_path):
    # a sweep over length, then one over width, then length again: both figures are kept,
    # and the third run replaces the first one's figure without a backup (it is unchanged)
    out = tmp_path / "s"
    for axis, text in [("length", "L1"), ("width", "W"), ("length", "L2")]:
        with output_set(out, "figures") as stage:
            _write(stage, {f"sweep_{axis}.png": text})
    assert _snapshot(out) == {"sweep_length.png": "L2", "sweep_width.png": "W"}


def test_a_file_the_user_edited_is_kept_as_a_backup(tmp_path, capsys):
    out = tmp_path / "r"
    with output_set(out, "figures") as stage:
        _write(stage, {"B2.png": "lusm", "sub/a.txt": "lusm"})
    (out / "B2.png").write_text("annotated by the user")
    with output_set(out, "figures") as stage:
        _write(stage, {"B2.png": "new", "sub/a.txt": "new"})
    assert _snapshot(out) == {"B2.png": "new", "B2.png.bak-1": "annotated by the user",
                              "sub/a.txt": "new"}
    assert "B2.png.bak-1" in capsys.readouterr().err


def test_a_marker_without_hashes_never_costs_a_file(tmp_path):
    # a marker from before hashes were recorded cannot tell an edit: the old file is kept
    out = tmp_path / "r"
    _write(out, {"B2.png": "maybe edited", MARKER: '{"kind": "figures", "files": ["B2.png"]}'})
    with output_set(out, "figures") as stage:
        _write(stage, {"B2.png": "new"})
    assert _snapshot(out) == {"B2.png": "new", "B2.png.bak-1": "maybe edited"}


@pytest.mark.parametrize("entry", ["../victim.txt", "ABSOLUTE", "sub/../../victim.txt",
                                   "link/victim.txt", "", ".", "./B2.png"])
def test_a_planted_marker_cannot_reach_outside_the_folder(tmp_path, entry):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    out = tmp_path / "r"
    out.mkdir()
    (out / "link").symlink_to(tmp_path, target_is_directory=True)
    name = str(victim) if entry == "ABSOLUTE" else entry
    (out / MARKER).write_text(json.dumps({"kind": "figures", "files": [name, "B2.png"]}))
    with output_set(out, "figures", force=True) as stage:
        _write(stage, {"B2.png": "new", "victim.txt": "new"})
    assert victim.read_text() == "precious"
    assert (out / "victim.txt").read_text() == "new"


def test_a_folder_that_is_not_a_report_is_refused_and_left_alone(tmp_path):
    out = tmp_path / "mine"
    _write(out, {"index.md": "my index", "figures/plot.png": "my plot"})
    before = _snapshot(out)
    with pytest.raises(OutputError, match="--out .* did not write.*--force"):
        with output_set(out, "report") as stage:
            _write(stage, {"index.md": "report"})
    assert _snapshot(out) == before


def test_force_keeps_colliding_user_files_as_backups(tmp_path):
    out = tmp_path / "mine"
    _write(out, {"index.md": "my index", "figures/plot.png": "my plot"})
    with output_set(out, "report", force=True) as stage:
        _write(stage, {"index.md": "report", "figures/f.png": "fig"})
    snap = _snapshot(out)
    assert snap["index.md"] == "report" and snap["index.md.bak-1"] == "my index"
    assert snap["figures/plot.png"] == "my plot" and snap["figures/f.png"] == "fig"


def test_a_failure_leaves_the_folder_and_its_parents_as_they_were(tmp_path):
    out = tmp_path / "new" / "nested"
    with pytest.raises(RuntimeError):
        with output_set(out, "report") as stage:
            _write(stage, {"index.md": "half"})
            raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []  # no parent folders, no staging folder


@pytest.mark.parametrize("make", ["file", "below_file"])
def test_a_file_where_the_folder_should_be_is_refused(tmp_path, make):
    f = tmp_path / "f"
    f.write_text("keep")
    out = f if make == "file" else f / "sub"
    with pytest.raises(OutputError, match="--out must be a folder"):
        with output_set(out, "report"):
            pass
    assert f.read_text() == "keep"


def test_lusm_report_refuses_a_users_folder_before_any_work(tmp_path):
    (tmp_path / "figures").mkdir()
    (tmp_path / "figures" / "precious.png").write_bytes(b"mine")
    (tmp_path / "index.md").write_text("my notes")
    proc = subprocess.run([sys.executable, "-m", "lusm.cli", "report", "--quick",
                           "--no-progress", "--out", str(tmp_path)],
                          cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert "--out" in proc.stderr and "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert (tmp_path / "figures" / "precious.png").read_bytes() == b"mine"
    assert (tmp_path / "index.md").read_text() == "my notes"


def test_a_marker_that_is_a_link_is_never_written_through(tmp_path):
    # the marker was written into the link's target: the user's file became lusm's JSON
    precious = tmp_path / "precious.txt"
    precious.write_text("precious")
    out = tmp_path / "o"
    out.mkdir()
    (out / MARKER).symlink_to(precious)
    with pytest.raises(OutputError, match="did not write"):  # not lusm's marker
        with output_set(out, "figures") as stage:
            _write(stage, {"a.png": "x"})
    with output_set(out, "figures", force=True) as stage:
        _write(stage, {"a.png": "x"})
    assert precious.read_text() == "precious"
    assert (out / f"{MARKER}.bak-1").is_symlink() and not (out / MARKER).is_symlink()


def test_a_marker_listing_nothing_usable_is_refused_before_any_work(tmp_path):
    from lusm.output_set import check_target

    out = tmp_path / "o"
    _write(out, {"admittance.png": "mine",
                 MARKER: json.dumps({"kind": "admittance", "files": [1, "../x"]})})
    with pytest.raises(OutputError, match="did not write"):
        check_target(out, "admittance")


def test_a_link_to_a_folder_is_written_through_and_a_dangling_one_refused(tmp_path):
    # a link to an empty folder failed after the work ("cannot write (Not a directory)")
    from lusm.output_set import check_target

    (tmp_path / "real").mkdir()
    (tmp_path / "link").symlink_to(tmp_path / "real", target_is_directory=True)
    with output_set(tmp_path / "link", "figures") as stage:
        _write(stage, {"a.png": "x"})
    assert _snapshot(tmp_path / "real") == {"a.png": "x"}
    assert (tmp_path / "link").is_symlink()
    (tmp_path / "dangling").symlink_to(tmp_path / "nowhere")
    with pytest.raises(OutputError, match="does not exist"):
        check_target(tmp_path / "dangling", "figures")


def test_another_commands_folder_is_named_as_such(tmp_path):
    # "a folder that lusm characteristic did not write" read as if lusm had not written it
    from lusm.output_set import check_target

    out = tmp_path / "figs"
    with output_set(out, "simulate") as stage:
        _write(stage, {"fig9.png": "x"})
    with pytest.raises(OutputError, match="holds the output of lusm simulate, not of lusm "
                                          "characteristic"):
        check_target(out, "characteristic", "--plot")


def test_a_subfolder_that_is_a_link_is_kept_aside_whole_with_force(tmp_path):
    # report --force into a report whose figures/ was a link to another folder: the link was
    # kept aside, then figures/a.png (reached through it) could not be, and the new set was
    # lost halfway with the old index.md pointing nowhere
    elsewhere = tmp_path / "vf"
    _write(elsewhere, {"a.png": "old figure"})
    out = tmp_path / "o"
    _write(out, {"index.md": "old"})
    (out / "figures").symlink_to(elsewhere)
    with output_set(out, "report", force=True) as stage:
        _write(stage, {"index.md": "new", "figures/a.png": "new figure"})
    assert (out / "index.md").read_text() == "new"
    assert (out / "figures").is_dir() and not (out / "figures").is_symlink()
    assert (out / "figures" / "a.png").read_text() == "new figure"
    assert (out / "figures.bak-1").is_symlink()
    assert (elsewhere / "a.png").read_text() == "old figure"  # the user's folder untouched
    assert (out / "index.md.bak-1").read_text() == "old"


def test_an_empty_folder_stays_the_users_folder(tmp_path):
    """An existing empty folder was removed and the staging folder renamed in its place: its
    mode (a private 0700 folder came back 0755), group and inode were lost, and so was the
    shell's current folder. The files now move into it."""
    import os
    import stat

    out = tmp_path / "shared"
    out.mkdir()
    out.chmod(0o2750)
    before = out.stat()
    with output_set(out, "figures") as stage:
        _write(stage, {"a.png": "1", "sub/b.png": "2"})
    after = out.stat()
    assert (after.st_ino, stat.S_IMODE(after.st_mode)) == (before.st_ino,
                                                          stat.S_IMODE(before.st_mode))
    assert _snapshot(out) == {"a.png": "1", "sub/b.png": "2"} and (out / MARKER).exists()
    assert [p.name for p in tmp_path.rglob(".*partial*")] == []
    # the current folder, empty: the set lands in it (the staging folder had made it
    # non-empty, and the finished set was refused as "the current folder, which is not
    # empty")
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    old = os.getcwd()
    os.chdir(cwd)
    try:
        with output_set(Path("."), "figures", "--plot") as stage:
            _write(stage, {"c.png": "3"})
    finally:
        os.chdir(old)
    assert _snapshot(cwd) == {"c.png": "3"}


def test_a_users_file_named_like_the_marker_is_kept_under_force(tmp_path):
    """--force into the user's folder overwrote their own .lusm-output.json; and another
    command's marker (render's set written into sweep's folder) vanished with its list."""
    out = tmp_path / "d"
    out.mkdir()
    (out / MARKER).write_text("my data")
    with output_set(out, "sweep", force=True) as stage:
        _write(stage, {"s.png": "1"})
    assert (out / f"{MARKER}.bak-1").read_text() == "my data"
    assert json.loads((out / MARKER).read_text())["kind"] == "sweep"
    with output_set(out, "render", force=True) as stage:
        _write(stage, {"r.png": "2"})
    marker = json.loads((out / MARKER).read_text())
    assert marker["kind"] == "render" and set(marker["sets"]) == {"sweep", "render"}
    assert marker["sets"]["sweep"]["files"] == ["s.png"]


def test_another_commands_set_written_beside_keeps_both_lusms(tmp_path, capsys):
    """--force of one command's set into another's folder (a characteristic's PNG into a
    report) had kept the report's list aside as a .bak marker: the report's files were then
    no longer lusm's, and the next report refused the folder, or with --force kept each of
    its own files aside as .bak. Both sets are now recorded: each command replaces its own
    unchanged files cleanly and leaves the other's alone."""
    out = tmp_path / "rep"
    with output_set(out, "report") as stage:
        _write(stage, {"index.md": "r1", "figures/a.png": "a1"})
    with output_set(out, "characteristic", force=True) as stage:
        _write(stage, {"characteristic.png": "c1"})
    with output_set(out, "report") as stage:  # no --force needed: its own set is known
        _write(stage, {"index.md": "r2", "figures/a.png": "a2"})
    with output_set(out, "characteristic") as stage:
        _write(stage, {"characteristic.png": "c2"})
    assert _snapshot(out) == {"index.md": "r2", "figures/a.png": "a2",
                              "characteristic.png": "c2"}
    assert ".bak" not in capsys.readouterr().err
    # another command's file is not replaced without --force; with it, it is kept aside and
    # leaves the older set's list
    with pytest.raises(OutputError, match="already holds 'index.md'"):
        with output_set(out, "characteristic") as stage:
            _write(stage, {"index.md": "c's index"})
    with output_set(out, "characteristic", force=True) as stage:
        _write(stage, {"characteristic.png": "c3", "index.md": "c's index"})
    assert (out / "index.md.bak-1").read_text() == "r2"
    assert "index.md" not in json.loads((out / MARKER).read_text())["sets"]["report"]["files"]


def test_a_refusal_after_the_work_names_the_option_typed(tmp_path):
    """A user's file standing where a set in a folder lusm wrote wants to write: the
    refusal named --out when the user had typed --plot."""
    out = tmp_path / "m"
    with output_set(out, "figures", "--plot") as stage:
        _write(stage, {"a.png": "1"})
    (out / "b.png").write_text("mine")
    with pytest.raises(OutputError, match="^--plot "):
        with output_set(out, "figures", "--plot") as stage:
            _write(stage, {"a.png": "1", "b.png": "2"})
    assert (out / "b.png").read_text() == "mine"


_NO_FOLDER = Path("/proc/lusm-no-folder-here")  # /proc takes no new folder, even from root


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux's /proc")
def test_a_plot_folder_that_cannot_be_made_is_refused_before_the_study(tmp_path, capsys):
    """explore --plot /proc/maps ran the whole study, wrote the dataset and only then said
    the maps could not be written: the check had asked the permission bits, which root
    passes everywhere."""
    from lusm.cli import main

    study = tmp_path / "s.toml"
    study.write_text('outputs = ["split"]\n[axes]\nlength = ["29 mm", "30 mm"]\n'
                     '[solver]\nfe_refine = 1\n')  # a curve to draw
    out = tmp_path / "r.nc"
    assert main(["explore", str(study), "--out", str(out), "--workers", "1",
                 "--plot", str(_NO_FOLDER)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"lusm explore: error: --plot {_NO_FOLDER}: cannot write there")
    assert len(err.splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]  # no dataset, no parts


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux's /proc")
def test_render_refuses_an_out_that_cannot_be_made_before_any_fe_solve(monkeypatch, capsys):
    import fem.modes
    from lusm.cli import main

    def no_solve(*args, **kwargs):
        raise AssertionError("solved before the output folder was checked")

    monkeypatch.setattr(fem.modes, "plate_modes", no_solve)
    assert main(["render", "--out", str(_NO_FOLDER / "r")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"lusm render: error: --out {_NO_FOLDER / 'r'}: cannot write there")


def test_the_current_folder_lusm_wrote_is_written_again(tmp_path, monkeypatch, capsys):
    """``--plot .`` run twice: the second run was refused ("the current folder, which is not
    empty") though the folder was lusm's own set and ``--plot "$PWD"`` on it was accepted.
    '.' now follows the rules of its absolute name; the folder itself (the process's current
    folder) stays where it is, with the same inode: only files move into it."""
    import os

    from lusm.cli import main

    here = tmp_path / "dot"
    here.mkdir()
    monkeypatch.chdir(here)
    inode = here.stat().st_ino
    argv = ["characteristic", "--voltage", "400", "--preload", "14", "--accuracy", "fast",
            "--loads", "0:1:0.5"]
    for plot in [".", "./", ".", str(here)]:
        assert main([*argv, "--plot", plot]) == 0, capsys.readouterr().err
    assert sorted(os.listdir(here)) == [MARKER, "characteristic.png"]
    assert here.stat().st_ino == inode and Path.cwd() == here
    assert ".bak" not in capsys.readouterr().err  # lusm's unchanged file simply replaced
    assert [p.name for p in tmp_path.rglob(".*partial*")] == []


@pytest.mark.parametrize("typed", [".", "./", ""])
def test_the_current_folder_holding_the_users_files_is_refused(tmp_path, monkeypatch, typed):
    """The current folder that lusm did not write is still refused, saying which folder '.'
    is, and with --force the set is written beside the user's files, none of them lost."""
    from lusm.output_set import check_target

    monkeypatch.chdir(tmp_path)
    (tmp_path / "characteristic.png").write_text("mine")
    (tmp_path / "notes.txt").write_text("notes")
    with pytest.raises(OutputError, match=r"^--plot \. \(the current folder\) is a non-empty "
                                          r"folder that lusm characteristic did not write"):
        check_target(Path(typed), "characteristic", "--plot")
    with output_set(Path(typed), "characteristic", "--plot", force=True) as stage:
        _write(stage, {"characteristic.png": "new"})
    assert _snapshot(tmp_path) == {"characteristic.png": "new",
                                   "characteristic.png.bak-1": "mine", "notes.txt": "notes"}


# 250, 255 and 254 bytes: all names the file system takes
_LONG_NAMES = [pytest.param("a" * 250, id="a250"), pytest.param("a" * 255, id="a255"),
               pytest.param("é" * 127, id="e-acute127")]


@pytest.mark.parametrize("name", [pytest.param("r", id="r"), pytest.param("a" * 200, id="a200"),
                                  *_LONG_NAMES])
def test_a_staging_name_fits_the_file_systems_limit_and_stays_unique(tmp_path, name):
    import os
    import re

    from lusm.staging import staging_name

    a, b = (staging_name(name, "partial", tmp_path) for _ in range(2))
    assert a != b
    for s in (a, b):
        assert len(os.fsencode(s)) <= 255
        m = re.fullmatch(r"\.(.*)-partial-[0-9a-f]{12}", s)
        assert m and name.startswith(m.group(1)) and m.group(1)  # a cut of the name, kept
    if len(os.fsencode(name)) <= 255 - len(".-partial-") - 12:
        assert a.startswith(f".{name}-partial-")  # a name that fits is not cut


def test_a_staging_name_follows_a_smaller_limit(tmp_path, monkeypatch):
    # eCryptfs takes names of at most 143 bytes
    import os

    from lusm.staging import staging_name

    monkeypatch.setattr(os, "pathconf", lambda folder, what: 143)
    assert len(os.fsencode(staging_name("a" * 140, "probe", tmp_path))) == 143


@pytest.mark.parametrize("name", _LONG_NAMES)
@pytest.mark.parametrize("exists", [False, True])
def test_a_folder_with_a_long_name_is_written(tmp_path, name, exists):
    """A folder name of about 230 bytes or more, which the file system takes, was refused
    ("cannot write there (File name too long)"): the staging and probe names beside it,
    ``.NAME-partial-<12 hex>``, went over 255 bytes."""
    from lusm.output_set import check_target, check_writable

    out = tmp_path / name
    if exists:
        out.mkdir()
    for text in ("1", "2"):  # the second run replaces lusm's own set
        check_target(out, "figures", "--plot")
        check_writable(out, "--plot")
        with output_set(out, "figures", "--plot") as stage:
            _write(stage, {"a.png": text})
    assert _snapshot(out) == {"a.png": "2"}
    assert [p.name for p in tmp_path.iterdir()] == [name]  # no staging or probe folder left


def test_lusm_characteristic_plots_into_a_long_folder_name(tmp_path, monkeypatch, capsys):
    """The reported case: ``--plot`` with a 250-letter folder name exited 2 ("cannot write
    there (File name too long)"), before any work, on the probe's name."""
    from lusm.cli import main

    name = "a" * 250
    (tmp_path / name).mkdir()
    monkeypatch.chdir(tmp_path)
    argv = ["characteristic", "--voltage", "400", "--preload", "14", "--accuracy", "fast",
            "--loads", "0:1:0.5", "--plot", name]
    for _ in range(2):
        assert main(argv) == 0, capsys.readouterr().err
    assert sorted(p.name for p in (tmp_path / name).iterdir()) == [MARKER, "characteristic.png"]
    assert [p.name for p in tmp_path.iterdir()] == [name]


def test_an_entry_already_named_like_the_staging_folder_is_never_removed(tmp_path,
                                                                          monkeypatch):
    """The staging folder is removed in ``finally`` by its name. When its mkdir failed
    because that name was taken (another entry, not lusm's, by the cut name and the same
    random suffix), the entry of that name was removed with it, files and all."""
    import uuid

    from lusm.errors import LusmError
    from lusm.staging import staging_name

    class Fixed:
        hex = "0123456789ab" * 2

    monkeypatch.setattr(uuid, "uuid4", lambda: Fixed())
    out = tmp_path / ("a" * 250)
    theirs = tmp_path / staging_name(out.name, "partial", tmp_path)
    _write(theirs, {"precious.txt": "not lusm's"})
    with pytest.raises(LusmError, match="File exists"):
        with output_set(out, "figures", "--plot") as stage:
            _write(stage, {"a.png": "1"})
    assert _snapshot(theirs) == {"precious.txt": "not lusm's"}
    assert not out.exists()


# --- staging folders left by runs killed outright ----------------------------------------------

_KILLED = """
import os, signal, sys
from pathlib import Path
from lusm.output_set import output_set
with output_set(Path(sys.argv[1]), "figures", "--out") as stage:
    (stage / "L1.png").write_text("half")
    os.kill(os.getpid(), signal.SIGKILL)  # as SIGKILL or a power cut: no finally runs
"""


def _killed_run(out: Path) -> Path:
    """Stage ``out`` in a process killed outright; its staging folder, as it left it."""
    run = subprocess.run([sys.executable, "-c", _KILLED, str(out)], cwd=ROOT, timeout=120)
    assert run.returncode == -9
    (left,) = out.parent.glob(f".{out.name}-partial-*")
    return left


def _stale(folder: Path, name: str, record: dict | None, token: str = "0123456789ab") -> Path:
    """A staging folder as a killed run leaves it, with ``record`` in its lock file (None:
    no lock file, as lusm left them before it had one)."""
    import os
    import socket

    from lusm.staging import STAGING_LOCK, _boot_id

    entry = folder / f".{name}-partial-{token}"
    (entry / "set").mkdir(parents=True)
    (entry / "set" / "L1.png").write_text("half")
    if record is not None:
        folder = os.stat(entry)
        full = {"lusm": "staging", "token": token, "dev": folder.st_dev, "ino": folder.st_ino,
                "pid": _dead_pid(), "host": socket.gethostname(), "boot": _boot_id(), **record}
        (entry / STAGING_LOCK).write_text(json.dumps(full))
        os.chmod(entry, 0o700)
    return entry


def _dead_pid() -> int:
    """The id of a process that has ended (and been reaped)."""
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


def test_a_killed_runs_staging_folder_is_removed_by_the_next_run(tmp_path, capsys):
    """`timeout -s KILL 6 lusm render --animate --out kk` left `.kk-partial-<hex>/` with
    L1.png and a 0-byte L1.gif; later runs neither removed nor named it, and each kill added
    one more. Its lock is free and its process gone: the next run removes it and says so."""
    out = tmp_path / "kk"
    left = _killed_run(out)
    assert (left / "set" / "L1.png").read_text() == "half"  # what the killed run left
    mine = tmp_path / "mine.txt"
    mine.write_text("the user's")
    with output_set(out, "figures") as stage:
        _write(stage, {"L1.png": "whole"})
    err = capsys.readouterr().err
    assert not left.exists()
    assert "lusm: removed the staging folder of a lusm run killed before it finished" in err
    assert str(left) in err
    assert _snapshot(out) == {"L1.png": "whole"}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kk", "mine.txt"]
    assert mine.read_text() == "the user's"


def test_a_staging_folder_in_use_is_left_unsaid(tmp_path, capsys):
    """A run still staging holds its folder's lock: a second run writing the same target
    leaves that folder alone and says nothing of it."""
    out = tmp_path / "kk"
    with output_set(out, "figures") as first:
        with output_set(tmp_path / "kk", "figures") as second:
            _write(second, {"b.png": "2"})
        assert first.exists() and capsys.readouterr().err == ""
        _write(first, {"a.png": "1"})
    assert _snapshot(out) == {"a.png": "1", "b.png": "2"}
    assert [p.name for p in tmp_path.rglob(".*partial*")] == []


@pytest.mark.parametrize("record, why", [
    (None, "no lock file: an older lusm's, or not lusm's"),
    ({"pid": "alive"}, "its process id is taken (a live process)"),
    ({"host": "another-host"}, "recorded on another host: its process cannot be checked"),
    ({"token": "ffffffffffff"}, "the record is another folder's (a copy)"),
    ({"ino": 1}, "the record is another folder's (a copy under the same name)"),
    ({"boot": "another-boot"}, "another boot: an earlier one, or another machine of that "
                               "name whose locks this host does not see"),
    ({"lusm": "other"}, "not lusm's record"),
])
def test_a_staging_folder_lusm_cannot_prove_dead_is_named_not_removed(tmp_path, capsys,
                                                                       record, why):
    import os
    import re

    if record == {"pid": "alive"}:
        record = {"pid": os.getpid()}  # this process: alive, and its lock free
    entry = _stale(tmp_path, "kk", record)
    before = _snapshot(entry)
    with output_set(tmp_path / "kk", "figures", "--plot") as stage:
        _write(stage, {"a.png": "1"})
    err = capsys.readouterr().err.strip().splitlines()
    assert _snapshot(entry) == before, why  # nothing of it removed
    assert len(err) == 1, err
    # "lusm" alone here; a command's name once main() has run one in this process
    assert re.match(r"lusm( \w+)?: warning: ", err[0]), err
    assert f": warning: --plot {tmp_path / 'kk'}: {entry} has the name and layout of a lusm " \
           "staging folder; if an interrupted run left it, remove it once no lusm run is " \
           f"writing {tmp_path / 'kk'}" in err[0], err


def test_every_stale_entry_is_named_in_one_line_and_links_are_left(tmp_path, capsys):
    """Two folders without a record: one line names both; a link of that name (never
    lusm's) and another target's staging folder are not named."""
    a = _stale(tmp_path, "kk", None, "aaaaaaaaaaaa")
    b = _stale(tmp_path, "kk", None, "bbbbbbbbbbbb")
    link = tmp_path / ".kk-partial-dddddddddddd"
    link.symlink_to(a)
    other = _stale(tmp_path, "kkk", {})
    with output_set(tmp_path / "kk", "figures") as stage:
        _write(stage, {"a.png": "1"})
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"{a}, {b} have the names and layout of lusm staging folders; " \
        "if interrupted runs left them, remove them" in err[0], err
    assert "dddd" not in err[0] and "kkk" not in err[0]
    assert a.is_dir() and b.is_dir() and link.is_symlink()
    assert other.is_dir()  # another target's: its own next run deals with it


def test_an_entry_that_merely_has_a_staging_name_is_never_named(tmp_path, monkeypatch, capsys):
    """Any entry named ``.NAME-partial-<12 hex>`` without a lock file, even a file, was
    named as "the staging folder of an earlier lusm run ...: remove it" (review: a folder of
    the user's holding data.txt). Only the layout lusm makes, a folder holding its lock file
    or its ``set`` folder, is named; the rest is left, unsaid."""
    from lusm.cli import main

    mine = tmp_path / "o1" / ".figs-partial-0123456789ab"
    _write(mine, {"data.txt": "the user's"})
    file = tmp_path / "o1" / ".figs-partial-cccccccccccc"
    file.write_text("a file")
    monkeypatch.chdir(tmp_path)
    assert main(["characteristic", "--voltage", "400", "--preload", "14", "--accuracy", "fast",
                 "--loads", "0:1:0.5", "--plot", str(tmp_path / "o1" / "figs")]) == 0
    assert "partial" not in capsys.readouterr().err
    assert _snapshot(mine) == {"data.txt": "the user's"} and file.read_text() == "a file"
    assert sorted(p.name for p in (tmp_path / "o1").iterdir()) == [mine.name, file.name, "figs"]


def test_a_copy_of_a_dead_runs_staging_folder_is_named_not_removed(tmp_path, capsys):
    """A copy (``cp -a``) keeps the staging folder's name and its record, which named only
    the folder's random suffix: the copy of a dead run's folder was removed as its own. The
    record names the folder's device and inode too; only the original is removed."""
    import shutil

    (tmp_path / "a").mkdir()
    left = _killed_run(tmp_path / "a" / "kk")
    shutil.copytree(tmp_path / "a", tmp_path / "b", symlinks=True)  # cp -a
    copy = tmp_path / "b" / left.name
    for folder in ("b", "a"):
        with output_set(tmp_path / folder / "kk", "figures") as stage:
            _write(stage, {"a.png": "1"})
    err = capsys.readouterr().err.strip().splitlines()
    assert (copy / "set" / "L1.png").read_text() == "half"  # left whole
    assert len(err) == 2 and f"{copy} has the name and layout" in err[0], err
    assert not left.exists() and err[1].startswith("lusm: removed") and str(left) in err[1]


@pytest.mark.parametrize("pid", ["alive", "gone"])
def test_a_staging_folder_of_another_boot_is_named_not_removed(tmp_path, capsys, pid):
    """A record of another boot had been taken as proof of death. It may be an earlier boot
    of this machine, or another machine of this name sharing the folder over NFS, where
    locks may be each host's own: its lock being free here and its process id, alive or
    gone here, prove nothing. It is named, not removed."""
    import os

    from lusm.staging import _boot_id

    if _boot_id() is None:
        pytest.skip("needs Linux's boot id")
    record = {"boot": "an-earlier-boot", **({"pid": os.getpid()} if pid == "alive" else {})}
    entry = _stale(tmp_path, "kk", record)
    with output_set(tmp_path / "kk", "figures") as stage:
        _write(stage, {"a.png": "1"})
    assert (entry / "set" / "L1.png").read_text() == "half"
    err = capsys.readouterr().err
    assert "lusm: removed" not in err and f"{entry} has the name and layout" in err


@pytest.fixture
def nfs(monkeypatch):
    """NFS's ways, as far as staging meets them: a file unlinked while this process has it
    open is renamed to a hidden ``.nfsXXXX`` in its folder (which then cannot be removed),
    and ``flock``, which NFS emulates with byte-range locks, refuses an exclusive lock on a
    file open only for reading (EBADF)."""
    import errno
    import fcntl
    import itertools
    import os

    real_open, real_close, real_flock = os.open, os.close, fcntl.flock
    open_files: dict[int, tuple[int, int]] = {}
    silly = itertools.count()

    def nfs_open(path, flags, mode=0o777, *, dir_fd=None):
        fd = real_open(path, flags, mode, dir_fd=dir_fd)
        st = os.fstat(fd)
        open_files[fd] = (st.st_dev, st.st_ino)
        return fd

    def nfs_close(fd):
        open_files.pop(fd, None)
        real_close(fd)

    def nfs_unlink(path, *, dir_fd=None, real_unlink=os.unlink):
        st = os.lstat(path, dir_fd=dir_fd)
        if (st.st_dev, st.st_ino) in open_files.values():
            hidden = os.path.join(os.path.dirname(os.fsdecode(path)), f".nfs{next(silly):020x}")
            os.rename(path, hidden, src_dir_fd=dir_fd, dst_dir_fd=dir_fd)
        else:
            real_unlink(path, dir_fd=dir_fd)

    def nfs_flock(fd, operation):
        if operation & fcntl.LOCK_EX and fcntl.fcntl(fd, fcntl.F_GETFL) & os.O_ACCMODE \
                == os.O_RDONLY:
            raise OSError(errno.EBADF, os.strerror(errno.EBADF))
        real_flock(fd, operation)

    monkeypatch.setattr(os, "open", nfs_open)
    monkeypatch.setattr(os, "close", nfs_close)
    monkeypatch.setattr(os, "unlink", nfs_unlink)
    monkeypatch.setattr(os, "remove", nfs_unlink)
    monkeypatch.setattr(fcntl, "flock", nfs_flock)


def test_on_nfs_a_run_leaves_no_staging_folder(tmp_path, nfs):
    """On NFS each run left an empty ``.NAME-partial-<hex>`` behind (review): it removed
    its lock file while it still had it open, NFS kept that file as ``.nfsXXXX`` and the
    folder could not be removed; every later run then named it."""
    out = tmp_path / "kk"
    with output_set(out, "figures") as stage:
        _write(stage, {"a.png": "1"})
    with pytest.raises(RuntimeError, match="failed"):  # a failing run cleans up as well
        with output_set(out, "figures") as stage:
            _write(stage, {"a.png": "2"})
            raise RuntimeError("failed")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kk"]
    assert _snapshot(out) == {"a.png": "1"}


def test_on_nfs_a_killed_runs_staging_folder_is_removed(tmp_path, capsys, nfs):
    """On NFS the lock of a dead run's folder was asked for on a file open only for
    reading: NFS refused it (EBADF), that read as a lock still held, and the folder was
    never removed (review)."""
    out = tmp_path / "kk"
    left = _killed_run(out)  # killed on this disk, as a run killed on NFS leaves it
    with output_set(out, "figures") as stage:
        _write(stage, {"L1.png": "whole"})
    assert "lusm: removed the staging folder" in capsys.readouterr().err
    assert not left.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kk"]


def test_a_lock_file_that_is_a_fifo_is_not_waited_on(tmp_path, capsys):
    """The lock file is opened to test its lock: a FIFO by that name (not lusm's) must not
    block the run, which would wait for a writer for ever."""
    import os

    from lusm.staging import STAGING_LOCK

    entry = _stale(tmp_path, "kk", None)
    os.mkfifo(entry / STAGING_LOCK)
    with output_set(tmp_path / "kk", "figures") as stage:
        _write(stage, {"a.png": "1"})
    assert (entry / STAGING_LOCK).exists() and str(entry) in capsys.readouterr().err


def test_a_dataset_and_an_export_clear_their_own_stale_staging(tmp_path, capsys):
    """`explore --out r.nc` and `modes --export m.vtu` stage the same way: a killed run's
    folder is removed by the next write of that target, and one that cannot be proven dead
    is named."""
    import numpy as np
    import xarray as xr

    from lusm.cli import main
    from studies.explore import write_dataset

    dead_nc = _stale(tmp_path, "r.nc", {})
    unknown_nc = _stale(tmp_path, "r.nc", None, "aaaaaaaaaaaa")
    write_dataset(xr.Dataset({"v": ("x", np.arange(3.0))}), tmp_path / "r.nc")
    err = capsys.readouterr().err
    assert not dead_nc.exists() and "lusm: removed the staging folder" in err
    assert unknown_nc.is_dir() and f"--out {tmp_path / 'r.nc'}: {unknown_nc} has the" in err
    dead_vtu = _stale(tmp_path, "m.vtu", {})  # an export stages by its whole name
    # --plot m's staging folder: m.vtu's run had cleared it (or named it) as its own
    dead_plot = _stale(tmp_path, "m", {}, "cccccccccccc")
    assert main(["modes", "--refine", "2", "--export", str(tmp_path / "m.vtu")]) == 0
    err = capsys.readouterr().err
    assert not dead_vtu.exists() and str(dead_vtu) in err
    assert dead_plot.is_dir() and dead_plot.name not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        [dead_plot.name, unknown_nc.name, "m.vtu", "r.nc"])


def test_another_users_held_lock_reads_held(tmp_path, monkeypatch):
    """explore's parts folder's .lock is 0644: another user cannot open it read-write, and
    the read-write open had said "not held", so a second run was told it could remove a live
    study's folder (review). A shared lock on a read-only open tells."""
    import fcntl
    import os

    from lusm import staging

    lock = tmp_path / ".lock"
    lock.write_text("")
    holder = os.open(lock, os.O_RDWR)
    fcntl.flock(holder, fcntl.LOCK_EX | fcntl.LOCK_NB)  # the running study
    real_open = os.open

    def as_another_user(path, flags, *args):
        if os.fspath(path) == os.fspath(lock) and flags & os.O_RDWR:
            raise PermissionError(13, "Permission denied")
        return real_open(path, flags, *args)

    monkeypatch.setattr(os, "open", as_another_user)
    monkeypatch.setattr(os, "access", lambda path, mode: False)
    try:
        assert staging.lock_held(lock)
    finally:
        os.close(holder)
    assert not staging.lock_held(lock)  # released: nobody holds it
