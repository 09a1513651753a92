"""Physical limits of an operating point (contact.operating_limits), the default drive
frequency of a designer's set, and the limits warning said before the results."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from contact.operating_limits import (
    STRESS_COMBINED,
    branch_amplitudes_m,
    free_amplitudes_m,
    limits_from_amplitudes,
    operating_limits,
)
from fem.beam_shapes import phi_B
from fem.mode_peaks import combined_factors
from rom.beam import beam_params
from rom.beam_stator import BeamStator
from rom.shape_data import ShapeData, beam_combined_stress_Pa
from rom.table2 import table2


def test_beam_limits_equal_a_hand_calculation():
    """On a beam set: L1's stress is E times the rod's strain at its node, u pi / l; B2's is
    E times the edge fibre's bending strain (b/2) |phi_B''| w at the largest curvature; the
    antinode velocity is omega times the amplitude at the free end; the field V/h."""
    beam = BeamStator(length_m=40e-3, width_m=10e-3, thickness_m=2.5e-3)
    p = beam_params(beam)
    omega, u, w = 2 * math.pi * 45e3, 3e-7, 2e-7
    lim = limits_from_amplitudes(p, 250.0, omega, (u, 0.0), "test")
    e = beam.cE11_Pa
    assert lim.values["stress"] == pytest.approx(e * u * math.pi / beam.length_m, rel=1e-12)
    assert lim.values["vibration_velocity"] == pytest.approx(omega * u, rel=1e-12)
    assert lim.values["drive_field"] == pytest.approx(250.0 / 2.5e-3, rel=1e-15)
    # B2 alone: the curvature's largest value found independently (a fine grid, refined)
    y = np.linspace(0.0, beam.length_m, 200001)
    curv = np.max(np.abs(phi_B(y, beam.length_m, 2)))
    lim_b = limits_from_amplitudes(p, 250.0, omega, (0.0, w), "test")
    assert lim_b.values["stress"] == pytest.approx(e * 0.5 * beam.width_m * curv * w,
                                                   rel=1e-6)
    ends = max(abs(phi_B(0.0, beam.length_m)), abs(phi_B(beam.length_m, beam.length_m)))
    assert lim_b.values["vibration_velocity"] == pytest.approx(omega * w * ends, rel=1e-9)
    # both: the velocity is the larger mode's; the stress is the two combined over the
    # period (L1's peak at mid-length, B2's where it bends most: apart, so below the peaks'
    # sum, which stays beside it as the bound), the beam's own combination within the
    # tabulation's linear interpolation, which bounds it from above
    both = limits_from_amplitudes(p, 250.0, omega, (u, w), "test")
    total = lim.values["stress"] + lim_b.values["stress"]
    assert both.stress_bound_Pa == pytest.approx(total, rel=1e-12)
    exact = beam_combined_stress_Pa(beam.length_m, lim.values["stress"], lim_b.values["stress"])
    assert exact <= both.values["stress"] <= 1.002 * exact
    assert both.values["stress"] < 0.99 * total
    assert lim.stress_bound_Pa == lim.values["stress"]
    # harmonic modes dissipate omega^2 C U^2 / 2 each; the ceramic (PZT-8, Q_m = 1000)
    # takes its own loss's share 1/(2 Q_m zeta) of each, over the volume l b h
    p_l, p_b = 0.5 * omega**2 * p.C_l * u**2, 0.5 * omega**2 * p.C_b * w**2
    assert both.values["dissipated_power"] == pytest.approx(p_l + p_b, rel=1e-12)
    heat = p_l * 0.5e-3 / p.zeta_L1 + p_b * 0.5e-3 / p.zeta_B2
    assert both.values["power_density"] == pytest.approx(heat / (40e-3 * 10e-3 * 2.5e-3),
                                                         rel=1e-12)
    assert math.isnan(both.limits["dissipated_power"]) and both.limits["power_density"] == 5e5
    # PZT-8's limits (beam theory takes the paper's PZT-8), the ratio and the JSON form
    assert both.limits["stress"] == 24e6
    d = both.to_dict()
    assert d["stress"]["ratio"] == pytest.approx(both.values["stress"] / 24e6)
    assert set(d["stress"]) == {"value", "limit", "ratio", "unit", "basis", "sum_of_peaks"}
    assert d["stress"]["basis"] == STRESS_COMBINED
    assert d["stress"]["sum_of_peaks"] == pytest.approx(total, rel=1e-12)


def test_combined_stress_against_a_hand_calculation():
    """Two stress fields at two points: peaks at one point and in phase add (the combined
    stress is the peaks' sum, factor 1); peaks at different points do not (factor
    max(1 - t, t)); two perpendicular uniaxial stresses at one point give the principal
    stresses of diag(1 - t, t); a shear and a normal stress at one point give Mohr's circle,
    (1 - t)/2 + sqrt((1 - t)^2/4 + t^2)."""
    t = np.linspace(0.0, 1.0, 21)
    one, zero = np.array([1.0, 0.0]), np.zeros(2)
    same = combined_factors((one, zero, zero), (2 * one, zero, zero))
    assert same == pytest.approx(np.ones(21), abs=1e-15)
    apart = combined_factors((one, zero, zero), (one[::-1], zero, zero))
    assert apart == pytest.approx(np.maximum(1 - t, t), abs=1e-15)
    cross = combined_factors((one, zero, zero), (zero, one, zero))
    assert cross == pytest.approx(np.maximum(1 - t, t), abs=1e-15)
    shear = combined_factors((one, zero, zero), (zero, zero, -one))
    assert shear == pytest.approx((1 - t) / 2 + np.sqrt((1 - t) ** 2 / 4 + t**2), abs=1e-15)
    # the set's stress: the sum times the factor at B2's share, the sum without factors
    shape = replace(table2().shape, combined_stress=(1.0, 0.5, 1.0))
    s_l, s_b = shape.stress_L1_Pa_m, shape.stress_B2_Pa_m
    u, w = 1e-7, 1e-7 * s_l / s_b  # equal peaks: B2's share 1/2
    assert shape.stress_Pa(u, w) == pytest.approx(0.5 * 2 * s_l * u, rel=1e-12)
    assert shape.stress_bound_Pa(u, w) == pytest.approx(2 * s_l * u, rel=1e-12)
    assert replace(shape, combined_stress=None).stress_Pa(u, w) == shape.stress_bound_Pa(u, w)
    assert ShapeData.from_dict(shape.to_dict()) == shape
    old = shape.to_dict()
    del old["combined_stress"]  # a parameter file written without it
    assert ShapeData.from_dict(old).combined_stress is None


@pytest.mark.slow
def test_fe_combined_stress_lies_between_the_larger_peak_and_the_sum():
    """On the FE plate, L1's and B2's stress fields combined: 1 at either mode alone, below
    the sum between (their peaks lie apart) and never below the larger single peak."""
    from fem.material import get_material
    from fem.mesh_settings import MeshSettings
    from fem.mode_peaks import combined_stress_factors
    from fem.model import plate_model
    from fem.modes import plate_modes

    mat = get_material("pzt8")
    modes = plate_modes(None, mat, MeshSettings(1, 2))
    model = plate_model(None, mat, MeshSettings(1, 2))
    k = np.array(combined_stress_factors(model, modes.L1.shape, modes.B2.shape))
    t = np.linspace(0.0, 1.0, len(k))
    assert k[0] == pytest.approx(1.0) and k[-1] == pytest.approx(1.0)
    assert np.all(k <= 1.0) and np.all(k >= np.maximum(1 - t, t) - 1e-12)
    assert k.min() < 0.95


def test_branch_amplitudes_come_from_the_damper_powers():
    """A harmonic modal velocity of amplitude omega U dissipates C omega^2 U^2 / 2: the
    amplitudes are recovered from a branch's powers."""
    p, omega, u, w = table2(), 2 * math.pi * 40e3, 4e-7, 6e-7

    class Branch:
        damping_power_B2_W = 0.5 * p.C_b * (omega * w) ** 2
        damping_power_W = 0.5 * p.C_l * (omega * u) ** 2 + damping_power_B2_W

    assert branch_amplitudes_m(p, Branch(), omega) == pytest.approx((u, w), rel=1e-12)


