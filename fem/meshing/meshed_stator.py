"""A stator whose planform is a given mesh, and how the FE stage finds that mesh.

:class:`MeshedStator` is a :class:`fem.geometry.PlateStator` that carries its own planform
mesh (read from a stator file's ``[mesh]`` table, :mod:`fem.stator_file`). The 2D model
(:func:`fem.model.plate_model`) and the 3D model (:func:`fem.solid3d.model.build_solid_model`)
ask :func:`planform_mesh` for it instead of generating the structured rectangle; a
:class:`fem.meshing.parametric.ParametricStator` (a plate with a tip, chamfers, holes) gets its mesh
there too, from gmsh.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from fem.geometry import PlateStator
from fem.meshing.mesh import PlateMesh
from fem.meshing.parametric import ParametricStator, parametric_mesh


def bbox_mm(mesh: PlateMesh) -> str:
    x0, x1, y0, y1 = (v * 1e3 for v in mesh.bounding_box_m())
    return f"x in [{x0:g}, {x1:g}] mm, y in [{y0:g}, {y1:g}] mm"


@dataclass(frozen=True)
class MeshedStator(PlateStator):
    """A stator whose planform is a given mesh (a :class:`PlateStator` the FE stage accepts).

    ``length_m`` and ``width_m`` are the mesh's bounding box (they set the sampling grid and
    the reference shapes of the mode identification); ``electrode_gap_m`` is unused (the
    mesh's tags define the electrodes).

    Attributes
    ----------
    mesh : PlateMesh
        The planform mesh (m) with electrode tags; :func:`fem.model.plate_model` uses it and
        ignores ``refine``.
    tip_m, preload_m : (float, float)
        Contact tip and preload point ``(x, y)`` (m), inside the mesh.
    mesh_file : str
        Where the mesh came from (for reports).
    """

    mesh: PlateMesh | None = None
    tip_m: tuple[float, float] = (0.0, 0.0)
    preload_m: tuple[float, float] = (0.0, 0.0)
    mesh_file: str = ""

    def __post_init__(self) -> None:
        super().__post_init__()
        if not isinstance(self.mesh, PlateMesh):
            raise ValueError("MeshedStator.mesh must be a fem.meshing.mesh.PlateMesh")
        for name in ("tip_m", "preload_m"):
            pt = tuple(float(v) for v in getattr(self, name))
            if len(pt) != 2 or not all(math.isfinite(v) for v in pt):
                raise ValueError(f"MeshedStator.{name} must be a finite (x, y) pair (m)")
            if not bool(self.mesh.contains(np.array(pt)[:, None])[0]):
                raise ValueError(
                    f"MeshedStator.{name} = ({pt[0] * 1e3:g}, {pt[1] * 1e3:g}) mm lies off the "
                    f"mesh (bounding box {bbox_mm(self.mesh)})"
                )
            object.__setattr__(self, name, pt)

    @property
    def tip_point_m(self) -> tuple[float, float]:
        """Contact tip ``(x, y)`` (m)."""
        return self.tip_m

    @property
    def preload_point_m(self) -> tuple[float, float]:
        """Preload point ``(x, y)`` (m)."""
        return self.preload_m

    def electrode_of(self, x_m: np.ndarray, y_m: np.ndarray) -> np.ndarray:
        """Electrode tag of the mesh element containing each point (0: gap or outside)."""
        x = np.asarray(x_m, dtype=float)
        y = np.asarray(y_m, dtype=float)
        shape = np.broadcast(x, y).shape
        pts = np.vstack((np.broadcast_to(x, shape).ravel(), np.broadcast_to(y, shape).ravel()))
        mesh = self.mesh
        assert mesh is not None
        out = np.zeros(pts.shape[1], dtype=int)
        inside = mesh.contains(pts)
        if np.any(inside):
            cells = mesh.to_skfem().element_finder()(*pts[:, inside])
            out[inside] = mesh.electrode[cells]
        return out.reshape(shape)



def has_planform(stator: PlateStator) -> bool:
    """Whether ``stator`` carries its own planform (:func:`planform_mesh` is not None),
    decided without meshing it."""
    return isinstance(stator, (MeshedStator, ParametricStator))


def planform_mesh(stator: PlateStator) -> PlateMesh | None:
    """The planform mesh of a :class:`MeshedStator` or of a
    :class:`fem.meshing.parametric.ParametricStator` (meshed by gmsh, cached); None for a plain
    (generated) plate."""
    if isinstance(stator, MeshedStator):
        return stator.mesh
    if isinstance(stator, ParametricStator):
        return parametric_mesh(stator)
    return None


def overall_length_m(stator: PlateStator) -> float:
    """Extent of the planform along y (m): the plate length plus a parametric tip."""
    return float(getattr(stator, "overall_length_m", stator.length_m))
