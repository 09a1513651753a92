"""Peak displacement and peak stress of a mode shape of the 2D plate model.

A designer's limits (vibration velocity, dynamic tensile strength) are about the largest
values over the stator; :func:`shape_peaks` gives them per unit amplitude of a shape, for
the reduction to carry into the parameter set (:func:`rom.from_fem.fem_params`).
"""

from __future__ import annotations

import numpy as np

from fem.material import plane_stress


def shape_peaks(model, shape: np.ndarray) -> tuple[float, float]:
    """``(displacement, stress)``: the largest displacement magnitude over the mesh's nodes
    (in the shape's units) and the largest principal stress magnitude over the quadrature
    points (Pa per unit of the shape's displacement in m).

    The stress is the plane-stress ``T = c* S`` at constant field (short circuit, the
    state of the mode shape), ``c*`` of :func:`fem.material.plane_stress`, from the
    in-plane strain of the shape; the principal values of ``[[T1, T6], [T6, T2]]`` are
    ``(T1 + T2)/2 +- sqrt(((T1 - T2)/2)^2 + T6^2)``. The stress is the ceramic's: a tip of
    its own material (alumina, steel) is left out, its limits not being the ceramic's.

    Parameters
    ----------
    model : fem.model.PiezoPlateModel
    shape : numpy.ndarray
        A displacement field on ``model.basis`` (m, or per unit amplitude).
    """
    basis = model.basis
    ux = shape[basis.nodal_dofs[0]]
    uy = shape[basis.nodal_dofs[1]]
    displacement = float(np.max(np.hypot(ux, uy)))
    grad = basis.interpolate(shape).grad  # (2, 2, elements, points): d u_i / d x_j
    s1, s2, s6 = grad[0, 0], grad[1, 1], grad[0, 1] + grad[1, 0]
    c = plane_stress(model.material).c_Pa
    t1 = c[0, 0] * s1 + c[0, 1] * s2 + c[0, 2] * s6
    t2 = c[1, 0] * s1 + c[1, 1] * s2 + c[1, 2] * s6
    t6 = c[2, 0] * s1 + c[2, 1] * s2 + c[2, 2] * s6
    mean, radius = 0.5 * (t1 + t2), np.hypot(0.5 * (t1 - t2), t6)
    peak = np.maximum(np.abs(mean + radius), np.abs(mean - radius))
    stress = float(np.max(peak[_ceramic(model)]))
    return displacement, stress


def _ceramic(model) -> np.ndarray:
    """The elements of the piezoceramic (bool per element): all but a tip of its own
    material (:func:`fem.meshing.parametric.tip_elements`)."""
    from fem.meshing.parametric import tip_elements

    keep = np.ones(model.mesh.n_elements, dtype=bool)
    tip = tip_elements(model.mesh, model.stator)
    if tip is not None:
        keep[tip[1]] = False
    return keep


def plate_volume_m3(model) -> float:
    """The ceramic's volume (m^3): the planform's area (the quadrature of 1 over the mesh,
    a tip of its own material left out) times the thickness."""
    return float(np.sum(model.basis.dx[_ceramic(model)])) * model.stator.thickness_m
