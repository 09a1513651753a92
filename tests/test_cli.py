"""The ``lusm`` command line: output contracts, parity with the library, bad input."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import ROOT, cached_run

MOTIONS = {"slip-separation", "stick-slip", "stick-slip-separation", "pure-stick", "pure-slip"}


def lusm(*args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "lusm.cli", *args],
        cwd=ROOT, capture_output=True, text=True, env=env, timeout=600,
    )


@pytest.mark.slow
def test_simulate_json_matches_the_library():
    out = lusm("simulate", "--voltage", "200", "--preload", "14", "--json")
    assert out.returncode == 0, out.stderr
    d = json.loads(out.stdout)
    for key in ("steady_velocity_m_s", "motion", "stick_fraction", "separation_fraction",
                "mu_d_effective", "steps", "wall_time_s"):
        assert key in d
    assert d["motion"] in MOTIONS
    lib = cached_run(200.0, 14.0)
    # one source of truth: the CLI prints what the library computes
    assert d["steady_velocity_m_s"] == lib.steady.velocity_m_s
    assert d["stick_fraction"] == lib.steady.stick_fraction
    assert d["steps"] == 500_000


@pytest.mark.slow
def test_a_lusm_process_refuses_bad_input_in_one_line_exit_2():
    """Bad input (tests/test_bad_input.py) from a process of its own: its exit code and its
    whole stderr."""
    for args, needle in ((("--voltage", "nan", "--preload", "14"), "--voltage"),
                         (("--voltage", "200", "--preload", "14", "--bogus"), "--bogus")):
        out = lusm("simulate", *args)
        assert out.returncode == 2
        assert "Traceback" not in out.stderr
        lines = [ln for ln in out.stderr.splitlines() if ln.strip()]
        assert len(lines) == 1, out.stderr
        assert needle in lines[0]


@pytest.mark.slow
def test_plot_writes_valid_non_blank_pngs(tmp_path: Path):
    import numpy as np
    from matplotlib.image import imread

    out = lusm("simulate", "--voltage", "400", "--preload", "14", "--duration", "0.005",
               "--plot", str(tmp_path), "--json")
    assert out.returncode == 0, out.stderr
    figs = json.loads(out.stdout)["figures"]
    assert len(figs) == 4
    for f in figs:
        img = imread(f)
        assert img.ndim == 3 and img.shape[0] > 100
        assert float(np.std(img[..., :3])) > 0.01  # not a blank canvas


@pytest.mark.slow
def test_map_json_classifies_every_point():
    out = lusm("map", "--voltages", "0,400", "--preloads", "6,40", "--duration", "0.01",
               "--json")
    assert out.returncode == 0, out.stderr
    d = json.loads(out.stdout)
    motion = d["motion"]
    assert len(motion) == 2 and len(motion[0]) == 2
    assert motion[0] == ["pure-stick", "pure-stick"]  # no voltage: no motion
    assert "stick" in motion[1][1]  # a 40 N preload makes the tip stick part of the time
    assert motion[1][0] in ("slip-separation", "pure-slip")  # 6 N: no stick at 400 V
    v = d["steady_velocity_m_s"]
    assert v[1][0] > v[1][1] > 0.0


@pytest.mark.slow
def test_contact_and_table2_do_not_import_the_fe_stack():
    code = (
        "import sys, contact.simulate, contact.maps, contact.transient.reference, rom.table2, rom;"
        "bad=[m for m in ('skfem','pyvista','vtk','meshio','fem.model','fem.modes') "
        "if m in sys.modules];"
        "print(bad); sys.exit(1 if bad else 0)"
    )
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 0, out.stdout + out.stderr


@pytest.mark.slow
@pytest.mark.benchmark  # a full cold compile; CI's first command starts cold anyway
def test_cold_numba_cache_gives_the_same_answer(tmp_path: Path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba-cache")}
    out = lusm("simulate", "--voltage", "200", "--preload", "14", "--duration", "0.002",
               "--json", env=env)
    assert out.returncode == 0, out.stderr
    warm = lusm("simulate", "--voltage", "200", "--preload", "14", "--duration", "0.002",
                "--json")
    assert json.loads(out.stdout)["steady_velocity_m_s"] == json.loads(warm.stdout)[
        "steady_velocity_m_s"]
    assert any((tmp_path / "numba-cache").rglob("*.nbi"))  # the cold run wrote its cache


@pytest.mark.slow
def test_simulate_runs_any_parameter_set_at_its_own_frequency():
    from contact.drive import auto_frequency
    from rom.from_fem import fem_params_from_file

    path = ROOT / "examples" / "tip_protrusion" / "stator.toml"
    out = lusm("simulate", "--voltage", "300", "--preload", "5", "--geometry", str(path),
               "--frequency", "auto", "--duration", "0.005", "--json")
    assert out.returncode == 0, out.stderr
    d = json.loads(out.stdout)
    params = fem_params_from_file(path)
    assert d["frequency_Hz"] == pytest.approx(auto_frequency(params), rel=1e-12)
    # the operating point lies between the set's own L1 and B2 resonances (widened by 20 %)
    lo, hi = sorted((params.f_L1_Hz, params.f_B2_Hz))
    assert 0.8 * lo <= d["frequency_Hz"] <= 1.2 * hi
    assert "tip_protrusion" in d["source"]
    bad = lusm("simulate", "--voltage", "200", "--preload", "14", "--geometry",
               str(ROOT / "no-such-stator.toml"))
    assert bad.returncode == 2 and "not found" in bad.stderr


def test_modes_refuses_plate_options_next_to_a_stator_file():
    path = ROOT / "examples" / "chamfered" / "stator.toml"
    out = lusm("modes", "--geometry", str(path), "--width-mm", "8")
    assert out.returncode == 2
    assert "--width-mm cannot be combined with --geometry" in out.stderr


def test_compare_takes_the_designers_stator(capsys):
    """``lusm compare --length-mm 36``: the fem column is the longer plate's (L1 ~ 1/l)."""
    import json

    from lusm.cli import main

    assert main(["compare", "--sources", "fem", "--json"]) == 0
    base = json.loads(capsys.readouterr().out)["values"]["fem"]
    assert main(["compare", "--sources", "fem", "--length-mm", "36", "--json"]) == 0
    long = json.loads(capsys.readouterr().out)["values"]["fem"]
    assert long["f_L1_Hz"] / base["f_L1_Hz"] == pytest.approx(30 / 36, rel=0.03)


