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
