"""``--uncertainty``: a calibration's covariance stored in the calibrated file and carried to
the steady engine's predictions by Monte Carlo (:mod:`calibration.uncertainty`).

The draws must follow the stored covariance (a linear prediction's spread is ``g Sigma g^T``
exactly), hold the parameters that are not identifiable, and give a speed's spread that
agrees with the linearised one ``J Sigma J^T`` (finite differences) within the Monte Carlo
error where the covariance is small. The calibrated files must carry the fit so that
``simulate --steady``, ``characteristic`` and ``map`` can draw from it.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from calibration.uncertainty import Calibration, from_table, propagate, read_calibration
from lusm.cli import main
from rom.table2 import table2


def _cal(cov, names=("C_l", "a_mu"), held=()) -> Calibration:
    p = table2()
    allnames = (*names, *held)
    return Calibration(names=allnames, values=np.array([getattr(p, n) for n in allnames]),
                       stderr=np.sqrt(np.r_[np.diag(cov), [np.inf] * len(held)]),
                       identifiable=(True,) * len(names) + (False,) * len(held),
                       reasons=("",) * len(names) + ("correlation",) * len(held),
                       covariance=np.asarray(cov, dtype=float))


def test_a_linear_prediction_spreads_as_the_covariance_says():
    """std of g . x over the draws is sqrt(g Sigma g^T) within the Monte Carlo error; a held
    parameter keeps its value in every draw."""
    cov = np.array([[4.0, 0.006], [0.006, 2.5e-5]])  # C_l +/- 2, a_mu +/- 0.005, r = 0.6
    g = np.array([1.0, 400.0])
    cal = _cal(cov, held=("b_mu",))
    band = propagate(cal, table2(), lambda p: [g @ [p.C_l, p.a_mu], p.b_mu], samples=2000)
    want = np.sqrt(g @ cov @ g)
    assert band.std[0] == pytest.approx(want, rel=3 / np.sqrt(2 * 1999))
    assert band.std[1] == 0.0 and band.mean[1] == table2().b_mu
    assert band.held == ("b_mu",) and band.sampled == ("C_l", "a_mu")
    assert band.low[0] < band.mean[0] < band.high[0]
    from calibration.uncertainty import DEFAULT_SAMPLES
    from lusm.uncertainty import DEFAULT_SAMPLES as CLI_DEFAULT  # repeated: --help lacks NumPy

    assert CLI_DEFAULT == DEFAULT_SAMPLES
    # the table round trip, as the files carry it
    back = from_table(json.loads(json.dumps(cal.to_table(json_ready=True))), "x")
    assert back.held == ("b_mu",) and np.array_equal(back.covariance, cal.covariance)


@pytest.mark.slow
def test_the_spread_of_a_speed_is_the_linearised_one():
    """Table 2 at 300 V, 14 N (paper's coupling), C_l and a_mu correlated: the Monte Carlo
    standard deviation of the steady speed agrees with sqrt(J Sigma J^T), J from central
    differences, within three of its standard errors (1 / sqrt(2 (N - 1)) relative)."""
    from calibration.bands import speed_band, steady_speed_m_s

    cov = np.array([[4.0, 0.006], [0.006, 2.5e-5]])
    p = table2()
    engine = {"coupling": "paper"}

    def speed(q):
        return steady_speed_m_s(q, 300.0, 14.0, 40e3, **engine)

    h = np.sqrt(np.diag(cov))
    jac = np.array([(speed(p.with_(C_l=p.C_l + h[0])) - speed(p.with_(C_l=p.C_l - h[0]))),
                    (speed(p.with_(a_mu=p.a_mu + h[1])) - speed(p.with_(a_mu=p.a_mu - h[1])))
                    ]) / (2 * h)
    want = np.sqrt(jac @ cov @ jac)
    n = 96
    band = speed_band(_cal(cov), p, [300.0], 14.0, 40e3, samples=n, **engine)
    assert band.std[0] == pytest.approx(want, rel=3 / np.sqrt(2 * (n - 1)))
    assert band.mean[0] == pytest.approx(speed(p), abs=3 * want / np.sqrt(n))


@pytest.mark.slow
def test_the_commands_give_bands_on_a_calibrated_file(tmp_path, capsys):
    """A free-amplitude calibration of C_l, C_b (mu_d not identifiable) writes its fit into
    the parameter file; simulate --steady, characteristic and map draw from it, and a run
    with another coupling than the fit's is warned of."""
    from tests.test_calibration import DAMPINGS, _free_csv, _toml

    _free_csv(tmp_path / "free.csv", 4)
    meas = _toml(tmp_path, DAMPINGS + "mu_d = { start = 0.3, min = 0.2, max = 0.5 }\n")
    out = tmp_path / "cal.json"
    assert main(["calibrate", str(meas), "--source", "table2", "--out", str(out),
                 "--starts", "1", "--profile", "none"]) == 0
    capsys.readouterr()
    cal = read_calibration(out)
    assert cal.sampled == ("C_l", "C_b") and cal.held == ("mu_d",)
    assert cal.covariance.shape == (2, 2)
    drive = ["--params", str(out), "--frequency", "40e3", "--json"]
    assert main(["simulate", "--steady", "--voltage", "300", "--preload", "14", *drive,
                 "--uncertainty", "8"]) == 0
    got = capsys.readouterr()
    assert "ran the steady engine with" not in got.err  # the fit's own coupling
    u = json.loads(got.out)["uncertainty"]
    assert u["samples"] == 8 and u["held"] == ["mu_d"]
    v = u["velocity_m_s"]
    assert v["q2.5"] <= v["mean"] <= v["q97.5"] and v["std"] > 0
    assert main(["characteristic", "--voltage", "300", "--preload", "14", "--loads", "0,0.5",
                 *drive, "--uncertainty", "2"]) == 0
    u = json.loads(capsys.readouterr().out)["uncertainty"]
    assert u["stall_force_N"]["std"] > 0 and len(u["velocity_m_s"]["mean"]) == 2
    assert main(["map", "--voltages", "300", "--preloads", "14", *drive,
                 "--uncertainty", "2"]) == 0
    u = json.loads(capsys.readouterr().out)["uncertainty"]
    assert np.array(u["velocity_m_s"]["std"]).shape == (1, 1)
    assert u["velocity_relative_std"][0][0] > 0
    # another coupling than the fit's is said
    assert main(["simulate", "--steady", "--voltage", "300", "--preload", "14", *drive,
                 "--coupling", "paper", "--uncertainty", "2"]) == 0
    assert "pass --coupling consistent" in capsys.readouterr().err


def test_the_report_section_names_the_fit():
    """The design report's "Calibration" section: values, standard errors, what is not
    identifiable and why, chi-square per degree of freedom."""
    from dataclasses import replace

    from validation.report_calibration import calibration_section

    cal = replace(_cal(np.diag([4.0, 2.5e-5]), held=("b_mu",)), chi2=46.2, dof=46,
                  coupling="paper")
    md, data = calibration_section(cal, "--geometry cal.toml", 6)
    text = "\n".join(md)
    assert md[0] == "## 6. Calibration" and "--coupling paper" in text
    assert "| C_l | 173 | 2 | N s/m | yes |" in text
    assert "| b_mu | 1e+06 | - | 1/m | no: correlation |" in text
    assert data["reduced_chi2"] == pytest.approx(46.2 / 46) and data["held"] == ["b_mu"]


def test_the_report_reads_the_fit_of_a_calibrated_stator_file(tmp_path):
    """lusm report's reading of --geometry: the [calibration] table's fit, None without one,
    a malformed table refused naming --geometry."""
    from lusm.commands.report import _calibration
    from lusm.errors import LusmError

    plate = "[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n"
    (tmp_path / "plain.toml").write_text(plate)
    assert _calibration(str(tmp_path / "plain.toml")) is None
    (tmp_path / "cal.toml").write_text(
        plate + '[calibration]\nnames = ["C_l", "a_mu"]\nvalues = [173.0, 0.15]\n'
        "stderr = [2.0, inf]\nidentifiable = [true, false]\n"
        'reasons = ["", "correlation"]\ncovariance = [[4.0]]\nchi2 = 10.0\ndof = 8\n')
    cal = _calibration(str(tmp_path / "cal.toml"))
    assert cal.held == ("a_mu",) and cal.dof == 8
    (tmp_path / "bad.toml").write_text(plate + '[calibration]\nnames = ["C_l"]\n'
                                       "values = [1.0]\nidentifiable = [true]\n"
                                       "covariance = [[-1.0]]\nstderr = [1.0]\n")
    with pytest.raises(LusmError, match="positive semi-definite"):
        _calibration(str(tmp_path / "bad.toml"))
