"""Generate ``chamfered.msh``: the paper's plate with its four corners chamfered at 45 deg.

The plate is 30 x 7.5 mm with four quadrant electrodes (0.5 mm gaps); each corner is cut by
a 1.5 x 1.5 mm chamfer. The mesh is a structured grid split into **triangles**, with the
diagonals chosen so that the chamfer lines follow them; triangles beyond a chamfer are
dropped. Written as gmsh MSH 4.1 ASCII in metres with physical groups ``electrode1..4``,
``gap``, ``tip`` and ``preload``. The FE stage splits every triangle into three quads when
it reads the file. No gmsh binary is needed: ``python examples/chamfered/make_mesh.py``.
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

LENGTH_M = 30e-3
WIDTH_M = 7.5e-3
GAP_M = 0.5e-3
CHAMFER_M = 1.5e-3
H_M = 1.5e-3
"""Target element size (m): one square cell per corner block, split along the chamfer."""


def chamfered_mesh(
    chamfer_m: float = CHAMFER_M, h_m: float = H_M
) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[str, int]]:
    """The mesh as :func:`~fem.meshing.mesh_io.write_stator_msh` takes it: nodes (n, 2) in m,
    ``{"triangle": (m, 3)}`` counter-clockwise, ``{"triangle": tags}``, the point nodes.

    ``chamfer_m = 0`` gives the plain plate meshed the same way (a reference for tests).
    """
    w2, g2, c, length = WIDTH_M / 2, GAP_M / 2, chamfer_m, LENGTH_M
    xb = sorted({-w2, -w2 + c, -g2, 0.0, g2, w2 - c, w2})
    yb = sorted({0.0, c, length / 2 - g2, length / 2 + g2, length - c, length})
    x, y = grid_segments(xb, h_m), grid_segments(yb, h_m)
    nx = len(x)
    X, Y = np.meshgrid(x, y)
    nodes = np.column_stack((X.ravel(), Y.ravel()))
    ix = np.arange(nodes.shape[0]).reshape(len(y), nx)
    a, b = ix[:-1, :-1].ravel(), ix[:-1, 1:].ravel()  # (x0, y0), (x1, y0)
    cc, d = ix[1:, 1:].ravel(), ix[1:, :-1].ravel()  # (x1, y1), (x0, y1)
    centre = 0.25 * (nodes[a] + nodes[b] + nodes[cc] + nodes[d])
    # diagonal parallel to the chamfer of the nearest corner: (x0,y1)-(x1,y0) where
    # x * (y - l/2) > 0, else (x0,y0)-(x1,y1); mirror-symmetric about x = 0
    anti = centre[:, 0] * (centre[:, 1] - length / 2) > 0
    t_anti = np.vstack((np.column_stack((a, b, d)), np.column_stack((b, cc, d))))
    t_main = np.vstack((np.column_stack((a, b, cc)), np.column_stack((a, cc, d))))
    tris = np.where(np.concatenate((anti, anti))[:, None], t_anti, t_main)
    tc = nodes[tris].mean(axis=1)
    # keep triangles inside all four chamfers: |x| - w/2 + c >= distance into the corner
    dist_end = np.minimum(tc[:, 1], length - tc[:, 1])
    keep = (np.abs(tc[:, 0]) - (w2 - c)) + (c - dist_end) <= c + 1e-12 * length
    tris, tc = tris[keep], tc[keep]
    plate = PlateStator(length_m=length, width_m=WIDTH_M, electrode_gap_m=GAP_M)
    tags = plate.electrode_of(tc[:, 0], tc[:, 1])
    nodes, tris, points = keep_used_nodes_at(
        nodes, tris, {"tip": (0.0, length), "preload": (0.0, 0.0)})
    return nodes, {"triangle": tris}, {"triangle": tags}, points


if __name__ == "__main__":
    print(write_stator_msh(HERE / "chamfered.msh", *chamfered_mesh()))
