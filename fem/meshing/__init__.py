"""Meshes of the stator planform: structured grids (:mod:`fem.meshing.mesh`), mesh files
(:mod:`fem.meshing.mesh_io`), parametric gmsh stators (:mod:`fem.meshing.parametric`) and the
stator a mesh file or a parametric design describes (:mod:`fem.meshing.meshed_stator`)."""
