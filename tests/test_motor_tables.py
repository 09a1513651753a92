"""The motor tables of a stator file ([damping], [contact], [slider], [friction]): they reach
the parameter set, bad values are refused naming the key, and every printed speed names the
damping behind it."""

from __future__ import annotations

import json
import math
from dataclasses import fields
from pathlib import Path

import pytest

from contact.drive import free_tip_amplitudes
from contact.steady.engine import steady_state
from fem.mesh_settings import MeshSettings
from fem.stator_file import load_stator
from lusm.cli import main
from rom.from_fem import design_base, fem_params, fem_params_from_file
from rom.table2 import table2

ROOT = Path(__file__).resolve().parents[1]
PLATE = "[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n"
REFINE = 2  # coarse FE: these tests check the plumbing of the constants, not the FE
MESH = MeshSettings(refine=REFINE)


def _write(tmp_path, text, name="stator.toml"):
    path = tmp_path / name
    path.write_text(PLATE + text)
    return path


@pytest.fixture(scope="module")
def plain():
    """The plate's FE set with Table 2's constants (the reference for the file's sets)."""
    return fem_params(mesh=MESH)


def test_damping_ratios_reach_the_parameter_set(tmp_path, plain):
    p = fem_params_from_file(_write(tmp_path, "[damping]\nzeta_L1 = 0.01\nzeta_B2 = 0.02\n"),
                             mesh=MESH)
    # C = 2 zeta sqrt(K M), recomputed from the set's own K and M
    assert p.C_l == pytest.approx(2 * 0.01 * math.sqrt(p.K_l * p.M_l), rel=1e-12)
    assert p.C_b == pytest.approx(2 * 0.02 * math.sqrt(p.K_b * p.M_b), rel=1e-12)
    # only the damping changed
    for f in fields(p):
        if f.name not in ("C_l", "C_b", "source"):
            assert getattr(p, f.name) == getattr(plain, f.name), f.name
    assert "[damping] zeta_L1, zeta_B2" in p.source
    # an explicit damping_ratios argument wins over the file
    q = fem_params_from_file(tmp_path / "stator.toml", mesh=MESH, damping_ratios=(0.03, 0.03))
    assert q.zeta_L1 == pytest.approx(0.03) and "given by the caller" in q.source


def test_quality_factor_and_table2_source(tmp_path):
    d = load_stator(_write(tmp_path, "[damping]\nQ_m = 80\n"))
    assert d.damping_ratios == (1 / 160, 1 / 160)
    assert "Q_m = 80" in d.damping_origin
    d = load_stator(_write(tmp_path, '[damping]\nsource = "table2"\n'))
    assert d.damping_ratios is None and "table2" in d.damping_origin
    d = load_stator(_write(tmp_path, '[material]\nname = "paper"\n'))
    assert d.damping_ratios is None and d.damping_origin == "" and d.motor == {}


def test_default_damping_combines_material_and_mount_q(tmp_path):
    """No [damping]: the material's data-sheet Q_m (PZT-8: 1000) and the default mount's
    (300) in series, 1/Q = 1/1000 + 1/300, zeta = 1/(2 Q) in both modes; Q_mount and
    Q_contact in the file take part; a material without Q_m keeps the source's default and
    refuses a mount loss it cannot combine."""
    from fem.stator_file import DEFAULT_Q_MOUNT

    d = load_stator(_write(tmp_path, ""))
    assert DEFAULT_Q_MOUNT == 300.0
    z = 0.5 * (1 / 1000 + 1 / 300)
    assert d.damping_ratios == pytest.approx((z, z), rel=1e-14)
    assert "Q_m = 1000 (data sheet)" in d.damping_origin and "Q = 230.8" in d.damping_origin
    d = load_stator(_write(tmp_path, "[damping]\nQ_mount = 100\nQ_contact = 500\n"))
    z = 0.5 * (1 / 1000 + 1 / 100 + 1 / 500)
    assert d.damping_ratios == pytest.approx((z, z), rel=1e-14)
    assert "[damping] Q_mount = 100" in d.damping_origin
    d = load_stator(_write(tmp_path, '[material]\nname = "pzt5a"\n'))
    z = 0.5 * (1 / 75 + 1 / 300)
    assert d.damping_ratios == pytest.approx((z, z), rel=1e-14)
    with pytest.raises(ValueError, match=r"\[damping\] Q_mount combines with the material"):
        load_stator(_write(tmp_path, '[material]\nname = "paper"\n[damping]\nQ_mount = 100\n'))
    with pytest.raises(ValueError, match=r"Q_mount .* cannot be combined with Q_m"):
        load_stator(_write(tmp_path, "[damping]\nQ_mount = 100\nQ_m = 50\n"))
    with pytest.raises(ValueError, match=r"\[damping\] Q_mount must be a number in"):
        load_stator(_write(tmp_path, "[damping]\nQ_mount = 0\n"))


