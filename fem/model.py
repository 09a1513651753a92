"""Assembly of the 2D plane-stress piezoelastic plate model (scikit-fem).

Unknowns are the in-plane displacements ``(u_x, u_y)`` (m) of the mid-plane; the electrode
voltages enter through the thickness field ``E3`` (the paper's Appendix A convention
``E3 = V0/h_s``: a positive voltage drives the field along the poling axis). With ``S = B u``
the in-plane strains ``[S1, S2, S6]`` (Voigt, engineering shear)::

    K   = h  integral( B^T c* B ) dA          (short circuit, all electrodes grounded)
    M   = h  integral( rho N^T N ) dA + rho h^3/12 integral( B^T a a^T B ) dA
    G_e =    integral( B^T e*^T w_e ) dA      (force per volt, N/V)
    C   =    4x4 clamped Maxwell capacitance matrix (F)

so that ``M u'' + K u = sum_e G_e V_e`` and the charges are ``Q = G^T u + C V``
(``docs/fem.md``, section 1):

* ``w_e(x, y)`` is the fraction of ``V_e`` on the top face: 1 under electrode e, 0 under the
  others, the cross-section potential of :mod:`fem.capacitance` in the gap strips. The strips
  are shorted by their grounded neighbours (valid for gaps up to thickness/6; beyond that
  :class:`GapValidityWarning`) and take the short-circuit stiffness ``c*``;
  ``gap_model='open'`` keeps the earlier ``D3 = 0`` strips (``c*_open``, no coupling).
* ``C`` adds to the parallel-plate diagonal ``eps33* A_e / h`` the gap fringes and the
  (negative) mutual capacitances across the strips, from one cross-section solve per strip.
* The second mass term is the inertia of the thickness motion ``u_z = z S3`` with
  ``S3 = -a . S + (e33/c33) E3``; its field part couples ``u`` and ``V`` (``M_uV``, ``M_VV``).

Open circuit (floating electrodes, zero charge, the others grounded):
``V_o = -C_oo^-1 G_o^T u``, ``K_open = K + G_o C_oo^-1 G_o^T`` and
``M_open = M - M_uV R - R^T M_uV^T + R^T M_VV R`` with ``R = C_oo^-1 G_o^T``.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.sparse as sp

from bounds import ParameterError
from fem.errors import GapValidityWarning as GapValidityWarning
from fem.errors import ShortedDriveError as ShortedDriveError
from fem.geometry import ELECTRODES, PlateStator
from fem.material import PiezoMaterial, get_material, plane_stress
from fem.mesh_settings import MeshSettings
from fem.meshing.mesh import (
    PlateMesh,
    boundary_edges,
    check_generated_size,
    grid_lines_m,
    structured_mesh,
)
from fem.meshing.meshed_stator import overall_length_m, planform_mesh
from fem.meshing.parametric import tip_elements

ORDERS = (1, 2)
"""Supported element orders (bilinear ``ElementQuad1``, biquadratic ``ElementQuad2``)."""


def _element(order: int):
    from skfem import ElementQuad1, ElementQuad2, ElementVector

    if order not in ORDERS:
        raise ValueError(f"order must be one of {ORDERS}, got {order!r}")
    return ElementVector(ElementQuad1() if order == 1 else ElementQuad2())


def _voigt(eps):
    """In-plane strain vector ``[S1, S2, S6]`` from a symmetric gradient (x = 1, y = 2)."""
    return (eps[0, 0], eps[1, 1], 2.0 * eps[0, 1])


def _stiffness_form(c: np.ndarray, thickness_m: float):
    from skfem import BilinearForm
    from skfem.helpers import sym_grad

    c = np.asarray(c, dtype=float)

    @BilinearForm
    def form(u, v, w):
        su = _voigt(sym_grad(u))
        sv = _voigt(sym_grad(v))
        out = 0.0
        for i in range(3):
            for j in range(3):
                if c[i, j] != 0.0:
                    out = out + c[i, j] * su[j] * sv[i]
        return thickness_m * out

    return form


def _mass_form(rho_h: float):
    from skfem import BilinearForm
    from skfem.helpers import dot

    @BilinearForm
    def form(u, v, w):
        return rho_h * dot(u, v)

    return form


def _coupling_form(e_star: np.ndarray):
    from skfem import LinearForm
    from skfem.helpers import sym_grad

    e = np.asarray(e_star, dtype=float)

    @LinearForm
    def form(v, w):
        sv = _voigt(sym_grad(v))
        return e[0] * sv[0] + e[1] * sv[1] + e[2] * sv[2]

    return form


def _weighted_coupling_form(e_star: np.ndarray, weight):
    """Coupling over a gap strip: ``integral B^T e*^T w(x, y) dA`` with ``w`` the fraction of
    the electrode voltage on the gap's top face (thickness-averaged ``E3 = w V / h``)."""
    from skfem import LinearForm
    from skfem.helpers import sym_grad

    e = np.asarray(e_star, dtype=float)

    @LinearForm
    def form(v, w):
        sv = _voigt(sym_grad(v))
        return weight(w.x[0], w.x[1]) * (e[0] * sv[0] + e[1] * sv[1] + e[2] * sv[2])

    return form


def _thickness_inertia_form(rho_h3_12: float, a: np.ndarray):
    """Kinetic energy of the thickness motion ``u_z = z S3`` with ``S3 = -a . [S1, S2, S6]``:
    ``rho h^3/12 integral (a . S(u)) (a . S(v)) dA`` (``docs/fem.md``, section 1)."""
    from skfem import BilinearForm
    from skfem.helpers import sym_grad

    a = np.asarray(a, dtype=float)

    @BilinearForm
    def form(u, v, w):
        su = _voigt(sym_grad(u))
        sv = _voigt(sym_grad(v))
        s3u = a[0] * su[0] + a[1] * su[1] + a[2] * su[2]
        s3v = a[0] * sv[0] + a[1] * sv[1] + a[2] * sv[2]
        return rho_h3_12 * s3u * s3v

    return form


