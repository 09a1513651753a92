"""``lusm simulate --params FILE``: a saved parameter set round-trips, and its edits act."""

import json

import pytest

from lusm.cli import main
from rom import table2
from rom.params import MotorParams


def _run(capsys, *argv):
    assert main(["simulate", "--voltage", "300", "--preload", "14", "--duration", "0.02",
                 "--json", *argv]) == 0
    return json.loads(capsys.readouterr().out)


def test_params_json_round_trips_into_simulate(tmp_path, capsys):
    assert main(["params", "--json"]) == 0
    path = tmp_path / "set.json"
    path.write_text(capsys.readouterr().out)
    assert MotorParams.from_dict(json.loads(path.read_text())) == table2()
    direct = _run(capsys)
    saved = _run(capsys, "--params", str(path))
    assert saved["steady_velocity_m_s"] == direct["steady_velocity_m_s"]


def test_lower_damping_in_the_file_moves_the_slider_faster(tmp_path, capsys):
    """Halving both modal dampings raises the free tip amplitudes, hence the speed."""
    d = {k: v for k, v in table2().to_dict().items()
         if k not in ("eta_N", "eta_T", "f_L1_Hz", "f_B2_Hz", "zeta_L1", "zeta_B2")}
    d["C_l"] *= 0.5
    d["C_b"] *= 0.5
    path = tmp_path / "light.json"
    path.write_text(json.dumps(d))
    base = _run(capsys)["steady_velocity_m_s"]
    light = _run(capsys, "--params", str(path))["steady_velocity_m_s"]
    assert light > 1.2 * base > 0


def test_an_edit_of_a_stored_field_carries_its_derived_keys_along(tmp_path, capsys):
    # editing C_l, as the help says, was refused because zeta_L1 no longer matched; an edit of
    # a derived key itself is not applied, and both are said
    d = table2().to_dict()
    d["C_l"] = 100.0
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(d))
    # --frequency: an edited set is not Table 2's, whose default drive is the paper's 40 kHz
    args = ["simulate", "--voltage", "200", "--preload", "14", "--steady", "--json",
            "--coupling", "paper", "--frequency", "40e3"]
    assert main([*args, "--params", str(path)]) == 0
    cap = capsys.readouterr()
    assert "zeta_L1 = 0.1169 in the file is derived; recomputed" in cap.err
    assert "edit M_l, K_l, C_l" in cap.err
    v_file = json.loads(cap.out)["steady_velocity_m_s"]
    from contact.simulate import simulate

    ref = simulate(table2().with_(C_l=100.0), 200, 14, 40e3, method="steady",
                   coupling="paper")  # as --coupling paper above
    assert v_file == ref.steady.velocity_m_s
    # the source line says the set was edited (it still described the set before the edit)
    from lusm.options import params_from_file

    assert params_from_file(str(path)).source.endswith(
        f"[edited in {path}: zeta_L1 {table2().with_(C_l=100.0).zeta_L1:.4g}]")


def test_a_bad_value_names_the_files_key(tmp_path, capsys):
    # "MotorParams.K_l must be finite" named the dataclass; the file's key is K_l
    import json

    from lusm.cli import main
    from rom import table2

    d = table2().to_dict()
    d["K_l"] = "nan"
    f = tmp_path / "bad.json"
    f.write_text(json.dumps(d))
    assert main(["simulate", "--params", str(f), "--voltage", "200", "--preload", "14"]) == 2
    err = capsys.readouterr().err
    assert "key K_l must be a real number" in err and "MotorParams" not in err


