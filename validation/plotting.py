"""The two matplotlib basics every figure module shares: a lazy pyplot and a PNG writer.

Library code never picks a backend; ``lusm`` sets ``MPLBACKEND=Agg`` before matplotlib loads.
"""

from __future__ import annotations

from pathlib import Path


def pyplot():
    """matplotlib.pyplot, imported on first use (the CLI sets the file backend, Agg)."""
    import matplotlib.pyplot as plt

    return plt


def save(fig, path: Path, tight: bool = True) -> Path:
    """Save a figure as PNG (creating its folder), close it, return the path.

    ``tight=False`` keeps a layout set by hand (e.g. room for a figure legend).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if tight:
        fig.tight_layout()
    fig.savefig(path, dpi=110)
    pyplot().close(fig)
    return path


def stack_rows(spans, gap: float = 0.0) -> list[int]:
    """The row of each horizontal span ``(x0, x1)`` (any unit, ``x0 <= x1``) such that two
    spans in one row are at least ``gap`` apart: each span, taken from the left, goes to the
    lowest row whose spans all end ``gap`` before it starts.

    This is interval-graph colouring, and it takes no more rows than the most spans a point
    lies in (with each span widened by ``gap``): labels of close peaks stack, far ones share
    row 0.
    """
    order = sorted(range(len(spans)), key=lambda i: spans[i][0])
    ends: list[float] = []  # right end of the last span of each row
    rows = [0] * len(spans)
    for i in order:
        x0, x1 = spans[i]
        for r, end in enumerate(ends):
            if end + gap <= x0:
                rows[i], ends[r] = r, x1
                break
        else:
            rows[i] = len(ends)
            ends.append(x1)
    return rows
