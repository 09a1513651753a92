"""Design for degeneracy (fem.tuning), sweeps (fem.sweep) and their CLIs."""

from __future__ import annotations

import json

import numpy as np
import pytest

from fem.geometry import PlateStator
from fem.modes import plate_modes
from fem.sweep import sweep_dimension
from fem.tuning import tune_plate
from validation.cli import main


@pytest.fixture(scope="module")
def tuned():
    return tune_plate(40e3)


def test_tuned_plate_is_degenerate_at_target(tuned):
    st = tuned.stator
    assert st.thickness_m == pytest.approx(3e-3)
    # independent check: a fresh FE solve of the reported design
    res = plate_modes(PlateStator(st.length_m, st.width_m, st.thickness_m))
    f = 40e3
    assert abs(res.L1.f_short_Hz - res.B2.f_short_Hz) / f < 1e-3
    assert res.L1.f_short_Hz == pytest.approx(f, rel=1e-3)
    assert tuned.relative_mismatch < 1e-3
    assert tuned.fe_solves == len(tuned.history) > 0


def test_tuning_from_reversed_mode_order(tuned):
    """Start where B2 lies above L1 (wide plate): same design."""
    start = PlateStator(width_m=12e-3)
    r0 = plate_modes(start)
    assert r0.B2.f_short_Hz > r0.L1.f_short_Hz  # reversed w.r.t. the default plate
    d = tune_plate(40e3, start=start)
    assert d.stator.length_m == pytest.approx(tuned.stator.length_m, rel=1e-4)
    assert d.stator.width_m == pytest.approx(tuned.stator.width_m, rel=1e-4)


def test_scaling_with_thickness_ratio(tuned):
    d = tune_plate(40e3, fix="thickness_ratio")
    # the 2D frequencies depend on h only through the thickness inertia (~(h/l)^2, 7e-4 of
    # L1 at h/l = 0.1): nearly the same planform, h scaled with l
    assert d.stator.length_m == pytest.approx(tuned.stator.length_m, rel=1e-3)
    assert d.stator.thickness_m == pytest.approx(3e-3 * d.stator.length_m / 30e-3, rel=1e-9)


def test_bad_tuning_input():
    with pytest.raises(ValueError, match="target_frequency_Hz"):
        tune_plate(-1.0)
    with pytest.raises(ValueError, match="fix"):
        tune_plate(40e3, fix="width")
    with pytest.raises(ValueError, match="model"):
        tune_plate(40e3, model="1d")


def test_sweep_crossing_matches_tuning_shape():
    res = sweep_dimension("width", np.arange(7.5, 9.01, 0.5) * 1e-3)
    assert np.all(np.isfinite(res.f_L1_short_Hz)) and np.all(np.isfinite(res.f_B2_short_Hz))
    assert np.all(np.diff(res.f_B2_short_Hz) > 0)
    (xc,) = res.crossings_m()
    # at 30 mm the crossing width is the tuned aspect ratio times 30 mm (up to the fixed gap)
    assert 8.0e-3 < xc < 8.5e-3
    with pytest.raises(ValueError, match="parameter"):
        sweep_dimension("thickness", [1e-3])


def test_cli_tune_and_sweep(tmp_path, capsys):
    assert main(["tune", "--target-frequency", "40e3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("length_mm", "width_mm", "thickness_mm", "fe_solves", "L1", "B2"):
        assert key in out
    assert set(out["L1"]) == {"f_short_Hz", "f_open_Hz", "k_eff"}
    assert main(["sweep", "--length-mm", "28:32:2", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "sweep_length.png").stat().st_size > 1000
    capsys.readouterr()
    assert main(["sweep", "--width-mm", "6:5:1"]) == 2
    assert main(["tune", "--target-frequency", "0"]) == 2