GAP_MODELS = ("shorted", "open")
"""Gap-strip models: ``'shorted'`` (default; the grounded neighbours short the strip, its
material has the short-circuit stiffness and is driven by the neighbours' voltages through
the cross-section potential, inter-electrode capacitances from :mod:`fem.capacitance`) and
``'open'`` (the earlier model: ``D3 = 0`` in the strip, stiffness ``c*_open``, no coupling,
diagonal capacitance matrix)."""

GAP_VALIDITY_RATIO = 1.0 / 6.0
"""Largest gap / thickness for which the shorted-gap 2D model is valid (``docs/fem.md``)."""


def gap_validity(gap_m: float, thickness_m: float) -> GapValidityWarning | None:
    """The warning to give when ``gap_m > thickness_m / 6``, else None."""
    if gap_m <= GAP_VALIDITY_RATIO * thickness_m * (1.0 + 1e-9):
        return None
    return GapValidityWarning(gap_m, thickness_m, GAP_VALIDITY_RATIO * thickness_m)


def gap_validity_message(gap_m: float, thickness_m: float) -> str | None:
    """One-line warning text when ``gap_m > thickness_m / 6``, else None."""
    warning = gap_validity(gap_m, thickness_m)
    return None if warning is None else str(warning)


def stator_gap_m(stator: PlateStator) -> float:
    """The electrode gap (m): a meshed stator's comes from its mesh's gap strips."""
    mesh = planform_mesh(stator)
    return gap_layout(mesh).gap_m if mesh is not None else stator.electrode_gap_m


def stator_gap_validity(stator: PlateStator) -> GapValidityWarning | None:
    """:func:`gap_validity` for a stator (a meshed stator's gaps come from its mesh)."""
    return gap_validity(stator_gap_m(stator), stator.thickness_m)


BORDER_SHARE = 0.2
"""Share of a planform's outline along unelectroded material outside the gap strips above
which the 2D model warns (:class:`UnelectrodedBorderWarning`): a protruding tip takes a few
per cent of it, electrodes set back from the edges nearly all."""


class UnelectrodedBorderWarning(UserWarning):
    """Electrodes set back from the plate's edges: the 2D model takes the border as
    open-circuit (D3 = 0) material, stiffer than the 3D model finds it; use ``--model 3d``."""


def unelectroded_outline_share(mesh: PlateMesh, layout: GapLayout, near_m: float) -> float:
    """Share (-) of the mesh's outline length (outer edges and holes) along unelectroded
    elements outside the two gap strips (:meth:`GapLayout.in_strip`) whose centres lie within
    ``near_m`` (m) of an electroded node: a border an electrode's edge shorts, not the far
    part of a protruding tip (a tip as wide as the plate put 29 % of the outline along bare
    material)."""
    from scipy.spatial import cKDTree

    q = mesh.quads
    edges, el = boundary_edges(q)  # the outline: edges in one element only, and that element
    p = mesh.points_m
    length = np.linalg.norm(p[:, edges[:, 0]] - p[:, edges[:, 1]], axis=0)
    centres = p[:, q[:, el]].mean(axis=1)
    bare = (mesh.electrode[el] == 0) & ~layout.in_strip(centres[0], centres[1])
    if bare.any():
        nodes = np.unique(q[:, mesh.electrode > 0])
        idx = np.flatnonzero(bare)
        dist, _ = cKDTree(p[:, nodes].T).query(centres[:, idx].T)
        # the nearest electroded node may be an element away along the edge: allow the
        # element's own size (its largest centre-to-corner distance)
        size = np.max(np.linalg.norm(p[:, q[:, el[idx]]] - centres[:, None, idx], axis=0),
                      axis=0)
        bare[idx[dist > near_m + size]] = False
    total = float(length.sum())
    return float(length[bare].sum()) / total if total > 0 else 0.0


def border_message(share: float) -> str:
    """The warning for a planform whose outline is ``share`` unelectroded."""
    return (f"{share:.0%} of the plate's outline is unelectroded outside the gap strips "
            f"(electrodes set back from its edges): the 2D model takes that border as "
            f"open-circuit material (D3 = 0), stiffer than a border its grounded neighbour "
            f"shorts (a 0.5 mm border on the paper's plate: L1 0.6 % and B2 1.2 % above the "
            f"3D model, B2 k_eff 18 % below; docs/fem.md); use the 3D model "
            f"(lusm modes --model 3d)")


@dataclass(frozen=True)
class GapLayout:
    """The two gap strips of a quadrant-electrode mesh, read from its electrode tags.

    Attributes
    ----------
    x_mid_m, gap_x_m : float
        Centre and width of the strip parallel to y (between 1, 2 at larger x and 3, 4) (m).
    y_mid_m, gap_y_m : float
        Centre and width of the strip parallel to x (between 2, 4 at larger y and 1, 3) (m).
    x_lo_m, x_hi_m, y_lo_m, y_hi_m : float
        Extent of the electroded area (m).
    """

    x_mid_m: float
    gap_x_m: float
    y_mid_m: float
    gap_y_m: float
    x_lo_m: float
    x_hi_m: float
    y_lo_m: float
    y_hi_m: float

    @property
    def gap_m(self) -> float:
        """The wider of the two gaps (m)."""
        return max(self.gap_x_m, self.gap_y_m)

    def in_strip(self, x_m: np.ndarray, y_m: np.ndarray) -> np.ndarray:
        """True for points inside a gap strip (within the electroded extent)."""
        in_x = (np.abs(x_m - self.x_mid_m) < 0.5 * self.gap_x_m) & (y_m > self.y_lo_m) & (
            y_m < self.y_hi_m)
        in_y = (np.abs(y_m - self.y_mid_m) < 0.5 * self.gap_y_m) & (x_m > self.x_lo_m) & (
            x_m < self.x_hi_m)
        return in_x | in_y


