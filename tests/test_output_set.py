"""Output sets never delete or overwrite a file lusm did not write, and never half-write."""

from __future__ import annotations

import hashlib
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
    with output_set(out) as stage:
        _write(stage, {"index.md": "1", "figures/f.png": "x"})
    assert _snapshot(out) == {"index.md": "1", "figures/f.png": "x"}
    assert (out / MARKER).exists()
    assert [p.name for p in tmp_path.rglob(".*partial*")] == []


def test_a_report_replaces_only_its_own_files(tmp_path):
    out = tmp_path / "r"
    with output_set(out) as stage:
        _write(stage, {"index.md": "old", "figures/old.png": "o", "figures/keep.png": "k"})
    (out / "figures" / "mine.txt").write_text("user")  # the user's file inside a report
    (out / "notes.md").write_text("user notes")
    with output_set(out) as stage:
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
        with output_set(out) as stage:
            _write(stage, {f"sweep_{axis}.png": text})
    assert _snapshot(out) == {"sweep_length.png": "L2", "sweep_width.png": "W"}


def test_a_file_the_user_edited_is_kept_as_a_backup(tmp_path, capsys):
    out = tmp_path / "r"
    with output_set(out) as stage:
        _write(stage, {"B2.png": "lusm", "sub/a.txt": "lusm"})
    (out / "B2.png").write_text("annotated by the user")
    with output_set(out) as stage:
        _write(stage, {"B2.png": "new", "sub/a.txt": "new"})
    assert _snapshot(out) == {"B2.png": "new", "B2.png.bak-1": "annotated by the user",
                              "sub/a.txt": "new"}
    assert "B2.png.bak-1" in capsys.readouterr().err


@pytest.mark.parametrize("entry", ["../victim.txt", "ABSOLUTE", "sub/../../victim.txt",
                                   "link/victim.txt", "", ".", "./B2.png"])
def test_a_planted_marker_cannot_reach_outside_the_folder(tmp_path, entry):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    out = tmp_path / "r"
    out.mkdir()
    (out / "link").symlink_to(tmp_path, target_is_directory=True)
    name = str(victim) if entry == "ABSOLUTE" else entry
    digest = hashlib.sha256(b"precious").hexdigest()  # as if lusm had written the victim
    (out / MARKER).write_text(json.dumps({"sha256": {name: digest, "B2.png": digest}}))
    with output_set(out, force=True) as stage:
        _write(stage, {"B2.png": "new", "victim.txt": "new"})
    assert victim.read_text() == "precious"
    assert (out / "victim.txt").read_text() == "new"


def test_a_folder_that_is_not_a_report_is_refused_and_left_alone(tmp_path):
    out = tmp_path / "mine"
    _write(out, {"index.md": "my index", "figures/plot.png": "my plot"})
    before = _snapshot(out)
    with pytest.raises(OutputError, match="--out .* did not write.*--force"):
        with output_set(out) as stage:
            _write(stage, {"index.md": "report"})
    assert _snapshot(out) == before


def test_force_keeps_colliding_user_files_as_backups(tmp_path):
    out = tmp_path / "mine"
    _write(out, {"index.md": "my index", "figures/plot.png": "my plot"})
    with output_set(out, force=True) as stage:
        _write(stage, {"index.md": "report", "figures/f.png": "fig"})
    snap = _snapshot(out)
    assert snap["index.md"] == "report" and snap["index.md.bak-1"] == "my index"
    assert snap["figures/plot.png"] == "my plot" and snap["figures/f.png"] == "fig"


def test_a_failure_leaves_the_folder_and_its_parents_as_they_were(tmp_path):
    out = tmp_path / "new" / "nested"
    with pytest.raises(RuntimeError):
        with output_set(out) as stage:
            _write(stage, {"index.md": "half"})
            raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []  # no parent folders, no staging folder


@pytest.mark.parametrize("make", ["file", "below_file"])
def test_a_file_where_the_folder_should_be_is_refused(tmp_path, make):
    f = tmp_path / "f"
    f.write_text("keep")
    out = f if make == "file" else f / "sub"
    with pytest.raises(OutputError, match="--out must be a folder"):
        with output_set(out):
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
        with output_set(out) as stage:
            _write(stage, {"a.png": "x"})
    with output_set(out, force=True) as stage:
        _write(stage, {"a.png": "x"})
    assert precious.read_text() == "precious"
    assert (out / f"{MARKER}.bak-1").is_symlink() and not (out / MARKER).is_symlink()


def test_a_marker_listing_nothing_usable_is_refused_before_any_work(tmp_path):
    from lusm.output_set import check_target

    out = tmp_path / "o"
    _write(out, {"admittance.png": "mine",
                 MARKER: json.dumps({"sha256": {"x": 1}})})
    with pytest.raises(OutputError, match="did not write"):
        check_target(out)


