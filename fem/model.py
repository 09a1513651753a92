"""Assembly of the 2D plane-stress piezoelastic plate model (scikit-fem).

Unknowns are the in-plane displacements ``(u_x, u_y)`` (m) of the mid-plane; the electrode
voltages enter through the thickness field ``E3 = V/h`` under each electrode (the paper's
Appendix A convention ``E3 = V0/h_s``: a positive voltage drives the field along the poling
axis). With ``S = B u`` the in-plane strains ``[S1, S2, S6]`` (Voigt, engineering shear)::

    K   = h  integral( B^T c* B ) dA          (short circuit, all electrodes grounded)
    M   = h  integral( rho N^T N ) dA
    G_e =    integral_e( B^T e*^T ) dA        (force per volt, N/V: integral B^T e*^T E3 dV / V)
    C_e =    integral_e( eps33* / h ) dA      (clamped capacitance of electrode e, F)

so that ``M u'' + K u = sum_e G_e V_e`` and the charge of electrode e is
``Q_e = G_e^T u + C_e V_e``. In the unelectroded gap strips the free faces carry no charge:
``D3 = 0``, which eliminates ``E3`` locally and stiffens the material to
``c*_open = c* + e* e*^T / eps33*`` (no coupling vector, no capacitance there).

Open circuit (floating electrodes, zero charge): ``V_e = -C_e^-1 G_e^T u`` and
``K_open = K + sum_e G_e C_e^-1 G_e^T`` over the open electrodes.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.sparse as sp

from fem.geometry import ELECTRODES, PlateStator
from fem.material import PiezoMaterial, get_material, plane_stress
from fem.mesh import DEFAULT_REFINE, PlateMesh, structured_mesh
from fem.meshed_stator import planform_mesh

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


@dataclass(frozen=True, eq=False)
class PiezoPlateModel:
    """Assembled matrices of the plate (treat them as read-only; results may be cached).

    Attributes
    ----------
    stator : PlateStator
    material : PiezoMaterial
    order : int
        Element order (1 or 2).
    mesh : PlateMesh
    basis : skfem.CellBasis
        Vector basis on the whole plate (for probing fields).
    K : scipy.sparse.csr_matrix
        Short-circuit stiffness (N/m), symmetric.
    M : scipy.sparse.csr_matrix
        Mass (kg), symmetric.
    G : numpy.ndarray
        Coupling vectors, shape (n_dofs, 4), column ``e-1`` for electrode e (N/V).
    C_F : numpy.ndarray
        Clamped capacitances of electrodes 1..4 (F); the capacitance matrix is diagonal.
    assembly_time_s : float
        Wall time of mesh generation and assembly (s).
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

    @property
    def n_dofs(self) -> int:
        """Number of displacement degrees of freedom."""
        return int(self.K.shape[0])

    def coupling(self, electrodes: tuple[int, ...]) -> np.ndarray:
        """Sum of the coupling vectors of ``electrodes`` driven at the same voltage (N/V)."""
        _check_electrodes(electrodes)
        return self.G[:, [e - 1 for e in electrodes]].sum(axis=1)

    def open_circuit_update(
        self, open_electrodes: tuple[int, ...] = ELECTRODES
    ) -> tuple[np.ndarray, np.ndarray]:
        """Low-rank factors ``(U, D)`` with ``K_open = K + U diag(D) U^T`` (``D = 1/C``)."""
        _check_electrodes(open_electrodes)
        idx = [e - 1 for e in open_electrodes]
        return self.G[:, idx], 1.0 / self.C_F[idx]

    def K_open(self, open_electrodes: tuple[int, ...] = ELECTRODES) -> sp.csr_matrix:
        """Open-circuit stiffness ``K + sum_e G_e G_e^T / C_e`` (explicit; dense blocks)."""
        u, d = self.open_circuit_update(open_electrodes)
        return (self.K + sp.csr_matrix((u * d) @ u.T)).tocsr()

    def probe(self, points_m: np.ndarray) -> sp.csr_matrix:
        """Matrix ``P`` of shape (2 n_points, n_dofs): ``P @ u`` stacks ``u_x`` then ``u_y``."""
        pts = np.atleast_2d(np.asarray(points_m, dtype=float))
        if pts.shape[0] != 2:
            pts = pts.T
        return self.basis.probes(pts).tocsr()


def _check_electrodes(electrodes: tuple[int, ...]) -> None:
    if any(e not in ELECTRODES for e in electrodes):
        raise ValueError(f"electrodes must be numbers in 1..4, got {electrodes!r}")


def _check_mesh_fits(mesh: PlateMesh, stator: PlateStator) -> None:
    x0, x1, y0, y1 = mesh.bounding_box_m()
    w, length = stator.width_m, stator.length_m
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
    """
    from skfem import Basis, asm

    t0 = time.perf_counter()
    mat = get_material(material)
    elem = _element(order)
    _check_mesh_fits(mesh, stator)
    ps = plane_stress(mat)
    h = stator.thickness_m
    skmesh = mesh.to_skfem()
    basis = Basis(skmesh, elem)
    gap = mesh.elements_of(0)
    electroded = np.flatnonzero(mesh.electrode > 0)
    K = asm(_stiffness_form(ps.c_Pa, h), basis.with_elements(electroded))
    if gap.size:
        K = K + asm(_stiffness_form(ps.c_open_Pa, h), basis.with_elements(gap))
    M = asm(_mass_form(mat.rho_kg_m3 * h), basis)
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
    K = (0.5 * (K + K.T)).tocsr()
    M = (0.5 * (M + M.T)).tocsr()
    G.setflags(write=False)
    C.setflags(write=False)
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
    )


@lru_cache(maxsize=16)
def _cached_model(
    stator: PlateStator, material: PiezoMaterial, order: int, refine: int
) -> PiezoPlateModel:
    t0 = time.perf_counter()
    # a stator that carries its own mesh (fem.meshed_stator.MeshedStator) ignores ``refine``
    mesh = planform_mesh(stator)
    if mesh is None:
        mesh = structured_mesh(stator, refine)
    model = build_model(mesh, stator, material, order)
    object.__setattr__(model, "assembly_time_s", time.perf_counter() - t0)
    return model


def plate_model(
    stator: PlateStator | None = None,
    material: PiezoMaterial | str = "pzt8",
    order: int = 2,
    refine: int = DEFAULT_REFINE,
) -> PiezoPlateModel:
    """Structured-mesh model of ``stator`` (cached on its arguments).

    Parameters
    ----------
    stator : PlateStator, optional
        Defaults to the paper's 30 x 7.5 x 3 mm plate.
    material : PiezoMaterial or str
        ``'pzt8'`` (default) or ``'paper'``, or a material.
    order : int
        Element order, 1 or 2.
    refine : int
        Elements per smaller plate dimension (see :func:`fem.mesh.structured_mesh`).
    """
    stator = PlateStator() if stator is None else stator
    _element(order)  # validate before caching
    if isinstance(refine, bool) or not isinstance(refine, (int, np.integer)) or refine < 1:
        raise ValueError(f"refine must be an integer >= 1, got {refine!r}")
    return _cached_model(stator, get_material(material), int(order), int(refine))
