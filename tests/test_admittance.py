"""Admittance by modal superposition (fem.admittance) against direct harmonic solves."""

from __future__ import annotations

import json

import numpy as np
import pytest

from fem.admittance import (
    direct_admittance_S,
    modal_port,
    plate_admittance,
    resonance_pairs,
)
from fem.mesh_settings import MeshSettings
from fem.model import plate_model
from fem.modes import plate_modes
from lusm.cli import main

F_CHECK = np.array([1e3, 20e3, 50e3, 54.5e3, 56.9e3, 62e3])


@pytest.fixture(scope="module")
def model():
    return plate_model()


@pytest.mark.parametrize("zeta", [1e-3, 0.05])
def test_modal_matches_direct_harmonic(model, zeta):
    port = modal_port(model, 65e3, None, None, zeta, zeta, zeta)
    y_direct = direct_admittance_S(model, port, F_CHECK)
    y_modal = port.admittance_S(F_CHECK)
    assert np.max(np.abs(y_modal / y_direct - 1)) < 1e-4
    # without the residual mode the error is three orders larger
    y_trunc = port.admittance_S(F_CHECK, residual=False)
    assert np.max(np.abs(y_trunc / y_direct - 1)) > 1e-2


def test_asymptotes(model):
    port = modal_port(model, 65e3, None, None, 1e-3, 1e-3, 1e-3)
    w = 2 * np.pi
    # low frequency: free static capacitance; high frequency: clamped capacitance
    c_low = (port.admittance_S(np.array([1.0])) / (1j * w))[0].real
    assert c_low == pytest.approx(port.C_free_F, rel=1e-6)
    c_high = (port.admittance_S(np.array([1e9])) / (1j * w * 1e9))[0].real
    assert c_high == pytest.approx(port.C0_F, rel=1e-3)
    assert port.C_free_F > port.C0_F
    # the admittance of a passive port has a non-negative real part
    y = port.admittance_S(np.linspace(40e3, 70e3, 301))
    assert np.all(y.real >= -1e-15)


def test_k_eff_from_resonance_pairs_matches_modal(model):
    """All four electrodes in phase isolate L1; the B2 polarity (+ - - +) isolates B2."""
    modes = plate_modes()
    f = np.linspace(50e3, 62e3, 2401)
    for name, pol in (("L1", (1, 1, 1, 1)), ("B2", (1, -1, -1, 1))):
        port = modal_port(model, 62e3, (1, 2, 3, 4), pol, 1e-4, 1e-4, 1e-4)
        (pair,) = [p for p in resonance_pairs(port, f) if p.mode == name]
        m = getattr(modes, name)
        assert pair.f_resonance_Hz == pytest.approx(m.f_short_Hz, rel=1e-4)
        assert pair.f_antiresonance_Hz == pytest.approx(m.f_open_Hz, rel=2e-3)
        assert pair.k_eff == pytest.approx(m.k_eff, rel=0.02)


def test_default_drive_pairs_and_bad_input(model):
    res = plate_admittance(zeta=1e-3)
    names = [p.mode for p in res.pairs]
    assert "L1" in names and "B2" in names
    for p in res.pairs:
        assert p.f_antiresonance_Hz > p.f_resonance_Hz
    with pytest.raises(ValueError, match="f_min_Hz"):
        plate_admittance(f_min_Hz=70e3, f_max_Hz=60e3)
    with pytest.raises(ValueError, match="electrodes"):
        modal_port(model, 65e3, (5,), None, 0.01, 0.01)
    with pytest.raises(ValueError, match="polarity"):
        modal_port(model, 65e3, (1, 4), (1, 2), 0.01, 0.01)
    with pytest.raises(ValueError, match="zeta_L1"):
        modal_port(model, 65e3, zeta_L1=-0.1)