def test_a_link_to_a_folder_is_written_through_and_a_dangling_one_refused(tmp_path):
    # a link to an empty folder failed after the work ("cannot write (Not a directory)")
    from lusm.output_set import check_target

    (tmp_path / "real").mkdir()
    (tmp_path / "link").symlink_to(tmp_path / "real", target_is_directory=True)
    with output_set(tmp_path / "link") as stage:
        _write(stage, {"a.png": "x"})
    assert _snapshot(tmp_path / "real") == {"a.png": "x"}
    assert (tmp_path / "link").is_symlink()
    (tmp_path / "dangling").symlink_to(tmp_path / "nowhere")
    with pytest.raises(OutputError, match="does not exist"):
        check_target(tmp_path / "dangling")


def test_a_subfolder_that_is_a_link_is_kept_aside_whole_with_force(tmp_path):
    # report --force into a report whose figures/ was a link to another folder: the link was
    # kept aside, then figures/a.png (reached through it) could not be, and the new set was
    # lost halfway with the old index.md pointing nowhere
    elsewhere = tmp_path / "vf"
    _write(elsewhere, {"a.png": "old figure"})
    out = tmp_path / "o"
    _write(out, {"index.md": "old"})
    (out / "figures").symlink_to(elsewhere)
    with output_set(out, force=True) as stage:
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
    with output_set(out) as stage:
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
        with output_set(Path("."), "--plot") as stage:
            _write(stage, {"c.png": "3"})
    finally:
        os.chdir(old)
    assert _snapshot(cwd) == {"c.png": "3"}


def test_a_users_file_named_like_the_marker_is_kept_under_force(tmp_path):
    """--force into the user's folder must not overwrite their own .lusm-output.json."""
    out = tmp_path / "d"
    out.mkdir()
    (out / MARKER).write_text("my data")
    with output_set(out, force=True) as stage:
        _write(stage, {"s.png": "1"})
    assert (out / f"{MARKER}.bak-1").read_text() == "my data"
    assert set(json.loads((out / MARKER).read_text())["sha256"]) == {"s.png"}


def test_sets_of_several_commands_share_a_folder_without_harm(tmp_path, capsys):
    """A characteristic's PNG written into a report's folder takes --force; each command
    then replaces its own unchanged files without it; a file the user put where a set
    writes is refused, or with --force kept aside."""
    out = tmp_path / "rep"
    with output_set(out, command="report") as stage:
        _write(stage, {"index.md": "r1", "figures/a.png": "a1"})
    with pytest.raises(OutputError, match="holds the output of lusm report"):
        with output_set(out, command="characteristic") as stage:
            _write(stage, {"characteristic.png": "c0"})
    with output_set(out, force=True, command="characteristic") as stage:
        _write(stage, {"characteristic.png": "c1"})
    with output_set(out, command="report") as stage:
        _write(stage, {"index.md": "r2", "figures/a.png": "a2"})
    assert _snapshot(out) == {"index.md": "r2", "figures/a.png": "a2",
                              "characteristic.png": "c1"}
    assert ".bak" not in capsys.readouterr().err
    (out / "notes.md").write_text("mine")
    with pytest.raises(OutputError, match="already holds 'notes.md'"):
        with output_set(out) as stage:
            _write(stage, {"notes.md": "lusm's"})
    with output_set(out, force=True) as stage:
        _write(stage, {"notes.md": "lusm's"})
    assert (out / "notes.md.bak-1").read_text() == "mine"


def test_a_refusal_after_the_work_names_the_option_typed(tmp_path):
    """A user's file standing where a set in a folder lusm wrote wants to write: the
    refusal named --out when the user had typed --plot."""
    out = tmp_path / "m"
    with output_set(out, "--plot") as stage:
        _write(stage, {"a.png": "1"})
    (out / "b.png").write_text("mine")
    with pytest.raises(OutputError, match="^--plot "):
        with output_set(out, "--plot") as stage:
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


