"""3D piezoelastic reference model of the stator: the full solid (:mod:`fem.solid3d.model`),
its quarter by symmetry (:mod:`fem.solid3d.symmetric`) and the fill-reducing ordering of its
grid (:mod:`fem.solid3d.grid_ordering`)."""

from fem.solid3d.model import solid_modes

__all__ = ["solid_modes"]