def test_a_set_with_no_stick_force_is_refused_by_every_scheme(tmp_path, capsys):
    """phi_B0 at phi_Bl makes the paper's gamma_T zero, and phi_B0 a little above it makes
    phi_Bl gamma_T / M_b reach 1 / M_slider: the stick force divides by both. The literal
    scheme returned 6.6e30 m/s, the event scheme blamed dt_s (found by API testing). Every
    scheme now refuses the set, and the CLI names the file."""
    from contact.simulate import simulate

    t = table2()
    bad = (t.with_(phi_B0=t.phi_Bl),
           t.with_(phi_B0=t.phi_Bl + t.M_b / (t.M_slider * t.phi_Bl)))
    for q in bad:
        for method in ("event", "literal", "reference"):
            with pytest.raises(ValueError, match="no tangential force keeps a stuck tip"):
                simulate(q, 200, 14, duration_s=1e-3, method=method, coupling="paper")
    d = {k: v for k, v in bad[0].to_dict().items()
         if k not in ("eta_N", "eta_T", "f_L1_Hz", "f_B2_Hz", "zeta_L1", "zeta_B2")}
    (tmp_path / "p.json").write_text(json.dumps(d))
    assert main(["simulate", "--params", str(tmp_path / "p.json"), "--voltage", "200",
                 "--preload", "14", "--coupling", "paper", "--duration", "0.002"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith(f"lusm simulate: error: --params {tmp_path / 'p.json'}: phi_B0")


def _single_precision(params, arithmetic: bool, scalars: bool = False) -> dict:
    """``params.to_dict()`` as a float32 pipeline writes it: every number rounded to single
    precision, the derived keys rounded from the float64 values or (``arithmetic``) computed
    in float32 from the rounded fields; ``scalars`` keeps them as ``np.float32``."""
    import numpy as np

    d = params.to_dict()
    r = {k: np.float32(v) for k, v in d.items() if k not in ("source", "shape")}
    if arithmetic:
        two_pi = np.float32(2.0) * np.float32(np.pi)
        r["eta_N"] = r["phi_L0"] - r["phi_Ll"]
        r["eta_T"] = r["phi_B0"] - r["phi_Bl"]
        for m, k, c, f, z in (("M_l", "K_l", "C_l", "f_L1_Hz", "zeta_L1"),
                              ("M_b", "K_b", "C_b", "f_B2_Hz", "zeta_B2")):
            r[f] = np.sqrt(r[k] / r[m]) / two_pi
            r[z] = r[c] / (np.float32(2.0) * np.sqrt(r[k] * r[m]))
    out = {k: (v if scalars else float(v)) for k, v in r.items()}
    return {**out, "source": d["source"]}


@pytest.mark.parametrize("source", ["table2", "beam"])
@pytest.mark.parametrize("arithmetic, scalars", [(False, False), (True, False), (False, True)])
def test_a_set_written_from_single_precision_data_is_read(source, arithmetic, scalars):
    """A set written from float32 data (its derived keys rounded too) was refused: the derived
    keys were compared at 1e-9 relative, where single precision rounds to 6e-8 (eta_T of
    Table 2, a difference of two shapes near 2, came 3e-8 off), and an ``np.float32`` derived
    value was refused whatever its value. It reads as the set of its rounded fields."""
    import numpy as np

    from rom.params import DERIVED_KEYS
    from rom.sources import get_params

    d = _single_precision(get_params(source), arithmetic, scalars)
    got = MotorParams.from_dict(d)
    stored = {k: v for k, v in d.items() if k not in DERIVED_KEYS}
    assert got == MotorParams.from_dict(stored)
    assert got.K_l == float(np.float32(get_params(source).K_l))


def test_the_derived_tolerance_is_single_precisions_rounding_and_no_more():
    """Against randomly scaled sets: the float32 pipelines' derived keys stay within
    :func:`rom.params.derived_tolerance`, which is under 1e-6 of the value (eta: of the
    shapes' size); an edit of one part in 1e5 (a derived key typed over) is still refused."""
    import numpy as np

    from rom.params import DERIVED_KEYS, derived_disagrees, derived_tolerance

    rng = np.random.default_rng(7)
    base = table2()
    worst = 0.0
    for _ in range(300):
        scale = {k: float(10.0 ** rng.uniform(-3, 3)) for k in ("M_l", "K_l", "C_l", "M_b",
                                                                 "K_b", "C_b")}
        shapes = {k: float(rng.uniform(-2, 2)) for k in ("phi_L0", "phi_Ll", "phi_B0",
                                                         "phi_Bl")}
        p = base.with_(**{k: getattr(base, k) * v for k, v in scale.items()}, **shapes)
        for arithmetic in (False, True):
            d = _single_precision(p, arithmetic)
            q = MotorParams.from_dict({k: v for k, v in d.items() if k not in DERIVED_KEYS})
            for key in DERIVED_KEYS:
                tol = derived_tolerance(q, key)
                worst = max(worst, abs(d[key] - getattr(q, key)) / tol)
                size = (abs(q.phi_L0) + abs(q.phi_Ll) if key == "eta_N" else
                        abs(q.phi_B0) + abs(q.phi_Bl) if key == "eta_T" else 0.0)
                assert tol < 1e-6 * max(abs(getattr(q, key)), size)
                edited = getattr(q, key) + 1e-5 * max(abs(getattr(q, key)), size)
                assert derived_disagrees(q, key, edited)
                with pytest.raises(ValueError, match=f"{key} = .* disagrees"):
                    MotorParams.from_dict({**d, key: edited})
    assert 0.05 < worst <= 1.0  # the rounding does reach a part of the bound


def test_a_params_file_written_from_single_precision_is_not_called_edited(tmp_path, capsys):
    """``--params`` compared the derived keys at 1e-9 too: a float32 file was said to have
    edited eta_T and its source text changed."""
    from lusm.options import params_from_file

    path = tmp_path / "single.json"
    path.write_text(json.dumps(_single_precision(table2(), arithmetic=True)))
    params = params_from_file(str(path))
    assert params.source == table2().source
    assert capsys.readouterr().err == ""
