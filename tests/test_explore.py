"""``lusm explore``: studies on a LocalCluster against the same points computed in-process,
resume after an interruption, a killed worker, and bad study files."""

from __future__ import annotations

import os
import re
import signal
from pathlib import Path

import numpy as np
import pytest

xr = pytest.importorskip("xarray")
pytest.importorskip("distributed")

from studies.cluster import local_cluster  # noqa: E402
from studies.dataset import assemble, open_result, write_dataset  # noqa: E402
from studies.explore import explore  # noqa: E402
from studies.parts import parts_folder  # noqa: E402
from studies.study import FE_OUTPUTS, load_study, study_from_dict  # noqa: E402
from studies.task import compute_geometry, empty_outputs, package_version  # noqa: E402

TINY = {
    "outputs": ["f_L1_short", "f_L1_open", "f_B2_short", "f_B2_open", "k_eff", "split",
                "no_load_velocity", "motion_class", "velocity"],
    "study": {"name": "tiny"},
    "axes": {
        "length": {"start": "28 mm", "stop": "32 mm", "num": 3},
        "width": ["7 mm", "8 mm"],
        "voltage": ["200 V", "300 V"],
        "preload": "6 N",
        "load": ["0 N", "1 N"],
    },
    "solver": {"fe_order": 2, "fe_refine": 1, "accuracy": "fast"},
}
"""3 x 2 geometries x 2 voltages x 2 loads: one FE solve and 2 drive points per task, at the
steady engine's fast level (a fraction of a second a task: what the cluster tests claim does
not depend on the contact model's accuracy level)."""


@pytest.fixture(scope="module")
def study():
    return study_from_dict(TINY)


@pytest.fixture(scope="module")
def reference(study, tmp_path_factory):
    """The dataset of the same points computed one by one in this process, read back."""
    parts = {i: compute_geometry(study, i) for i in range(study.n_geometries)}
    for p in parts.values():
        p.pop("task_time_s")
    path = tmp_path_factory.mktemp("ref") / "ref.nc"
    write_dataset(assemble(study, parts), path)
    return open_result(path)


@pytest.fixture(scope="module")
def windowed_run(study, dask_client, tmp_path_factory):
    """TINY on the session's cluster with an in-flight window of 2 tasks, run once for the
    tests below: the result, the dataset's path, and the geometry tasks the scheduler knew
    at each part written (counted on the scheduler itself)."""
    import studies.explore as E

    known = []

    def count(_i):
        known.append(dask_client.run_on_scheduler(
            lambda dask_scheduler: sum(k.startswith("lusm-geometry-")
                                       for k in map(str, dask_scheduler.tasks))))

    out = tmp_path_factory.mktemp("windowed") / "study.nc"
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(E, "MIN_IN_FLIGHT", 2)
        mp.setattr(E, "IN_FLIGHT_PER_WORKER", 1)
        r = explore(study, out, client=dask_client, progress=False, on_part=count)
    return r, out, known


@pytest.fixture(scope="module")
def scheduler(dask_client):
    """The address of the session's cluster, for --scheduler."""
    return dask_client.scheduler.address


@pytest.mark.slow
def test_cluster_equals_in_process(study, reference, windowed_run):
    r, out, _known = windowed_run
    assert (r.computed, r.reused, r.workers) == (study.n_geometries, 0, 2)
    ds = open_result(out)
    xr.testing.assert_identical(ds, reference)  # bit-identical, NaN == NaN
    assert not parts_folder(out).exists()  # the parts are gone once the dataset is in
    # the labels mean what they say: one dimension per axis, SI units, provenance
    assert ds["f_L1_short"].dims == ("length", "width", "thickness", "gap", "material")
    assert ds["velocity"].dims[-4:] == ("material", "voltage", "preload", "load")
    np.testing.assert_allclose(ds["length"].values, [28e-3, 30e-3, 32e-3])
    assert ds["length"].attrs["units"] == "m" and ds["f_B2_open"].attrs["units"] == "Hz"
    assert "fem_params" in ds.attrs["parameter_set_source"] and ds.attrs["lusm_version"]
    np.testing.assert_array_equal(ds["split"], ds["f_B2_short"] - ds["f_L1_short"])
    # open circuit stiffens both modes, and k_eff is the coupling of that shift
    for m in ("L1", "B2"):
        fs, fo = ds[f"f_{m}_short"].values, ds[f"f_{m}_open"].values
        assert np.all(fo > fs)
        np.testing.assert_allclose(ds[f"k_eff_{m}"], np.sqrt((fo**2 - fs**2) / fo**2),
                                   rtol=1e-9)
    # the L1 rod frequency falls like 1/length
    f = ds["f_L1_short"].isel(width=0).values.ravel()
    assert np.all(np.diff(f) < 0)
    # the velocity at zero load is the no-load velocity, and the steady engine answers the
    # loaded points
    np.testing.assert_array_equal(ds["velocity"].sel(load=0.0), ds["no_load_velocity"])
    assert np.isfinite(ds["velocity"].sel(load=1.0)).all()


@pytest.mark.slow
def test_a_bounded_window_of_tasks_is_in_flight(study, windowed_run):
    """At most the window of tasks is known to the scheduler at any time, and one finishing,
    topped up as tasks finish (one future per geometry submitted up front would grow the
    client of a 100 000-plate study by 55 MB/s before any part is written); the run's dataset
    is the in-process one (test_cluster_equals_in_process)."""
    r, _out, known = windowed_run
    assert r.computed == study.n_geometries == len(known) == 6
    # the window, plus the finished task being taken in (its release reaches the scheduler
    # after the count)
    assert max(known) <= 3 < study.n_geometries


@pytest.mark.slow
def test_the_local_cluster_has_no_more_workers_than_geometries(scheduler, monkeypatch,
                                                               tmp_path):
    """--workers 8 on a 2-geometry study asks for a LocalCluster of 2 processes, not 8 (6 of
    them idle, 330 MB); the session's cluster stands in for the one it would start
    (test_a_ctrl_c_while_the_cluster_starts_is_not_lost starts a real one of the size asked)."""
    from distributed import Client

    import studies.cluster

    asked = []

    def lend(_scheduler, _scheduler_file, workers):
        asked.append(workers)
        return Client(scheduler), None

    monkeypatch.setattr(studies.cluster, "connect", lend)
    two = study_from_dict({"outputs": ["f_L1_short"], "axes": {"length": ["29 mm", "30 mm"]},
                           "solver": {"fe_refine": 1}})
    r = explore(two, tmp_path / "two.nc", workers=8, progress=False)
    assert asked == [2] and r.computed == 2


class Interrupt(Exception):
    pass


@pytest.mark.slow
def test_resume_after_interruption_is_identical(study, reference, dask_client, tmp_path):
    out = tmp_path / "study.nc"
    seen = []

    def stop_after_two(i):
        seen.append(i)
        if len(seen) == 2:
            raise Interrupt

    with pytest.raises(Interrupt):
        explore(study, out, client=dask_client, progress=False, on_part=stop_after_two)
    assert not out.exists()
    assert len(list(parts_folder(out).glob("g*.npz"))) == 2
    with pytest.raises(ValueError, match="--resume"):  # no silent restart over the parts
        explore(study, out, client=dask_client, progress=False)
    r = explore(study, out, client=dask_client, progress=False, resume=True)
    assert (r.reused, r.computed) == (2, study.n_geometries - 2)
    xr.testing.assert_identical(open_result(out), reference)
    again = explore(study, out, client=dask_client, progress=False, resume=True)
    assert again.already_complete and again.computed == 0
    xr.testing.assert_identical(open_result(out), reference)


@pytest.mark.slow
def test_resume_refuses_another_study(study, dask_client, tmp_path):
    out = tmp_path / "study.nc"
    with pytest.raises(Interrupt):
        explore(study, out, client=dask_client, progress=False,
                on_part=lambda i: (_ for _ in ()).throw(Interrupt()))
    other = study_from_dict({**TINY, "axes": {**TINY["axes"], "preload": "7 N"}})
    with pytest.raises(ValueError, match="another study"):
        explore(other, out, client=dask_client, progress=False, resume=True)


@pytest.mark.slow
def test_killed_worker_loses_nothing(study, reference, dask_client, tmp_path):
    """A worker killed mid-study: its tasks are computed again elsewhere, the dataset is the
    in-process one. The session's cluster gets its worker back from the nanny before the
    test ends."""
    killed = []

    def kill_a_busy_worker(i):
        if killed:
            return
        pids = dask_client.run(os.getpid)
        busy = [w for w, keys in dask_client.processing().items() if keys] or list(pids)
        killed.append(pids[busy[0]])
        os.kill(pids[busy[0]], signal.SIGKILL)

    out = tmp_path / "study.nc"
    try:
        r = explore(study, out, client=dask_client, progress=False,
                    on_part=kill_a_busy_worker)
        assert killed and r.computed == study.n_geometries
        xr.testing.assert_identical(open_result(out), reference)
    finally:
        dask_client.wait_for_workers(2, timeout=60)
    assert killed[0] not in dask_client.run(os.getpid).values()  # it really died


# --- bad study files ------------------------------------------------------------------------

