"""Peak displacement and peak stress of a mode shape of the 2D plate model.

A designer's limits (vibration velocity, dynamic tensile strength) are about the largest
values over the stator; :func:`shape_peaks` gives them per unit amplitude of a shape, for
the reduction to carry into the parameter set (:func:`rom.from_fem.fem_params`).
"""

from __future__ import annotations

import numpy as np

from fem.material import plane_stress

COMBINED_POINTS = 21
"""Shares of B2 at which :func:`combined_stress_factors` tabulates the combined stress."""


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
    return displacement, float(np.max(_principal_peak(*stress_field(model, shape))))


def stress_field(model, shape: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(T1, T2, T6)`` (Pa per unit of the shape's displacement in m): the plane-stress
    ``T = c* S`` of the shape at the quadrature points of the ceramic's elements
    (:func:`shape_peaks`), each ``(elements, points)``."""
    grad = model.basis.interpolate(shape).grad  # (2, 2, elements, points): d u_i / d x_j
    s1, s2, s6 = grad[0, 0], grad[1, 1], grad[0, 1] + grad[1, 0]
    c = plane_stress(model.material).c_Pa
    keep = _ceramic(model)
    return tuple((c[i, 0] * s1 + c[i, 1] * s2 + c[i, 2] * s6)[keep] for i in range(3))


def _principal_peak(t1: np.ndarray, t2: np.ndarray, t6: np.ndarray) -> np.ndarray:
    """The larger principal stress magnitude of ``[[T1, T6], [T6, T2]]`` at each point:
    ``|mean| + radius`` of Mohr's circle."""
    return np.abs(0.5 * (t1 + t2)) + np.hypot(0.5 * (t1 - t2), t6)


def combined_stress_factors(model, shape_l: np.ndarray, shape_b: np.ndarray,
                            n: int = COMBINED_POINTS) -> tuple[float, ...]:
    """The peak stress of L1 and B2 together over a period, per unit of their peaks' sum,
    at ``n`` shares of B2 (:attr:`rom.shape_data.ShapeData.combined_stress`): the
    :func:`combined_factors` of the shapes' :func:`stress_field`."""
    return combined_factors(stress_field(model, shape_l), stress_field(model, shape_b), n)


def combined_factors(field_l, field_b, n: int = COMBINED_POINTS) -> tuple[float, ...]:
    """The combined stress factors of two plane stress fields ``(T1, T2, T6)`` (Pa, arrays
    of one shape, the same points).

    With each field's peak principal stress magnitude ``s_L``, ``s_B``, the share ``t``
    (``0 .. 1``, ``n`` of them) gives ``max |principal((1 - t) T_L / s_L +- t T_B / s_B)|``
    over the points and both signs: the largest principal stress magnitude over a period of
    two sinusoidal fields of peaks ``(1 - t)`` and ``t`` at the worst phase between them
    (for any direction the normal stress of two sinusoids peaks at ``|a| + |b|``, reached
    in phase or in opposition). It is 1 at ``t = 0`` and ``t = 1``, at most 1 between (the
    peaks' sum bounds it), less where the peaks lie apart, and convex in ``t``, so
    interpolating it linearly bounds it from above.
    """
    fl = [np.asarray(a, dtype=float) for a in field_l]
    fb = [np.asarray(b, dtype=float) for b in field_b]
    sl, sb = float(np.max(_principal_peak(*fl))), float(np.max(_principal_peak(*fb)))
    out = []
    for t in np.linspace(0.0, 1.0, n):
        worst = max(float(np.max(_principal_peak(*((1.0 - t) * a / sl + sign * t * b / sb
                                                   for a, b in zip(fl, fb, strict=True)))))
                    for sign in (1.0, -1.0))
        out.append(min(worst, 1.0))
    return tuple(out)


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