@pytest.mark.slow
def test_cli_admittance(tmp_path, capsys):
    assert main(["admittance", "--zeta", "0.002", "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {p["mode"] for p in out["pairs"]} >= {"L1", "B2"}
    assert (tmp_path / "admittance.png").stat().st_size > 1000
    assert main(["admittance", "--f-min", "7e4", "--f-max", "6e4"]) == 2


def test_modal_port_is_bit_identical_run_to_run(model):
    """A fixed eigsh start vector: two identical calls give identical numbers."""
    a = modal_port(model, 65e3, None, None, 0.01, 0.02)
    b = modal_port(model, 65e3, None, None, 0.01, 0.02)
    f = np.linspace(45e3, 65e3, 101)
    assert np.array_equal(a.admittance_S(f), b.admittance_S(f))


def test_merged_peaks_are_labelled_as_merged():
    """Light damping resolves L1 and B2 as two pairs; Table 2's heavy damping merges them into
    one peak, which must name both modes instead of the nearer one alone."""
    from fem.admittance import plate_admittance
    from fem.geometry import PlateStator

    light = plate_admittance(PlateStator(), "pzt8", 45e3, 65e3, 2001, zeta=0.005)
    assert [p.mode for p in light.pairs] == ["B2", "L1"]
    heavy = plate_admittance(PlateStator(), "pzt8", 45e3, 65e3, 2001,
                             zeta_L1=0.1169, zeta_B2=0.07095)
    assert [p.mode for p in heavy.pairs] == ["B2+L1 (merged)"]


def test_a_mode_the_port_cannot_drive_is_no_part_of_a_peak():
    """Four electrodes in phase drive L1 only (B2 is antisymmetric across the width): its
    peak was labelled "B2+L1 (merged)" on an 8.5 mm plate, where B2 lies between L1's
    resonance and antiresonance, and a warning said the grid had missed B2's pair."""
    from fem.admittance import MIN_PORT_COUPLING, plate_admittance
    from fem.geometry import PlateStator

    st = PlateStator(width_m=8.5e-3)
    both = plate_admittance(st, "pzt8", 47e3, 67e3, 2001, (1, 2, 3, 4), zeta=1e-3)
    k = dict(zip(both.port.mode_names, both.port.coupling(), strict=True))
    assert k["B2"] < 1e-6 * k["L1"] and k["L1"] > 0.2
    assert [p.mode for p in both.pairs] == ["L1"] and both.unpaired_modes() == []
    diagonal = plate_admittance(st, "pzt8", 47e3, 67e3, 2001, (1, 4), zeta=1e-3)
    k = dict(zip(diagonal.port.mode_names, diagonal.port.coupling(), strict=True))
    assert min(k.values()) > 100 * MIN_PORT_COUPLING
    # the port's coupling is the pair's k_eff of an isolated mode: L1's, within 1 %
    assert both.pairs[0].k_eff == pytest.approx(
        dict(zip(both.port.mode_names, both.port.coupling(), strict=True))["L1"], rel=1e-2)


def test_default_band_follows_a_40_kHz_design(capsys):
    """``lusm admittance --length-mm 42``: L1 near 40 kHz lies outside the old fixed 45-65 kHz
    band; the default band is centred on the design's own modes and resolves both."""
    import json

    from fem.geometry import PlateStator
    from fem.modes import plate_modes
    from lusm.cli import main

    assert main(["admittance", "--length-mm", "42", "--zeta", "0.005", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    m = plate_modes(PlateStator(length_m=42e-3))
    assert d["f_min_Hz"] < min(m.L1.f_short_Hz, m.B2.f_short_Hz)
    assert d["f_max_Hz"] > max(m.L1.f_open_Hz, m.B2.f_open_Hz)
    assert m.L1.f_short_Hz < 45e3
    pairs = {p["mode"]: p for p in d["pairs"]}
    assert set(pairs) == {"L1", "B2"}
    assert pairs["L1"]["f_resonance_Hz"] == pytest.approx(m.L1.f_short_Hz, rel=0.01)


@pytest.mark.parametrize("f_Hz", [60e3, 390e3, 1.8e6])
@pytest.mark.slow
def test_the_mode_count_from_inertia_matches_the_eigensolve(model, f_Hz):
    # Sylvester's law of inertia (negative pivots of K - w^2 M) against the eigenvalues
    import math

    import scipy.sparse.linalg as sla

    from fem.admittance import modes_below

    n = model.K.shape[0]
    w = sla.eigsh(model.K, k=n - 2, M=model.M, sigma=-(2 * math.pi * 100.0) ** 2,
                  which="LM", v0=np.random.default_rng(0).standard_normal(n))[0]
    f = np.sign(w) * np.sqrt(np.abs(w)) / (2 * math.pi)
    assert modes_below(model.K, model.M, f_Hz) == int(np.sum(f < f_Hz))


def test_a_band_beyond_the_mesh_is_refused_before_the_eigensolve(capsys):
    # modes up to 6 x 10 MHz on a fine mesh: the whole spectrum, which took minutes
    assert main(["admittance", "--f-min", "1e4", "--f-max", "1e7", "--refine", "12"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("lusm admittance: error: --f-max 1e+07 Hz") and "LUSM_MAX_WORK" in err
    assert len(err.splitlines()) == 1


@pytest.mark.slow
def test_a_residual_mode_is_never_below_the_cut(model):
    # with nearly every mode of the mesh retained the two moments of the rest are roundoff:
    # their "residual mode" fell at 1.43 MHz inside a 6 MHz cut (inside a 1.5 MHz band);
    # the modal sum still matches the direct harmonic solution across the band
    f_max = 1.5e6
    port = modal_port(model, f_max, None, None, 0.01, 0.01, 0.01)
    assert port.f_res_Hz >= 6 * f_max
    f = np.array([20e3, 300e3, 1.2e6])
    assert np.allclose(port.admittance_S(f), direct_admittance_S(model, port, f), rtol=1e-6)


@pytest.mark.slow
@pytest.mark.benchmark
def test_a_band_beyond_what_the_mesh_resolves_is_said_so(capsys):
    assert main(["admittance", "--f-min", "1e4", "--f-max", "1e6", "--json"]) == 0
    assert "frequencies that high are not converged" in capsys.readouterr().err
    assert main(["admittance", "--json"]) == 0
    assert "warning" not in capsys.readouterr().err


def test_k_eff_does_not_move_with_the_damping():
    """f_s / f_p (max Re Y, max Re 1/Y) stay put as the damping grows; the |Y| extrema do
    not (at zeta = 0.01 B2's k_eff from them was 0.175 against 0.092)."""
    from fem.admittance import plate_admittance

    keff = {}
    for z in (1e-4, 1e-2):
        res = plate_admittance(f_min_Hz=53e3, f_max_Hz=60e3, n_points=3001, zeta=z)
        keff[z] = {p.mode: p for p in res.pairs}
    for mode in ("B2", "L1"):
        low, high = keff[1e-4][mode], keff[1e-2][mode]
        assert high.k_eff == pytest.approx(low.k_eff, rel=5e-3)
        assert high.f_resonance_Hz == pytest.approx(low.f_resonance_Hz, rel=1e-3)
        # the |Y| extrema moved apart by far more
        spread = (high.f_min_abs_Hz - high.f_max_abs_Hz) / (low.f_min_abs_Hz - low.f_max_abs_Hz)
        assert spread > 1.2


@pytest.mark.slow
@pytest.mark.benchmark  # a message check that costs a fine admittance sweep
def test_a_grid_too_coarse_for_the_design_modes_is_said_so(capsys):
    """--f-min 1 --f-max 1e6 --points 101 (a 10 kHz step) finds no pair of L1 or B2 at
    54-56 kHz: it listed the others without a word. The default band says nothing."""
    from lusm.cli import main

    assert main(["admittance", "--f-min", "1", "--f-max", "1e6", "--points", "101",
                 "--json"]) == 0
    out = capsys.readouterr()
    assert {p["mode"] for p in json.loads(out.out)["pairs"]}.isdisjoint({"L1", "B2"})
    assert "B2 (54137 Hz) and L1 (56178 Hz) lie in the band but no resonance pair" in out.err
    assert main(["admittance", "--json"]) == 0
    assert "warning" not in capsys.readouterr().err


def test_a_pair_cut_by_the_band_asks_for_a_wider_band_not_more_points(capsys):
    """--f-min 54000 --f-max 54300 --zeta 0.001: B2 (54 137 Hz) lies in the band, its
    antiresonance (54 369 Hz) does not. The warning said "raise --points or narrow the band"
    while the text said "widen it", and 20 001 points found nothing either. Now the warning
    names --f-max; the reference: the band widened to 54 500 Hz finds B2's pair on the same
    grid step."""
    from lusm.cli import main

    base = ["admittance", "--f-min", "54000", "--zeta", "0.001"]
    for points in ("11", "20001"):
        assert main([*base, "--f-max", "54300", "--points", points, "--json"]) == 0
        out = capsys.readouterr()
        assert "B2" not in {p["mode"] for p in json.loads(out.out)["pairs"]}
        assert "--f-max: B2 (54137 Hz) lies in the band but its resonance pair reaches " \
            "beyond it" in out.err and "raise --points" not in out.err
        missed = json.loads(out.out)["missed_modes"]  # the warning's content in the JSON
        assert [(m["mode"], m["why"]) for m in missed] == [("B2", "band")]
        assert missed[0]["f_min_abs_Y_Hz"] > 54300
    assert main([*base, "--f-max", "54500", "--points", "33334", "--json"]) == 0
    out = capsys.readouterr()
    assert "B2" in {p["mode"] for p in json.loads(out.out)["pairs"]} and "warning" not in out.err


@pytest.mark.slow
def test_a_mode_damping_leaves_without_a_peak_is_told_apart_from_a_coarse_grid(capsys):
    """One quadrant (electrode 1) with Table 2's damping: B2's coupling (k_r^2 0.0056) is far
    below its damping (0.071), and neither B2 nor L1 has a resonance pair on any grid. The
    warning told the user to raise --points, which cannot help. Reference: a grid 100 times
    finer over the whole band finds no pair either, while a lighter damping finds both."""
    kw = dict(f_min_Hz=45.8e3, f_max_Hz=66.7e3, n_points=2001, electrodes=(1,))
    heavy = plate_admittance(zeta_L1=0.1169, zeta_B2=0.07095, **kw)
    assert sorted(n for n, _ in heavy.peakless_modes()) == ["B2", "L1"]
    assert heavy.unpaired_modes() == []
    fine = np.linspace(heavy.f_Hz[0], heavy.f_Hz[-1], 200_001)
    assert resonance_pairs(heavy.port, fine) == ()
    light = plate_admittance(zeta=0.01, **kw)
    assert [p.mode for p in light.pairs] == ["B2", "L1"] and light.peakless_modes() == []
    # the coarse grid's modes have a peak: they stay the grid's (and the --points warning)
    coarse = plate_admittance(zeta=0.01, f_min_Hz=1.0, f_max_Hz=1e6, n_points=101)
    assert [n for n, _ in coarse.unpaired_modes()] and coarse.peakless_modes() == []

    # the plate options take the material's light damping: Table 2's L1 ratio by --zeta
    assert main(["admittance", "--electrodes", "1", "--zeta", "0.1169"]) == 0
    err = capsys.readouterr().err
    assert "no resonance peak through electrode 1 at this damping" in err
    assert "--zeta" in err and "--points" not in err


def test_a_grid_too_coarse_for_two_light_peaks_does_not_merge_them(model):
    """At zeta = 0.001 B2 (54.1 kHz) and L1 (56.2 kHz) make separate peaks; a 5 kHz grid had
    paired B2's resonance with L1's antiresonance as "B2+L1 (merged)", k_eff 0.306, without a
    warning (found by exploratory testing). The reference: the same port on a fine grid."""
    port = modal_port(model, 65e3, None, None, 1e-3, 1e-3, 1e-3)
    fine = {q.mode: q for q in resonance_pairs(port, np.linspace(50e3, 60e3, 20001))}
    assert {"B2", "L1"} <= set(fine)
    coarse = resonance_pairs(port, np.linspace(45767.7, 1e7, 2001))
    assert not any("merged" in q.mode for q in coarse)
    assert not any(q.f_resonance_Hz < 60e3 for q in coarse)  # left to the grid warning
    # a merge of heavy damping is one peak on any grid, and stays
    heavy = modal_port(model, 65e3, None, None, 0.1169, 0.07095, 0.1)
    assert [q.mode for q in resonance_pairs(heavy, np.linspace(45e3, 66e3, 2001))
            if "+" in q.mode] == ["B2+L1 (merged)"]


def test_two_peaks_closer_than_their_bandwidths_are_not_one_merged_peak(model):
    """At zeta = 0.02 B2 and L1 make two overlapping peaks: both rows had been labelled
    "B2+L1 (merged)" under a line saying the modes make one peak (code review). Each is now
    named by its nearer mode; the reference: the modes' own frequencies."""
    port = modal_port(model, 65e3, None, None, 0.02, 0.02, 0.02)
    pairs = resonance_pairs(port, np.linspace(45e3, 66e3, 2001))
    near = [q for q in pairs if 50e3 < q.f_resonance_Hz < 60e3]
    assert [q.mode for q in near] == ["B2 (overlaps L1)", "L1 (overlaps B2)"]
    f = dict(zip(port.mode_names, port.frequencies_Hz, strict=True))
    assert abs(near[1].f_resonance_Hz - f["L1"]) < abs(near[1].f_resonance_Hz - f["B2"])


def test_an_undamped_admittance_is_refused_naming_its_parameter():
    """plate_admittance(zeta=0.0) ran and paired B2's antiresonance as its resonance (k_eff
    0.020 against 0.092 at zeta 1e-12; found by API testing); the CLI's --zeta refuses 0."""
    from fem.admittance import plate_admittance

    with pytest.raises(ValueError, match=r"^zeta must lie in \(0, 1\)"):
        plate_admittance(zeta=0.0)
    with pytest.raises(ValueError, match=r"^zeta_B2 must lie in \(0, 1\)"):
        plate_admittance(zeta_L1=0.1, zeta_B2=0.0)


def test_an_admittance_result_is_read_only():
    """AdmittanceResult's f_Hz and Y_S were writable where its port's arrays are not."""
    from fem.admittance import plate_admittance

    r = plate_admittance(f_min_Hz=50e3, f_max_Hz=60e3, n_points=201, zeta=0.01,
                         mesh=MeshSettings(refine=1))
    for a in (r.f_Hz, r.Y_S):
        with pytest.raises(ValueError, match="read-only"):
            a[0] = 0


def _overlap(a, b) -> bool:
    """Whether two display boxes share any area (touching edges do not)."""
    return min(a.x1, b.x1) > max(a.x0, b.x0) and min(a.y1, b.y1) > max(a.y0, b.y0)


def _label_geometry(result):
    """The k_eff labels' boxes, the |Y| panel's box and the curve's highest point (pixels)."""
    from validation.fem_figures import draw_admittance
    from validation.plotting import pyplot

    fig, labels = draw_admittance(result)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    boxes = [t.get_window_extent(renderer) for t in labels]
    line = ax.get_lines()[0]
    top = ax.transData.transform(np.column_stack(line.get_data()))[:, 1].max()
    panel = ax.get_window_extent(renderer)
    pyplot().close(fig)
    return boxes, panel, top


def _synthetic(resonances_Hz, f_min_Hz, f_max_Hz, zeta=0.005):
    """A port of a 1 nF capacitance and modes at ``resonances_Hz``, each its own pair (k_eff
    0.1), drawn as :func:`validation.fem_figures.admittance_figure` draws a result."""
    from types import SimpleNamespace

    from fem.admittance import ResonancePair

    f = np.linspace(f_min_Hz, f_max_Hz, 4001)
    w = 2 * np.pi * f
    y = 1j * w * 1e-9
    for fr in resonances_Hz:
        wr = 2 * np.pi * fr
        y = y + 1j * w * 1e-10 * wr**2 / (wr**2 - w**2 + 2j * zeta * wr * w)
    pairs = tuple(ResonancePair(fr, fr * 1.005, 0.1, ("B2", "L1", "")[k % 3])
                  for k, fr in enumerate(resonances_Hz))
    return SimpleNamespace(f_Hz=f, Y_S=y, pairs=pairs, port=SimpleNamespace(electrodes=(1, 4)))


def test_the_k_eff_labels_of_close_peaks_do_not_overlap(capsys):
    """At ``--zeta 0.005`` the B2 and L1 labels, 2 kHz apart, were printed over each other
    at the top of the panel, on the L1 peak. Measured on the drawn figure: no two labels
    share a pixel, each lies inside the |Y| panel, and the curve stays below all of them."""
    res = plate_admittance(zeta=0.005)
    assert len(res.pairs) >= 2
    boxes, panel, top = _label_geometry(res)
    assert not any(_overlap(a, b) for i, a in enumerate(boxes) for b in boxes[i + 1:])
    assert all(panel.x0 <= b.x0 and b.x1 <= panel.x1 and panel.y0 <= b.y0 and b.y1 <= panel.y1
               for b in boxes)
    assert top < min(b.y0 for b in boxes)


@pytest.mark.parametrize("resonances_kHz", [
    (50.0, 50.05, 50.1, 50.2, 51.0, 55.0),  # a cluster, and one beside it
    (41.0, 59.5, 59.9),                     # the last two at the band's right end
    (45.0, 45.0),                           # one frequency, two labels
])
def test_labels_of_any_cluster_of_peaks_do_not_overlap(resonances_kHz):
    boxes, panel, top = _label_geometry(_synthetic([f * 1e3 for f in resonances_kHz],
                                                   40e3, 60e3))
    assert not any(_overlap(a, b) for i, a in enumerate(boxes) for b in boxes[i + 1:])
    assert all(panel.x0 <= b.x0 and b.x1 <= panel.x1 for b in boxes)
    assert top < min(b.y0 for b in boxes)


def test_rows_are_as_few_as_the_deepest_pile_of_spans():
    """:func:`validation.plotting.stack_rows`: spans in one row are ``gap`` apart, and the
    rows are as few as possible, the most spans (widened by the gap) over any one point
    (interval colouring's lower bound, counted here independently)."""
    from validation.plotting import stack_rows

    rng = np.random.default_rng(3)
    for _ in range(200):
        n = int(rng.integers(1, 15))
        x0 = rng.uniform(0, 100, n)
        spans = [(a, a + w) for a, w in zip(x0, rng.uniform(0, 30, n), strict=True)]
        gap = float(rng.uniform(0, 5))
        rows = stack_rows(spans, gap)
        for i in range(n):
            for j in range(i + 1, n):
                if rows[i] == rows[j]:
                    (a0, a1), (b0, b1) = spans[i], spans[j]
                    assert b0 - a1 >= gap or a0 - b1 >= gap
        depth = max(sum(1 for a, b in spans if a <= x < b + gap) for x, _ in spans)
        assert max(rows) + 1 == depth
