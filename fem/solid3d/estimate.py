"""The designer's 3D answer: L1 and B2 on a graded mesh, with their discretisation error.

:func:`estimated_solid_modes` solves the 3D model on two meshes of one family, a coarse and
a fine one (:func:`default_meshes`), and reports the fine mesh's frequencies and k_eff with,
beside each, :data:`SAFETY` times its change from the coarse mesh as the estimate of the fine
mesh's discretisation error. The estimate rests on how the meshes converge (docs/fem3d.md
section 1.1): if a quantity's error shrinks by a factor ``rho`` from the coarse to the fine
mesh, the fine mesh's error is ``|fine - coarse| / (rho - 1)``. Grading towards the electrode
edges shrinks the k_eff error by 2-2.5 per level and the in-plane refinement the frequency
errors by more, but L1's short-circuit frequency, which rises slowly with the grading
through the thickness, converges at about 1.8 per level: hence the factor (Roache's grid
convergence index takes 1.25-3 for the same reason). Checked against converged meshes on
the measured stators (docs/fem3d.md) and in the tests.

A plain rectangular plate is solved on its quarter (:mod:`fem.solid3d.symmetric`: the
full model's numbers at a quarter of the size); a stator with its own planform mesh on the
full extruded mesh, where only the layers are graded (``refine`` plays no part).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

from fem.geometry import PlateStator
from fem.material import PiezoMaterial, get_material
from fem.mesh_settings import MeshSettings
from fem.meshing.meshed_stator import has_planform
from fem.solid3d.symmetric import quarter_model_applies


@dataclass(frozen=True)
class MeshLevel:
    """One 3D mesh of the family: in-plane ``refine`` (elements per width, generated plates
    only), equal ``layers`` through the thickness and ``edge_grading`` levels of geometric
    lines towards the electrode edges (``fem.solid3d.model.hex_grid_lines``); a parametric
    stator's gmsh planform is meshed at ``size_factor`` times its element size."""

    refine: int
    layers: int
    edge_grading: int
    size_factor: float = 1.0

    def text(self, planform: bool = False) -> str:
        """``refine R, layers N, edge grading K`` (on a ``planform`` its size factor in place
        of the refine)."""
        if planform:
            size = (f"planform element size x {self.size_factor:g}, "
                    if self.size_factor != 1.0 else "")
            return f"{size}layers {self.layers}, edge grading {self.edge_grading}"
        return f"refine {self.refine}, layers {self.layers}, edge grading {self.edge_grading}"

    def settings(self, order: int = 2) -> MeshSettings:
        """The FE entry points' :class:`fem.mesh_settings.MeshSettings` of this mesh."""
        return MeshSettings(order, self.refine, self.layers, edge_grading=self.edge_grading)


DEFAULT_MESHES = (MeshLevel(3, 3, 1), MeshLevel(5, 3, 2))
"""The coarse and the fine mesh of ``lusm modes --model 3d`` (docs/fem3d.md, "Default 3D
answer": the cheapest pair whose fine mesh is within 1e-4 in frequency and 1 % in k_eff of
converged meshes on the measured stators, and whose difference bounds that error)."""

PLANFORM_MESHES = (MeshLevel(3, 3, 0, 1.5), MeshLevel(3, 3, 1))
"""The coarse and the fine mesh for a stator with its own planform mesh: the layers graded
towards the top face in the fine one, and a parametric stator's gmsh planform 1.5 times
coarser in the coarse one (a mesh file's planform is the file's: its estimate sees the
layers only)."""

SAFETY = 2.0
"""The estimated error over the change from the coarse to the fine mesh (module docstring)."""

QUICK_MESH = MeshLevel(3, 3, 0)
"""``lusm modes --model 3d --quick``: the uniform mesh, one solve, no estimate (B2's k_eff
about 5 % low on the paper's plate)."""


