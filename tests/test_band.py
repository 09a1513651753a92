"""Every mode in a band (fem.band): complete against the dense spectrum, named by its shape."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as sl

from fem.band import band_modes, bending_shape, count_below, default_band_Hz
from fem.beam_shapes import phi_B
from fem.geometry import PlateStator
from fem.mesh_settings import MeshSettings
from fem.model import plate_model
from fem.modes import modal_assurance, modes_of_model, sign_changes
from fem.solid3d.model import modes_of_solid_model, solid_model

TUNED_WIDTH_MM = 9.531995236379645
"""The width ``lusm tune --fix length`` gives issue 38's stator (L1 = B2 = 47 840 Hz in 2D)."""


def _dense_Hz(K, M) -> np.ndarray:
    """The whole spectrum (Hz) of dense ``K x = w^2 M x``."""
    w = sl.eigh(K, M, eigvals_only=True)
    return np.sign(w) * np.sqrt(np.abs(w)) / (2.0 * math.pi)


def _ops(modes) -> dict[str, float]:
    return {"L1": modes.L1.f_short_Hz, "B2": modes.B2.f_short_Hz}


def _check_complete(band, f_all: np.ndarray) -> None:
    """Every eigenvalue of the dense spectrum in the band appears once, at its frequency."""
    want = np.sort(f_all[(f_all >= band.f_min_Hz) & (f_all <= band.f_max_Hz)])
    got = np.array([m.f_short_Hz for m in band.modes])
    assert got.size == want.size == band.counted
    np.testing.assert_allclose(got, want, rtol=1e-7)


def test_bending_shape_is_the_free_free_beam_mode():
    length = 0.03
    y = np.linspace(0.0, length, 401)
    b2 = bending_shape(2, y, length)
    assert modal_assurance(b2, phi_B(y, length)) == pytest.approx(1.0, abs=1e-9)
    for n in (1, 2, 3, 4, 6, 9):
        assert sign_changes(bending_shape(n, y, length)) == n + 1
        # free ends: the slope's integral is the shape's change end to end
        d = bending_shape(n, y, length, derivative=1)
        change = np.sum(0.5 * (d[1:] + d[:-1]) * np.diff(y))
        shape = bending_shape(n, y, length)
        assert change == pytest.approx(shape[-1] - shape[0], rel=1e-4)


def test_2d_band_is_the_dense_spectrum_with_names():
    model = plate_model(PlateStator(), "pzt8", MeshSettings(2, 2))
    band = band_modes(model, 10e3, 150e3, _ops(modes_of_model(model)))
    _check_complete(band, _dense_Hz(model.K.toarray(), model.M.toarray()))
    names = [m.name for m in band.modes]
    assert names[:6] == ["B1", "B2", "L1", "B3", "L2", "B4"]
    assert [m.operating for m in band.modes].count(True) == 2
    l1 = band.modes[names.index("L1")]
    ref = modes_of_model(model).L1
    assert l1.f_open_Hz == pytest.approx(ref.f_open_Hz, rel=1e-9)
    assert l1.k_eff == pytest.approx(ref.k_eff, rel=1e-7)


def test_3d_band_is_the_dense_spectrum_with_names():
    model = solid_model(PlateStator(), "pzt8", MeshSettings(2, 1, 2))
    t = model.potential_map(False)
    kup = (model.Kuphi @ t).toarray()
    kpp = (t.T @ model.Kphiphi @ t).toarray()
    kc = model.Kuu.toarray() + kup @ np.linalg.solve(kpp, kup.T)  # potentials condensed
    f_all = _dense_Hz(0.5 * (kc + kc.T), model.M.toarray())
    pair = modes_of_solid_model(model)
    band = band_modes(model, 20e3, 100e3, _ops(pair))
    _check_complete(band, f_all)
    assert [m.name for m in band.modes] == ["T1", "B1", "OB2", "T2", "B2", "L1", "OB3", "T3",
                                            "B3", "OB4"]
    for m in band.modes:
        in_plane = m.name[0] in "LB"
        assert (m.in_plane > 0.9) == in_plane
    by_name = {m.name: m for m in band.modes}
    assert by_name["L1"].f_short_Hz == pytest.approx(pair.L1.f_short_Hz, rel=1e-9)
    assert by_name["B2"].k_eff == pytest.approx(pair.B2.k_eff, rel=1e-6)
    # below every mode: the six rigid-body modes only
    assert count_below(model, 1e3) == 6


def test_risk_window_flags_neighbours_not_the_pair():
    model = plate_model(PlateStator(), "pzt8", MeshSettings(2, 2))
    ops = _ops(modes_of_model(model))
    lo, hi = default_band_Hz(ops)
    assert (lo, hi) == pytest.approx((0.8 * ops["B2"], 1.2 * ops["L1"]))
    wide = band_modes(model, 10e3, 150e3, ops, risk_pct=60.0)
    assert [m.name for m in wide.risks] == ["B1", "B3"]  # L2, B4: 98 %, 112 % above L1
    narrow = band_modes(model, 10e3, 150e3, ops)
    assert narrow.risks == ()
    d = narrow.to_dict()
    assert d["counted"] == len(d["modes"]) and d["operating_Hz"] == ops


