"""The size of a stator's FE model before it is built: its elements (2D) or bricks (3D)."""

from __future__ import annotations

import math


def fe_cell_count(stator, refine: int | None, layers: int | None = None,
                  edge_grading: int = 0, quarter: bool = False) -> int:
    """Elements (``layers`` None) or 3D bricks of the FE mesh ``stator`` and ``refine`` make,
    as :func:`lusm.options.check_fe_size` counts them against the bounds (the report states
    them too): the quarter plate's with ``quarter``, the graded one's with ``edge_grading``."""
    from fem.meshing.meshed_stator import planform_mesh

    mesh = planform_mesh(stator)
    if mesh is not None and layers is not None and edge_grading:
        from fem.solid3d.model import planform_layer_lines  # graded layers (the 3D model's)

        n = int(mesh.quads.shape[1]) * (planform_layer_lines(mesh, stator.thickness_m, layers,
                                                             edge_grading).size - 1)
    elif mesh is not None:
        n = int(mesh.quads.shape[1]) * (layers or 1)
    elif layers is not None and quarter:
        from fem.solid3d.symmetric import quarter_grid_lines

        lines = quarter_grid_lines(stator, refine, layers, edge_grading)
        n = math.prod(len(v) - 1 for v in lines)
    elif layers is not None and edge_grading:
        from fem.solid3d.model import hex_grid_lines

        lines = hex_grid_lines(stator, refine, layers, edge_grading)
        n = math.prod(len(v) - 1 for v in lines)
    else:
        from fem.meshing.mesh import DEFAULT_REFINE, grid_lines_m

        x, y = grid_lines_m(stator, DEFAULT_REFINE if refine is None else refine)
        n = (len(x) - 1) * (len(y) - 1) * (layers or 1)
    return n
