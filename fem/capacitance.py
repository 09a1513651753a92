"""Electrostatics of the plate's cross-section across an electrode gap (scikit-fem).

The 2D plate model sees only the thickness field ``E3`` under each electrode. Across a gap
strip of width ``g`` in a plate of thickness ``h`` the field is two-dimensional: in the
cross-section perpendicular to the gap (coordinate ``s`` across the gap, ``z`` through the
thickness) the top face carries electrode ``a`` (``s > g/2``) and electrode ``b``
(``s < -g/2``), the bottom face is grounded, the gap's top face and the outer side faces are
free (``D . n = 0``: the air outside has a permittivity ~1000 times smaller). The potential
solves ``d/ds(eps_l dphi/ds) + d/dz(eps_t dphi/dz) = 0`` with the plate model's
permittivities (``docs/fem.md``, section 1):

* through the thickness ``eps_t = eps33*`` (plane stress, ``T3 = 0``: the 2D model's value);
* across the gap ``eps_l = eps11^S + e15^2 / c44`` (``T5 = 0``, the transverse-shear stress
  the plane-stress plate also neglects: a lateral field ``E1`` shears the material freely
  through ``e15``).

From the two unit solutions ``phi_a`` (``V_a = 1``, ``V_b = 0``) and ``phi_b`` the
capacitance per unit gap length is the Maxwell matrix
``c_ij = integral eps grad(phi_i) . grad(phi_j) dA`` (F/m): symmetric positive definite,
``c_ab < 0``. The parallel-plate part ``eps_t w_i / h`` of ``c_ii`` is what the 2D model
already counts under the electrode (area / h), the rest is the gap's share. The top-face
potential ``phi_a(s, h)`` in the gap is the fraction of ``V_a`` that drives the gap material
(its thickness-averaged field is ``phi_top / h``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from fem.geometry import MIN_GAP_M


@dataclass(frozen=True, eq=False)
class GapCrossSection:
    """Result of one cross-section solve (per unit length along the gap).

    Attributes
    ----------
    c_F_m : numpy.ndarray
        2x2 Maxwell capacitance matrix per unit gap length (F/m), order (a, b); ``a`` is the
        electrode at ``s > g/2``.
    parallel_plate_F_m : numpy.ndarray
        ``eps_t w_a / h`` and ``eps_t w_b / h`` (F/m): the part of the diagonal already in
        the 2D model's ``eps33* A / h``.
    s_m : numpy.ndarray
        Positions across the gap, ``-g/2 .. g/2`` (m).
    weight_a : numpy.ndarray
        Top-face potential of the unit solution ``phi_a`` at ``s_m`` (-): 0 at the edge of
        ``b``, 1 at the edge of ``a``. By symmetry ``phi_b(s) = phi_a(-s)`` when both
        electrodes are equally wide.
    n_dofs : int
        Unknowns of the solve.
    """

    c_F_m: np.ndarray
    parallel_plate_F_m: np.ndarray
    s_m: np.ndarray
    weight_a: np.ndarray
    n_dofs: int

    @property
    def excess_F_m(self) -> np.ndarray:
        """Diagonal beyond the parallel-plate value (F/m): each electrode's gap fringe."""
        return np.diag(self.c_F_m) - self.parallel_plate_F_m

    @property
    def mutual_F_m(self) -> float:
        """Inter-electrode term ``c_ab`` (F/m), negative."""
        return float(self.c_F_m[0, 1])

    def weight(self, s_m: np.ndarray, side: str = "a") -> np.ndarray:
        """Top-face potential fraction of electrode ``side`` ('a' or 'b') at ``s_m`` (-).

        Outside the gap it is 1 under the electrode and 0 under the other one.
        """
        s = np.asarray(s_m, dtype=float)
        if side == "b":
            s = -s
        elif side != "a":
            raise ValueError(f"side must be 'a' or 'b', got {side!r}")
        return np.interp(s, self.s_m, self.weight_a, left=0.0, right=1.0)


def lateral_permittivity_F_m(material) -> float:
    """In-plane permittivity for a lateral field in the plate: ``eps11^S + e15^2/c44`` (F/m).

    ``T5 = 0`` (the plate's free transverse shear, as in the plane-stress reduction): the
    field ``E1`` shears the material through ``e15`` without stress, which raises the
    permittivity from ``eps11^S`` to the shear-free value (for PZT-8 this is ``eps11^T``).
    """
    e15 = float(material.e_C_m2[0, 4])
    c44 = float(material.cE_Pa[4, 4])
    return float(material.epsS_F_m[0, 0]) + e15**2 / c44


def _graded(a: float, b: float, h_min: float, ratio: float = 1.25, h_max: float | None = None):
    """Points from ``a`` to ``b`` (b > a) growing geometrically from size ``h_min`` at ``a``."""
    if b <= a:
        return np.array([a])
    h_max = (b - a) / 4.0 if h_max is None else h_max
    pts = [a]
    h = h_min
    while pts[-1] + h < b - 0.5 * min(h, h_max):
        pts.append(pts[-1] + h)
        h = min(h * ratio, h_max)
    pts.append(b)
    return np.array(pts)


def _electrode_side(width: float, h_min: float, h_far: float, near: float) -> np.ndarray:
    """Points from the gap's edge (0) across an electrode of ``width``: graded from
    ``h_min`` to ``h_far`` within ``near`` of the edge; beyond it the field is uniform
    through the thickness (linear potential, exact for quadratic elements), so the
    elements grow on to ``width / 6``: a 500 mm electrode on a 0.1 mm plate would take
    30 000 lines at ``h_far`` (16 GB); the paper's plate lies within ``near``."""
    pts = _graded(0.0, min(width, near), h_min, h_max=h_far)
    if width <= near:
        return pts
    far = near + _graded(0.0, width - near, h_far, h_max=max(h_far, (width - near) / 6.0))
    return np.unique(np.concatenate((pts, far)))


