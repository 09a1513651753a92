"""The contact stage's figures (validation.figures): what a reader sees stays on the page."""

from __future__ import annotations

import pytest


@pytest.mark.parametrize(("size", "overflowed"), [((6, 4.5), True), ((7, 4), False)])
def test_a_long_title_is_wrapped_inside_the_figure(size, overflowed):
    """A stator file's run titled its phase plane past the PNG's right edge ("...(stator file
    examples/tuned_40k/stator"): titles are wrapped to the figure's width, every line inside
    it once drawn."""
    from validation.figures import set_label, set_wrapped_title
    from validation.plotting import pyplot

    plt = pyplot()
    fig, ax = plt.subplots(figsize=size)
    source = "stator file examples/tuned_40k/stator.toml (FE reduction, consistent coupling)"
    text = ("stick-slip-separation: V0 = 400 V, F_P = 14 N, f = 40.31 kHz "
            f"({set_label(source)})")
    ax.set_title(text, fontsize=9)  # as it was: past the right edge of the phase plane's
    fig.canvas.draw()
    assert bool(ax.title.get_window_extent().x1 > fig.bbox.x1) is overflowed
    set_wrapped_title(ax, text)
    fig.canvas.draw()
    box, page = ax.title.get_window_extent(), fig.bbox
    assert page.x0 <= box.x0 and box.x1 <= page.x1 and box.y1 <= page.y1
    assert ax.title.get_text().replace("\n", " ") == text  # wrapped, not cut
    plt.close(fig)


def _curve(stall_N: float, creep_from_N: float, creep_m_s: float):
    """A hand-made exact-level characteristic at 400 V / 14 N: linear to a knee at
    ``creep_from_N``, creeping from there to ``stall_N``."""
    import math

    import numpy as np

    from contact.characteristic import Characteristic
    from contact.model import OperatingPoint

    loads = np.linspace(0.0, stall_N, 11)
    v = np.where(loads < creep_from_N, 0.03 * (1 - loads / creep_from_N), 5e-5)
    v[-1] = 0.0
    return Characteristic(OperatingPoint(400.0, 14.0, 40e3), 0.03, stall_N, loads, v,
                          np.full(11, 2.6), loads * v, loads * v / 2.6, (-2.0, 2.0), "exact",
                          0.0, 0, creep_from_N, creep_from_N, "averaged stall",
                          creep_speed_m_s=creep_m_s if math.isfinite(creep_from_N) else math.nan)


def test_speed_thrust_marks_the_stall_force_and_shades_the_creep_band():
    """The curve meets the axis at its knee (0.5 N) but stalls at 0.985 N: the figure puts
    the stall marker at 0.985 N on zero speed, shades 0.5 to 0.985 N, draws the creep speed;
    a curve without a band has its stall marker and no shading."""
    import math

    import numpy as np

    from validation.plotting import pyplot
    from validation.report_motor import speed_thrust_axes

    plt = pyplot()
    fig, ax = plt.subplots()
    drawn = speed_thrust_axes(ax, [_curve(0.985, 0.5, 1.4e-4), _curve(0.6, math.nan, 0.0)])
    assert len(drawn["curves"]) == 2 and len(drawn["stall"]) == 2
    assert [float(m.get_xdata()[0]) for m in drawn["stall"]] == [0.985, 0.6]
    assert all(float(m.get_ydata()[0]) == 0.0 for m in drawn["stall"])
    (span,) = drawn["creep"]
    xs = span.get_path().transformed(span.get_patch_transform()).vertices[:, 0]
    assert float(np.min(xs)) == pytest.approx(0.5) and float(np.max(xs)) == pytest.approx(0.985)
    (speed,) = drawn["creep_speed"]
    assert float(speed.get_ydata()[0]) == 1.4e-4 * 1e3  # mm/s
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "stall 0.985 N" in labels and "creep band 0.5 to 0.985 N" in labels
    plt.close(fig)


def _map():
    """A hand-made 3 x 3 steady map: speeds rise with voltage and fall with preload, except
    150 V / 10 N (slower than 100 V / 10 N by 5.7 times, the issue's creep-level case); the
    point 200 V / 12 N has two stable states."""
    import numpy as np

    from contact.maps import StickSlipMap

    v = np.array([[0.372, 0.2, 0.1], [0.065, 0.5, 0.3], [3.0, 2.0, 1.0]]) * 1e-3
    branches = np.empty((3, 3), dtype=object)
    for i in range(3):
        for j in range(3):
            branches[i, j] = ((v[i, j], 1, "stick-slip", True, False),)
    branches[2, 1] = (*branches[2, 1], (0.0, 1, "pure-stick", False, True))
    shape = (3, 3)
    return StickSlipMap(np.array([100.0, 150.0, 200.0]), np.array([10.0, 12.0, 14.0]),
                        np.full(shape, "stick-slip"), v, np.full(shape, 0.5),
                        np.zeros(shape), np.full(shape, 0.2), np.ones(shape, bool), 0.0,
                        "steady", branches, np.zeros(shape, bool))


def test_map_names_the_points_with_several_states_and_against_the_trend():
    m = _map()
    assert m.several_branches() == [(2, 1)]
    assert m.non_monotone_pairs() == [((0, 0), (1, 0)), ((1, 0), (1, 1))]


def test_map_figure_draws_log_speed_contours_and_marks_them():
    """The map's figure: filled contours of |v| on a log scale spanning the speeds, a diamond
    at the point with two stable states, a dashed segment per non-monotone pair."""
    from matplotlib.colors import LogNorm

    from validation.figures import map_axes
    from validation.plotting import pyplot

    plt = pyplot()
    fig, ax = plt.subplots()
    drawn = map_axes(ax, _map())
    cs = drawn["contours"]
    assert isinstance(cs.norm, LogNorm)
    assert cs.levels[0] <= 0.065 and cs.levels[-1] >= 3.0  # mm/s
    assert drawn["several"] == [(12.0, 200.0)]
    assert drawn["non_monotone"] == [((10.0, 10.0), (100.0, 150.0)),
                                     ((10.0, 12.0), (150.0, 150.0))]
    plt.close(fig)