@pytest.mark.slow
def test_steady_branches_of_table2_give_limits_below_the_free_response():
    """The steady engine's branch at the paper's 400 V / 14 N: the damper powers split into
    the two modes, amplitudes below the free stator's (the contact loads the modes)."""
    from contact.steady.engine import steady_state

    p = table2()
    r = steady_state(p, 400.0, 14.0, frequency_Hz=40e3)
    b = r.from_rest
    assert 0.0 < b.damping_power_B2_W < b.damping_power_W
    lim = operating_limits(p, 400.0, 40e3, b)
    free = free_amplitudes_m(p, 400.0, 2 * math.pi * 40e3)
    assert lim.basis == "steady state"
    assert all(0.0 < a < f for a, f in zip(lim.amplitudes_m, free, strict=True))
    assert lim.values["drive_field"] == pytest.approx(400.0 / 3e-3)


def _run(args, cwd, env_extra=None):
    env = {**os.environ, "PYTHONUNBUFFERED": "1", **(env_extra or {})}
    return subprocess.run([sys.executable, "-m", "lusm.cli", *args], cwd=cwd, env=env,
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          timeout=300)


PLATE = ("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n"
         "[material]\nname = \"pzt8\"\n")


@pytest.mark.slow
def test_a_q200_stator_at_400_V_is_warned_of_before_its_results(tmp_path):
    """A stator of Q_m = 200 at 400 V / 14 N, driven at its own operating point by
    default, goes beyond the ceramic's limits: one warning line, before the first result
    line (stdout and stderr unbuffered in one stream)."""
    (tmp_path / "q200.toml").write_text(PLATE + "[damping]\nQ_m = 200\n")
    out = _run(["simulate", "--geometry", "q200.toml", "--voltage", "400", "--preload", "14",
                "--steady"], tmp_path)
    assert out.returncode == 0, out.stdout
    lines = out.stdout.splitlines()
    beyond = [i for i, line in enumerate(lines) if "beyond the ceramic's limits" in line]
    first_result = next(i for i, line in enumerate(lines) if line.startswith("source"))
    assert len(beyond) == 1 and beyond[0] < first_result
    assert "warning:" in lines[beyond[0]] and "> limit" in lines[beyond[0]]


