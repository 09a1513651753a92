"""Generate ``tip_protrusion.msh``: the paper's plate with a small contact-tip protrusion.

The body is the 30 x 7.5 mm plate with its four quadrant electrodes (0.5 mm gaps, Fig. 1
of the paper); a 2 mm wide, 1 mm high unelectroded protrusion sticks out of the centre of
the tip end (y = 30 .. 31 mm). The mesh is a structured quad grid whose lines follow the
electrode and protrusion edges, written as gmsh MSH 4.1 ASCII in millimetres (the stator file
says ``unit = "mm"``) with physical groups ``electrode1..4``, ``gap``, ``tip`` and
``preload``. No gmsh binary is needed: ``python examples/tip_protrusion/make_mesh.py``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1]))  # run from anywhere inside the repository

from fem.geometry import PlateStator  # noqa: E402
from fem.meshing.mesh import grid_segments  # noqa: E402
from fem.meshing.mesh_io import keep_used_nodes_at, write_stator_msh  # noqa: E402

LENGTH_MM = 30.0
WIDTH_MM = 7.5
GAP_MM = 0.5
TIP_WIDTH_MM = 2.0
TIP_HEIGHT_MM = 1.0
H_MM = 0.9375
"""Target element size (mm): 8 elements across the width."""


def protrusion_mesh(
    tip_width_mm: float = TIP_WIDTH_MM, tip_height_mm: float = TIP_HEIGHT_MM, h_mm: float = H_MM
) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[str, int]]:
    """The mesh as :func:`~fem.meshing.mesh_io.write_stator_msh` takes it: nodes (n, 2) in mm,
    ``{"quad": (m, 4)}`` counter-clockwise, ``{"quad": tags}``, the point nodes."""
    w2, g2, t2 = WIDTH_MM / 2, GAP_MM / 2, tip_width_mm / 2
    xb = sorted({-w2, -t2, -g2, 0.0, g2, t2, w2})
    yb = [0.0, LENGTH_MM / 2 - g2, LENGTH_MM / 2 + g2, LENGTH_MM]
    if tip_height_mm > 0:
        yb.append(LENGTH_MM + tip_height_mm)
    x, y = grid_segments(xb, h_mm), grid_segments(yb, h_mm)
    nx = len(x)
    X, Y = np.meshgrid(x, y)
    nodes = np.column_stack((X.ravel(), Y.ravel()))
    ix = np.arange(nodes.shape[0]).reshape(len(y), nx)
    quads = np.column_stack(
        (ix[:-1, :-1].ravel(), ix[:-1, 1:].ravel(), ix[1:, 1:].ravel(), ix[1:, :-1].ravel())
    )
    c = nodes[quads].mean(axis=1)
    keep = (c[:, 1] < LENGTH_MM) | (np.abs(c[:, 0]) < t2)
    quads, c = quads[keep], c[keep]
    # the plate's quadrants (in m); the protrusion beyond the plate's end is bare
    plate = PlateStator(length_m=LENGTH_MM * 1e-3, width_m=WIDTH_MM * 1e-3,
                        electrode_gap_m=GAP_MM * 1e-3)
    tags = np.where(c[:, 1] < LENGTH_MM, plate.electrode_of(c[:, 0] * 1e-3, c[:, 1] * 1e-3), 0)
    # drop the grid nodes beside the protrusion
    nodes, quads, points = keep_used_nodes_at(
        nodes, quads, {"tip": (0.0, y[-1]), "preload": (0.0, 0.0)})
    return nodes, {"quad": quads}, {"quad": tags}, points


if __name__ == "__main__":
    print(write_stator_msh(HERE / "tip_protrusion.msh", *protrusion_mesh()))