BAD = {
    "study not a table": ('study = "x"\n', "study must be a table"),
    "study name a number": ("[study]\nname = 3\n", "study.name must be a non-empty string"),
    "unknown axis": ("[axes]\ndiameter = '3 mm'\n", "axes.diameter"),
    "unit in the key": ("[axes]\nlength_mm = 30\n", "axes.length_mm"),
    "empty list": ("[axes]\nwidth = []\n", "axes.width"),
    "empty range": ("[axes]\nvoltage = { start = '300 V', stop = '100 V', step = '50 V' }\n",
                    "axes.voltage is an empty range: stop '100 V' is below start '300 V'"),
    # the same range with num was taken silently, in descending order
    "descending range with num": (
        "[axes]\nvoltage = { start = '300 V', stop = '100 V', num = 3 }\n",
        "axes.voltage is an empty range: stop '100 V' is below start '300 V'; a range "
        "ascends"),
    "unit-less number": ("[axes]\nlength = 30\n", "axes.length"),
    "unit-less string": ("[axes]\npreload = '14'\n", "axes.preload"),
    "wrong unit": ("[axes]\nvoltage = '200 mm'\n", "axes.voltage"),
    "missing output": ("outputs = ['f_L1_short', 'torque']\n", "outputs[1]"),
    "unit-less solver": ("[solver]\ndt = 1e-7\n", "solver.dt"),
    "gap eats the plate": ("[axes]\nwidth = '2 mm'\ngap = '3 mm'\n", "axes.gap"),
    "output twice": ("outputs = ['f_L1_short', 'f_L1_short']\n", "outputs[1]"),
    # one conductor driven as a short circuit: it failed per geometry, after its FE solve
    "motor outputs at gap 0": ("[axes]\ngap = ['0 mm', '0.5 mm']\n",
                               "axes.gap 0 mm makes the four electrodes one conductor"),
    # said in the file's unit: it was "got (2.0,) (SI)"
    "length too long": ("[axes]\nlength = ['30 mm', '2000 mm']\n",
                        "axes.length values must lie in [0.1, 1000] mm, got 2000 mm"),
    # contact.transient.reference.MAX_REFERENCE_PERIODS: refused by the file, not by every point
    "reference too long": ("[axes]\nfrequency = '40 kHz'\n[solver]\nmethod = 'reference'\n"
                           "duration = '1 s'\n",
                           "solver.duration 1 s must be at most 500 ms (20000 drive periods) "
                           "with solver.method 'reference'"),
    # --gap-mm's range in the study's words: it failed per geometry after its FE setup, as
    # "--gap-mm: PlateStator.electrode_gap_m must be 0 ... or at least 1e-06 m"
    "gap too narrow to model": ("[axes]\ngap = ['0.5 mm', '0.0001 mm']\n",
                                "axes.gap values must be 0 or lie in [0.001, 1000] mm, got "
                                "0.0001 mm"),
    "friction switch as text": ("[solver]\nultrasonic_friction = 'no'\n",
                                "solver.ultrasonic_friction must be true or false"),
    "empty file": ("# only a comment\n", "the study file is empty"),
    "rest unknown": ("[solver]\nrest = 'shortcut'\n",
                     "solver.rest must be probe or transient, got 'shortcut'"),
    "gap negative": ("[axes]\ngap = '-0.1 mm'\n",
                     "axes.gap values must be 0 or lie in [0.001, 1000] mm, got -0.1 mm"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_study_file_names_the_key(name, tmp_path):
    text, key = BAD[name]
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ValueError) as info:
        load_study(path)
    msg = str(info.value)
    assert key in msg and "\n" not in msg


def test_a_study_file_that_is_not_text_is_named(tmp_path):
    path = tmp_path / "bin.toml"
    path.write_bytes(b"\xff\xfe\x00binary")
    with pytest.raises(ValueError, match=r"bin\.toml: not UTF-8 text"):
        load_study(path)


def _fifo_with_a_study(tmp_path):
    """A FIFO a thread writes a valid study into: read, it loads (as it did before the file
    type was checked); the writer's open waits for a reader, so the test opens one after."""
    import threading

    fifo = tmp_path / "s.toml"
    os.mkfifo(fifo)

    def write():
        try:
            with open(fifo, "w") as fh:  # waits for a reader
                fh.write('outputs = ["f_L1_short"]\n')
        except BrokenPipeError:  # _release's reader was gone before the write
            pass

    threading.Thread(target=write, daemon=True).start()
    return fifo


def _release(path):
    """Let a FIFO's writer thread finish (it waits for a reader), without blocking here."""
    if path.is_fifo():
        os.close(os.open(path, os.O_RDONLY | os.O_NONBLOCK))


@pytest.mark.skipif(not hasattr(os, "mkfifo") or not Path("/dev/null").exists(),
                    reason="needs POSIX devices and FIFOs")
@pytest.mark.parametrize("kind, words", [
    # /dev/zero and /dev/urandom were read until memory ran out (24 GB, killed); /dev/null
    # is the same kind of file without the danger, and read as an empty study it loaded
    ("device", "/dev/null: is a character device, not a study file; give a regular TOML "
               "file of at most 1 MB"),
    ("fifo", "s.toml: is a FIFO (named pipe), not a study file"),  # it waited for ever
    ("large", "s.toml: 1100000 bytes is above the 1 MB a study file may have"),  # it ran
])
def test_a_study_path_that_is_not_a_small_regular_file_is_refused_unread(kind, words,
                                                                         tmp_path, capsys):
    from lusm.cli import main

    if kind == "device":
        path = Path("/dev/null")
    elif kind == "fifo":
        path = _fifo_with_a_study(tmp_path)
    else:  # valid TOML (comments), so only its size can refuse it
        path = tmp_path / "s.toml"
        path.write_text(("#" * 99 + "\n") * 11_000)  # 1.1 MB of comments
    try:
        with pytest.raises(ValueError) as info:
            load_study(path)
        assert words in str(info.value) and "\n" not in str(info.value)
        assert main(["explore", str(path), "--out", str(tmp_path / "r.nc")]) == 2
    finally:
        _release(path)
    err = capsys.readouterr().err.strip()
    assert err.startswith("lusm explore: error: ") and words in err, err
    assert len(err.splitlines()) == 1 and not list(tmp_path.glob("r.nc*"))


EXPLORE_REFUSALS = {
    # name: (arguments after `lusm explore`, what the one line is about: an option or a study
    # key). {study} is a valid one-plate study, {bad:NAME} a file of BAD[NAME], {tmp} the
    # test's folder, which holds the user's file mine.nc
    "unknown axis": (["{bad:unknown axis}", "--out", "{tmp}/r.nc"], "axes.diameter"),
    "unit-less number": (["{bad:unit-less number}", "--out", "{tmp}/r.nc"], "axes.length"),
    "missing output": (["{bad:missing output}", "--out", "{tmp}/r.nc"], "outputs[1]"),
    "empty study path": (["", "--out", "{tmp}/r.nc"], "STUDY.toml"),
    "empty --out": (["{study}", "--out", ""], "--out"),
    # '' is not "no scheduler" (a LocalCluster), and with --workers it is --scheduler's error
    "empty --scheduler": (["{study}", "--out", "{tmp}/r.nc", "--scheduler", ""], "--scheduler"),
    "empty --scheduler and --workers": (
        ["{study}", "--out", "{tmp}/r.nc", "--scheduler", "", "--workers", "1"], "--scheduler"),
    "empty --scheduler-file": (["{study}", "--out", "{tmp}/r.nc", "--scheduler-file", ""],
                               "--scheduler-file"),
    # --workers does nothing on an existing cluster
    "--workers with --scheduler": (
        ["{study}", "--out", "{tmp}/r.nc", "--scheduler", "tcp://127.0.0.1:9", "--workers", "4"],
        "--workers"),
    # refused before the study runs, not after it
    "--plot naming the dataset": (["{study}", "--out", "{tmp}/r.nc", "--plot", "{tmp}/r.nc"],
                                  "--plot"),
    # never overwritten without --force, which the line names
    "--out an existing file": (["{study}", "--out", "{tmp}/mine.nc"], "--out"),
    "--out whose parts cannot be written": (["{study}", "--out", "/sys/x.nc"], "--out"),
}


@pytest.mark.parametrize("name", sorted(EXPLORE_REFUSALS))
def test_explore_refuses_bad_input_in_one_line(name, tmp_path, capsys):
    """Exit 2, one line about the option or study key at fault, nothing written, the user's
    file kept."""
    from lusm.cli import main

    argv, about = EXPLORE_REFUSALS[name]
    if "/sys/x.nc" in argv and not Path("/sys/kernel").is_dir():
        pytest.skip("needs Linux's sysfs")
    study, mine = tmp_path / "s.toml", tmp_path / "mine.nc"
    study.write_text('outputs = ["f_L1_short"]\n[solver]\nfe_refine = 1\n')
    mine.write_text("mine")
    given = []
    for a in argv:
        if a.startswith("{bad:"):
            a = str(tmp_path / "bad.toml")
            Path(a).write_text(BAD[argv[0][5:-1]][0])
        given.append(a.replace("{study}", str(study)).replace("{tmp}", str(tmp_path)))
    inputs = sorted(p.name for p in tmp_path.iterdir())
    assert main(["explore", *given]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("lusm explore: error: "), err
    subject = err.removeprefix("lusm explore: error: ").removeprefix(f"{tmp_path}/bad.toml: ")
    assert subject.startswith(about), err
    if name == "--out an existing file":
        assert "--force" in subject
    assert sorted(p.name for p in tmp_path.iterdir()) == inputs and mine.read_text() == "mine"


# --- what a task computes -------------------------------------------------------------------

def test_fe_only_study_never_runs_the_contact_model(monkeypatch):
    import studies.task as ex

    def boom(*a, **k):
        raise AssertionError("the contact model ran for an FE-only study")

    monkeypatch.setattr(ex, "motor_answers", boom)
    s = study_from_dict({"outputs": ["f_B2_open", "k_eff"], "solver": {"fe_refine": 1}})
    part = compute_geometry(s, 0)
    assert str(part["status"]) == "ok" and np.isfinite(part["f_B2_open"])
    ds = assemble(s, {0: part})
    assert set(ds.data_vars) == {"f_B2_open", "k_eff_L1", "k_eff_B2", "status", "warnings"}


def test_coordinates_are_the_decimals_the_study_gives():
    """"6.5 mm" was 6.5 * 1e-3 = 0.006500000000000001 m: the example's width coordinate,
    which ds.sel(width=0.0065) did not find, the study attribute, and a fingerprint other
    than the same study's in m; a range summed start + i * step in binary (found by
    exploratory testing). Each value is the double nearest its decimal, a range's the exact
    decimals start + i * step, whatever the unit."""
    from fractions import Fraction

    ex = load_study(Path(__file__).parents[1] / "examples" / "studies" / "length_width.toml")
    assert ex.axes["width"] == (0.0065, 0.0075, 0.0085)
    assert '"width": [0.0065, 0.0075, 0.0085]' in ex.text
    fe = {"outputs": ["f_L1_short"], "solver": {"fe_refine": 1}}
    same = [study_from_dict({**fe, "axes": {"width": w, "length": {
        "start": start, "stop": "34 mm", "step": "0.1 mm"}}})
        for w, start in (("6.5 mm", "26 mm"), ("0.0065 m", "0.026 m"), ("6500 um", "26000 um"))]
    assert len({s.fingerprint for s in same}) == 1
    assert same[0].axes["length"] == tuple(float(f"{260 + i}e-4") for i in range(81))
    thirds = study_from_dict({"axes": {"load": {"start": "0 N", "stop": "1 N", "num": 4},
                                       "voltage": "200 V"}, "solver": {"fe_refine": 1}})
    assert thirds.axes["load"] == tuple(float(Fraction(i, 3)) for i in range(4))
    one = study_from_dict({**fe, "axes": {"width": "6.5 mm", "length": "26 mm"}})
    ds = assemble(one, {0: compute_geometry(one, 0)})
    assert ds["f_L1_short"].sel(width=0.0065, length=0.026).size == 1


def test_a_plate_in_mm_is_the_same_double_in_a_study_a_stator_file_and_the_commands(
        tmp_path):
    """A study's "6.5 mm", a stator file's width_mm = 6.5 and --width-mm 6.5 are one double,
    so that a study's plate at a stator file's own decimal is that file's plate (a gmsh plate
    1 ulp off is meshed anew) and the commands' plate is the study's."""
    import argparse

    from fem.stator_file import load_stator
    from fem.units import to_si
    from lusm.options import stator_from_args
    from studies.study import plate_with

    assert (to_si(6.5, 1e-3), to_si("6.5", 1e-3), to_si("-2.6e1", 1e-3)) == (
        0.0065, 0.0065, -0.026)
    assert to_si("1e-99999999", 1e-3) == 0.0  # at once, not a 10**99999999 denominator
    with pytest.raises(ValueError):
        to_si("1e400", 1.0)
    path = tmp_path / "stator.toml"
    path.write_text("[plate]\nlength_mm = 26\nwidth_mm = 6.5\nthickness_mm = 3\n")
    design = load_stator(path)
    assert (design.stator.length_m, design.stator.width_m) == (0.026, 0.0065)
    s = study_from_dict({"study": {"stator": str(path)}, "outputs": ["f_L1_short"],
                         "axes": {"width": ["6.5 mm", "7 mm"], "length": "26 mm"}})
    assert plate_with(design.stator, {"length_m": s.axes["length"][0],
                                      "width_m": s.axes["width"][0]}) is design.stator
    cli = stator_from_args(argparse.Namespace(length_mm=26.0, width_mm=6.5, thickness_mm=None,
                                              gap_mm=None, material=None, geometry=None))
    assert (cli.stator.length_m, cli.stator.width_m) == (0.026, 0.0065)


@pytest.mark.slow
def test_fixed_frequencies_are_a_dimension():
    s = study_from_dict({"outputs": ["no_load_velocity", "motion_class"],
                         "axes": {"frequency": ["52 kHz", "56 kHz"], "preload": "6 N"},
                         "solver": {"fe_refine": 1, "duration": "2 ms"}})
    ds = assemble(s, {0: compute_geometry(s, 0)})
    assert ds["no_load_velocity"].dims[-3:] == ("frequency", "voltage", "preload")
    np.testing.assert_array_equal(ds["frequency"], [52e3, 56e3])
    assert "f_drive" not in ds and ds["frequency"].attrs["units"] == "Hz"
    # each frequency really drives its own run: the answers differ
    v = ds["no_load_velocity"].values.ravel()
    assert np.all(np.isfinite(v)) and v[0] != v[1]


@pytest.mark.slow
def test_cli_on_an_existing_scheduler(scheduler, tmp_path, capsys):
    import json

    from lusm.cli import main

    path = tmp_path / "fe.toml"
    path.write_text('outputs = ["f_L1_short", "split"]\n[axes]\n'
                    'length = ["28 mm", "30 mm"]\nwidth = ["7 mm", "8 mm"]\n'
                    '[solver]\nfe_refine = 1\n')
    out, maps = tmp_path / "fe.nc", tmp_path / "maps"
    assert main(["explore", str(path), "--out", str(out), "--scheduler", scheduler, "--json",
                 "--plot", str(maps)]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["computed"] == 4 and summary["workers"] == 2
    assert [Path(f).name for f in summary["figures"]] == ["split_length_width.png"]
    assert (maps / "split_length_width.png").stat().st_size > 1000
    ds = open_result(out)
    s = load_study(path)
    for i in range(4):
        g = np.unravel_index(i, s.geometry_shape)
        assert ds["split"].values[g] == compute_geometry(s, i)["split"]
    # resuming the finished study is idempotent: exit 0, the dataset left as it is
    before = out.stat()
    assert main(["explore", str(path), "--out", str(out), "--resume"]) == 0
    assert "is complete" in capsys.readouterr().out
    after = out.stat()
    assert (after.st_ino, after.st_mtime_ns) == (before.st_ino, before.st_mtime_ns)


@pytest.mark.slow
def test_a_stator_study_runs_on_the_clusters_workers_as_in_process(scheduler, tmp_path):
    """``[study] stator``: the loaded stator file travels with the study to the workers (a
    remote worker need not see the file: it is gone before they run), and they give the
    in-process bits."""
    import shutil

    example = Path(__file__).resolve().parents[1] / "examples" / "tuned_60k" / "stator.toml"
    stator = tmp_path / "stator.toml"
    shutil.copy(example, stator)
    s = study_from_dict({"study": {"stator": str(stator)}, "outputs": ["f_L1_short", "split"],
                         "axes": {"length": ["25 mm", "26 mm"]}})
    stator.unlink()  # the workers get the loaded file with the study, not its path
    out = tmp_path / "st.nc"
    explore(s, out, scheduler=scheduler, progress=False)
    ds = open_result(out)
    assert ds.attrs["stator_file"] == str(stator)
    for i in range(2):
        assert ds["split"].values.ravel()[i] == compute_geometry(s, i)["split"]


def test_force_keeps_the_old_file(tmp_path):
    s = study_from_dict({"outputs": ["f_L1_short"], "solver": {"fe_refine": 1}})
    out = tmp_path / "r.nc"
    out.write_text("mine")
    write_dataset(assemble(s, {0: compute_geometry(s, 0)}), out, force=True)
    assert (tmp_path / "r.nc.bak-1").read_text() == "mine"
    assert open_result(out)["f_L1_short"].size == 1


def test_a_dataset_with_a_long_file_name_is_written(tmp_path):
    """A 235-byte --out, which the file system takes (and its 241-byte parts folder too),
    ran the whole study and then failed on the staging file's name,
    ``.NAME-partial-<12 hex>``, over the 255-byte limit ("File name too long")."""
    out = tmp_path / ("e" * 232 + ".nc")
    write_dataset(xr.Dataset({"v": ("x", np.arange(3.0))}), out)
    assert open_result(out)["v"].size == 3
    assert [p.name for p in tmp_path.iterdir()] == [out.name]  # no staging file left


@pytest.mark.skipif(not hasattr(signal, "SIGXFSZ"), reason="needs POSIX file size limits")
@pytest.mark.slow
def test_a_dataset_the_disk_refuses_is_one_error_and_leaves_no_staging_file(tmp_path):
    """Under a file size limit (ulimit -f 16) HDF5's own write failed in h5py's close, which
    h5netcdf's __del__ ran again at exit: a segmentation fault (exit 139) after the error
    line, a flood of HDF5 tracebacks, and the .X.nc-partial-* staging file left beside the
    target. A subprocess, since that limit is per process (and the crash took it down)."""
    import subprocess
    import sys

    from tests.conftest import ROOT

    code = """
import resource, sys
from pathlib import Path
import numpy as np, xarray as xr
from studies.dataset import write_dataset
ds = xr.Dataset({"v": ("x", np.arange(20_000.0))}, attrs={"title": "160 kB"})
resource.setrlimit(resource.RLIMIT_FSIZE, (16384, resource.getrlimit(resource.RLIMIT_FSIZE)[1]))
try:
    write_dataset(ds, Path(sys.argv[1]))
except ValueError as exc:  # what the CLI says in one line, with exit code 2
    print(exc, file=sys.stderr)
    sys.exit(2)
"""
    out = tmp_path / "r.nc"
    run = subprocess.run([sys.executable, "-c", code, str(out)], cwd=ROOT,
                         capture_output=True, text=True, timeout=120)
    err = run.stderr.strip()
    assert run.returncode == 2, (run.returncode, err[-2000:])
    assert err.startswith(f"--out {out}: cannot write the dataset (File too large"), err
    assert len(err.splitlines()) == 1, err
    assert not list(tmp_path.iterdir())  # no staging file, no dataset


@pytest.mark.skipif(os.name != "posix", reason="needs file names of arbitrary bytes")
def test_a_study_path_that_is_not_utf8_is_stored_readably(tmp_path):
    """A study at b'st\\xfe.toml' computed every geometry, then the dataset's write failed
    on its path in study_source (and on the name it gives, in title): "'utf-8' codec can't
    encode character '\\udcfe'"; --resume failed the same way (one assemble for both)."""
    path = Path(os.fsdecode(bytes(tmp_path) + b"/st\xfe.toml"))
    path.write_text('outputs = ["f_L1_short"]\n[solver]\nfe_refine = 1\n')
    s = load_study(path)
    out = tmp_path / "r.nc"
    write_dataset(assemble(s, {0: compute_geometry(s, 0)}), out)
    attrs = open_result(out).attrs
    assert attrs["study_source"] == os.fsdecode(tmp_path) + "/st\\xfe.toml"
    assert attrs["title"] == "lusm explore: st\\xfe"
    assert os.fsencode(attrs["study_source"].replace("\\xfe", "\udcfe")) == bytes(path)


def test_an_out_that_is_a_dangling_link_is_kept_as_an_existing_file(tmp_path, capsys):
    """--out naming a link to nowhere passed check_out (exists() follows the link) and the
    dataset was renamed over the link, silently; lusm modes --export refuses it."""
    from lusm.cli import main
    from studies.dataset import check_out

    out = tmp_path / "d.nc"
    out.symlink_to("nowhere.nc")
    study = tmp_path / "s.toml"
    study.write_text('outputs = ["f_L1_short"]\n[solver]\nfe_refine = 1\n')
    assert main(["explore", str(study), "--out", str(out), "--workers", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (f"lusm explore: error: --out {out} exists, a symbolic link to nowhere.nc, "
                   "which does not exist; choose a new name or pass --force (the link is kept "
                   "as a .bak file)"), err
    assert os.readlink(out) == "nowhere.nc" and not parts_folder(out).exists()
    check_out(out, force=True)  # --force takes it, and keeps the link aside
    write_dataset(xr.Dataset({"v": ("x", np.arange(3.0))}), out, force=True)
    assert os.readlink(tmp_path / "d.nc.bak-1") == "nowhere.nc"
    assert not out.is_symlink() and open_result(out)["v"].size == 3


@pytest.mark.slow
def test_workers_of_another_version_are_refused(scheduler, monkeypatch, tmp_path):
    import studies.task

    # the client (and the scheduler, in this process) says so; the workers 0.1.0 etc.
    monkeypatch.setattr(studies.task, "package_version", lambda: "0.0.0-client")
    s = study_from_dict({"outputs": ["f_L1_short"], "solver": {"fe_refine": 1}})
    out = tmp_path / "r.nc"
    with pytest.raises(ValueError, match="--scheduler: worker .* runs lusm"):
        explore(s, out, scheduler=scheduler, progress=False)
    assert not out.exists() and not parts_folder(out).exists()


@pytest.mark.slow
def test_workers_without_gmsh_are_refused_for_a_parametric_stator(scheduler, monkeypatch,
                                                                  tmp_path):
    """A study of a stator file meshed by gmsh needs gmsh on every worker: refused before any
    task (each task had failed on its mesh with an internal error)."""
    import fem.meshing.parametric

    # pickled by value: run on the workers
    monkeypatch.setattr(fem.meshing.parametric, "gmsh_problem",
                        lambda: "gmsh is not installed: pip install it")
    stator = Path(__file__).resolve().parents[1] / "examples" / "tuned_60k" / "stator.toml"
    s = study_from_dict({"study": {"stator": str(stator)}, "outputs": ["f_L1_short"]})
    out = tmp_path / "g.nc"
    with pytest.raises(ValueError, match=r"--scheduler: worker .* cannot mesh the "
                                         r"study.stator's features: gmsh is not installed: pip "
                                         r"install it \(on every worker\)"):
        explore(s, out, scheduler=scheduler, progress=False)
    assert not out.exists() and not parts_folder(out).exists()


def test_a_failed_fe_solve_is_recorded_not_fatal():
    # a 5 x 40 mm plate has no B2 (bending along the length) near its L1: the mode solver
    # says so before any solve (fem.modes.WidePlateError, a ModeSolverError), and the study
    # keeps going with NaN and the reason in ``status``
    s = study_from_dict({"outputs": ["f_L1_short", "no_load_velocity"],
                         "axes": {"length": "5 mm", "width": "40 mm"},
                         "solver": {"fe_refine": 1, "duration": "1 ms"}})
    ds = assemble(s, {0: compute_geometry(s, 0)})
    assert str(ds["status"].item()).startswith("FE: WidePlateError: a 5 x 40 mm plate")
    assert np.isnan(ds["f_L1_short"].item()) and np.isnan(ds["no_load_velocity"]).all()
    # its drive points are "failed", as documented (they read "", which a filter missed)
    s = study_from_dict({"outputs": ["f_L1_short", "motion_class"],
                         "axes": {"length": "5 mm", "width": "40 mm"},
                         "solver": {"fe_refine": 1, "duration": "1 ms"}})
    ds = assemble(s, {0: compute_geometry(s, 0)})
    assert set(np.asarray(ds["motion_class"]).ravel()) == {"failed"}


@pytest.mark.slow
def test_steady_method_gives_the_loaded_answers():
    """solver.method = "steady": stall force, peak efficiency and velocity under load, from
    the steady engine; the no-load point agrees with the characteristic's own zero load and
    the velocity falls with the load."""
    s = study_from_dict({
        "outputs": ["no_load_velocity", "stall_force", "peak_efficiency", "velocity",
                    "motion_class"],
        "axes": {"voltage": "300 V", "preload": "6 N", "load": ["0 N", "0.2 N"]},
        "solver": {"fe_refine": 1, "method": "steady"}})
    ds = assemble(s, {0: compute_geometry(s, 0)})
    v0 = float(ds["no_load_velocity"].values.ravel()[0])
    stall = float(ds["stall_force"].values.ravel()[0])
    v = ds["velocity"].values.ravel()
    assert v0 > 0 and stall > 0.2
    assert v[0] == pytest.approx(v0, rel=1e-6) and 0 < v[1] < v[0]
    assert 0 < float(ds["peak_efficiency"].values.ravel()[0]) < 1


@pytest.mark.slow
def test_a_studys_answers_are_the_single_point_commands_bit_for_bit(capsys):
    """A study with the default solver is lusm characteristic --frequency auto and lusm modes
    at the same plate, to the bit: its default mesh was coarser (fe_refine 2 against the
    commands' 4), which put the auto drive frequency 113 Hz and B2 145 Hz high and the stall
    force 11 % low (the test took 5 %). The exact level is the CLI's default too."""
    import json

    from fem.meshing.mesh import DEFAULT_REFINE
    from lusm.cli import main
    from studies.study import SOLVER_DEFAULTS

    assert SOLVER_DEFAULTS["fe_refine"] == DEFAULT_REFINE
    s = study_from_dict({
        "outputs": ["f_B2_short", "no_load_velocity", "stall_force"],
        "axes": {"voltage": "400 V", "preload": "14 N"}})
    ds = assemble(s, {0: compute_geometry(s, 0)})
    assert main(["characteristic", "--source", "fem", "--voltage", "400", "--preload", "14",
                 "--frequency", "auto", "--loads", "0:0.1:0.1", "--json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    assert float(ds["f_drive"].item()) == cli["frequency_Hz"]
    assert float(ds["stall_force"].item()) == cli["stall_force_N"]
    assert float(ds["no_load_velocity"].item()) == cli["no_load_velocity_m_s"]
    assert main(["modes", "--json"]) == 0
    modes = json.loads(capsys.readouterr().out)
    assert float(ds["f_B2_short"].item()) == modes["B2"]["f_short_Hz"]


@pytest.mark.slow
def test_ctrl_c_to_the_process_group_prints_one_line_per_fact(tmp_path):
    # a terminal's Ctrl-C reaches the client and every worker process: only the client may
    # answer (workers printed their KeyboardInterrupt tracebacks, the scheduler its cancelled
    # gathers: 66 lines), and the finished parts are kept for --resume
    import subprocess
    import sys
    import time

    from tests.conftest import ROOT

    path = tmp_path / "study.toml"  # TINY over 40 lengths
    path.write_text("""outputs = ["f_L1_short", "no_load_velocity", "velocity"]
[axes]
length = { start = "28 mm", stop = "32 mm", num = 40 }
width = ["7 mm", "8 mm"]
voltage = ["200 V", "300 V"]
preload = "6 N"
load = ["0 N", "1 N"]
[solver]
fe_order = 2
fe_refine = 1
accuracy = "fast"
""")
    out = tmp_path / "r.nc"
    proc = subprocess.Popen(
        [sys.executable, "-m", "lusm.cli", "explore", str(path), "--out", str(out),
         ], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    parts = parts_folder(out)
    deadline = time.monotonic() + 120
    while not list(parts.glob("g*.npz")) and time.monotonic() < deadline \
            and proc.poll() is None:
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    lines = err.strip().splitlines()
    assert lines[-1] == "lusm explore: interrupted", err
    assert len(lines) == 2 and "--resume" in lines[0], err  # nothing from dask
    assert list(parts.glob("g*.npz")) and not out.exists()


def test_a_studys_contact_solves_are_bounded_in_all():
    # 1000 geometries x 2000 drive points: each bound alone allows it, the 2e6 contact solves
    # together are refused before any work; the same grid without motor outputs is FE only
    axes = {"length": {"start": "28 mm", "stop": "32 mm", "num": 1000},
            "voltage": {"start": "100 V", "stop": "300 V", "num": 2000}}
    with pytest.raises(ValueError, match="2000000 contact solves is above the limit 1000000"):
        study_from_dict({"outputs": ["no_load_velocity"], "axes": axes})
    with pytest.warns(UserWarning, match="axes.voltage is unused: the study asks for FE "):
        assert study_from_dict({"outputs": ["f_B2_open"], "axes": axes}).n_geometries == 1000


@pytest.mark.slow
def test_a_studys_fe_work_is_bounded_in_all():
    """100 000 plates at fe_refine 48 (each mesh within the single-solve bound, the count at
    the geometry limit) had started, days of work, the client at 3.3 GB after a minute. The
    study's elements x solves is now bounded before any work, counted at its largest plate:
    the sum over the plates' own meshes is below that count, and above the limit."""
    import time

    from fem.meshing.mesh import structured_mesh
    from studies.study import MAX_STUDY_FE_WORK

    axes = {"length": {"start": "20 mm", "stop": "40 mm", "num": 1000},
            "width": {"start": "5 mm", "stop": "10 mm", "num": 100}}
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=r"100000 geometries \(FE solves\) x 18865 2D "
                                         r"elements .* above the limit 1e\+07"):
        study_from_dict({"outputs": ["f_L1_short"], "axes": axes,
                         "solver": {"fe_refine": 48}})
    assert time.perf_counter() - t0 < 30  # before any FE work (a bound, not a timing claim)
    # an independent count: the real meshes of a sample of the plates, scaled to the grid
    from fem.geometry import PlateStator

    sample = [structured_mesh(PlateStator(length_m=L * 1e-3, width_m=W * 1e-3), 48).quads.shape[1]
              for L in (20.0, 30.0, 40.0) for W in (5.0, 7.5, 10.0)]
    assert max(sample) <= 18865 and sum(sample) / len(sample) * 100_000 > MAX_STUDY_FE_WORK
    # a stator file's plates are meshed by gmsh at its [mesh] size_mm: the refusal names
    # that, not solver.fe_refine, which does nothing there (review)
    from tests.conftest import ROOT

    with pytest.raises(ValueError, match=r"a coarser mesh of study.stator .*tuned_60k.*"
                                         r"\(its \[mesh\] size_mm or mesh file\)"):
        study_from_dict({"outputs": ["f_L1_short"],
                         "study": {"stator": str(ROOT / "examples/tuned_60k/stator.toml")},
                         "axes": {"length": {"start": "25 mm", "stop": "27 mm", "num": 2000},
                                  "width": {"start": "6 mm", "stop": "7 mm", "num": 40}}})
    # the same grid at the default mesh of a compact plate stays allowed
    axes["length"] = {"start": "28 mm", "stop": "32 mm", "num": 1000}
    axes["width"] = {"start": "7 mm", "stop": "8 mm", "num": 10}
    assert study_from_dict({"outputs": ["f_L1_short"], "axes": axes}).n_geometries == 10_000


def test_a_plates_settling_time_counts_in_its_contact_work():
    """A transient study without solver.duration runs each plate for its settling time: the
    study's bound counts 50 ms per point before any FE solve (and says so), the plate's task
    its own settling time, and the refusal says what to do (a solver.duration or the steady
    engine), not "a shorter solver.duration" of a duration the study never gave."""
    from contact.drive import settling_time_s
    from rom.sources import get_params
    from studies.task import _plate_work_problem, _settled_study

    axes = {"voltage": {"start": "100 V", "stop": "300 V", "num": 20},
            "preload": {"start": "5 N", "stop": "20 N", "num": 20}}
    study = study_from_dict({"outputs": ["no_load_velocity"], "axes": axes,
                             "solver": {"method": "event"}})  # 400 x 5e5 steps: allowed
    assert study.solver.settle
    light = get_params("beam", damping_ratios=(1e-4, 1e-4))  # tau = 1 / (zeta omega): 23 ms
    settle = max(settling_time_s(light, v, p, 40e3) for v in (100.0, 300.0)
                 for p in (5.0, 20.0))
    assert settle > 0.1  # 400 points x over 1e6 steps each: above 4e8, the limit
    settled = _settled_study(study, light, [40e3])
    assert settled.solver.duration_s == pytest.approx(settle, rel=0.05)
    reason = _plate_work_problem(settled, light, [40e3])
    assert reason is not None and "(this plate's settling time 121" in reason
    assert 'points, a solver.duration or method = "steady", or ' in reason
    assert "shorter solver.duration" not in reason
    assert len("failed: " + reason) <= 300  # whole in a point's status
    # the same study counted before any FE solve: 50 ms, at least
    big = {**axes, "voltage": {"start": "100 V", "stop": "300 V", "num": 90}}
    with pytest.raises(ValueError, match=r"x at least 5e\+05 steps each \(each plate's "
                       r"settling time, at least 50 ms before its FE solve, / solver\.dt\)"):
        study_from_dict({"outputs": ["no_load_velocity"], "axes": big,
                         "solver": {"method": "event"}})


def test_a_studys_contact_work_is_bounded_as_lusm_maps_is(monkeypatch):
    """100 voltages x 100 preloads of 2 s event runs (2e11 time steps, hours) were taken where
    lusm map --method transient refuses 4e8; a steady study was allowed 1e6 contact solves
    whatever each cost, where the steady map allows 5e5 solves x steps per drive period."""
    from studies.study import STEADY_MIN_STEPS_PER_PERIOD

    axes = {"voltage": {"start": "1 V", "stop": "100 V", "num": 100},
            "preload": {"start": "1 N", "stop": "100 N", "num": 100}}
    big = {"outputs": ["no_load_velocity"], "axes": axes,
           "solver": {"method": "event", "duration": "2 s"}}
    with pytest.raises(ValueError) as info:
        study_from_dict(big)
    assert str(info.value) == (
        "axes: 1 geometry x 10000 drive points x at least 2e+07 steps each (solver.duration / "
        "solver.dt) = 2e+11 time steps, above the limit 4e+08; use fewer geometries or "
        "axes.voltage/axes.preload points, a shorter solver.duration or larger solver.dt, or "
        "set LUSM_MAX_WORK=N to allow N times more")
    # the steady engine: 1 + 21 solves per drive point (the state from rest, the 21-load
    # characteristic; one more per load other than 0 N), at least 25 steps per period each
    steady = {"outputs": ["no_load_velocity"], "axes": {
        **axes, "preload": {"start": "1 N", "stop": "50 N", "num": 50}, "load": ["0 N", "1 N"]}}
    with pytest.raises(ValueError, match=r"^axes: 1 geometry x 5000 drive points x 23 steady "
                                         r"solves x at least 25 steps per drive period = "
                                         r"2\.88e\+06, above the steady limit 5e\+05; "):
        study_from_dict(steady)
    # the same count as lusm map's; LUSM_MAX_WORK raises it as every work bound
    monkeypatch.setenv("LUSM_MAX_WORK", "500")
    assert study_from_dict(big).n_drive_points == 10_000
    assert study_from_dict(steady).n_drive_points == 10_000
    from contact.steady.periodic_orbit import STEPS_PER_PERIOD

    assert STEADY_MIN_STEPS_PER_PERIOD == STEPS_PER_PERIOD  # written out, not imported
    import inspect

    from contact.characteristic import characteristic
    from studies.study import CURVE_LOADS

    # the loads a study's steady point counts are characteristic's default curve
    assert inspect.signature(characteristic).parameters["points"].default == CURVE_LOADS


def test_a_plates_steady_work_is_bounded_before_its_drive_points(monkeypatch):
    """A steady point's steps per drive period depend on the plate's FE set (416 at 1 kHz on
    this plate, against 25 at 40 kHz): the study's reading counts 25, each plate its own
    before its drive points, as the steady map does before its points."""
    import studies.task as ex

    def no_contact(*args, **kwargs):
        raise AssertionError("a drive point ran")

    monkeypatch.setattr(ex, "motor_answers", no_contact)
    s = study_from_dict({"outputs": ["no_load_velocity"], "solver": {"fe_refine": 1},
                         "axes": {"length": ["28 mm", "30 mm"], "frequency": "1 kHz",
                                  "voltage": {"start": "100 V", "stop": "490 V",
                                              "num": 40}}})
    part = compute_geometry(s, 0)
    status = str(part["status"])
    assert status.startswith("40 drive point(s) failed: axes: 2 geometries x 40 drive points "
                             "x 22 steady solves x "), status
    assert "steps per drive period (this plate's, at axes.frequency 1 kHz) = " in status
    assert status.endswith("above the steady limit 5e+05; use fewer geometries or "
                           "axes.voltage/axes.preload points, a higher axes.frequency, or set "
                           "LUSM_MAX_WORK=N to allow N times more"), status
    assert (part["motion_class"] == "failed").all()


def test_each_fe_mesh_of_a_study_is_bounded_as_modes_bounds_it():
    # a 30 x 1 mm plate at fe_refine 48 (69 120 elements) ran for minutes at 2.8 GB; lusm modes
    # refuses the same plate at once
    from fem.geometry import PlateStator
    from fem.meshing.mesh import grid_lines_m

    x, y = grid_lines_m(PlateStator(length_m=30e-3, width_m=1e-3), 48)
    cells = (len(x) - 1) * (len(y) - 1)
    with pytest.raises(ValueError, match=f"30 x 1 mm plate of the study needs {cells} 2D "
                                         "elements, above the limit 20000"):
        study_from_dict({"axes": {"length": ["28 mm", "30 mm"], "width": ["1 mm", "7 mm"]},
                         "solver": {"fe_refine": 48}})
    assert study_from_dict({"axes": {"width": ["1 mm", "7 mm"]}}).n_geometries == 2


@pytest.mark.slow
def test_a_study_says_which_geometries_failed_and_refuses_when_all_did(scheduler, tmp_path, capsys):
    # every failure sat silently in the dataset's 'status' with exit 0
    from lusm.cli import main

    path = tmp_path / "s.toml"
    path.write_text('outputs = ["f_L1_short"]\n[axes]\nlength = ["10 mm", "30 mm"]\n')
    assert main(["explore", str(path), "--out", str(tmp_path / "a.nc"), "--workers", "1"]) == 0
    out, err = capsys.readouterr()
    assert "1 of 2 geometries did not compute fully" in err and "variable 'status'" in err
    assert "computed on 1 worker, " in out  # it said "on 1 workers"
    path.write_text('outputs = ["f_L1_short"]\n[axes]\nlength = ["10 mm", "11 mm"]\n')
    assert main(["explore", str(path), "--out", str(tmp_path / "b.nc"),
                 "--scheduler", scheduler]) == 2
    err = capsys.readouterr().err.strip()
    assert "no geometry of the study computed fully (2 of 2" in err and "\n" not in err
    # no dataset of NaN at --out (a corrected rerun refused it as existing); the parts, each
    # with its reason, are kept and said to be
    assert not (tmp_path / "b.nc").exists()
    assert len(list(parts_folder(tmp_path / "b.nc").glob("g*.npz"))) == 2
    assert f"kept in {parts_folder(tmp_path / 'b.nc')}" in err
    # the same command again had said "an unfinished run; pass --resume", whose --resume
    # gave the first refusal again: a circle. It is a finished run, and says so
    argv = ["explore", str(path), "--out", str(tmp_path / "b.nc"), "--scheduler", scheduler]
    assert main(argv) == 2
    again = capsys.readouterr().err.strip()
    assert "holds a finished run in which no geometry computed fully" in again
    assert "remove that folder to run a corrected study" in again and "unfinished" not in again
    assert main(argv + ["--resume"]) == 2
    assert "no geometry of the study computed fully (2 of 2" in capsys.readouterr().err


def test_a_torn_part_is_computed_again_not_an_internal_error(tmp_path):
    # a truncated .npz raised zipfile.BadZipFile through --resume: "internal error"
    from studies.parts import part_path, read_part, write_part

    write_part(tmp_path, 0, {"f_L1_short": np.array(1.0), "task_time_s": np.array(0.1)})
    assert read_part(tmp_path, 0)["f_L1_short"] == 1.0
    path = part_path(tmp_path, 0)
    path.write_bytes(path.read_bytes()[:40])
    assert read_part(tmp_path, 0) is None


def test_a_study_of_thick_plates_gets_the_thin_plate_warning(capsys):
    # a 0.6 mm wide, 3 mm thick plate was "ok" without the warning modes gives
    from lusm.commands.explore import _warn_thick

    _warn_thick(study_from_dict({"axes": {"width": ["0.6 mm", "7.5 mm"]}}))
    assert "5 x the study's smallest in-plane size" in capsys.readouterr().err
    _warn_thick(study_from_dict({"axes": {"width": ["6 mm", "7.5 mm"]}}))
    assert capsys.readouterr().err == ""


def test_a_transient_point_that_did_not_settle_is_said_so(tmp_path, capsys):
    # 200 V / 0 N accelerates for longer than 5 ms: its velocity was stored as the steady
    # one without a word (simulate warns of the same run)
    from lusm.commands.explore import _report_failures

    s = study_from_dict({"axes": {"voltage": "200 V", "preload": ["0 N", "14 N"]},
                         "solver": {"method": "event", "duration": "5 ms"}})
    ds = assemble(s, {0: compute_geometry(s, 0)})
    status = str(ds["status"].item())
    # (the plate's light default damping leaves the 14 N point unsettled too)
    assert re.match(r"[12] drive point\(s\) not settled within solver.duration 0.005 s", status)
    assert "200 V, 0 N" in status
    said = _report_failures(ds, tmp_path / "r.nc")  # a warning, not a refusal
    err = capsys.readouterr().err
    assert "did not settle" in err and len(said) == 1 and said[0] in err


@pytest.mark.slow
def test_the_json_summary_carries_the_settling_warning(scheduler, tmp_path, capsys):
    """--json's "warnings" was [] while stderr said drive points had not settled (found by
    exploratory testing): a script reading the JSON could not see it."""
    import json

    from lusm.cli import main

    path = tmp_path / "s.toml"
    path.write_text('outputs = ["no_load_velocity"]\n[axes]\nvoltage = "200 V"\n'
                    'preload = ["0 N", "14 N"]\n[solver]\nfe_refine = 1\nmethod = "event"\n'
                    'duration = "5 ms"\n')
    assert main(["explore", str(path), "--out", str(tmp_path / "r.nc"), "--scheduler", scheduler,
                 "--json"]) == 0
    cap = capsys.readouterr()
    warnings = json.loads(cap.out)["warnings"]
    assert any("did not settle" in w for w in warnings) and "did not settle" in cap.err


@pytest.mark.parametrize("toml, words", [
    ('outputs = ["f_L1_short", "split"]\n[axes]\nthickness = ["3 mm", "50 mm"]\n'
     '[solver]\nfe_refine = 1\nduration = "5 ms"\n',
     ["solver.duration is unused", "thickness up to 50 mm is 6.67 x",
      "1 of 2 geometries did not compute fully"]),
    ('outputs = ["no_load_velocity"]\n[axes]\nvoltage = "700 V"\npreload = "6 N"\n'
     '[solver]\nfe_refine = 1\naccuracy = "fast"\n',
     ["axes.voltage 700 V is above 600 V"]),
])
@pytest.mark.slow
def test_the_json_summary_lists_every_warning_said(scheduler, toml, words, tmp_path, capsys):
    """--json's "warnings" had only the workers' and the failures': the warnings of reading
    the study (an unused solver key), of its plates (thin plate) and of its drive (700 V)
    went to stderr alone (found by exploratory testing). It lists each line stderr says."""
    import json

    from lusm.cli import main

    path = tmp_path / "s.toml"
    path.write_text(toml)
    assert main(["explore", str(path), "--out", str(tmp_path / "r.nc"), "--scheduler", scheduler,
                 "--json"]) == 0
    cap = capsys.readouterr()
    said = [line.split(": warning: ", 1)[1] for line in cap.err.splitlines()
            if line.startswith("lusm explore: warning: ")]
    listed = json.loads(cap.out)["warnings"]
    assert listed == said and len(said) == len(words)
    assert all(w in text for w, text in zip(words, listed, strict=True)), listed


@pytest.mark.slow
def test_resume_refuses_parts_of_another_version_and_recomputes_a_malformed_part(
        study, reference, dask_client, monkeypatch, tmp_path):
    """Parts computed by another lusm version are not mixed into the resumed dataset; a
    part that loads but lacks an array is computed again. The same study under another file
    name (name = the stem) is the same study."""
    import studies.parts

    out = tmp_path / "study.nc"
    with pytest.raises(Interrupt):
        explore(study, out, client=dask_client, progress=False,
                on_part=lambda i: (_ for _ in ()).throw(Interrupt()))
    renamed = study_from_dict({**TINY, "study": {"name": "tiny, copied"}})
    assert renamed.fingerprint == study.fingerprint
    monkeypatch.setattr(studies.parts, "package_version", lambda: "9.9.9")
    with pytest.raises(ValueError, match="--resume: .* was computed by lusm .*this is lusm "
                                         "9.9.9"):
        explore(renamed, out, client=dask_client, progress=False, resume=True)
    # without --resume the version is blamed too, first: another version may read the same
    # file as another study, and "restore the study and pass --resume" could not help
    with pytest.raises(ValueError, match="--out .* was computed by lusm .* remove that "
                                         "folder"):
        explore(renamed, out, client=dask_client, progress=False)
    monkeypatch.undo()
    part = next(parts_folder(out).glob("g*.npz"))
    with np.load(part) as z:
        data = {k: z[k] for k in z.files if k != "velocity"}
    np.savez(part, **data)
    r = explore(renamed, out, client=dask_client, progress=False, resume=True)
    assert (r.reused, r.computed) == (0, study.n_geometries)
    got = open_result(out)
    for name in ("velocity", "f_L1_short", "motion_class"):
        xr.testing.assert_identical(got[name], reference[name])


def test_a_worker_of_another_version_is_refused_by_its_result(study, monkeypatch, tmp_path):
    """check_workers runs once, before the tasks: a worker joining an external scheduler
    later is checked by the lusm version each result carries (here a worker's is made to
    differ, in process)."""
    import studies.explore as ex

    s = study_from_dict({"outputs": ["f_L1_short"], "solver": {"fe_refine": 1}})
    part = compute_geometry(s, 0)
    assert str(part["lusm_version"]) == package_version()
    from distributed import Client

    with Client(processes=False, n_workers=1, threads_per_worker=1,
                dashboard_address=None) as c:
        # the worker (in process here) returns a result stamped by other code
        monkeypatch.setattr(ex, "compute_geometry",
                            lambda st, i: {**_real_compute(st, i), "lusm_version": np.array("1")})
        with pytest.raises(ValueError, match="a worker computed geometry 0 with lusm 1, "):
            explore(s, tmp_path / "r.nc", client=c, progress=False)
    assert not (tmp_path / "r.nc").exists()


def _real_compute(st, i):
    from studies.task import _compute

    return {**_compute(st, i), "task_time_s": np.array(0.0)}


@pytest.mark.slow
def test_a_scheduler_that_is_not_dask_gets_one_line(monkeypatch, tmp_path):
    """A listener that accepts and never answers hung past dask's 10 s timeout (still
    waiting at 45 s); a scheduler file of '{}' was an internal AssertionError."""
    import socket

    import studies.cluster as ex

    monkeypatch.setattr(ex, "CONNECT_DEADLINE_S", 1.0)
    with socket.socket() as srv:
        srv.bind(("127.0.0.1", 0))
        srv.listen(1)
        port = srv.getsockname()[1]
        with pytest.raises(ValueError, match=r"^--scheduler tcp://.*no answer within 1 s"):
            ex.connect(scheduler=f"tcp://127.0.0.1:{port}")
    bad = tmp_path / "s.json"
    bad.write_text("{}")
    with pytest.raises(ValueError, match="^--scheduler-file .*is not a dask scheduler file "
                                         ".*: it has no 'address'"):
        ex.connect(scheduler_file=str(bad))
    # a study file given there had said "cannot connect ... (AssertionError)"
    bad.write_text('outputs = ["f_L1_short"]\n')
    with pytest.raises(ValueError, match="^--scheduler-file .*is not a dask scheduler file "
                                         ".*: not JSON$"):
        ex.connect(scheduler_file=str(bad))
    # a well-formed file whose scheduler is gone still says it cannot connect
    bad.write_text('{"address": "tcp://127.0.0.1:9"}')
    with pytest.raises(ValueError, match="^--scheduler-file .*cannot connect"):
        ex.connect(scheduler_file=str(bad))


def test_a_scheduler_file_that_is_a_folder_is_not_said_to_be_missing(tmp_path):
    """--scheduler-file naming a folder (or a device) was told it "does not exist"."""
    import studies.cluster as ex

    with pytest.raises(ValueError, match=f"^--scheduler-file {tmp_path} is a folder, not a "
                                         "dask scheduler file$"):
        ex.connect(scheduler_file=str(tmp_path))
    with pytest.raises(ValueError, match="^--scheduler-file /dev/null is not a regular file"):
        ex.connect(scheduler_file="/dev/null")
    with pytest.raises(ValueError, match="does not exist$"):
        ex.connect(scheduler_file=str(tmp_path / "gone.json"))


@pytest.mark.slow
def test_a_signal_after_the_dataset_is_written_says_it_is_complete(scheduler, monkeypatch, tmp_path,
                                                                     capsys):
    """A SIGTERM landing just after the dataset was in place said only "interrupted"
    (exit 130), and a rerun then refused the complete file."""
    import lusm.commands.explore as ce
    from lusm.cli import main

    study = tmp_path / "s.toml"
    study.write_text('outputs = ["f_L1_short"]\n[solver]\nfe_refine = 1\n')

    def stop(*_):
        raise KeyboardInterrupt

    monkeypatch.setattr(ce, "_report_failures", stop)
    out = tmp_path / "r.nc"
    assert main(["explore", str(study), "--out", str(out), "--scheduler", scheduler]) == 130
    err = capsys.readouterr().err
    assert f"{out} is complete" in err and open_result(out)["f_L1_short"].size == 1
    assert not parts_folder(out).exists()


@pytest.mark.slow
def test_a_ctrl_c_while_the_cluster_starts_is_not_lost(monkeypatch):
    """The client ignored SIGINT while the LocalCluster started (so that the workers
    inherited the ignore); a Ctrl-C that the kernel delivered to one of dask's threads in
    those seconds was thrown away, and the study ran to the end with exit 0. Now the start
    records it and raises it once the cluster is closed again; the workers still ignore
    SIGINT (the kernel's view, /proc/PID/status)."""
    import distributed

    real = distributed.LocalCluster
    made = []

    def interrupted_start(*args, **kwargs):
        os.kill(os.getpid(), signal.SIGINT)  # lands while the cluster starts
        made.append(real(*args, **kwargs))
        return made[-1]

    monkeypatch.setattr(distributed, "LocalCluster", interrupted_start)
    with pytest.raises(KeyboardInterrupt):
        local_cluster(1)
    assert made and made[0].status.name == "closed"
    monkeypatch.undo()
    if not Path("/proc/self/status").exists():
        return
    from distributed import Client

    cluster = local_cluster(1)
    try:
        with Client(cluster) as c:
            pids = list(c.run(os.getpid).values())
        assert len(pids) == 1  # the size asked for
        pid = pids[0]
        status = Path(f"/proc/{pid}/status").read_text()
        ignored = int(next(ln for ln in status.splitlines()
                           if ln.startswith("SigIgn")).split()[1], 16)
        assert ignored & (1 << (signal.SIGINT - 1))
    finally:
        cluster.close()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


@pytest.mark.slow
def test_a_workers_warning_is_said_once_by_the_client(scheduler, tmp_path, capsys):
    """A 1 mm gap on a 3 mm plate is outside the 2D model's validity: the warning printed on
    the worker's stderr as a raw Python warning with its source line, once per geometry."""
    from lusm.cli import main

    study = tmp_path / "s.toml"
    study.write_text('outputs = ["f_L1_short"]\n[axes]\ngap = "1 mm"\n'
                     'length = ["29 mm", "30 mm"]\n[solver]\nfe_refine = 1\n')
    assert main(["explore", str(study), "--out", str(tmp_path / "r.nc"), "--scheduler",
                 scheduler]) == 0
    err = capsys.readouterr().err
    assert err.count("lusm explore: warning: electrode gap 1 mm exceeds") == 1, err
    assert "GapValidityWarning" not in err


def test_an_interrupt_before_any_geometry_leaves_no_folder_it_made(monkeypatch, tmp_path):
    """`--out new1/sub/x.nc` interrupted while connecting left an empty new1/sub/."""
    import studies.cluster as ex

    def interrupted(*_a, **_k):
        raise KeyboardInterrupt

    monkeypatch.setattr(ex, "connect", interrupted)
    s = study_from_dict({"outputs": ["f_L1_short"], "solver": {"fe_refine": 1}})
    (tmp_path / "mine").mkdir()
    with pytest.raises(KeyboardInterrupt):
        explore(s, tmp_path / "mine" / "new1" / "sub" / "x.nc", progress=False)
    assert [p.name for p in tmp_path.rglob("*")] == ["mine"]


def test_an_fe_only_dataset_carries_no_drive_coordinates():
    """An FE-only study's dataset had voltage, preload and load coordinates and a
    motor_solver attribute, though no contact model ran."""
    s = study_from_dict({"outputs": ["f_L1_short", "split"], "solver": {"fe_refine": 1}})
    ds = assemble(s, {0: compute_geometry(s, 0)})
    assert not {"voltage", "preload", "load", "frequency"} & set(ds.coords)
    assert "motor_solver" not in ds.attrs


@pytest.mark.slow
def test_a_transient_study_runs_as_lusm_simulate_by_default(capsys):
    """method = "event" ran 5 ms at exactly 100 ns where lusm simulate runs 50 ms with a step
    that divides the drive period, and then one 50 ms for every plate where simulate follows
    the set's settling time: the same plate and drive now give simulate's numbers, and the
    dataset records the run length of each plate."""
    import json

    from lusm.cli import main

    s = study_from_dict({"outputs": ["no_load_velocity", "motion_class"],
                         "axes": {"voltage": "200 V", "preload": "14 N"},
                         "solver": {"method": "event"}})
    assert s.solver.settle and json.loads(s.text)["solver"]["settle"]
    ds = assemble(s, {0: compute_geometry(s, 0)})
    assert main(["simulate", "--source", "fem", "--frequency", "auto", "--voltage", "200",
                 "--preload", "14", "--json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    assert float(ds["duration"].item()) == cli["duration_s"] > 0.05
    assert cli["dt_s"] == s.solver.step_s(float(ds["f_drive"].item()))
    assert float(ds["f_drive"].item()) == cli["frequency_Hz"]
    assert float(ds["no_load_velocity"].item()) == cli["steady_velocity_m_s"]
    assert ds["motion_class"].item() == cli["motion"]
    assert ds["status"].item() == "ok"
    assert "dividing the drive period" in ds.attrs["motor_solver"]
    assert "settling time" in ds.attrs["motor_solver"]


def test_a_typed_duration_is_kept_and_a_steady_study_keeps_its_fingerprint():
    """A typed solver.duration runs every plate for it (no per-plate duration); the
    steady engine has no run length, and its canonical text has no settle key, so a study
    written before keeps its fingerprint."""
    import json

    typed = study_from_dict({"outputs": ["no_load_velocity"], "axes": {"voltage": "200 V"},
                             "solver": {"method": "event", "duration": "50 ms"}})
    assert not typed.solver.settle and "settle" not in json.loads(typed.text)["solver"]
    steady = study_from_dict({"outputs": ["no_load_velocity"], "axes": {"voltage": "200 V"}})
    assert not steady.solver.settle and "settle" not in json.loads(steady.text)["solver"]
    assert "duration" not in empty_outputs(typed) and "duration" not in empty_outputs(steady)


@pytest.mark.parametrize("solver, axes, words", [
    # a fixed frequency: each is checked as lusm simulate checks it
    ({"method": "event", "dt": "1 ms"}, {"frequency": "40 kHz"},
     "solver.dt 1 ms must be at most 1/(20 f) = 1.25 us at axes.frequency 40 kHz"),
    ({"method": "event", "duration": "100 us"}, {"frequency": ["40 kHz", "80 kHz"]},
     "solver.duration 100 us must cover at least 10 drive periods, 250 us at axes.frequency "
     "40 kHz"),
    # auto: what no frequency could make valid (10 periods at the most 1/(20 dt) allows)
    ({"method": "event", "dt": "1 ms"}, {},
     "solver.duration 50 ms is shorter than 10 drive periods at every frequency solver.dt "
     "1 ms allows (up to 1/(20 dt) = 50 Hz, axes.frequency auto): give solver.duration >= "
     "200 ms"),
    ({"method": "event", "duration": "0.5 us"}, {},
     "solver.duration 500 ns is shorter than 10 drive periods at every drive frequency up to "
     "10 MHz"),
])
def test_transient_settings_no_point_could_run_are_refused_before_any_work(solver, axes,
                                                                            words):
    """They were refused per drive point after every FE solve, in the library's words
    ('duration_s ... 9.999999999999999e-06'), and a dataset of NaN was written."""
    with pytest.raises(ValueError) as info:
        study_from_dict({"outputs": ["no_load_velocity"], "axes": axes, "solver": solver})
    assert str(info.value) == words or str(info.value).startswith(words), str(info.value)


@pytest.mark.parametrize("solver, axes, words", [
    # auto: the plate's own frequency is known after its FE solve only
    ({"method": "event", "duration": "10 us"}, {},
     "solver.duration 10 us must cover at least 10 drive periods, "),
    # the steady engine's bound depends on the plate's fastest mode (the FE set)
    ({"method": "steady"}, {"frequency": "10 Hz"},
     "axes.frequency 10 Hz is too far below this plate's fastest mode for the steady engine "
     "(solver.method = \"steady\"), which takes "),
])
@pytest.mark.slow
def test_a_study_no_plate_could_run_writes_no_dataset_and_keeps_the_parts(
        solver, axes, words, scheduler, tmp_path, capsys):
    from lusm.cli import main

    path = tmp_path / "s.toml"
    lines = [f'{k} = "{v}"' for k, v in axes.items()]
    path.write_text('outputs = ["no_load_velocity"]\n[axes]\nlength = ["29 mm", "30 mm"]\n'
                    + "\n".join(lines) + "\n[solver]\nfe_refine = 1\n"
                    + "\n".join(f'{k} = "{v}"' for k, v in solver.items()) + "\n")
    out = tmp_path / "r.nc"
    assert main(["explore", str(path), "--out", str(out), "--scheduler",
                 scheduler]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and words in err, err
    assert "no geometry of the study computed fully (2 of 2)" in err
    assert "_s" not in err.split("; no dataset")[0]  # no library parameter names
    assert not out.exists() and f"kept in {parts_folder(out)}" in err
    assert len(list(parts_folder(out).glob("g*.npz"))) == 2


@pytest.mark.slow
def test_a_task_makes_no_semaphore_a_terminated_worker_would_leak():
    """The characteristic's tqdm bar (disabled) made a multiprocessing RLock, a named
    semaphore registered with the client's resource_tracker, in every worker; a worker the
    nanny terminated at a Ctrl-C's close, or one that crashed, never unlinked it, and the
    tracker printed "There appear to be N leaked semaphore objects" after the run (also after
    one that then finished with exit 0). A task now registers none."""
    import subprocess
    import sys

    from tests.conftest import ROOT

    code = """
import multiprocessing
import multiprocessing.resource_tracker as rt
multiprocessing.set_start_method("spawn")  # a LocalCluster worker's (names its semaphores)
made = []
rt.register = lambda name, rtype: made.append(rtype)
from studies.task import compute_geometry
from studies.study import study_from_dict
s = study_from_dict({"outputs": ["stall_force"],
                     "solver": {"fe_refine": 1, "accuracy": "fast"},
                     "axes": {"voltage": "200 V", "preload": "6 N"}})
part = compute_geometry(s, 0)
print(float(part["stall_force"].ravel()[0]) > 0, made)
"""
    run = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split("\n")[0] == "True []", run.stdout


@pytest.mark.slow
def test_a_scheduler_that_cannot_import_lusm_is_refused_in_one_line(tmp_path, capsys):
    """The scheduler unpickles every task: without lusm the first submission ended in
    "internal error: RuntimeError: Error during deserialization of the task graph ... please
    report it" (exit 1). It is asked before any task now."""
    import subprocess
    import sys
    import time

    from lusm.cli import main

    file = tmp_path / "sched.json"
    code = ("import sys\n"
            "for m in ('validation', 'fem', 'rom', 'contact'):\n"
            "    sys.modules[m] = None  # this scheduler cannot import lusm\n"
            f"sys.argv = ['dask-scheduler', '--scheduler-file', {str(file)!r}, '--port', '0',\n"
            "            '--no-dashboard', '--host', '127.0.0.1']\n"
            "from distributed.cli.dask_scheduler import main\n"
            "main()\n")
    proc = subprocess.Popen([sys.executable, "-c", code], cwd=tmp_path,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 60
        while not file.exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        time.sleep(0.5)  # the file is written before the scheduler listens
        study = tmp_path / "s.toml"
        study.write_text('outputs = ["f_L1_short"]\n[solver]\nfe_refine = 1\n')
        out = tmp_path / "r.nc"
        assert main(["explore", str(study), "--out", str(out), "--scheduler-file",
                     str(file)]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1, err
        assert err.startswith("lusm explore: error: --scheduler-file: the dask scheduler "
                              "cannot run lusm (ModuleNotFoundError"), err
        assert "install lusm on the scheduler" in err
        assert not out.exists() and not parts_folder(out).exists()
    finally:
        proc.terminate()
        proc.wait(timeout=30)


@pytest.mark.slow
def test_a_studys_motion_class_is_simulate_steadys(capsys):
    """The study took the steady branch's own word, "dead-zone", where lusm simulate --steady
    says "pure-stick" (and "separated" at 0 V and 0 N) for the same held slider."""
    import json

    from lusm.cli import main

    s = study_from_dict({"outputs": ["motion_class"],
                         "axes": {"voltage": ["0 V", "100 V"], "preload": ["0 N", "14 N"]}})
    ds = assemble(s, {0: compute_geometry(s, 0)})
    got = {}
    for v, p in ((0, 0), (100, 14), (0, 14), (100, 0)):
        assert main(["simulate", "--steady", "--source", "fem", "--frequency", "auto",
                     "--voltage", str(v), "--preload", str(p), "--json"]) == 0
        cli = json.loads(capsys.readouterr().out)["motion"]
        got[v, p] = ds["motion_class"].sel(voltage=float(v), preload=float(p)).item()
        assert got[v, p] == cli, (v, p, got[v, p], cli)
    assert got[0, 0] == "separated" and got[100, 14] == "pure-stick"


@pytest.mark.slow
def test_a_plot_folder_that_cannot_be_written_says_the_dataset_is_complete(
        scheduler, monkeypatch, tmp_path, capsys):
    """--plot /sys/maps failed after the study with only its error: the user was not told
    the dataset at --out had been written."""
    import lusm.commands.explore as ce
    from lusm.cli import main

    def refused(*_a, **_k):
        raise OSError(1, "Operation not permitted")

    study = tmp_path / "s.toml"
    study.write_text('outputs = ["split"]\n[axes]\nlength = ["29 mm", "30 mm"]\n'
                     'width = ["7 mm", "8 mm"]\n[solver]\nfe_refine = 1\n')
    monkeypatch.setattr(ce, "figure_set", refused)  # as a folder the user cannot write
    out = tmp_path / "r.nc"
    assert main(["explore", str(study), "--out", str(out), "--scheduler",
                 scheduler, "--plot", str(tmp_path / "maps")]) == 2
    err = capsys.readouterr().err
    assert f"{out} is complete; the --plot maps were not written" in err
    assert open_result(out)["split"].size == 4


def test_a_study_gives_the_clis_drive_warnings_once(tmp_path, capsys):
    """lusm simulate and characteristic warn above 600 V, above 100 N and at 0 V with 0 N; a
    study of such points said nothing."""
    from lusm.cli import main
    from lusm.commands.explore import _warn_drive

    _warn_drive(study_from_dict({"axes": {"voltage": ["0 V", "200 V", "700 V"],
                                          "preload": ["0 N", "150 N"]}}))
    err = [line.split(" warning: ", 1)[1]
           for line in capsys.readouterr().err.strip().splitlines()]
    assert err == [
        "axes.voltage 700 V is above 600 V: the linear piezoelectric model and the contact "
        "constants were not validated there",
        "axes.preload 150 N is above 100 N: the contact stiffness and friction constants were "
        "not validated there",
        "axes.voltage 0 and axes.preload 0: no drive and no contact force, nothing moves "
        "(motion class 'separated')"], err
    with pytest.warns(UserWarning, match="axes.voltage is unused"):  # drives nothing
        _warn_drive(study_from_dict({"outputs": ["f_L1_short"], "axes": {"voltage": "700 V"}}))
    _warn_drive(study_from_dict({"axes": {"voltage": ["0 V", "200 V"], "preload": "14 N"}}))
    assert capsys.readouterr().err == ""
    # said by the command, before it runs (here it then refuses an existing --out)
    study = tmp_path / "s.toml"
    study.write_text('[axes]\nvoltage = "700 V"\n')
    (tmp_path / "r.nc").write_text("mine")
    assert main(["explore", str(study), "--out", str(tmp_path / "r.nc")]) == 2
    assert "axes.voltage 700 V is above 600 V" in capsys.readouterr().err


def test_the_studys_loads_on_the_curve_cost_no_second_characteristic(monkeypatch):
    """motor_answers called characteristic a second time for the study's loads even when
    they were all on its 21-load curve (0 N always is); the velocities are those of a
    characteristic at the study's loads either way, to the bit."""
    import contact.characteristic as cc
    from contact.model import default_coupling
    from studies.task import Drive, motor_answers

    s = study_from_dict({"outputs": ["velocity"],
                         "solver": {"fe_refine": 1, "accuracy": "fast"},
                         "axes": {"voltage": "300 V", "preload": "6 N"}})
    from fem.geometry import PlateStator
    from fem.mesh_settings import MeshSettings
    from rom.from_fem import fem_params

    params = fem_params(PlateStator(), "pzt8", MeshSettings(2, 1))
    f = 54e3
    real, calls = cc.characteristic, []

    def counted(*a, **k):
        calls.append(a[3])
        return real(*a, **k)

    monkeypatch.setattr(cc, "characteristic", counted)
    ans = motor_answers(params, Drive(300.0, 6.0, f, (0.0,)), s.solver)
    assert calls == [None]  # the curve only
    calls.clear()
    ans2 = motor_answers(params, Drive(300.0, 6.0, f, (0.0, 0.2)), s.solver)
    assert calls == [None, [0.2]]  # the curve, then the load not on it
    monkeypatch.undo()
    direct = cc.characteristic(params, 300.0, 6.0, [0.0, 0.2], frequency_Hz=f,
                               coupling=default_coupling(params)[0], accuracy="fast")
    np.testing.assert_array_equal(ans2["velocity"], direct.velocity_m_s)
    assert ans["velocity"][0] == direct.velocity_m_s[0] > 0


def test_k_eff_long_names_name_their_mode():
    """k_eff_L1's long_name read "L1 effective ... coupling factor of L1 and B2"."""
    s = study_from_dict({"outputs": ["k_eff"], "solver": {"fe_refine": 1}})
    ds = assemble(s, {0: compute_geometry(s, 0)})
    for m in ("L1", "B2"):
        assert ds[f"k_eff_{m}"].attrs["long_name"] == \
            f"effective electromechanical coupling factor of {m}"


def test_a_parts_folder_without_its_study_file_is_not_called_another_studys(tmp_path):
    s = study_from_dict({"outputs": ["f_L1_short"], "solver": {"fe_refine": 1}})
    out = tmp_path / "r.nc"
    parts_folder(out).mkdir()
    with pytest.raises(ValueError, match=r"^--resume: .*r\.nc\.parts has no study\.json, so "
                                         "it is not the parts folder of a lusm explore run"):
        explore(s, out, resume=True, progress=False)
    # without --resume it had said "holds an unfinished run; pass --resume", which then
    # refused it as above (found by exploratory testing); the user's file stays
    (parts_folder(out) / "notes.txt").write_text("mine")
    with pytest.raises(ValueError, match=r"^--out .*r\.nc: .*r\.nc\.parts has no study\.json"):
        explore(s, out, progress=False)
    assert (parts_folder(out) / "notes.txt").read_text() == "mine"


@pytest.mark.slow
def test_an_error_after_finished_geometries_says_they_are_kept(scheduler, monkeypatch, tmp_path,
                                                               capsys):
    """An error exit after some geometries were done said only the error; the parts were
    there for --resume, unsaid (an interrupt says it)."""
    import studies.explore as ex
    from lusm.cli import main

    real, written = ex.write_part, []

    def full_after_one(folder, i, data):
        if written:
            raise OSError(28, "No space left on device")
        written.append(i)
        real(folder, i, data)

    monkeypatch.setattr(ex, "write_part", full_after_one)
    study = tmp_path / "s.toml"
    study.write_text('outputs = ["f_L1_short"]\n[axes]\nlength = ["29 mm", "30 mm"]\n'
                     '[solver]\nfe_refine = 1\n')
    out = tmp_path / "r.nc"
    assert main(["explore", str(study), "--out", str(out), "--scheduler",
                 scheduler]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[0] == (f"lusm explore: 1 finished geometry is kept in {parts_folder(out)}; run "
                      "the same command with --resume to continue once the cause is fixed")
    assert "No space left on device" in err[1] and len(err) == 2


def test_a_study_can_take_the_constant_dynamic_friction():
    """``[solver] ultrasonic_friction = false`` is the single-point commands'
    ``--no-ultrasonic-friction``: the study had no way to say it, while the unsettled-A_N
    warning a worker raises named that switch. The answer is the steady engine's with the
    constant mu_d, to the bit, and differs from Eq. 11's (mu_d,eff < mu_d changes the thrust);
    the warning's remedy is said in the study file's terms."""
    from bounds import Words, said_in
    from contact.model import default_coupling
    from contact.steady.engine import steady_state
    from rom import table2
    from studies.task import STUDY_FORMS, Drive, motor_answers

    params = table2()
    coupling = default_coupling(params)[0]
    answers = {}
    for uf in (True, False):
        s = study_from_dict({"outputs": ["no_load_velocity"],
                             "solver": {"ultrasonic_friction": uf, "accuracy": "fast"}})
        answers[uf] = motor_answers(params, Drive(300.0, 14.0, 40e3, (0.0,)), s.solver)
        direct = steady_state(params, 300.0, 14.0, frequency_Hz=40e3, coupling=coupling,
                              accuracy="fast", ultrasonic_friction=uf)
        assert answers[uf]["no_load_velocity"] == direct.velocity_m_s
    assert answers[False]["no_load_velocity"] != answers[True]["no_load_velocity"]
    remedy = UserWarning(Words("damp L1 more, or {ultrasonic_friction} for a constant mu_d",
                               {"ultrasonic_friction": "set {name} = {value}"},
                               ultrasonic_friction="False"))
    text = said_in(remedy, STUDY_FORMS)
    assert text.endswith("set ultrasonic_friction = false in the study's [solver] for a "
                         "constant mu_d")


@pytest.mark.slow
def test_a_one_plate_study_says_one_geometry(scheduler, tmp_path, capsys):
    # "study 's': 1 geometries (FE outputs only)"
    from lusm.cli import main

    path = tmp_path / "s.toml"
    path.write_text('outputs = ["f_L1_short"]\n[solver]\nfe_refine = 1\n')
    assert main(["explore", str(path), "--out", str(tmp_path / "a.nc"),
                 "--scheduler", scheduler]) == 0
    assert "study 's': 1 geometry (FE outputs only); " in capsys.readouterr().out


@pytest.mark.slow
def test_solver_rest_reaches_every_steady_call(monkeypatch):
    """[solver] rest = "transient" is the commands' --rest transient: the no-load point and
    both characteristics of a drive point take it."""
    import contact.characteristic
    import contact.steady.engine
    from rom import table2
    from studies.study import Solver
    from studies.task import Drive, motor_answers

    seen = []
    real = contact.steady.engine.steady_state

    def spy(*args, **kwargs):
        seen.append(kwargs.get("rest"))
        return real(*args, **kwargs)

    monkeypatch.setattr(contact.steady.engine, "steady_state", spy)
    monkeypatch.setattr(contact.characteristic, "steady_state", spy)
    ans = motor_answers(table2(), Drive(200.0, 14.0, 40e3, (0.0, 0.123)),
                        Solver(rest="transient"))
    assert seen and set(seen) == {"transient"}
    ref = real(table2(), 200, 14, frequency_Hz=40e3, energy=False,
               rest="transient")
    assert ans["no_load_velocity"] == pytest.approx(ref.velocity_m_s, rel=1e-12)


def _synthetic(sizes: dict[str, int]):
    """A study-shaped dataset with the given axis sizes (the others of length 1): the
    no-load velocity varies with every axis, the split with the geometry only."""
    import xarray as xr

    from studies.study import GEOMETRY_AXES

    dims = ["length", "width", "thickness", "gap", "material", "voltage", "preload"]
    coords = {}
    for d in dims:
        n = sizes.get(d, 1)
        if d == "material":
            coords[d] = (d, np.array(["pzt8", "paper"][:n], dtype=object),
                         {"long_name": "stator material"})
        else:
            unit = "m" if d in GEOMETRY_AXES else {"voltage": "V", "preload": "N"}[d]
            coords[d] = (d, np.linspace(1.0, 2.0, n) * (1e-3 if unit == "m" else 100.0),
                         {"units": unit, "long_name": d})
    shape = [sizes.get(d, 1) for d in dims]
    gdims = [d for d in dims if d in GEOMETRY_AXES]
    return xr.Dataset({
        "no_load_velocity": (dims, np.random.default_rng(0).random(shape),
                             {"units": "m/s", "long_name": "v"}),
        "split": (gdims, np.random.default_rng(1).random(shape[:len(gdims)]),
                  {"units": "Hz", "long_name": "split"})}, coords=coords)


@pytest.mark.parametrize("sizes, files", [
    ({"length": 3, "width": 2, "voltage": 2},
     ["no_load_velocity_length_width.png", "split_length_width.png"]),
    ({"length": 3, "voltage": 2}, ["no_load_velocity_length_voltage.png", "split_length.png"]),
    ({"voltage": 3, "preload": 2}, ["no_load_velocity_voltage_preload.png"]),
    ({"thickness": 4}, ["no_load_velocity_thickness.png", "split_thickness.png"]),
    ({"material": 2}, ["no_load_velocity_material.png", "split_material.png"]),
    ({"length": 3, "width": 2, "material": 2},
     ["no_load_velocity_length_width_material.png", "split_length_width_material.png"]),
    ({"voltage": 3, "material": 2},
     ["no_load_velocity_voltage_material.png", "split_material.png"]),
])
@pytest.mark.slow
def test_a_studys_figures_follow_the_axes_that_vary(sizes, files, tmp_path):
    """Maps over length x width where both vary, else over the first two axes along which
    a variable varies, else its curve over the one axis: a study of one length axis (a
    designer's stator at several lengths) drew nothing."""
    from studies.maps import design_maps, drawable_maps

    ds = _synthetic(sizes)
    assert bool(drawable_maps(ds)) == bool(files)
    written = design_maps(ds, tmp_path)
    assert sorted(p.name for p in written) == sorted(files)
    assert all(p.stat().st_size > 1000 for p in written)


@pytest.mark.slow
def test_a_studys_figures_draw_every_material(tmp_path):
    """--plot drew the first material only, and a split that varies with the material alone
    not at all (found by exploratory testing): a curve has a line per material, a map a panel
    per material on one colour scale, and a variable along the materials alone its values
    against their names."""
    from matplotlib.axes import Axes

    from studies.maps import design_maps

    drawn = {"plot": [], "pcolormesh": [], "xticks": []}
    real = {k: getattr(Axes, k) for k in ("plot", "pcolormesh", "set_xticks")}

    def recorded(kind):
        def call(self, *args, **kwargs):
            key = "xticks" if kind == "set_xticks" else kind
            drawn[key].append((args, kwargs))
            return real[kind](self, *args, **kwargs)
        return call

    curves = _synthetic({"voltage": 3, "material": 2})
    maps = _synthetic({"length": 3, "width": 2, "material": 2})
    with pytest.MonkeyPatch.context() as mp:
        for k in real:
            mp.setattr(Axes, k, recorded(k))
        design_maps(curves, tmp_path)
        lines, ticks = list(drawn["plot"]), list(drawn["xticks"])
        drawn["plot"].clear()
        design_maps(maps, tmp_path)
    v = curves["no_load_velocity"].isel(length=0, width=0, thickness=0, gap=0, preload=0)
    # the velocity's two curves (mm/s), then the split against the materials
    assert [kw.get("label") for _a, kw in lines[:2]] == ["pzt8", "paper"]
    for k in range(2):
        np.testing.assert_allclose(lines[k][0][1], v.isel(material=k).values * 1e3)
    np.testing.assert_allclose(lines[2][0][1], curves["split"].values.ravel() * 1e-3)
    assert [list(kw.get("labels", ())) for _a, kw in ticks] == [["pzt8", "paper"]]
    # each variable's map: one panel per material, on the same colour limits
    # (a colour bar draws itself with pcolormesh too)
    panels = [c for c in drawn["pcolormesh"] if c[1].get("shading") == "nearest"]
    assert len(panels) == 4
    for j, name in enumerate(("no_load_velocity", "split")):
        da = maps[name].isel({d: 0 for d in maps[name].dims
                              if d not in ("length", "width", "material")})
        scale = 1e3 if name == "no_load_velocity" else 1e-3
        for k in range(2):
            args, kw = panels[2 * j + k]
            np.testing.assert_allclose(args[2], da.isel(material=k).transpose(
                "length", "width").values * scale)
            if name == "split":  # signed: a diverging scale centred on zero
                top = np.nanmax(np.abs(da.values * scale))
                assert (kw["vmin"], kw["vmax"], kw["cmap"]) == (-top, top, "RdBu_r")
            else:
                assert (kw["vmin"], kw["vmax"]) == (np.nanmin(da.values * scale),
                                                    np.nanmax(da.values * scale))


def test_a_studys_maps_centre_the_split_on_zero_with_units_and_the_extra_maps(tmp_path):
    """A split that changes sign: a diverging scale centred on zero and the zero contour;
    titles name the variable, its meaning and its unit; the peak efficiency and the auto
    drive frequency get maps of their own; the stall force's says it includes the creep
    band."""
    from matplotlib.axes import Axes

    from studies.maps import design_maps

    ds = _synthetic({"length": 3, "width": 3})
    g = ds["split"].dims
    ds["split"] = (g, np.array([[-900.0, -100.0, 400.0], [-500.0, 200.0, 800.0],
                                [-50.0, 600.0, 1200.0]]).reshape(ds["split"].shape),
                   {"units": "Hz", "long_name": "L1-B2 split"})
    ds["f_drive"] = (g, np.full(ds["split"].shape, 40e3), {"units": "Hz", "long_name": "f"})
    ds["peak_efficiency"] = ds["no_load_velocity"].copy().assign_attrs(units="1")
    ds["stall_force"] = ds["no_load_velocity"].copy().assign_attrs(units="N")
    contours, titles = [], []
    real_contour, real_title = Axes.contour, Axes.set_title

    def contour(self, *args, **kwargs):
        contours.append(kwargs.get("levels"))
        return real_contour(self, *args, **kwargs)

    def title(self, text, *args, **kwargs):
        titles.append(text)
        return real_title(self, text, *args, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(Axes, "contour", contour)
        mp.setattr(Axes, "set_title", title)
        written = design_maps(ds, tmp_path)
    assert sorted(p.name for p in written) == sorted(
        f"{n}_length_width.png" for n in ("no_load_velocity", "stall_force", "split",
                                          "peak_efficiency", "f_drive"))
    assert contours == [[0.0]]  # the split's zero contour only
    by_name = {t.split(":")[0]: t for t in titles}
    assert by_name["split"].startswith("split: L1-B2 split (kHz)")
    assert "(%)" in by_name["peak_efficiency"] and "(kHz)" in by_name["f_drive"]
    assert "creep band" in by_name["stall_force"]


@pytest.mark.slow
def test_a_studys_figures_draw_list_axes_in_ascending_order(tmp_path):
    """A list axis may come in any order: the map drew 4 of 9 cells, misplaced, with
    matplotlib's non-monotonic warning, and the curve zigzagged."""
    import warnings

    from matplotlib.axes import Axes

    from studies.maps import design_maps

    ds = _synthetic({"length": 3, "width": 3}).isel(length=[2, 0, 1], width=[1, 2, 0])
    one = _synthetic({"thickness": 3}).isel(thickness=[2, 0, 1])
    curves = []
    plot = Axes.plot

    def recorded(self, x, *args, **kwargs):
        curves.append(np.asarray(x))
        return plot(self, x, *args, **kwargs)

    with warnings.catch_warnings(), pytest.MonkeyPatch.context() as mp:
        warnings.simplefilter("error")  # matplotlib's warning on a non-monotonic map
        mp.setattr(Axes, "plot", recorded)
        written = design_maps(ds, tmp_path) + design_maps(one, tmp_path)
    assert len(written) == 4 and len(curves) == 2
    assert all(np.all(np.diff(x) > 0) for x in curves)


@pytest.mark.parametrize("solver, outputs, words", [
    ({"method": "event", "accuracy": "fast"}, ["no_load_velocity"],
     "solver.accuracy is unused: a setting of the steady engine, and method = 'event'"),
    ({"method": "literal", "rest": "probe"}, ["no_load_velocity"], "solver.rest is unused"),
    ({"method": "steady", "dt": "1 ns"}, ["no_load_velocity"],
     "solver.dt is unused: the steady engine takes its own time step"),
    ({"accuracy": "fast", "rest": "transient"}, ["no_load_velocity"],
     'solver.rest is unused: it decides the start from rest at accuracy = "exact" only'),
    ({"method": "event", "duration": "5 ms"}, ["f_L1_short"],
     "solver.method and solver.duration are unused: the study asks for FE outputs only"),
    ({"accuracy": "fast", "dt": "1 ns", "rest": "probe"}, ["no_load_velocity"],
     'solver.dt is unused: the steady engine takes its own time step; solver.rest is unused: '
     'it decides the start from rest at accuracy = "exact" only'),
])
def test_solver_settings_a_study_does_not_use_are_said(solver, outputs, words):
    """Settings the study's method ignores ran without a word (found by exploratory testing);
    each is now a warning, as the commands warn of options that do nothing. A study that
    uses what it sets stays quiet."""
    import re
    import warnings

    drives = any(o not in FE_OUTPUTS for o in outputs)  # else the axis is unused, and said
    with pytest.warns(UserWarning, match=re.escape(words)):
        study_from_dict({"outputs": outputs, "axes": {"voltage": "200 V"} if drives else {},
                         "solver": solver})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        study_from_dict({"outputs": ["no_load_velocity"], "axes": {"voltage": "200 V"},
                         "solver": {"method": "event", "duration": "5 ms", "dt": "100 ns"}})
        study_from_dict({"outputs": ["no_load_velocity"], "axes": {"voltage": "200 V"},
                         "solver": {"accuracy": "exact", "rest": "transient"}})


@pytest.mark.slow
def test_drive_axes_of_an_fe_only_study_are_said_unused(scheduler, tmp_path, capsys):
    """A study of FE outputs only dropped its drive axes without a word (its dataset has the
    geometry dimensions only), where an unused solver key is said (found by exploratory
    testing). They are named as the file writes them, in its order; a study that drives its
    plates, or names no drive axis, says nothing of them."""
    import warnings

    from lusm.cli import main

    path = tmp_path / "s.toml"
    path.write_text('outputs = ["split", "f_L1_short"]\n[axes]\npreload = "6 N"\n'
                    'voltage = ["200 V", "300 V"]\nload = "1 N"\nfrequency = "auto"\n'
                    '[solver]\nfe_refine = 1\n')
    assert main(["explore", str(path), "--out", str(tmp_path / "r.nc"),
                 "--scheduler", scheduler]) == 0
    err = capsys.readouterr().err
    assert (f"lusm explore: warning: {path}: axes.preload, axes.voltage and axes.load are "
            "unused: the study asks for FE outputs only") in err, err
    assert set(open_result(tmp_path / "r.nc")["split"].dims) == {
        "length", "width", "thickness", "gap", "material"}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        study_from_dict({"outputs": ["split"], "axes": {"length": "30 mm"}})
        # an axis written at its default asks for nothing (review)
        study_from_dict({"outputs": ["split"], "axes": {"frequency": "auto", "load": "0 N"}})
        study_from_dict({"outputs": ["split", "no_load_velocity"],
                         "axes": {"voltage": "200 V"}})


@pytest.mark.slow
def test_the_summary_says_which_axes_make_its_drive_points(scheduler, tmp_path, capsys):
    """"1 geometry x 4 drive points" for one voltage, one preload and four loads read as four
    voltage-preload points, the work bounds' sense of the words (exploratory testing)."""
    from lusm.cli import main

    path = tmp_path / "s.toml"
    path.write_text('outputs = ["no_load_velocity"]\n[axes]\nvoltage = ["200 V", "300 V"]\n'
                    'preload = "14 N"\nload = ["0 N", "0.1 N"]\n'
                    'frequency = ["54 kHz", "55 kHz"]\n[solver]\nfe_refine = 1\n'
                    'method = "event"\nduration = "2 ms"\n')
    assert main(["explore", str(path), "--out", str(tmp_path / "r.nc"),
                 "--scheduler", scheduler]) == 0
    out = capsys.readouterr().out
    assert ("1 geometry x 8 drive points (2 frequencies x 2 voltages x 1 preload x 2 loads)"
            in out)


@pytest.mark.slow
def test_a_second_resume_while_one_runs_is_refused(study, dask_client, tmp_path):
    """Two --resume runs at once had both computed every geometry left (found by
    exploratory testing). A run holds its parts folder's lock: a second one, started while
    the first is between two geometries, is refused before any work, and the first goes on
    to the same dataset as ever; once it ends, the folder is gone with its lock."""
    out = tmp_path / "study.nc"
    with pytest.raises(Interrupt):
        explore(study, out, client=dask_client, progress=False,
                on_part=lambda i: (_ for _ in ()).throw(Interrupt()))
    refusals = []

    def second_run(i):
        if not refusals:
            with pytest.raises(ValueError, match="another lusm explore is running on"):
                explore(study, out, client=dask_client, progress=False, resume=True)
            refusals.append(i)

    r = explore(study, out, client=dask_client, progress=False, resume=True,
                on_part=second_run)
    assert refusals and r.computed == study.n_geometries - 1
    assert out.exists() and not parts_folder(out).exists()


@pytest.mark.slow
def test_a_run_without_resume_never_advises_removing_a_live_runs_parts(dask_client, tmp_path,
                                                                     capsys, monkeypatch):
    """A second run without --resume, started while one ran, said "holds an unfinished run;
    pass --resume to continue it, or remove that folder to start over"; removing it ended the
    running one with all its work (found by exploratory testing). It is refused as a second
    --resume is, before any work and without a word of the running one's parts as its own,
    and the running one goes on to its dataset."""
    from lusm.cli import main
    from lusm.commands import explore as cmd_explore

    path = tmp_path / "s.toml"
    path.write_text('outputs = ["f_L1_short"]\n[axes]\nlength = ["29 mm", "30 mm", "31 mm"]\n'
                    '[solver]\nfe_refine = 1\n')
    out = tmp_path / "r.nc"
    counted = cmd_explore._count_parts
    calls = iter(range(100))  # as if the live run wrote a part between the second's counts
    monkeypatch.setattr(cmd_explore, "_count_parts", lambda f: counted(f) + next(calls))
    seen = []

    def second_run(_i):
        if not seen:
            seen.append(main(["explore", str(path), "--out", str(out)]))
            seen.append(capsys.readouterr().err)

    r = explore(load_study(path), out, client=dask_client, progress=False, on_part=second_run)
    assert seen[0] == 2
    assert seen[1].strip() == (f"lusm explore: error: --out {out}: another lusm explore is "
                               f"running on {parts_folder(out)}; wait for it to finish, or "
                               "choose another --out")
    assert r.computed == 3 and out.exists() and not parts_folder(out).exists()


@pytest.mark.slow
def test_a_run_stopped_after_its_last_part_is_resumed_not_thrown_away(dask_client, tmp_path):
    """Every part written, the dataset not (a signal or a failed write at the end): a rerun
    without --resume had said "no geometry computed fully ... remove that folder", which
    would have thrown the finished work away (review). It says the work is done and --resume
    writes the dataset, computing nothing; another study's folder is named as such."""
    two = study_from_dict({"outputs": ["f_L1_short"], "axes": {"length": ["29 mm", "30 mm"]},
                           "solver": {"fe_refine": 1}})
    out = tmp_path / "two.nc"
    seen = []

    def stop_after_last(i):
        seen.append(i)
        if len(seen) == two.n_geometries:
            raise Interrupt

    with pytest.raises(Interrupt):
        explore(two, out, client=dask_client, progress=False, on_part=stop_after_last)
    with pytest.raises(ValueError, match="holds every geometry of this study, computed .* "
                                         "pass --resume to write it"):
        explore(two, out, client=dask_client, progress=False)
    other = study_from_dict({"outputs": ["f_L1_short"], "axes": {"length": ["29 mm", "31 mm"]},
                             "solver": {"fe_refine": 1}})
    with pytest.raises(ValueError, match="holds the parts of another study"):
        explore(other, out, client=dask_client, progress=False)
    r = explore(two, out, client=dask_client, progress=False, resume=True)
    assert (r.computed, r.reused) == (0, 2) and out.exists()
