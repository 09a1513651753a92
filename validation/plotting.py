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