def gap_layout(mesh: PlateMesh) -> GapLayout:
    """Gap strips of ``mesh`` from the node coordinates of its electrode elements.

    Raises
    ------
    ValueError
        If the tags are not the plate's quadrants
        (:meth:`fem.meshing.mesh.PlateMesh.quadrant_problem`).
    """
    problem = mesh.quadrant_problem()
    if problem is not None:
        raise ValueError(f"the mesh's electrode tags: {problem}")
    p = mesh.points_m

    def nodes(tags):
        el = np.flatnonzero(np.isin(mesh.electrode, tags))
        return p[:, np.unique(mesh.quads[:, el])]

    hi_x, lo_x = nodes((1, 2)), nodes((3, 4))
    hi_y, lo_y = nodes((2, 4)), nodes((1, 3))
    xa, xb = float(hi_x[0].min()), float(lo_x[0].max())
    ya, yb = float(hi_y[1].min()), float(lo_y[1].max())
    every = nodes(ELECTRODES)
    return GapLayout(
        x_mid_m=0.5 * (xa + xb), gap_x_m=max(xa - xb, 0.0),
        y_mid_m=0.5 * (ya + yb), gap_y_m=max(ya - yb, 0.0),
        x_lo_m=float(every[0].min()), x_hi_m=float(every[0].max()),
        y_lo_m=float(every[1].min()), y_hi_m=float(every[1].max()),
    )


def check_mesh_wiring(mesh: PlateMesh, voltages: dict[int, float]) -> None:
    """Refuse a drive that puts two voltages on one conductor of ``mesh``, from its
    electrode tags alone (no FE work).

    ``voltages`` maps driven electrodes to their (relative) voltage; the others are
    grounded. Quadrants with no gap strip between them are one conductor
    (:func:`mesh_conductors`): driving 1 and 4 against grounded 2 and 3 on a plate without
    gaps shorts the source, and the force factors of such a drive mean nothing.

    Raises
    ------
    ShortedDriveError
        A ``ValueError`` naming the touching electrodes and their voltages.
    """
    for group in mesh_conductors(mesh):
        levels = {float(voltages.get(e, 0.0)) for e in group}
        if len(levels) > 1:
            wired = ", ".join(
                f"{e} {'grounded' if voltages.get(e, 0.0) == 0 else 'driven'}"
                + ("" if voltages.get(e, 0.0) in (0.0, 1.0) else " (-V)")
                for e in group)
            raise ShortedDriveError(
                f"electrodes {wired} touch (no gap strip between them) and are one "
                f"conductor, which cannot hold two voltages: the drive would short",
                tuple(group))


def mesh_conductors(mesh: PlateMesh,
                    open_electrodes: tuple[int, ...] = ELECTRODES) -> list[list[int]]:
    """The open electrodes of ``mesh`` grouped into conductors: quadrants with no gap strip
    between them touch and float as one conductor (one potential, one net charge).

    With a gap every quadrant is its own conductor. With no gap (``electrode_gap_m = 0``,
    or a mesh whose electrode tags meet) the four quadrants are one electrode, so in open
    circuit B2, whose charges cancel over the four, is not stiffened at all
    (``k_eff = 0``), as in the 3D model and SfePy (``docs/fem3d.md`` section 5).
    """
    _check_electrodes(open_electrodes)
    layout = gap_layout(mesh)
    touching = []
    if layout.gap_x_m <= 0.0:  # across x = 0: 1-3 and 2-4 meet
        touching += [(1, 3), (2, 4)]
    if layout.gap_y_m <= 0.0:  # across y = l/2: 1-2 and 3-4 meet
        touching += [(1, 2), (3, 4)]
    groups = [[e] for e in open_electrodes]
    for a, b in touching:
        ga = next((g for g in groups if a in g), None)
        gb = next((g for g in groups if b in g), None)
        if ga is not None and gb is not None and ga is not gb:
            ga += gb
            groups.remove(gb)
    return [sorted(g) for g in groups]