def test_modes_prints_the_split_and_the_identification(capsys):
    """``lusm modes``: the L1-B2 split a designer tunes away, MAC and symmetry of each mode
    (issue 13), in text and JSON, consistent with the library's result."""
    from fem.geometry import PlateStator
    from fem.modes import plate_modes
    from lusm.cli import main

    assert main(["modes", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    r = plate_modes(PlateStator())
    assert d["split_rel"] == pytest.approx(r.B2.f_short_Hz / r.L1.f_short_Hz - 1, rel=1e-12)
    assert d["mac"] == pytest.approx({"L1": r.L1.mac, "B2": r.B2.mac})
    assert all(0.9 < m <= 1.0 for m in d["mac"].values())
    assert d["length_mm"] == 30.0 and d["width_mm"] == 7.5
    assert main(["modes"]) == 0
    text = capsys.readouterr().out
    assert f"{d['split_rel']:+.3%}" in text and "MAC" in text
    # and in Hz, which a tuned stator's +0.000% had hidden
    assert f"({r.B2.f_short_Hz - r.L1.f_short_Hz:+.1f} Hz)" in text


def test_version(capsys):
    from lusm.cli import main

    assert main(["--version"]) == 0
    assert capsys.readouterr().out.startswith("lusm ")


def test_map_text_shows_the_velocities_of_its_json(capsys):
    """The map's text had only motion classes; its velocities were in --json alone."""
    import numpy as np

    from lusm.cli import main

    argv = ["map", "--voltages", "100,300", "--preloads", "10,14"]
    assert main(argv + ["--json"]) == 0
    v = np.array(json.loads(capsys.readouterr().out)["steady_velocity_m_s"])
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    at = lines.index(next(ln for ln in lines if ln.startswith("slider velocity (mm/s)")))
    rows = [[float(x) for x in ln.split()[1:]] for ln in lines[at + 2:at + 4]]
    np.testing.assert_allclose(rows, v * 1e3, rtol=1e-3)


def test_simulate_energy_prints_every_term_of_the_balance(capsys):
    """``lusm simulate --energy`` printed only the residual; its text now gives each term
    --json gives, equal to it, and they close: input - damping + the interface and guide
    terms + the load's work = the change of stored energy + the residual. Without a load,
    the load's work is 0 J, not -0."""
    from lusm.cli import main

    argv = ["simulate", "--voltage", "200", "--preload", "14", "--duration", "0.01",
            "--energy"]
    assert main(argv) in (0, None)
    text = {ln[len("energy "):30].strip(): ln[30:].strip()
            for ln in capsys.readouterr().out.splitlines() if ln.startswith("energy ")}
    assert main([*argv, "--json"]) in (0, None)
    e = json.loads(capsys.readouterr().out)["energy"]
    for key, value in e.items():
        shown = text["residual (rel.)" if key == "relative_residual" else key]
        digits = 3 if key == "relative_residual" else 6  # as printed
        assert float(shown) == pytest.approx(value, rel=10.0 ** (1 - digits), abs=1e-300)
    assert text["load_J"] == "0"
    total = (e["input_J"] - e["damping_J"] + e["normal_on_stator_J"]
             + e["tangential_on_stator_J"] + e["tangential_on_slider_J"] + e["guide_J"]
             + e["load_J"])
    assert total - e["delta_energy_J"] == pytest.approx(e["residual_J"], abs=1e-12)


def test_materials_lists_every_named_material(capsys):
    """``lusm materials --json`` has a row per name of ``fem.material.MATERIAL_NAMES`` with
    its key constants, Q_m and limits; the text table has a line per material."""
    from fem.material import MATERIAL_NAMES
    from lusm.cli import main

    assert main(["materials", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)["materials"]
    assert [r["name"] for r in rows] == list(MATERIAL_NAMES)
    for r in rows:
        assert {"rho_kg_m3", "s11E_m2_N", "d31_C_N", "k31", "N31_Hz_m", "mechanical_Q",
                "limits", "source", "cE_Pa"} <= set(r)
        assert r["limits"]["drive_field_V_m"] > 0 and r["source"]
    assert main(["materials", "--json"]) == 0
    tips = json.loads(capsys.readouterr().out)["tip_materials"]
    assert [t["name"] for t in tips] == ["alumina", "steel"]
    assert main(["materials"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert all(any(line.startswith(n + " ") for line in out) for n in MATERIAL_NAMES)
