"""2D plane-stress model against the 3D piezoelastic reference, for the report.

Works for the rectangular :class:`fem.geometry.PlateStator` (2D structured quads, 3D
structured bricks) and for stators with their own planform mesh
(:class:`fem.meshing.meshed_stator.MeshedStator`, e.g. ``load_stator(path).stator``): the 2D model
assembles on the planform mesh and the 3D model on its extrusion through the thickness
(:func:`fem.solid3d.model.extruded_hex_mesh`); the refinements are then ignored, ``layers`` is not.
"""

from __future__ import annotations

from dataclasses import dataclass

from fem.geometry import PlateStator
from fem.material import PiezoMaterial
from fem.mesh_settings import MeshSettings


@dataclass(frozen=True)
class PlaneStressError:
    """Frequencies and coupling of L1/B2 in 2D and 3D and the relative differences.

    Attributes
    ----------
    f2d_Hz, f3d_Hz : dict
        ``{'L1_short', 'L1_open', 'B2_short', 'B2_open'}`` -> frequency (Hz).
    k_eff_2d, k_eff_3d : dict
        ``{'L1', 'B2'}`` -> effective coupling (-).
    dofs_2d, dofs_3d : int
        Unknowns of each model.
    wall_time_2d_s, wall_time_3d_s : float
        Wall times of the (uncached) solutions (s).
    """

    f2d_Hz: dict
    f3d_Hz: dict
    k_eff_2d: dict
    k_eff_3d: dict
    dofs_2d: int
    dofs_3d: int
    wall_time_2d_s: float
    wall_time_3d_s: float

    @property
    def relative_error(self) -> dict[str, float]:
        """``f_2d / f_3d - 1`` for each frequency (-)."""
        return {k: self.f2d_Hz[k] / self.f3d_Hz[k] - 1.0 for k in self.f2d_Hz}

    def to_dict(self) -> dict[str, object]:
        """JSON-ready dictionary."""
        return {
            "f2d_Hz": dict(self.f2d_Hz), "f3d_Hz": dict(self.f3d_Hz),
            "relative_error": self.relative_error,
            "k_eff_2d": dict(self.k_eff_2d), "k_eff_3d": dict(self.k_eff_3d),
            "dofs_2d": self.dofs_2d, "dofs_3d": self.dofs_3d,
        }


def _table(res) -> tuple[dict, dict]:
    f = {f"{n}_{c}": getattr(getattr(res, n), f"f_{c}_Hz") for n in ("L1", "B2")
         for c in ("short", "open")}
    k = {n: getattr(res, n).k_eff for n in ("L1", "B2")}
    return f, k


def plane_stress_error(
    stator: PlateStator | None = None,
    material: PiezoMaterial | str = "pzt8",
    refine_2d: int | None = None,
    refine_3d: int | None = None,
    layers: int | None = None,
) -> PlaneStressError:
    """Compare :func:`fem.modes.plate_modes` (2D) with :func:`fem.solid3d.model.solid_modes` (3D).

    Parameters
    ----------
    stator : PlateStator, optional
        Default: the paper's plate. A ``MeshedStator`` is compared on its planform mesh
        (2D) and the extrusion of that mesh (3D).
    material : PiezoMaterial or str
    refine_2d, refine_3d, layers : int, optional
        Meshes (defaults of each model); the refinements do not apply to a planform mesh.
    """
    from fem.meshing.mesh import DEFAULT_REFINE
    from fem.modes import plate_modes
    from fem.solid3d.model import DEFAULT_LAYERS, DEFAULT_REFINE_3D, solid_modes

    stator = PlateStator() if stator is None else stator
    r2 = plate_modes(stator, material, MeshSettings(2, refine_2d or DEFAULT_REFINE))
    r3 = solid_modes(stator, material,
                     MeshSettings(2, refine_3d or DEFAULT_REFINE_3D, layers or DEFAULT_LAYERS))
    f2, k2 = _table(r2)
    f3, k3 = _table(r3)
    return PlaneStressError(f2, f3, k2, k3, r2.dofs, r3.dofs, r2.wall_time_s, r3.wall_time_s)