@pytest.mark.slow
def test_default_frequency_follows_the_stator_and_table2_keeps_40_kHz(tmp_path):
    """Without --frequency a stator file is driven at its own operating point (auto), names
    a damping of its material, and carries limits; Table 2's set keeps the paper's 40 kHz;
    a typed --frequency is kept."""
    from contact.drive import auto_frequency
    from rom.from_fem import fem_params_from_file

    (tmp_path / "plate.toml").write_text(PLATE)
    out = _run(["simulate", "--geometry", "plate.toml", "--voltage", "300", "--preload", "14",
                "--steady", "--json"], tmp_path)
    doc = json.loads(out.stdout[out.stdout.index("{"):])
    want = auto_frequency(fem_params_from_file(tmp_path / "plate.toml"))
    assert doc["frequency_Hz"] == pytest.approx(want, rel=1e-9)
    assert "Q_m = 1000" in doc["damping"]["from"] and "Table 2" not in doc["damping"]["from"]
    assert set(doc["limits"]) >= {"vibration_velocity", "stress", "drive_field",
                                  "dissipated_power", "power_density"}
    out = _run(["simulate", "--geometry", "plate.toml", "--voltage", "300", "--preload", "14",
                "--steady", "--json", "--frequency", "40e3"], tmp_path)
    assert json.loads(out.stdout[out.stdout.index("{"):])["frequency_Hz"] == 40e3


def test_table2_default_frequency_is_the_papers(capsys):
    from lusm.cli import main

    assert main(["simulate", "--voltage", "200", "--preload", "14", "--steady", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["frequency_Hz"] == 40e3
    assert doc["limits"]["drive_field"]["value"] == pytest.approx(200 / 3e-3)


def test_the_combined_beam_stress_against_hand_calculations():
    """One mode alone gives its own peak; in phase the two add point by point, below the
    peaks' sum (L1's peak at mid-length, where B2 does not bend), above either; in
    quadrature at each point sqrt(a^2 + c^2); no phase exceeds the in-phase figure."""
    from rom.shape_data import beam_combined_stress_Pa

    length = 30e-3
    assert beam_combined_stress_Pa(length, 7e6, 0.0) == pytest.approx(7e6, rel=1e-12)
    assert beam_combined_stress_Pa(length, 0.0, 38e6) == pytest.approx(38e6, rel=1e-12)
    y = np.linspace(0.0, length, 20001)
    a = 7e6 * np.abs(np.sin(np.pi * y / length))
    curv = np.abs(phi_B(y, length, 2))
    c = 38e6 * curv / curv.max()
    inphase = beam_combined_stress_Pa(length, 7e6, 38e6)
    assert inphase == pytest.approx(float(np.max(a + c)), rel=1e-12)
    assert 38e6 < inphase < 45e6
    assert beam_combined_stress_Pa(length, 7e6, 38e6, math.pi / 2) == pytest.approx(
        float(np.max(np.hypot(a, c))), rel=1e-12)
    assert max(beam_combined_stress_Pa(length, 7e6, 38e6, p)
               for p in np.linspace(0, 2 * math.pi, 37)) == pytest.approx(inphase, rel=1e-12)