def test_contact_slider_friction_reach_the_parameter_set(tmp_path):
    text = ("[contact]\nk_contact_N_m = 2.5e7\n[slider]\nM_slider_kg = 0.5\nmu_sd = 0.02\n"
            "[friction]\nmu_s = 0.6\nmu_d = 0.4\na_mu = 0.1\nb_mu_per_m = 2e6\n")
    design = load_stator(_write(tmp_path, text))
    p = design_base(design)
    want = {"k_contact": 2.5e7, "M_slider": 0.5, "mu_sd": 0.02, "mu_s": 0.6, "mu_d": 0.4,
            "a_mu": 0.1, "b_mu": 2e6}
    t2 = table2()
    for f in fields(p):
        if f.name != "source":
            assert getattr(p, f.name) == want.get(f.name, getattr(t2, f.name)), f.name
    assert "[slider] M_slider_kg = 0.5" in p.source
    # a file with only some keys keeps Table 2's others
    q = design_base(load_stator(_write(tmp_path, "[slider]\nM_slider_kg = 1.5\n")))
    assert q.M_slider == 1.5 and q.mu_s == t2.mu_s and q.k_contact == t2.k_contact


BAD = [
    ("[damping]\nzeta_L1 = 0\nzeta_B2 = 0.01",
     r"\[damping\] zeta_L1 must be a number in \[1e-05, 1\)"),
    ("[damping]\nzeta_L1 = 0.01\nzeta_B2 = 1.5", r"\[damping\] zeta_B2 must be a number in"),
    ("[damping]\nzeta_L1 = 0.01", r"\[damping\] zeta_B2 is missing"),
    ("[damping]\nQ_m = 0.3", r"\[damping\] Q_m must be a number in \(0.5, 50000\]"),
    ("[damping]\nQ_m = 100\nzeta_L1 = 0.01", r"\[damping\] Q_m .* cannot be combined"),
    ('[damping]\nsource = "paper"', r'\[damping\] source must be "table2"'),
    ("[damping]\nzeta = 0.01", r"unknown key 'zeta' at \[damping\]"),
    ("[damping]\nzeta_L1 = true\nzeta_B2 = 0.01", r"\[damping\] zeta_L1 must be a number"),
    ("[slider]\nM_slider_kg = -1",
     r"\[slider\] M_slider_kg must be a number in \[0.0001, 100\] kg"),
    ("[slider]\nmass_kg = 1", r"unknown key 'mass_kg' at \[slider\]"),
    ('[contact]\nk_contact_N_m = "stiff"', r"\[contact\] k_contact_N_m must be a number"),
    ("[friction]\nmu_s = 0.3\nmu_d = 0.4", r"\[friction\] mu_d = 0.4 must be <= \[friction\] mu_s"),
    ("[friction]\nmu_d = 0.2\na_mu = 0.3", r"\[friction\] a_mu = 0.3 must be <= \[friction\] mu_d"),
    ("[contact]\nk_contact_N_m = 1e12",
     r"\[contact\] k_contact_N_m must be a number in \[1000, 1e\+10\] N/m, got 1e\+12"),
]


@pytest.mark.parametrize(("text", "match"), BAD)
def test_bad_motor_tables_name_the_key(tmp_path, text, match):
    with pytest.raises(ValueError, match=match):
        load_stator(_write(tmp_path, text))


def test_friction_against_table2_names_the_key(tmp_path):
    """mu_d above Table 2's mu_s passes the file's own checks but makes no valid set."""
    design = load_stator(_write(tmp_path, "[friction]\nmu_d = 0.6\n"))
    with pytest.raises(ValueError, match=r"\[friction\] mu_d must be <= mu_s"):
        design_base(design)
    # mu_s alone below Table 2's mu_d: the file's key, and the base set's for the other
    design = load_stator(_write(tmp_path, "[friction]\nmu_s = 0.2\n", "s.toml"))
    with pytest.raises(ValueError, match=r"the base set's mu_d must be <= \[friction\] mu_s"):
        design_base(design)


def test_free_tip_amplitude_at_resonance_goes_as_one_over_zeta(tmp_path):
    """Free stator, no contact: at each mode's resonance its tip amplitude is A V/(C omega),
    so halving zeta doubles it, and Table 2's ratios give zeta_t2/zeta times less."""
    sets = {z: fem_params_from_file(_write(tmp_path, f"[damping]\nzeta_L1 = {z}\nzeta_B2 = {z}\n",
                                           f"z{z}.toml"), mesh=MESH) for z in (0.005, 0.01)}
    heavy = fem_params(mesh=MESH)
    for mode, f_attr, zeta_attr in ((0, "f_L1_Hz", "zeta_L1"), (1, "f_B2_Hz", "zeta_B2")):
        amp = {z: free_tip_amplitudes(p, getattr(p, f_attr) * math.sqrt(1 - 2 * z * z))[mode]
               for z, p in sets.items()}
        assert amp[0.005] / amp[0.01] == pytest.approx(2.0, rel=1e-3)
        f = getattr(heavy, f_attr)
        z_t2 = getattr(heavy, zeta_attr)
        a_heavy = free_tip_amplitudes(heavy, f)[mode]
        a_light = free_tip_amplitudes(sets[0.01], f)[mode]
        # the other mode's off-resonance response is not part of this mode's amplitude
        assert a_light / a_heavy == pytest.approx(z_t2 / 0.01, rel=1e-3)