@pytest.mark.parametrize("argv", [
    ["simulate", "--voltage", "200", "--preload", "14", "--plot"],
    ["map", "--plot"],
    ["characteristic", "--voltage", "200", "--preload", "14", "--plot"],
    ["render", "--out"],
    ["sweep", "--width-mm", "6:8:1", "--out"],
    ["admittance", "--out"],
    ["report", "--out"],
    ["explore", "{study}", "--out", "{nc}", "--plot"],
], ids=lambda argv: argv[0])
def test_a_folder_of_another_command_is_refused_before_any_work(argv, tmp_path, capsys):
    """Each command that writes a folder refuses one another command wrote (one line, exit
    2, nothing changed), and writes beside it with --force (the first command's files
    stay); the check runs before any solve or study, so the refusal takes no time."""
    from lusm.cli import main

    out = tmp_path / "theirs"
    owner = "report" if argv[0] == "render" else "render"
    with output_set(out, command=owner) as stage:
        (stage / "a.png").write_text("a")
    before = _snapshot(out)
    study = tmp_path / "s.toml"
    study.write_text('outputs = ["split"]\n[axes]\nlength = ["29 mm", "30 mm"]\n')
    names = {"study": str(study), "nc": str(tmp_path / "r.nc")}
    args = [a.format(**names) for a in argv] + [str(out)]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    option = argv[-1]
    assert err[-1].startswith(f"lusm {argv[0]}: error: {option} {out} holds the output of "
                              f"lusm {owner};"), err
    assert _snapshot(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml", "theirs"]


def test_a_command_writes_beside_another_commands_set_with_force(tmp_path, capsys):
    from lusm.cli import main

    out = tmp_path / "figs"
    with output_set(out, command="simulate") as stage:
        (stage / "fig09_slider_velocity.png").write_text("theirs")
    argv = ["characteristic", "--voltage", "400", "--preload", "14", "--accuracy", "fast",
            "--loads", "0:1:0.5", "--plot", str(out)]
    assert main(argv) == 2
    assert main([*argv, "--force"]) == 0, capsys.readouterr().err
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "characteristic.png",
                                                     "fig09_slider_velocity.png"]
    assert json.loads((out / MARKER).read_text())["commands"] == ["characteristic", "simulate"]
    assert main(argv) == 0  # a command named in the marker writes again without --force


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
                                          r"folder that lusm did not write"):
        check_target(Path(typed), "--plot")
    with output_set(Path(typed), "--plot", force=True) as stage:
        _write(stage, {"characteristic.png": "new"})
    assert _snapshot(tmp_path) == {"characteristic.png": "new",
                                   "characteristic.png.bak-1": "mine", "notes.txt": "notes"}


@pytest.mark.parametrize("name", [pytest.param("a" * 250, id="a250"),
                                  pytest.param("a" * 255, id="a255"),
                                  pytest.param("\u00e9" * 127, id="e-acute127")])
@pytest.mark.parametrize("exists", [False, True])
def test_a_folder_with_a_long_name_is_written(tmp_path, name, exists):
    """A folder name the file system takes is written, though its staging folder's name
    ``.NAME-partial-XXXXXXXX`` is cut to fit."""
    from lusm.output_set import check_target, check_writable

    out = tmp_path / name
    if exists:
        out.mkdir()
    for text in ("1", "2"):  # the second run replaces lusm's own set
        check_target(out, "--plot")
        check_writable(out, "--plot")
        with output_set(out, "--plot") as stage:
            _write(stage, {"a.png": text})
    assert _snapshot(out) == {"a.png": "2"}
    assert [p.name for p in tmp_path.iterdir()] == [name]  # no staging or probe folder left


def test_lusm_characteristic_plots_into_a_long_folder_name(tmp_path, monkeypatch, capsys):
    """``--plot`` with a 250-letter folder name, before any work and after."""
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


_KILLED = """
import os, signal, sys
from pathlib import Path
from lusm.output_set import output_set
with output_set(Path(sys.argv[1])) as stage:
    (stage / "L1.png").write_text("half")
    os.kill(os.getpid(), signal.SIGKILL)  # as SIGKILL or a power cut: no finally runs
"""


def test_a_run_killed_outright_leaves_the_target_as_it_was(tmp_path):
    """SIGKILL while the set is staged: the target keeps its earlier set; only the hidden
    staging folder is left, and the next run writes the target as usual."""
    out = tmp_path / "kk"
    with output_set(out) as stage:
        _write(stage, {"L1.png": "earlier"})
    run = subprocess.run([sys.executable, "-c", _KILLED, str(out)], cwd=ROOT, timeout=120)
    assert run.returncode == -9
    assert _snapshot(out) == {"L1.png": "earlier"}
    assert len(list(tmp_path.glob(".kk-partial-*"))) == 1
    with output_set(out) as stage:
        _write(stage, {"L1.png": "new"})
    assert _snapshot(out) == {"L1.png": "new"}


@pytest.mark.parametrize("stop", [KeyboardInterrupt, SystemExit])
def test_an_interrupt_while_staging_leaves_the_target_as_it_was(tmp_path, stop):
    out = tmp_path / "r"
    with output_set(out) as stage:
        _write(stage, {"index.md": "old"})
    with pytest.raises(stop):
        with output_set(out) as stage:
            _write(stage, {"index.md": "half", "more.md": "half"})
            raise stop()
    assert _snapshot(out) == {"index.md": "old"}
    assert [p.name for p in tmp_path.iterdir()] == ["r"]
