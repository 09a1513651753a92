"""Physics of the Appendix A beam-theory parameter set (rom.beam)."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fem.beam_shapes import BETA2_L
from rom.beam import (
    ELECTRODE_LAYOUTS,
    Electrode,
    b2_stiffness_readings,
    beam_constants,
    beam_frequencies,
    beam_params,
    euler_bernoulli_b2_frequency,
)
from rom.beam_stator import BeamStator
from rom.params import MotorParams
from rom.table2 import table2
from rom.timoshenko import timoshenko_b2_frequency

GEOM = BeamStator()
"""The paper's plate (Table 1: BeamStator's defaults)."""

dims = st.floats(min_value=1e-3, max_value=0.2)
moduli = st.floats(min_value=1e9, max_value=5e11)


@given(l_=dims, b=dims, h=dims, rho=st.floats(1e3, 2e4), c11=moduli)
@settings(max_examples=30, deadline=None)
def test_L1_mass_and_rod_frequency(l_: float, b: float, h: float, rho: float, c11: float):
    c = beam_constants(BeamStator(l_, b, h, rho, c11, 3e10, -5.0))
    assert c.M_l == pytest.approx(rho * b * h * l_ / 2.0, rel=1e-12)
    assert c.K_l / c.M_l == pytest.approx((math.pi / l_) ** 2 * c11 / rho, rel=1e-12)


@given(l_=dims, b=dims, h=dims, rho=st.floats(1e3, 2e4), c11=moduli)
@settings(max_examples=30, deadline=None)
def test_B2_euler_bernoulli_frequency_is_analytic(l_, b, h, rho, c11):
    p = beam_params(BeamStator(l_, b, h, rho, c11, 3e10, -5.0))
    inertia, area = h * b**3 / 12.0, b * h
    expected = BETA2_L**2 / (2 * math.pi * l_**2) * math.sqrt(c11 * inertia / (rho * area))
    # The printed beta2 l = 2.499753 pi is the root to ~1e-7, so the Rayleigh quotient of
    # the Eq. 3 shape matches the closed form to ~1e-6.
    assert p.f_B2_Hz == pytest.approx(expected, rel=1e-5)
    f_eb = euler_bernoulli_b2_frequency(BeamStator(l_, b, h, rho, c11))
    assert f_eb == pytest.approx(expected, rel=1e-12)


def test_B2_mass_of_eq3_shape():
    # Eq. 3 is the standard free-free shape scaled by -alpha2, whose mean square is 1.
    from fem.beam_shapes import ALPHA2

    c = beam_constants(replace(GEOM, e31_C_m2=-5.2))
    rho_a_l = GEOM.rho_kg_m3 * GEOM.width_m * GEOM.thickness_m * GEOM.length_m
    assert c.M_b == pytest.approx(rho_a_l * ALPHA2**2, rel=1e-5)


def test_doubling_thickness_doubles_masses_and_stiffnesses():
    one = beam_constants(replace(GEOM, e31_C_m2=-5.2))
    two = beam_constants(replace(GEOM, thickness_m=2 * GEOM.thickness_m, e31_C_m2=-5.2))
    for name in ("M_l", "K_l", "M_b", "K_b_bending", "K_b_shear", "K_b_timoshenko"):
        assert getattr(two, name) == pytest.approx(2 * getattr(one, name), rel=1e-12), name
    # E3 = V0/h halves while the driven volume doubles: the force factors do not change.
    assert two.A_l == pytest.approx(one.A_l, rel=1e-12)
    assert two.A_b == pytest.approx(one.A_b, rel=1e-12)
    p1, p2 = beam_params(GEOM), beam_params(replace(GEOM, thickness_m=2 * GEOM.thickness_m))
    assert p2.f_L1_Hz == pytest.approx(p1.f_L1_Hz, rel=1e-12)
    assert p2.f_B2_Hz == pytest.approx(p1.f_B2_Hz, rel=1e-12)


@pytest.mark.parametrize("factor", [0.5, 2.0, 3.0])
def test_length_scaling(factor: float):
    p1 = beam_params(GEOM)
    p2 = beam_params(replace(GEOM, length_m=factor * GEOM.length_m))
    assert p2.f_L1_Hz == pytest.approx(p1.f_L1_Hz / factor, rel=1e-12)
    assert p2.f_B2_Hz == pytest.approx(p1.f_B2_Hz / factor**2, rel=1e-9)


def test_width_scaling_of_bending():
    # f_B2 (Euler-Bernoulli) ~ sqrt(I/A) ~ b; f_L1 independent of b.
    p1 = beam_params(GEOM)
    p2 = beam_params(replace(GEOM, width_m=2 * GEOM.width_m))
    assert p2.f_B2_Hz == pytest.approx(2 * p1.f_B2_Hz, rel=1e-9)
    assert p2.f_L1_Hz == pytest.approx(p1.f_L1_Hz, rel=1e-12)


def test_force_factors_from_electrodes():
    e31 = -5.2
    b = GEOM.width_m
    c14 = beam_constants(replace(GEOM, e31_C_m2=e31), electrode_layout="quadrants-1-4")
    c23 = beam_constants(replace(GEOM, e31_C_m2=e31), electrode_layout="quadrants-2-3")
    full = beam_constants(replace(GEOM, e31_C_m2=e31), electrode_layout="full")
    # L1: both diagonal quadrants act; half width each over the full length in total.
    assert c14.A_l == pytest.approx(e31 * (b / 2) * (-1.0 - 1.0), rel=1e-12)
    assert c23.A_l == pytest.approx(c14.A_l, rel=1e-12)
    assert full.A_l == pytest.approx(2 * c14.A_l, rel=1e-12)
    # B2: the other diagonal flips the sign; a full-width electrode cannot bend.
    assert c14.A_b != 0.0
    assert c23.A_b == pytest.approx(-c14.A_b, rel=1e-12)
    assert full.A_b == pytest.approx(0.0, abs=1e-12 * abs(c14.A_b))
    # Antisymmetry of B2: one quadrant alone gives half of the diagonal pair.
    one = beam_constants(replace(GEOM, e31_C_m2=e31),
                         electrode_layout=[Electrode(0, 0.5, 0, 0.5)])
    assert one.A_b == pytest.approx(c14.A_b / 2, rel=1e-6)
    # Reversing the polarity reverses both force factors.
    neg = [Electrode(e.y_start, e.y_stop, e.x_start, e.x_stop, -1.0)
           for e in ELECTRODE_LAYOUTS["quadrants-1-4"]]
    cn = beam_constants(replace(GEOM, e31_C_m2=e31), electrode_layout=neg)
    assert (cn.A_l, cn.A_b) == pytest.approx((-c14.A_l, -c14.A_b), rel=1e-12)


def test_beam_params_takes_contact_from_base_and_damping_ratios():
    base = table2().with_(k_contact=2e7, M_slider=0.3)
    p = beam_params(base=base, damping_ratios=(0.01, 0.02))
    assert isinstance(p, MotorParams)
    assert (p.k_contact, p.M_slider, p.mu_s, p.mu_d) == (2e7, 0.3, base.mu_s, base.mu_d)
    assert (p.zeta_L1, p.zeta_B2) == pytest.approx((0.01, 0.02), rel=1e-12)
    default = beam_params()
    t2 = table2()
    assert (default.zeta_L1, default.zeta_B2) == pytest.approx((t2.zeta_L1, t2.zeta_B2))
    assert default.eta_N == pytest.approx(2.0)
    assert default.eta_T == pytest.approx(t2.eta_T)


def test_timoshenko_lowers_b2_and_tends_to_euler_bernoulli():
    f = beam_frequencies(GEOM)
    assert f.f_B2_params_Hz == f.f_B2_euler_bernoulli_Hz
    # Shear flexibility and rotary inertia only lower the frequency.
    assert f.f_B2_timoshenko_Hz < f.f_B2_condensed_Hz < f.f_B2_euler_bernoulli_Hz
    # Slender limit: stiff shear and no rotary inertia recover Euler-Bernoulli.
    slender = timoshenko_b2_frequency(replace(GEOM, cE66_Pa=1e6 * GEOM.cE11_Pa),
                                      rotary_inertia=False)
    assert slender == pytest.approx(f.f_B2_euler_bernoulli_Hz, rel=1e-4)
    # A long beam (l/b = 100) is nearly Euler-Bernoulli even with shear and rotary inertia.
    long_beam = replace(GEOM, length_m=100 * GEOM.width_m)
    f_t = timoshenko_b2_frequency(long_beam)
    f_eb = euler_bernoulli_b2_frequency(long_beam)
    assert f_t == pytest.approx(f_eb, rel=2e-3)
    assert f_t < f_eb


def test_timoshenko_option_is_consistent():
    c = beam_constants(replace(GEOM, e31_C_m2=-5.2))
    p = beam_params(GEOM, b2_stiffness="timoshenko")
    assert 1 / p.K_b == pytest.approx(1 / c.K_b_bending + 1 / c.K_b_shear, rel=1e-12)
    # The static tip deflection per volt A_b/K_b is the same as with Euler-Bernoulli
    # scaled by the ratio of compliances: the piezo moment strains the bending part only.
    assert p.A_b / p.K_b == pytest.approx(c.A_b / c.K_b_bending, rel=1e-12)
    assert beam_frequencies(GEOM, b2_stiffness="timoshenko").f_B2_params_Hz == pytest.approx(
        p.f_B2_Hz, rel=1e-12)


def test_readings_of_A4_are_all_reported():
    r = b2_stiffness_readings(GEOM)
    assert len(r) == 4
    assert all(v > 0 for v in r.values())


@pytest.mark.parametrize(
    "name", ["length_m", "width_m", "thickness_m", "rho_kg_m3", "cE11_Pa", "cE66_Pa"]
)
@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf])
def test_bad_inputs_name_the_parameter(name: str, bad: float):
    with pytest.raises(ValueError, match=rf"{name}.*\(0, inf\)"):
        replace(GEOM, **{name: bad})


def test_other_bad_inputs():
    with pytest.raises(ValueError, match="e31_C_m2"):
        BeamStator(e31_C_m2=math.nan)
    with pytest.raises(ValueError, match="electrode_layout"):
        beam_params(electrode_layout="quadrants-1-2")
    with pytest.raises(ValueError, match="zeta_B2"):
        beam_params(damping_ratios=(0.1, 1.5))
    with pytest.raises(ValueError, match="damping_ratios"):
        beam_params(damping_ratios=(0.1,))
    with pytest.raises(ValueError, match="b2_stiffness"):
        beam_params(b2_stiffness="rayleigh")
    with pytest.raises(ValueError, match="y_start"):
        Electrode(0.6, 0.5, 0.0, 0.5)
    with pytest.raises(ValueError, match="x_start"):
        Electrode(0.0, 0.5, 0.0, 0.7)
    with pytest.raises(ValueError, match="degree"):
        timoshenko_b2_frequency(degree=2)


def test_a_plate_drive_maps_onto_the_same_beam_regions():
    """The FE plate's electrodes (1, 2 at x > 0; 1, 3 in the preload half) as beam
    electrodes: (1, 4) is the paper's layout, (2, 3) the other diagonal, whose bending force
    factor has the opposite sign; compare's beam column kept (1, 4) for a plate driving 2, 3."""
    from rom.beam import ELECTRODE_LAYOUTS, beam_params, plate_layout

    assert plate_layout((1, 4)) == ELECTRODE_LAYOUTS["quadrants-1-4"]
    assert set(plate_layout((2, 3))) == set(ELECTRODE_LAYOUTS["quadrants-2-3"])
    a, b = beam_params(electrode_layout=plate_layout((1, 4))), beam_params(
        electrode_layout=plate_layout((2, 3)))
    assert b.A_b == pytest.approx(-a.A_b, rel=1e-12) and b.A_l == pytest.approx(a.A_l)
    with pytest.raises(ValueError, match="1..4"):
        plate_layout((5,))