def test_lighter_damping_in_the_file_moves_the_slider_faster(tmp_path):
    """In slip-separation (300 V, 5 N) the tip ellipse, hence the speed, goes as ~1/zeta."""
    v = {}
    for z in (0.01, 0.02):
        p = fem_params_from_file(_write(tmp_path, f"[damping]\nQ_m = {1 / (2 * z):g}\n",
                                        f"q{z}.toml"), mesh=MESH)
        from contact.drive import auto_frequency

        v[z] = steady_state(p, 300.0, 5.0, frequency_Hz=auto_frequency(p),
                            accuracy="fast").velocity_m_s
    assert 1.6 < v[0.01] / v[0.02] < 2.4, v


def test_guide_friction_from_the_file_acts_as_a_load(tmp_path):
    """[slider] mu_sd raised by d adds the guide force d (F_P + M g) against the motion, the
    same as an external load of that size on the file's set without the change."""
    from contact.drive import auto_frequency
    from rom.params import GRAVITY_M_S2

    light = "[damping]\nzeta_L1 = 0.01\nzeta_B2 = 0.01\n[slider]\nM_slider_kg = 0.3\n"
    p = fem_params_from_file(_write(tmp_path, light, "a.toml"), mesh=MESH)
    q = fem_params_from_file(_write(tmp_path, light + "mu_sd = 0.06\n", "b.toml"),
                             mesh=MESH)
    assert q.mu_sd == 0.06 and p.mu_sd == table2().mu_sd == 0.04 and p.M_slider == 0.3
    f = auto_frequency(p)
    load = 0.02 * (14.0 + 0.3 * GRAVITY_M_S2)
    moved = steady_state(q, 300.0, 14.0, frequency_Hz=f, accuracy="fast").velocity_m_s
    loaded = steady_state(p, 300.0, 14.0, frequency_Hz=f, accuracy="fast",
                          load_N=load).velocity_m_s
    free = steady_state(p, 300.0, 14.0, frequency_Hz=f, accuracy="fast").velocity_m_s
    assert moved == pytest.approx(loaded, rel=1e-9) and 0 < moved < free


@pytest.mark.slow
def test_cli_names_the_damping_beside_every_speed(tmp_path, capsys):
    light = ROOT / "examples" / "light_damping" / "stator.toml"
    base = ["--voltage", "300", "--preload", "14"]
    assert main(["simulate", "--steady", "--frequency", "auto", "--geometry", str(light),
                 *base]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.startswith("damping"))
    assert "zeta_L1 = 0.01, zeta_B2 = 0.01" in line and "stator file" in line
    assert "[damping] zeta_L1, zeta_B2" in line and "steady_velocity_m_s" in out
    assert main(["characteristic", "--json", "--frequency", "auto", "--geometry", str(light),
                 "--loads", "0:0.2:0.1", *base]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["damping"]["zeta_L1"] == pytest.approx(0.01)
    assert "light_damping" in doc["damping"]["from"]
    assert main(["characteristic", *base, "--loads", "0:0.2:0.1"]) == 0
    out = capsys.readouterr().out
    assert "no-load velocity" in out and "(from Table 2 (Li, Yao & Wu 2016))" in out
    assert main(["map", "--voltages", "300", "--preloads", "14", "--accuracy", "fast",
                 "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["damping"]["zeta_B2"] == pytest.approx(table2().zeta_B2)
    # a saved set names its file; compare names each set's origin
    assert main(["params", "--geometry", str(light), "--json"]) == 0
    saved = tmp_path / "set.json"
    saved.write_text(capsys.readouterr().out)
    assert main(["simulate", "--steady", "--frequency", "auto", "--params", str(saved),
                 "--json", *base]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["damping"]["from"].startswith("params file")
    assert doc["damping"]["zeta_L1"] == pytest.approx(0.01, rel=1e-9)
    assert main(["compare", "--sources", "table2", "fem", "--geometry", str(light),
                 "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert "[damping]" in doc["damping_from"]["fem"] and "Table 2" in doc["damping_from"][
        "table2"]


def test_cli_refuses_a_bad_damping_in_one_line(tmp_path, capsys):
    bad = _write(tmp_path, "[damping]\nQ_m = 0\n")
    assert main(["simulate", "--voltage", "200", "--preload", "14", "--geometry", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "[damping] Q_m" in err and "--geometry" in err
    bad = _write(tmp_path, "[friction]\nmu_d = 0.6\n")
    assert main(["simulate", "--voltage", "200", "--preload", "14", "--geometry", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "[friction] mu_d must be <= mu_s" in err