def test_empty_band_and_bad_band():
    model = plate_model(PlateStator(), "pzt8", MeshSettings(2, 2))
    band = band_modes(model, 30e3, 31e3, {"L1": 56e3})
    assert band.modes == () and band.counted == 0
    with pytest.raises(ValueError, match="f_min_Hz < f_max_Hz"):
        band_modes(model, 31e3, 30e3, {})


@pytest.mark.slow
@pytest.mark.benchmark
def test_designer_stator_3d_neighbours(tmp_path):
    """The issue's stator: 3D modes at 42.8 and 51.2 kHz around the 47.84 kHz pair."""
    from fem.stator_file import load_stator

    path = tmp_path / "designer.toml"
    from tools.doc_numbers import BAND_DESIGNER_TOML

    path.write_text(BAND_DESIGNER_TOML.replace("width_mm = 8.0",
                                               f"width_mm = {TUNED_WIDTH_MM!r}"),
                    encoding="utf-8")
    design = load_stator(path)
    model = solid_model(design.stator, design.material, MeshSettings(2, 3, 3))
    ops = _ops(modes_of_solid_model(model))
    band = band_modes(model, *default_band_Hz(ops), ops)
    assert band.counted == len(band.modes) == 4
    got = [(m.name, round(m.f_short_Hz / 100.0) / 10.0) for m in band.modes]
    assert got == [("OB3", 42.8), ("B2", 47.8), ("L1", 47.8), ("T3", 51.2)]
    assert not band.risks


def test_cli_band_table_json_and_risk_warning(capsys):
    """``lusm modes --band``: the table, ``band_modes`` in JSON, risks warned of."""
    import json

    from lusm.cli import main

    assert main(["modes", "--refine", "2", "--band", "10:150", "--risk-pct", "60"]) == 0
    cap = capsys.readouterr()
    assert "every mode of the 2D model in 10000-150000 Hz: 8" in cap.out
    lines = {ln.split()[0]: ln for ln in cap.out.splitlines() if ln[:2] in ("B1", "L1", "B3")}
    assert lines["L1"].endswith("operating") and lines["B1"].endswith("RISK")
    assert "--band: B1 (in-plane bending) at 24350 Hz lies -55.1% from B2" in cap.err
    assert main(["modes", "--refine", "2", "--band", "0.02MHz:100000Hz", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)["band_modes"]
    assert (d["f_min_Hz"], d["f_max_Hz"]) == (20e3, 100e3)
    assert [m["name"] for m in d["modes"]] == ["B1", "B2", "L1", "B3"] and d["counted"] == 4
    assert main(["modes", "--refine", "2", "--band", "--json"]) == 0  # the pair +- 20 %
    d = json.loads(capsys.readouterr().out)["band_modes"]
    assert d["f_min_Hz"] == pytest.approx(0.8 * d["operating_Hz"]["B2"])


@pytest.mark.parametrize("argv, option", [
    (["--band", "50:40"], "--band"), (["--band", "40kHz:x"], "--band"),
    (["--band", "1:2:3"], "--band"), (["--band", "0:10"], "--band"),
    (["--band", "10:20", "--risk-pct", "0"], "--risk-pct"), (["--risk-pct", "3"], "--risk-pct")])
def test_cli_band_refuses_bad_input(capsys, argv, option):
    from lusm.cli import main

    assert main(["modes", *argv]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and option in err


@pytest.mark.parametrize("name", ["tuned_40k", "tuned_60k", "tip_parametric", "chamfered",
                                  "tip_protrusion"])
def test_the_examples_pair_is_named_l1_and_b2(name):
    """On every example stator (2D, default mesh) the band's modes named L1 and B2 are the
    identified pair, and every mode of the default band is there."""
    from pathlib import Path

    from fem.modes import plate_modes
    from fem.stator_file import load_stator

    design = load_stator(Path(__file__).resolve().parents[1] / "examples" / name
                         / "stator.toml")
    pair = plate_modes(design.stator, design.material)
    model = plate_model(design.stator, design.material)
    band = band_modes(model, *default_band_Hz(_ops(pair)), _ops(pair))
    by = {m.name: m for m in band.modes}
    assert by["L1"].f_short_Hz == pytest.approx(pair.L1.f_short_Hz, rel=1e-9)
    assert by["B2"].f_short_Hz == pytest.approx(pair.B2.f_short_Hz, rel=1e-9)
    assert by["L1"].operating and by["B2"].operating
    assert band.counted == len(band.modes)