def default_meshes(stator: PlateStator) -> tuple[MeshLevel, MeshLevel]:
    """The coarse and the fine mesh of ``stator``'s default 3D answer: :data:`DEFAULT_MESHES`
    for a generated plate, :data:`PLANFORM_MESHES` for a stator with its own planform."""
    return PLANFORM_MESHES if has_planform(stator) else DEFAULT_MESHES


@dataclass(frozen=True, eq=False)
class EstimatedSolidModes:
    """The fine mesh's modes, the coarse mesh's, and the estimated error of the fine one.

    Attributes
    ----------
    fine, coarse : fem.solid3d.model.SolidModes
        The two solutions (``fine`` is the answer).
    meshes : tuple of MeshLevel
        ``(coarse, fine)``.
    quarter : bool
        Whether both were solved on the quarter-plate model.
    wall_time_s : float
        Both solutions, assembly included (s).
    """

    fine: object
    coarse: object
    meshes: tuple[MeshLevel, MeshLevel]
    quarter: bool
    wall_time_s: float

    def error(self, mode: str, quantity: str) -> float:
        """Estimated absolute error of the fine mesh's ``quantity`` (``'f_short_Hz'``,
        ``'f_open_Hz'`` or ``'k_eff'``) of ``mode`` (``'L1'``, ``'B2'``): :data:`SAFETY`
        times the change from the coarse mesh (Hz or -)."""
        return SAFETY * abs(getattr(getattr(self.fine, mode), quantity)
                   - getattr(getattr(self.coarse, mode), quantity))

    def errors(self) -> dict[str, dict[str, float]]:
        """``{mode: {quantity: error}}`` of :meth:`error` for L1 and B2, JSON-ready."""
        return {m: {q: self.error(m, q) for q in ("f_short_Hz", "f_open_Hz", "k_eff")}
                for m in ("L1", "B2")}


def _solve(stator: PlateStator, material: PiezoMaterial, order: int, level: MeshLevel,
           quarter: bool):
    from fem.meshing.parametric import ParametricStator

    if isinstance(stator, ParametricStator) and level.size_factor != 1.0:
        stator = replace(stator, mesh_size_m=stator.element_size_m * level.size_factor)
    if not quarter:
        from fem.solid3d.model import solid_modes

        return solid_modes(stator, material, level.settings(order))
    from fem.solid3d.symmetric import symmetric_solid_modes

    return symmetric_solid_modes(stator, material, level.settings(order))


def estimated_solid_modes(stator: PlateStator | None = None,
                          material: PiezoMaterial | str = "pzt8", order: int = 2,
                          meshes: tuple[MeshLevel, MeshLevel] | None = None,
                          quarter: bool | None = None) -> EstimatedSolidModes:
    """L1 and B2 of the 3D model on the fine mesh of ``meshes``, with the error estimate.

    Parameters
    ----------
    stator : PlateStator, optional
        Any stator the 3D model takes (default: the paper's plate). A plain plate with a gap
        is solved on its quarter; a planform mesh on the full extruded mesh.
    material : PiezoMaterial or str
    order : int
        Element order (2: the quadratic bricks the estimate is measured for).
    meshes : (MeshLevel, MeshLevel), optional
        The coarse and the fine mesh (default :func:`default_meshes`).
    quarter : bool, optional
        Solve on the quarter-plate model (default: where it applies, a plain plate on
        graded meshes); False: the full model (whose shapes ``--export`` writes).

    Raises
    ------
    fem.modes.ModeSolverError
        If a mode cannot be found on either mesh.
    """
    t0 = time.perf_counter()
    stator = PlateStator() if stator is None else stator
    mat = get_material(material)
    meshes = default_meshes(stator) if meshes is None else tuple(meshes)
    if quarter is None:
        quarter = all(quarter_model_applies(stator, level.edge_grading) for level in meshes)
    coarse, fine = (_solve(stator, mat, order, level, quarter) for level in meshes)
    return EstimatedSolidModes(fine=fine, coarse=coarse, meshes=meshes, quarter=quarter,
                               wall_time_s=time.perf_counter() - t0)
