"""How a plate's FE model is meshed: one frozen object for the 2D and the 3D entry points.

:func:`fem.model.plate_model`, :func:`fem.modes.plate_modes`,
:func:`fem.solid3d.model.solid_model`, :func:`fem.solid3d.model.solid_modes`,
:func:`fem.solid3d.model.build_solid_model` and the quarter-plate models of
:mod:`fem.solid3d.symmetric` take a :class:`MeshSettings`; each reads the fields of its own
model and leaves the others at their defaults. The CLI builds one from its options.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

DEFAULT_REFINE = 4
"""Default refinement of the structured mesh (elements per smaller plate dimension): the
mesh of :func:`fem.meshing.mesh.structured_mesh`, :func:`fem.model.plate_model` and
:func:`fem.modes.plate_modes` unless told otherwise (its discretisation error is in
``docs/fem.md`` section 6)."""
DEFAULT_ELEMENT = "hex20"
"""Default quadratic brick of the 3D model (see :mod:`fem.solid3d.model` and
``docs/fem3d.md``)."""
DEFAULT_REFINE_3D = 3
"""Default in-plane refinement of the 3D model: elements per plate width, as in
:func:`fem.meshing.mesh.grid_lines_m`."""
DEFAULT_LAYERS = 3
"""Default number of element layers through the thickness of the 3D model."""


@dataclass(frozen=True)
class MeshSettings:
    """The mesh and model choices of a plate's FE model (hashable: a cache key).

    The fields are checked by the entry point that takes them, against the model it builds
    (for instance a ``refine`` whose mesh would not fit in memory).

    Attributes
    ----------
    order : int
        Element order: 2 (quadratic, default) or 1 (bilinear in 2D, trilinear in 3D).
    refine : int or None
        In-plane refinement: elements per smaller plate dimension (2D) or per plate width
        (3D), grid lines following the electrode edges; None: the model's default,
        :data:`DEFAULT_REFINE` (2D) or :data:`DEFAULT_REFINE_3D` (3D). A stator that
        carries its own planform mesh ignores it.
    layers : int
        Element layers through the thickness (3D only).
    element : str
        ``'hex20'`` (default) or ``'hex27'`` (3D, order 2 only).
    edge_grading : int
        Levels of geometric refinement towards the electrode edges, 0 for a uniform mesh
        (3D only; :func:`fem.solid3d.model.build_solid_model`).
    gap_model : str
        ``'shorted'`` (default) or ``'open'``: how the 2D model treats the electrode gap
        (:func:`fem.model.build_model`; 2D only).
    thickness_inertia : bool
        Whether the 2D model includes the inertia of the thickness motion (2D only).
    """

    order: int = 2
    refine: int | None = None
    layers: int = DEFAULT_LAYERS
    element: str = DEFAULT_ELEMENT
    edge_grading: int = 0
    gap_model: str = "shorted"
    thickness_inertia: bool = True

    def plate(self) -> MeshSettings:
        """The 2D model's settings: ``refine`` resolved, the 3D-only fields at their
        defaults (so that one 2D model has one cache key)."""
        return MeshSettings(order=self.order,
                            refine=DEFAULT_REFINE if self.refine is None else self.refine,
                            gap_model=self.gap_model, thickness_inertia=self.thickness_inertia)

    def solid(self) -> MeshSettings:
        """The 3D model's settings: ``refine`` resolved, the 2D-only fields at their
        defaults."""
        return replace(self, refine=DEFAULT_REFINE_3D if self.refine is None else self.refine,
                       gap_model="shorted", thickness_inertia=True)
