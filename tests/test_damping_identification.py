"""Damping identified from free tip amplitudes (rom.damping), as the paper identified Table 2's
C_l and C_b (Section 4.1), and its stator-file form ``[damping] source = "paper_amplitudes"``."""

from __future__ import annotations

import json
import math

import pytest

from rom.damping import identify_damping, table2_free_amplitudes_m_per_V
from rom.from_fem import fem_params_from_file
from rom.table2 import table2

TUNED = "examples/tuned_40k/stator.toml"
FITTED = "examples/tuned_40k/identified.toml"


def _amplitude(M, C, K, A, phi, f):
    w = 2 * math.pi * f
    return abs(phi * A) / abs(complex(K - M * w * w, C * w))


def test_identifying_table2_on_its_own_amplitudes_returns_table2():
    """Table 2's dampings are the ones that reproduce Table 2's free tip amplitudes."""
    t = table2()
    r = identify_damping(t)
    assert r.params.C_l == pytest.approx(t.C_l, rel=1e-12)
    assert r.params.C_b == pytest.approx(t.C_b, rel=1e-12)


def test_fitted_set_vibrates_as_much_as_the_paper_stator_and_keeps_everything_else():
    p = fem_params_from_file(TUNED)
    r = identify_damping(p, 40e3)
    q = r.params
    t_l, t_b = table2_free_amplitudes_m_per_V()
    assert _amplitude(q.M_l, q.C_l, q.K_l, q.A_l, q.phi_Ll, 40e3) == pytest.approx(t_l, rel=1e-10)
    assert _amplitude(q.M_b, q.C_b, q.K_b, q.A_b, q.phi_Bl, 40e3) == pytest.approx(t_b, rel=1e-10)
    same = {k: v for k, v in q.to_dict().items() if k not in ("C_l", "C_b", "zeta_L1",
                                                              "zeta_B2")}
    assert same == {k: p.to_dict()[k] for k in same}
    # the tuned FE plate needs lighter damping than Table 2's to vibrate as much
    assert q.zeta_L1 < p.zeta_L1 and q.zeta_B2 < p.zeta_B2


def test_an_unreachable_amplitude_is_refused_with_the_reason():
    """The paper's 30 mm plate (L1 near 56 kHz) cannot reach the paper's 40 kHz amplitude
    at 40 kHz with any damping."""
    from rom.sources import get_params

    with pytest.raises(ValueError, match="even undamped.*natural frequency is 5"):
        identify_damping(get_params("fem"), 40e3)
    with pytest.raises(ValueError, match="target amplitude must be"):
        identify_damping(table2(), 40e3, (0.0, 1e-9))


def test_stator_file_fits_the_damping_and_every_command_uses_it(capsys):
    from lusm.cli import main

    expected = identify_damping(fem_params_from_file(TUNED), 40e3).params
    p = fem_params_from_file(FITTED)
    assert (p.C_l, p.C_b) == pytest.approx((expected.C_l, expected.C_b), rel=1e-12)
    assert main(["params", "--geometry", FITTED, "--json"]) in (0, None)
    d = json.loads(capsys.readouterr().out)
    assert d["zeta_L1"] == pytest.approx(expected.zeta_L1, rel=1e-12)
    # its description named the ratios the fit started from (Table 2's 0.1169, 0.07095)
    ratios = f"damping ratios ({expected.zeta_L1:.4g}, {expected.zeta_B2:.4g}), fitted"
    assert ratios in d["source"] and "(0.1169, 0.07095)" not in d["source"]
    assert main(["characteristic", "--voltage", "300", "--preload", "14", "--frequency",
                 "auto", "--geometry", FITTED, "--loads", "0:0.5:0.5"]) in (0, None)
    assert "paper_amplitudes" in capsys.readouterr().out


@pytest.mark.parametrize("body, key", [
    ('source = "paper_amplitudes"\nfrequency_Hz = 10', "[damping] frequency_Hz"),
    ('source = "paper_amplitudes"\nzeta_L1 = 0.01', "zeta_L1"),
    ('zeta_L1 = 0.01\nzeta_B2 = 0.01\nfrequency_Hz = 4e4', "frequency_Hz"),
    ('source = "measured"', "paper_amplitudes"),
])
def test_bad_identification_tables_name_the_key(tmp_path, body, key):
    from fem.stator_file import load_stator

    f = tmp_path / "s.toml"
    f.write_text(f"[plate]\nthickness_mm = 3.0\n[damping]\n{body}\n")
    with pytest.raises(ValueError, match=key.replace("[", r"\[").replace("]", r"\]")):
        load_stator(f)