@dataclass(frozen=True, eq=False)
class PiezoPlateModel:
    """Assembled matrices of the plate (treat them as read-only; results may be cached).

    Attributes
    ----------
    stator : PlateStator
        The plate modelled.
    material : PiezoMaterial
        Its constants (reduced to plane stress in the assembly).
    order : int
        Element order (1 or 2).
    mesh : PlateMesh
        The planform mesh (m).
    basis : skfem.CellBasis
        Vector basis on the whole plate (for probing fields).
    K : scipy.sparse.csr_matrix
        Short-circuit stiffness (N/m), symmetric.
    M : scipy.sparse.csr_matrix
        Mass (kg), symmetric.
    G : numpy.ndarray
        Coupling vectors, shape (n_dofs, 4), column ``e-1`` for electrode e (N/V).
    C_F : numpy.ndarray
        Diagonal of :attr:`capacitance_matrix_F`: clamped self-capacitances of electrodes
        1..4 (F), each with the other electrodes grounded.
    assembly_time_s : float
        Wall time of mesh generation and assembly (s).
    capacitance_matrix_F : numpy.ndarray
        Clamped 4x4 Maxwell capacitance matrix (F), symmetric positive definite:
        ``Q = G^T u + C V``; off-diagonal (negative) terms couple neighbouring electrodes
        across the gaps. Default: ``diag(C_F)``.
    gap_model : str
        One of :data:`GAP_MODELS`.
    thickness_inertia : bool
        Whether ``M`` includes the thickness-motion inertia ``rho h^3/12 (dS3/dt)^2``.
    M_uV : numpy.ndarray
        Inertia coupling of the displacements to the electrode voltages, shape (n_dofs, 4)
        (kg/V): the field part ``(e33/c33) E3`` of ``S3`` moves the faces too. Zero without
        thickness inertia.
    M_VV : numpy.ndarray
        Inertia of the voltages, 4x4 (kg/V^2). The kinetic energy is
        ``1/2 [u', V']^T [[M, M_uV], [M_uV^T, M_VV]] [u', V']``.
    """

    stator: PlateStator
    material: PiezoMaterial
    order: int
    mesh: PlateMesh
    basis: object
    K: sp.csr_matrix
    M: sp.csr_matrix
    G: np.ndarray
    C_F: np.ndarray
    assembly_time_s: float
    capacitance_matrix_F: np.ndarray | None = None
    gap_model: str = "shorted"
    thickness_inertia: bool = True
    M_uV: np.ndarray | None = None
    M_VV: np.ndarray | None = None

    def __post_init__(self) -> None:
        n_e = len(ELECTRODES)
        defaults = {
            "capacitance_matrix_F": lambda: np.diag(np.asarray(self.C_F, dtype=float)),
            "M_uV": lambda: np.zeros((self.K.shape[0], n_e)),
            "M_VV": lambda: np.zeros((n_e, n_e)),
        }
        for name, make in defaults.items():
            if getattr(self, name) is None:
                arr = make()
                arr.setflags(write=False)
                object.__setattr__(self, name, arr)

    @property
    def n_dofs(self) -> int:
        """Number of displacement degrees of freedom."""
        return int(self.K.shape[0])

    def coupling(self, electrodes: tuple[int, ...]) -> np.ndarray:
        """Sum of the coupling vectors of ``electrodes`` driven at the same voltage (N/V)."""
        _check_electrodes(electrodes)
        self.check_wiring({e: 1.0 for e in electrodes})
        return self.G[:, [e - 1 for e in electrodes]].sum(axis=1)

    def check_wiring(self, voltages: dict[int, float]) -> None:
        """Refuse a drive that puts two voltages on one conductor
        (:func:`check_mesh_wiring` on this model's mesh).

        Raises
        ------
        ShortedDriveError
            A ``ValueError`` naming the touching electrodes and their voltages.
        """
        check_mesh_wiring(self.mesh, voltages)

    def conductors(self, open_electrodes: tuple[int, ...] = ELECTRODES) -> list[list[int]]:
        """The open electrodes grouped into conductors (:func:`mesh_conductors` of this
        model's mesh)."""
        return mesh_conductors(self.mesh, open_electrodes)

    def _ports(self, open_electrodes: tuple[int, ...]) -> tuple[list[int], np.ndarray]:
        """Electrode columns of the open set and the incidence ``T`` (electrodes x
        conductors) that sums them into :meth:`conductors`."""
        idx = [e - 1 for e in open_electrodes]
        groups = self.conductors(open_electrodes)
        T = np.zeros((len(idx), len(groups)))
        for j, g in enumerate(groups):
            for e in g:
                T[open_electrodes.index(e), j] = 1.0
        return idx, T

    def open_circuit_update(
        self, open_electrodes: tuple[int, ...] = ELECTRODES
    ) -> tuple[np.ndarray, np.ndarray]:
        """Low-rank factors ``(U, D)`` with ``K_open = K + U diag(D) U^T``.

        The open electrodes float with zero charge, the others are grounded:
        ``0 = G_o^T u + C_oo V_o``, so ``K_open = K + G_o C_oo^-1 G_o^T`` (Schur complement on
        the open set). With the Cholesky factor ``C_oo = L L^T``, ``U = G_o L^-T`` and
        ``D = 1``; for a diagonal ``C_oo`` this is ``U = G_o``, ``D = 1 / C``.
        """
        idx, T = self._ports(tuple(open_electrodes))
        c_oo = T.T @ self.capacitance_matrix_F[np.ix_(idx, idx)] @ T
        g_o = self.G[:, idx] @ T
        if np.count_nonzero(c_oo - np.diag(np.diag(c_oo))) == 0:
            return g_o, 1.0 / np.diag(c_oo)
        chol = np.linalg.cholesky(c_oo)
        u = np.linalg.solve(chol, g_o.T).T  # G_o L^-T
        return u, np.ones(T.shape[1])

    def open_circuit_mass_update(
        self, open_electrodes: tuple[int, ...] = ELECTRODES
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """Low-rank factors ``(W, S)`` with ``M_open = M + W S W^T``, or None if ``M_uV = 0``.

        With ``V_o = -R u``, ``R = C_oo^-1 G_o^T``, the kinetic energy gives
        ``M_open = M - M_uV R - R^T M_uV^T + R^T M_VV R``; ``W = [G_o, M_uV_o]`` and
        ``S = [[C^-1 M_VV C^-1, -C^-1], [-C^-1, 0]]``.
        """
        idx, T = self._ports(tuple(open_electrodes))
        m_uv = self.M_uV[:, idx] @ T
        if not np.any(m_uv):
            return None
        c_inv = np.linalg.inv(T.T @ self.capacitance_matrix_F[np.ix_(idx, idx)] @ T)
        m_vv = T.T @ self.M_VV[np.ix_(idx, idx)] @ T
        S = np.block([[c_inv @ m_vv @ c_inv, -c_inv], [-c_inv, np.zeros_like(c_inv)]])
        return np.hstack((self.G[:, idx] @ T, m_uv)), 0.5 * (S + S.T)

    def M_open(self, open_electrodes: tuple[int, ...] = ELECTRODES) -> sp.csr_matrix:
        """Open-circuit mass ``M + W S W^T`` (explicit; dense blocks)."""
        upd = self.open_circuit_mass_update(open_electrodes)
        if upd is None:
            return self.M
        W, S = upd
        return (self.M + sp.csr_matrix(W @ S @ W.T)).tocsr()

    def K_open(self, open_electrodes: tuple[int, ...] = ELECTRODES) -> sp.csr_matrix:
        """Open-circuit stiffness ``K + G_o C_oo^-1 G_o^T`` (explicit; dense blocks)."""
        u, d = self.open_circuit_update(open_electrodes)
        return (self.K + sp.csr_matrix((u * d) @ u.T)).tocsr()

    def probe(self, points_m: np.ndarray) -> sp.csr_matrix:
        """Matrix ``P`` of shape (2 n_points, n_dofs): ``P @ u`` stacks ``u_x`` then ``u_y``."""
        pts = np.atleast_2d(np.asarray(points_m, dtype=float))
        if pts.shape[0] != 2:
            pts = pts.T
        # a point on the mesh's edge computed in other arithmetic lies outside it by roundoff
        # (a parametric tip at y = 0.035 + 0.001 = 0.036000000000000004 m beside nodes at
        # 0.036): scikit-fem's "Point is outside of the mesh." stopped params, simulate and
        # characteristic of such stators; within 1e-9 of the mesh's size it is moved onto it
        xy = self.basis.mesh.p
        lo, hi = xy.min(axis=1)[:, None], xy.max(axis=1)[:, None]
        tol = 1e-9 * float(np.max(hi - lo))
        near = (pts >= lo - tol) & (pts <= hi + tol)
        pts = np.where(near, np.clip(pts, lo, hi), pts)
        try:
            return self.basis.probes(pts).tocsr()
        except Exception as exc:  # noqa: BLE001 - scikit-fem raises a bare Exception here
            # its Newton inverse of the quad map can stall on a micrometre gap strip beside
            # millimetre elements (--gap-mm 0.001); a parallelogram's map is affine and
            # inverted exactly instead
            if "Newton" not in str(exc):
                raise
            probe = affine_probes(self.basis, pts)
            if probe is None:
                raise
            return probe


def affine_probes(basis, pts: np.ndarray, chunk: int = 2_000_000) -> sp.csr_matrix | None:
    """``basis.probes(pts)`` for a mesh of quads or hexes whose cells' maps are affine
    (parallelograms, boxes, parallelepipeds), inverted exactly: no Newton iteration.

    The map's values at the reference cell's corners give each cell's origin and Jacobian;
    a point's reference coordinates follow from one small solve. Returns None when the mesh
    is not of quads or hexes, or a cell's map is not affine (the caller keeps scikit-fem's
    answer). The 2D model (:meth:`PiezoPlateModel.probe`) and the 3D one
    (:meth:`fem.solid3d.model.SolidPlateModel.probe`) fall back on it where scikit-fem's Newton
    inverse stalls beside a micrometre gap.

    Parameters
    ----------
    basis : skfem.CellBasis
        A basis on a ``MeshQuad1`` or ``MeshHex1`` (reference cell the unit square or cube).
    pts : numpy.ndarray
        Points (dim, n) in m, inside the mesh.
    chunk : int
        Most point x cell pairs tested at once (memory).
    """
    dim, n = pts.shape
    if basis.mesh.t.shape[0] != 2**dim:
        return None
    corners = np.hstack([np.zeros((dim, 1)), np.eye(dim), np.ones((dim, 1))])
    f = basis.mapping.F(corners)  # (dim, cells, dim + 2): F(0), F(e_1), ..., F(1, ..., 1)
    origin = f[:, :, 0]
    jac = np.stack([f[:, :, k + 1] - origin for k in range(dim)], axis=-1)  # (dim, cells, dim)
    size = np.abs(jac).max(axis=(0, 2))
    if np.any(np.abs(f[:, :, -1] - origin - jac.sum(axis=-1)).max(axis=0) > 1e-9 * size):
        return None
    inv = np.linalg.inv(np.moveaxis(jac, 1, 0))  # (cells, dim, dim)
    n_cells = origin.shape[1]
    cells = np.full(n, -1)
    ref = np.zeros((dim, n))
    step = max(1, chunk // n_cells)
    tol = 1e-10
    for a in range(0, n, step):
        d = pts[:, a:a + step, None] - origin[:, None, :]  # (dim, points, cells)
        x = np.einsum("cij,jpc->ipc", inv, d)
        inside = np.all((x >= -tol) & (x <= 1 + tol), axis=0)
        found = inside.any(axis=1)
        first = np.argmax(inside, axis=1)
        rows = np.arange(first.size)
        cells[a:a + step] = np.where(found, first, -1)
        ref[:, a:a + step] = x[:, rows, first]
    if np.any(cells < 0):
        raise ValueError("a probe point lies outside the mesh")
    X = np.clip(ref, 0.0, 1.0)[:, :, None]
    phis = np.array([basis.elem.gbasis(basis.mapping, X, k, tind=cells)[0]
                     for k in range(basis.Nbfun)]).flatten()
    comp = int(np.prod(basis._base_tensor_order))
    rows = np.tile(np.arange(comp * n, dtype=np.int32), basis.Nbfun)
    cols = basis.element_dofs[:, np.tile(cells, comp)].flatten()
    return sp.coo_matrix((phis, (rows, cols)), shape=(comp * n, basis.N)).tocsr()


def _check_electrodes(electrodes: tuple[int, ...]) -> None:
    if any(e not in ELECTRODES for e in electrodes):
        raise ValueError(f"electrodes must be numbers in 1..4, got {electrodes!r}")


def _check_mesh_fits(mesh: PlateMesh, stator: PlateStator) -> None:
    x0, x1, y0, y1 = mesh.bounding_box_m()
    w, length = stator.width_m, overall_length_m(stator)
    tol = 1e-9 * max(w, length)
    if (
        abs(x0 + w / 2) > tol
        or abs(x1 - w / 2) > tol
        or abs(y0) > tol
        or abs(y1 - length) > tol
    ):
        raise ValueError(
            f"mesh bounding box x=[{x0}, {x1}] m, y=[{y0}, {y1}] m does not match the stator "
            f"(x=[{-w / 2}, {w / 2}] m, y=[0, {length}] m)"
        )


def build_model(
    mesh: PlateMesh,
    stator: PlateStator,
    material: PiezoMaterial | str = "pzt8",
    order: int = 2,
    gap_model: str = "shorted",
    thickness_inertia: bool = True,
) -> PiezoPlateModel:
    """Assemble K, M, G and C on a given (possibly file-read) mesh.

    Parameters
    ----------
    mesh : PlateMesh
        Quadrilateral mesh with electrode tags, x centred, y from 0 to l (m).
    stator : PlateStator
        Geometry (thickness, dimensions checked against the mesh).
    material : PiezoMaterial or str
        Material or its name (``'pzt8'``, ``'paper'``).
    order : int
        Element order, 1 or 2.
    gap_model : str
        ``'shorted'`` (default) or ``'open'`` (``D3 = 0`` strips); see :data:`GAP_MODELS` and
        ``docs/fem.md``.
    thickness_inertia : bool
        Add the inertia of the thickness motion ``u_z = z S3`` to ``M`` (default True).

    Warns
    -----
    GapValidityWarning
        With ``gap_model='shorted'`` and a gap wider than thickness/6.
    """
    from skfem import Basis, asm

    if gap_model not in GAP_MODELS:
        raise ValueError(f"gap_model must be one of {GAP_MODELS}, got {gap_model!r}")
    t0 = time.perf_counter()
    mat = get_material(material)
    elem = _element(order)
    _check_mesh_fits(mesh, stator)
    ps = plane_stress(mat)
    h = stator.thickness_m
    basis = Basis(mesh.to_skfem(), elem)
    layout = gap_layout(mesh)
    shorted = gap_model == "shorted" and layout.gap_m > 0.0
    strips, other, strip_centres = _strip_elements(mesh, layout, shorted, h)
    tip = tip_elements(mesh, stator)
    K, M = _stiffness_and_mass(basis, mesh, mat, ps, h, strips, other, thickness_inertia, tip)
    G, C = _electrode_coupling(basis, mesh, ps, h)
    cap = np.diag(C)
    weights = {k: (lambda x, y: np.zeros_like(x)) for k in ELECTRODES}
    sub = basis.with_elements(strips) if strips.size else None
    if shorted and sub is not None:
        strip_areas = np.asarray(sub.dx).sum(axis=1)  # m^2 per strip element
        weights, cap = _gap_terms(layout, mat, h, C, strip_centres, strip_areas)
        for k in ELECTRODES:
            G[:, k - 1] += asm(_weighted_coupling_form(ps.e_C_m2, weights[k]), sub)
        C = np.diag(cap).copy()
    m_uv, m_vv = (_thickness_inertia_coupling(basis, mesh, mat, h, sub, weights)
                  if thickness_inertia else (np.zeros_like(G), np.zeros_like(cap)))
    K = (0.5 * (K + K.T)).tocsr()
    M = (0.5 * (M + M.T)).tocsr()
    for arr in (G, C, cap, m_uv, m_vv):
        arr.setflags(write=False)
    return PiezoPlateModel(
        stator=stator,
        material=mat,
        order=int(order),
        mesh=mesh,
        basis=basis,
        K=K,
        M=M,
        G=G,
        C_F=C,
        assembly_time_s=time.perf_counter() - t0,
        capacitance_matrix_F=cap,
        gap_model=gap_model,
        thickness_inertia=bool(thickness_inertia),
        M_uV=m_uv,
        M_VV=m_vv,
    )


def _strip_elements(mesh: PlateMesh, layout: GapLayout, shorted: bool,
                    h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """The unelectroded elements split into the gap strips the shorted model takes
    (``E3 = 0`` with the gap terms) and the others (``D3 = 0``: a protruding tip, or every
    strip of the open model), and the strips' centres (m; None unless ``shorted``). Warns
    where the shorted model's assumptions are stretched (a wide gap, an unelectroded
    border)."""
    untagged = mesh.elements_of(0)
    if not shorted:
        return untagged[:0], untagged, None
    validity = gap_validity(layout.gap_m, h)
    if validity is not None:  # stacklevel: the caller of build_model
        warnings.warn(validity, stacklevel=3)
    share = unelectroded_outline_share(mesh, layout, GAP_VALIDITY_RATIO * h)
    if share > BORDER_SHARE:
        warnings.warn(border_message(share), UnelectrodedBorderWarning, stacklevel=3)
    centres = mesh.points_m[:, mesh.quads[:, untagged]].mean(axis=1)
    in_strip = layout.in_strip(centres[0], centres[1])
    return untagged[in_strip], untagged[~in_strip], centres[:, in_strip]


def _thickness_ratio(mat: PiezoMaterial) -> np.ndarray:
    """``a`` of the plane-stress thickness strain ``S3 = -a . [S1, S2, S6]`` (-)."""
    c = mat.cE_Pa
    return np.array([c[2, 0], c[2, 1], c[2, 5]]) / c[2, 2]


def _stiffness_and_mass(basis, mesh: PlateMesh, mat: PiezoMaterial, ps, h: float,
                        strips: np.ndarray, other: np.ndarray, thickness_inertia: bool,
                        tip: tuple[object, np.ndarray] | None = None):
    """Stiffness ``K`` and mass ``M`` (scikit-fem sparse matrices, not yet symmetrized).

    Electrodes and shorted strips take the short-circuit stiffness (``E3 = 0``); the
    unelectroded material away from the electrodes and the strips of the 'open' model the
    open-circuit one (``D3 = 0``); a ``tip`` of its own material
    (:class:`fem.material.ElasticMaterial`, its elements) its isotropic plane-stress
    stiffness, density and thickness strain."""
    from skfem import asm

    electroded = np.flatnonzero(mesh.electrode > 0)
    tip_el = tip[1] if tip is not None else other[:0]
    # the whole basis where the tip is the ceramic's (the same sums as ever)
    ceramic = np.setdiff1d(np.arange(mesh.n_elements), tip_el) if tip_el.size else None
    if tip_el.size:
        other = np.setdiff1d(other, tip_el)
    K = asm(_stiffness_form(ps.c_Pa, h), basis.with_elements(np.concatenate((electroded,
                                                                             strips))))
    if other.size:
        K = K + asm(_stiffness_form(ps.c_open_Pa, h), basis.with_elements(other))
    parts = [(ceramic, mat.rho_kg_m3, _thickness_ratio(mat))]
    if tip_el.size:
        K = K + asm(_stiffness_form(tip[0].plane_stress_Pa(), h), basis.with_elements(tip_el))
        parts.append((tip_el, tip[0].rho_kg_m3, tip[0].thickness_ratio()))
    M = None
    for elements, rho, a in parts:
        sub = basis if elements is None else basis.with_elements(elements)
        m = asm(_mass_form(rho * h), sub)
        if thickness_inertia:
            m = m + asm(_thickness_inertia_form(rho * h**3 / 12.0, a), sub)
        M = m if M is None else M + m
    return K, M


def _electrode_coupling(basis, mesh: PlateMesh, ps, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Coupling ``G`` (C/m per dof and electrode) and the capacitance ``C`` (F) of each
    electrode's own area; refuses a mesh with no element under an electrode."""
    from skfem import asm

    G = np.zeros((basis.N, len(ELECTRODES)))
    C = np.zeros(len(ELECTRODES))
    for k in ELECTRODES:
        idx = mesh.elements_of(k)
        if idx.size == 0:
            continue
        sub = basis.with_elements(idx)
        G[:, k - 1] = asm(_coupling_form(ps.e_C_m2), sub)
        area = float(sub.dx.sum())
        C[k - 1] = ps.eps33_F_m * area / h
    if np.any(C <= 0.0):
        missing = [k for k in ELECTRODES if C[k - 1] <= 0.0]
        raise ValueError(f"mesh has no elements under electrode(s) {missing}")
    return G, C


def _thickness_inertia_coupling(basis, mesh: PlateMesh, mat: PiezoMaterial, h: float, sub,
                                weights: dict) -> tuple[np.ndarray, np.ndarray]:
    """The inertia of the thickness motion between displacements and potentials, ``M_uV``,
    and between potentials, ``M_VV``.

    ``S3 = -a . S + b E3`` with ``b = e33/c33`` and ``E3 = sum_e w_e V_e / h``: the kinetic
    energy ``rho h^3/12 (S3')^2`` couples ``u'`` and ``V'`` (docs/fem.md, section 1); ``sub``
    is the basis on the shorted gap strips (None without), where ``weights`` spread each
    electrode's field."""
    from skfem import asm

    a = _thickness_ratio(mat)
    c = mat.cE_Pa
    b_h = float(mat.e_C_m2[2, 2] / c[2, 2]) / h
    scale = mat.rho_kg_m3 * h**3 / 12.0
    m_uv = np.zeros((basis.N, len(ELECTRODES)))
    m_vv = np.zeros((len(ELECTRODES), len(ELECTRODES)))
    for k in ELECTRODES:
        el = basis.with_elements(mesh.elements_of(k))
        m_uv[:, k - 1] = -scale * b_h * asm(_coupling_form(a), el)
        if sub is not None:
            m_uv[:, k - 1] -= scale * b_h * asm(_weighted_coupling_form(a, weights[k]), sub)
    xq = np.asarray(sub.global_coordinates()) if sub is not None else None
    for i in ELECTRODES:
        for j in ELECTRODES:
            val = float(basis.with_elements(mesh.elements_of(i)).dx.sum()) if i == j else 0.0
            if xq is not None:
                val += float(np.sum(weights[i](xq[0], xq[1]) * weights[j](xq[0], xq[1])
                                    * sub.dx))
            m_vv[i - 1, j - 1] = scale * b_h**2 * val
    return m_uv, m_vv


def _edge_lengths(layout: GapLayout, centres_m: np.ndarray | None,
                  areas_m2: np.ndarray | None) -> dict[tuple[int, int], float]:
    """Length (m) of each pair of electrodes' shared edge along a gap strip: the strip's
    material beside them (its elements' area over the gap width, the crossing left out),
    where holes, chamfers or notches cut the strip; the bounding box's length where the strip
    runs its full length (to 1e-9), so that a plain plate's matrix stays bit for bit.

    Keys ``(a, b)`` as in :func:`_gap_terms`: (1, 3), (2, 4) across the strip parallel to y,
    (2, 1), (4, 3) across the one parallel to x. The box lengths alone left the capacitance
    matrix of a plate with holes over both strips that of the plain plate (B2 k_eff 5 % low).
    """
    L = layout
    x_a, x_b = L.x_mid_m + 0.5 * L.gap_x_m, L.x_mid_m - 0.5 * L.gap_x_m
    y_a, y_b = L.y_mid_m + 0.5 * L.gap_y_m, L.y_mid_m - 0.5 * L.gap_y_m
    box = {(1, 3): y_b - L.y_lo_m, (2, 4): L.y_hi_m - y_a,
           (2, 1): L.x_hi_m - x_a, (4, 3): x_b - L.x_lo_m}
    if centres_m is None or areas_m2 is None:
        return box
    x, y = centres_m
    in_x = np.abs(x - L.x_mid_m) < 0.5 * L.gap_x_m  # the strip parallel to y
    in_y = np.abs(y - L.y_mid_m) < 0.5 * L.gap_y_m  # the strip parallel to x
    measured = {
        (1, 3): areas_m2[in_x & (y < y_b)].sum() / L.gap_x_m if L.gap_x_m > 0 else 0.0,
        (2, 4): areas_m2[in_x & (y > y_a)].sum() / L.gap_x_m if L.gap_x_m > 0 else 0.0,
        (2, 1): areas_m2[in_y & (x > x_a)].sum() / L.gap_y_m if L.gap_y_m > 0 else 0.0,
        (4, 3): areas_m2[in_y & (x < x_b)].sum() / L.gap_y_m if L.gap_y_m > 0 else 0.0,
    }
    return {k: box[k] if abs(measured[k] - box[k]) <= 1e-9 * box[k] else float(measured[k])
            for k in box}


def _gap_terms(layout: GapLayout, material: PiezoMaterial, thickness_m: float,
               c_plate_F: np.ndarray, strip_centres_m: np.ndarray | None = None,
               strip_areas_m2: np.ndarray | None = None):
    """Gap weights ``w_e(x, y)`` and the 4x4 capacitance matrix of the shorted-gap model.

    Each strip gets one cross-section solve (:func:`fem.capacitance.gap_cross_section`),
    applied along its length. ``w_e`` is the product of the two strips' top-face potential
    profiles (1 under electrode e, 0 under the others); it is exact in each strip away from
    the crossing and interpolates in the g x g crossing. The capacitance matrix adds to the
    parallel-plate diagonal ``c_plate_F`` each electrode's gap fringe (cross-section diagonal
    minus its parallel-plate part) and puts the cross-section's mutual term ``c_ab`` (< 0)
    between the neighbours across a strip, both per unit length times the length of the
    electrode's edge along the strip (:func:`_edge_lengths`, from the strip elements'
    centres ``strip_centres_m`` (2, n) and areas ``strip_areas_m2`` where given). Diagonal
    neighbours (1-4, 2-3) meet only at the crossing's corners; their coupling is neglected,
    like the crossing's own share.
    """
    from fem.capacitance import gap_cross_section, lateral_permittivity_F_m

    ps = plane_stress(material)
    eps_l = lateral_permittivity_F_m(material)
    L = layout
    x_a, x_b = L.x_mid_m + 0.5 * L.gap_x_m, L.x_mid_m - 0.5 * L.gap_x_m
    y_a, y_b = L.y_mid_m + 0.5 * L.gap_y_m, L.y_mid_m - 0.5 * L.gap_y_m
    cap = np.diag(np.asarray(c_plate_F, dtype=float))

    def one(gap, width_a, width_b):
        if gap <= 0.0:
            return None
        return gap_cross_section(float(gap), float(thickness_m), float(width_a),
                                 float(width_b), eps_l, ps.eps33_F_m)

    # strip parallel to y: a = electrodes 1, 2 (larger x); edges of length y_b - y_lo (1, 3)
    # and y_hi - y_a (2, 4)
    csx = one(L.gap_x_m, L.x_hi_m - x_a, x_b - L.x_lo_m)
    # strip parallel to x: a = electrodes 2, 4 (larger y); edges x_hi - x_a (1, 2), x_b - x_lo
    csy = one(L.gap_y_m, L.y_hi_m - y_a, y_b - L.y_lo_m)
    lengths = _edge_lengths(L, strip_centres_m, strip_areas_m2)
    for cs, pairs in ((csx, ((1, 3), (2, 4))), (csy, ((2, 1), (4, 3)))):
        if cs is None:
            continue
        for ea, eb in pairs:
            length = lengths[ea, eb]
            cap[ea - 1, ea - 1] += cs.excess_F_m[0] * length
            cap[eb - 1, eb - 1] += cs.excess_F_m[1] * length
            cap[ea - 1, eb - 1] = cap[eb - 1, ea - 1] = cs.mutual_F_m * length

    def profile(cs, mid, side):
        if cs is None:  # no strip in this direction: a step at the (zero-width) gap
            return lambda t: ((t > mid) if side == "a" else (t < mid)).astype(float)
        return lambda t: cs.weight(t - mid, side)

    wxa, wxb = profile(csx, L.x_mid_m, "a"), profile(csx, L.x_mid_m, "b")
    wya, wyb = profile(csy, L.y_mid_m, "a"), profile(csy, L.y_mid_m, "b")
    weights = {
        1: lambda x, y: wxa(x) * wyb(y),
        2: lambda x, y: wxa(x) * wya(y),
        3: lambda x, y: wxb(x) * wyb(y),
        4: lambda x, y: wxb(x) * wya(y),
    }
    cap = 0.5 * (cap + cap.T)
    return weights, cap


@lru_cache(maxsize=16)
def _cached_model(stator: PlateStator, material: PiezoMaterial,
                  settings: MeshSettings) -> PiezoPlateModel:
    t0 = time.perf_counter()
    # a stator that carries its own mesh (fem.meshing.meshed_stator.MeshedStator) or a parametric
    # one (fem.meshing.parametric.ParametricStator, meshed by gmsh) ignores ``refine``
    mesh = planform_mesh(stator)
    if mesh is None:
        mesh = structured_mesh(stator, settings.refine)
    model = build_model(mesh, stator, material, settings.order, settings.gap_model,
                        settings.thickness_inertia)
    object.__setattr__(model, "assembly_time_s", time.perf_counter() - t0)
    return model


def clear_model_cache() -> None:
    """Forget the models :func:`plate_model` cached in this process: the next model of a plate
    is assembled again (benchmarks time a cold solve with it)."""
    _cached_model.cache_clear()


def plate_model(stator: PlateStator | None = None, material: PiezoMaterial | str = "pzt8",
                mesh: MeshSettings | None = None) -> PiezoPlateModel:
    """Structured-mesh model of ``stator`` (cached on its arguments).

    Parameters
    ----------
    stator : PlateStator, optional
        Defaults to the paper's 30 x 7.5 x 3 mm plate.
    material : PiezoMaterial or str
        ``'pzt8'`` (default) or ``'paper'``, or a material.
    mesh : MeshSettings, optional
        Element order, refinement (elements per smaller plate dimension,
        :func:`fem.meshing.mesh.structured_mesh`), gap model (:func:`build_model`) and
        thickness inertia; default :class:`fem.mesh_settings.MeshSettings`.
    """
    stator = PlateStator() if stator is None else stator
    return _cached_model(stator, get_material(material), plate_arguments(stator, mesh))


def plate_arguments(stator: PlateStator, mesh: MeshSettings | None) -> MeshSettings:
    """Validated, normalized 2D settings (:meth:`fem.mesh_settings.MeshSettings.plate`) of a
    plate model, the key of the cached models and modes (:func:`plate_model`,
    :func:`fem.modes.plate_modes`), checked before anything is cached or meshed.

    Raises
    ------
    ValueError
        Naming the first bad argument and its allowed values, or if the generated mesh of
        ``stator`` would be too large for memory (``refine=1000``).
    TypeError
        If ``thickness_inertia`` is not a bool (the string ``"False"`` is true).
    """
    mesh = (MeshSettings() if mesh is None else mesh).plate()
    order, refine = mesh.order, mesh.refine
    gap_model, thickness_inertia = mesh.gap_model, mesh.thickness_inertia
    for name, value in (("order", order), ("refine", refine)):  # 2.5 would run as 2
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
            raise ParameterError(name, value, 1, None,
                                 message=f"{name} must be an integer >= 1, got {value!r}")
    _element(order)
    if not isinstance(thickness_inertia, (bool, np.bool_)):
        raise TypeError(f"thickness_inertia must be True or False, got {thickness_inertia!r}")
    if gap_model not in GAP_MODELS:
        raise ValueError(f"gap_model must be one of {GAP_MODELS}, got {gap_model!r}")
    if planform_mesh(stator) is None:
        check_generated_size(stator, int(refine), count=lambda: math.prod(
            len(v) - 1 for v in grid_lines_m(stator, int(refine))))
    return MeshSettings(order=int(order), refine=int(refine), gap_model=str(gap_model),
                        thickness_inertia=bool(thickness_inertia))
