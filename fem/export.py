"""Export the FE mesh with its mode shapes as point data (any meshio format; ParaView: vtu).

Point data (vectors with three components, ``z = 0``, values at the mesh vertices; for
order-2 elements the vertex values of the biquadratic field):

* ``L1``, ``B2``: the identified short-circuit shapes, mass-normalized
  (``u^T M u = 1`` kg, so the unit is m per sqrt(kg));
* ``mode_00_<f>Hz``, ``mode_01_<f>Hz``, ...: every short-circuit mode computed near the
  shift, in ascending frequency ``<f>`` (Hz, rounded), same normalization;
* ``magnitude_L1``, ``magnitude_B2``: ``|u|`` (scalars, convenient for colouring).

Cell data ``electrode`` (0 = gap). Field data ``f_<name>_Hz`` holds each exported mode's
frequency where the format keeps field data (meshio's vtu writer does not; hence the
frequencies in the names of the extra modes).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

RIGID_FRACTION = 1e-3
"""Modes below this fraction of the L1/B2 frequency are rigid-body motions (0 Hz up to
round-off) and are not exported."""


def vertex_displacements(model, shape: np.ndarray) -> np.ndarray:
    """Displacement ``(u_x, u_y)`` of a dof vector at the mesh vertices, shape (2, n_vertices)."""
    dofs = model.basis.nodal_dofs  # (2, n_vertices): u_x and u_y dofs of each vertex
    return np.asarray(shape)[dofs]


def mode_fields(model, modes, n_modes: int = 8) -> tuple[dict[str, np.ndarray], dict]:
    """Point-data arrays and their frequencies (Hz) for :func:`export_modes`.

    Parameters
    ----------
    model : fem.model.PiezoPlateModel
    modes : fem.modes.PlateModes
        Identified L1/B2 of ``model``.
    n_modes : int
        Number of short-circuit modes near the L1 estimate to add (0: L1 and B2 only).

    Returns
    -------
    fields : dict of str to numpy.ndarray
        Name to (n_vertices, 3) vectors or (n_vertices,) magnitudes.
    frequencies_Hz : dict of str to float
    """
    from fem.modes import natural_frequencies_Hz

    fields: dict[str, np.ndarray] = {}
    freqs: dict[str, float] = {}
    for mode in (modes.L1, modes.B2):
        u = vertex_displacements(model, mode.shape)
        fields[mode.name] = np.column_stack((u.T, np.zeros(u.shape[1])))
        fields[f"magnitude_{mode.name}"] = np.hypot(u[0], u[1])
        freqs[mode.name] = float(mode.f_short_Hz)
    if n_modes > 0:
        fc = 0.5 * (modes.L1.f_short_Hz + modes.B2.f_short_Hz)
        f, v = natural_frequencies_Hz(model, n_modes, fc)
        for i in range(v.shape[1]):
            if f[i] < RIGID_FRACTION * fc:  # a rigid-body motion of the free plate
                continue
            shape = v[:, i] / np.sqrt(float(v[:, i] @ (model.M @ v[:, i])))
            u = vertex_displacements(model, shape)
            name = f"mode_{i:02d}_{f[i]:.0f}Hz"
            fields[name] = np.column_stack((u.T, np.zeros(u.shape[1])))
            freqs[name] = float(f[i])
    return fields, freqs


def export_modes(
    path: str | Path, model, modes, n_modes: int = 8, file_format: str | None = None
) -> Path:
    """Write the mesh with mode shapes as point data through meshio.

    Parameters
    ----------
    path : str or Path
        Output file; the format follows the extension (``.vtu`` for ParaView, ``.xdmf``,
        ``.vtk``, ...) unless ``file_format`` is given.
    model : fem.model.PiezoPlateModel
    modes : fem.modes.PlateModes
    n_modes : int
        Extra short-circuit modes near the L1/B2 pair (see :func:`mode_fields`).
    file_format : str, optional
        meshio format name.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    ValueError
        If meshio cannot write that format.
    """
    import meshio

    path = Path(path)
    fields, freqs = mode_fields(model, modes, n_modes)
    mesh = model.mesh
    pts = np.column_stack((mesh.points_m.T, np.zeros(mesh.points_m.shape[1])))
    out = meshio.Mesh(
        pts,
        [("quad", mesh.quads.T.astype(np.int64))],
        point_data=fields,
        cell_data={"electrode": [mesh.electrode.astype(np.int32)]},
        field_data={f"f_{k}_Hz": np.array([v]) for k, v in freqs.items()},
    )
    return _write(path, out, file_format)


def export_solid_modes(path: str | Path, model, modes, file_format: str | None = None) -> Path:
    """Write the 3D brick mesh with the L1 and B2 shapes as point data through meshio.

    The shapes (mass-normalized short-circuit modes of :mod:`fem.solid3d.model`, m per sqrt(kg))
    are written at the brick vertices as ``L1``, ``B2`` (vectors) and ``magnitude_L1``,
    ``magnitude_B2``; the vertex order follows scikit-fem's own meshio converter
    (:func:`skfem.io.meshio.to_meshio`), so ParaView reads ``.vtu`` hexahedra directly.

    ``path``, ``file_format``, the file returned and the ``ValueError`` raised are those of
    :func:`export_modes`; ``model`` is a :class:`fem.solid3d.model.SolidPlateModel` and
    ``modes`` its :class:`fem.solid3d.model.SolidModes`.
    """
    from skfem.io.meshio import to_meshio

    path = Path(path)
    basis = model.basis
    vertices = basis.nodal_dofs[0]  # scalar dofs at the brick vertices
    fields: dict[str, np.ndarray] = {}
    for mode in (modes.L1, modes.B2):
        u = np.asarray(mode.shape).reshape(3, basis.N)[:, vertices].T  # (n_vertices, 3)
        fields[mode.name] = u
        fields[f"magnitude_{mode.name}"] = np.linalg.norm(u, axis=1)
    out = to_meshio(basis.mesh, point_data=fields, encode_cell_data=False)
    return _write(path, out, file_format)


def _write(path: Path, out, file_format: str | None) -> Path:
    """``meshio.write`` with every failure as ``ValueError`` naming the file."""
    import meshio

    if file_format is None and Path(path).suffix.lower() == ".msh":
        # meshio's first choice for .msh is ANSYS, which drops the point data: the mode
        # shapes need gmsh's format ($NodeData), which is also what .msh means to most
        file_format = "gmsh"
    if file_format == "gmsh" and out.field_data:
        # gmsh's field data is physical groups ([tag, dim]); the frequencies stored there for
        # VTK made meshio print "Field data contains entry that cannot be processed"
        out.field_data = {}
    try:
        meshio.write(path, out, file_format=file_format)
    except (Exception, SystemExit) as exc:  # meshio: KeyError/WriteError for unknown formats
        raise ValueError(f"could not write {path} with meshio: {exc}") from exc
    return path