def test_compare_drives_the_beam_through_the_plates_electrodes(tmp_path, capsys):
    import json

    from lusm.cli import main

    f = tmp_path / "plate.toml"
    f.write_text("[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n"
                 "[electrodes]\ndrive = [2, 3]\n")
    assert main(["params", "--source", "beam", "--json", "--material", "pzt8"]) == 0
    out = capsys.readouterr()
    paper = json.loads(out.out)
    assert "--material has no effect" in out.err
    assert main(["compare", "--geometry", str(f), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    beam = doc["values"]["beam"] if "values" in doc else doc["beam"]
    assert beam["A_b"] == pytest.approx(-paper["A_b"], rel=1e-9)


def test_the_beams_gap_is_said_not_to_enter_its_force_factors(capsys):
    """Appendix A's beam drives whole quadrants: --gap-mm 0.5 and 2 gave the same A_l,
    labelled as the plate's electrodes, without a word. The FE set is the reference that
    does see the gap (a wider gap, less electrode, smaller A_l)."""
    import json

    from lusm.cli import main

    a_l = {}
    for src in ("beam", "fem"):
        for gap in ("0.5", "2"):
            assert main(["params", "--source", src, "--gap-mm", gap, "--json"]) == 0
            out = capsys.readouterr()
            a_l[src, gap] = json.loads(out.out)["A_l"]
            assert ("gap's width does not enter" in out.err) == (src == "beam")
    assert a_l["beam", "0.5"] == a_l["beam", "2"]
    assert a_l["fem", "2"] < 0.95 * a_l["fem", "0.5"]