def _two_sided(a: float, b: float, h_min: float, h_max: float) -> np.ndarray:
    """Points on ``[a, b]`` graded towards both ends."""
    mid = 0.5 * (a + b)
    left = _graded(a, mid, h_min, h_max=h_max)
    right = b - _graded(0.0, b - mid, h_min, h_max=h_max)[::-1]
    return np.unique(np.concatenate((left, right + 0.0)))


@lru_cache(maxsize=64)
def _cross_section_mesh(g: float, h: float, width_a_m: float, width_b_m: float, r: int):
    """The cross-section's tensor mesh (m): graded towards the two electrode edges, where the
    potential is singular, and towards the top face; ``r`` the resolution factor."""
    from skfem import MeshQuad1

    # the singular corners need elements much smaller than the gap; far away, a tenth of the
    # thickness is enough (the field becomes uniform within ~h of the gap)
    h_min = min(g, h) / (40.0 * r)
    h_far = min(h, max(width_a_m, width_b_m)) / (6.0 * r)
    gap_pts = _two_sided(-g / 2, g / 2, h_min, g / (8.0 * r))
    near = 5.0 * max(h, g)  # beyond it, under an electrode, the field is the plate's own
    right = g / 2 + _electrode_side(width_a_m, h_min, h_far, near)
    left = -g / 2 - _electrode_side(width_b_m, h_min, h_far, near)[::-1]
    s = np.unique(np.concatenate((left, gap_pts, right)))
    # through the thickness the potential becomes linear a few electrode widths below the
    # top, which quadratic elements represent exactly: the elements may grow to h / 6 there
    # (a 1 m thick block at h_far would take 50 s and 3 GB; at the default plate
    # h / 6 = h_far)
    z = h - _graded(0.0, h, h_min, h_max=max(h_far, h / (6.0 * r)))[::-1]
    return MeshQuad1.init_tensor(s, z)


def gap_cross_section(
    gap_m: float,
    thickness_m: float,
    width_a_m: float,
    width_b_m: float,
    eps_lateral_F_m: float,
    eps_thickness_F_m: float,
    resolution: int = 1,
) -> GapCrossSection:
    """Capacitance per length and top-face potential across one gap (quadratic quads).

    Parameters
    ----------
    gap_m : float
        Gap width ``g`` (m), > 0.
    thickness_m : float
        Plate thickness ``h`` (m).
    width_a_m, width_b_m : float
        Electrode widths on either side of the gap (m), to the plate's free side faces.
    eps_lateral_F_m, eps_thickness_F_m : float
        Permittivities across the gap and through the thickness (F/m).
    resolution : int
        Mesh density factor (1: default; the mesh is graded towards the two electrode edges
        where the potential is singular, ``r^(1/2)``).

    Returns
    -------
    GapCrossSection
    """
    from skfem import Basis, BilinearForm, ElementQuad2, condense, solve

    g, h = float(gap_m), float(thickness_m)
    if not (g > 0.0 and h > 0.0 and width_a_m > 0.0 and width_b_m > 0.0):
        raise ValueError("gap, thickness and electrode widths must be > 0")
    # the graded mesh would need thousands of lines per micrometre decade; the tolerance
    # takes a gap measured off mesh lines (1 um can come back as 0.99999...e-6)
    if g < MIN_GAP_M * (1.0 - 1e-9):
        raise ValueError(f"electrode gap {g:g} m is below {MIN_GAP_M:g} m: too narrow to model "
                         "(make it 0 for touching quadrants)")
    basis = Basis(_cross_section_mesh(g, h, width_a_m, width_b_m, int(resolution)),
                  ElementQuad2())
    eps_l, eps_t = float(eps_lateral_F_m), float(eps_thickness_F_m)

    @BilinearForm
    def laplace(u, v, w):
        return eps_l * u.grad[0] * v.grad[0] + eps_t * u.grad[1] * v.grad[1]

    A = laplace.assemble(basis)
    x = basis.doflocs
    tol = 1e-12 * (h + g)
    top = np.abs(x[1] - h) < tol
    on_a = np.flatnonzero(top & (x[0] >= g / 2 - tol))
    on_b = np.flatnonzero(top & (x[0] <= -g / 2 + tol))
    bottom = np.flatnonzero(np.abs(x[1]) < tol)
    fixed = np.unique(np.concatenate((on_a, on_b, bottom)))
    phis = []
    for dofs in (on_a, on_b):
        phi = np.zeros(basis.N)
        phi[dofs] = 1.0
        phis.append(solve(*condense(A, x=phi, D=fixed)))
    c = np.array([[phi_i @ (A @ phi_j) for phi_j in phis] for phi_i in phis])
    c = 0.5 * (c + c.T)
    in_gap = np.flatnonzero(top & (np.abs(x[0]) <= g / 2 + tol))
    order = np.argsort(x[0, in_gap])
    s_gap = x[0, in_gap][order]
    w_a = phis[0][in_gap][order]
    pp = eps_t * np.array([width_a_m, width_b_m]) / h
    for arr in (c, pp, s_gap, w_a):
        arr.setflags(write=False)
    return GapCrossSection(c_F_m=c, parallel_plate_F_m=pp, s_m=s_gap, weight_a=w_a,
                           n_dofs=int(basis.N))
