"""3D piezoelastic reference model of the stator plate (quadratic hexahedra, scikit-fem).

The plate is meshed as a solid: ``x`` across the width (centred), ``y`` along the length
(``0..l``), ``z`` through the thickness (``-h/2..h/2``, the poling axis). Unknowns are the
three displacement components and the electric potential, all interpolated with the same
quadratic hexahedron. The default element is the 20-node serendipity brick
(``ElementHexS2``): on the rectangular boxes of this structured mesh it gives B2 as
accurately as the 27-node triquadratic brick (``ElementHex2``) on the same mesh with about
45 % fewer dofs, and the default mesh converges all four frequencies to 5e-4 in about a
second (measured, ``docs/fem3d.md``); ``element='hex27'`` selects the latter (better on L1
for the same mesh, slower) and ``order=1`` the trilinear ``ElementHex1`` (which locks in
bending; for comparison only).

Constitutive law (IEEE e-form, ``fem.material``) with ``E = -grad(phi)``::

    T = c^E S + e^T grad(phi)
    D = e S - eps^S grad(phi)

Weak form (virtual displacement ``v``, virtual potential ``psi``)::

    int S(v)^T c^E S(u) + S(v)^T e^T grad(phi) dV + int rho v . u'' dV = 0
    int grad(psi)^T (e S(u) - eps^S grad(phi)) dV = -sum_e psi_e Q_e

where ``Q_e`` is the free charge on electrode ``e`` (the electrode is a conductor, the charge
density on it is ``-D . n_out``). In matrix form, with ``K_uu``, ``K_uphi``, ``K_phiphi``::

    M u'' + K_uu u + K_uphi phi = 0,       Q = K_phiphi phi - K_uphi^T u  (per electrode).

Electrodes are equipotential surfaces: the bottom face ``z = -h/2`` is grounded
(``phi = 0``); on the top face every potential node under quadrant ``e`` (closed region, the
mesh lines follow the electrode edges) is tied to one unknown ``V_e``. The gap strips and the
side faces are free surfaces (``D . n = 0``, the natural condition).

* Short circuit: ``V_e = 0`` for all four electrodes.
* Open circuit: each ``V_e`` is a free unknown and the natural condition of its equation is
  ``Q_e = 0``: a floating electrode with zero net charge.

The free potentials are condensed exactly inside the shift-invert operator: the saddle-point
system ``[[K_uu - sigma M, K_uphi], [K_uphi^T, -K_phiphi]]`` is factorized once (sparse LU)
and ``eigsh`` works on the displacements only, with ``K_cond = K_uu + K_uphi K_phiphi^-1
K_uphi^T``. Sign convention: ``V_e`` is the potential of the top electrode; a positive ``V_e``
makes ``E3 = -V/h``, the opposite of the 2D model's convention ``E3 = +V/h`` (frequencies and
``k_eff`` do not depend on it).

Stators that carry their own planform mesh (:class:`fem.meshing.meshed_stator.MeshedStator`: a
protruding tip, chamfered corners, any imported quad mesh) are meshed by extruding that 2D
mesh through the thickness in ``layers`` element layers (:func:`extruded_hex_mesh`); the top
face of a top-layer brick belongs to electrode ``k`` when its 2D element is tagged ``k``
(closed: the nodes on its edges too), top faces of gap elements (tag 0) are free, and
``refine`` is ignored (as in 2D). A rectangular :class:`fem.geometry.PlateStator` keeps the
structured box mesh.

:func:`saddle_point_frequencies_Hz` (the shift-invert driver), :func:`assemble_solid` and
:func:`identify_sampled` are shared with the quarter-plate model of
:mod:`fem.solid3d.symmetric`.

Mode identification reuses the 2D rules of :mod:`fem.modes` on the mid-plane ``z = 0``
(symmetry about ``x = 0``, three nodes for B2, MAC with the Eq. 3 shapes) after rejecting
modes that are not symmetric through the thickness (out-of-plane bending, torsion). On a
non-rectangular planform the sampling points outside the mesh (and their mirror images about
``x = 0``) are dropped, as in :func:`fem.modes.sampling_points`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from bounds import ParameterError, Words
from fem.geometry import ELECTRODES, PlateStator
from fem.limits import work_factor
from fem.material import EPS0_F_M, PiezoMaterial, get_material
from fem.mesh_settings import DEFAULT_ELEMENT as DEFAULT_ELEMENT
from fem.mesh_settings import DEFAULT_LAYERS as DEFAULT_LAYERS
from fem.mesh_settings import DEFAULT_REFINE_3D as DEFAULT_REFINE_3D
from fem.mesh_settings import MeshSettings
from fem.meshing.mesh import (
    MAX_LIBRARY_BRICKS_3D,
    PlateMesh,
    check_generated_size,
    grid_lines_m,
    require_plate,
)
from fem.meshing.meshed_stator import overall_length_m, planform_mesh
from fem.model import affine_probes
from fem.modes import (
    SAMPLE_INSET,
    ModeSolverError,
    PlateModes,
    locatable,
    match_modes,
    reference_shapes,
    sampling_grid,
    shift_invert_eigsh,
    solve_short_open,
)

ELEMENTS = ("hex20", "hex27")
"""Quadratic bricks: 20-node serendipity (``ElementHexS2``), 27-node (``ElementHex2``)."""
MIN_THICKNESS_SYMMETRY = 0.5
"""Smallest energy fraction of a mode's sampled field that is symmetric through the thickness
(in-plane class: ``u_x, u_y`` even in z, ``u_z`` odd) for it to be a candidate L1/B2. Not
close to 1: with electrodes on the top face only, floating electrodes couple in-plane and
out-of-plane motion, so an out-of-plane mode near B2 can hybridize with it (seen on thin
plates); among candidates the largest ``MAC * thickness symmetry`` wins."""


def _element(order: int, element: str):
    from skfem import ElementHex1, ElementHex2, ElementHexS2

    if order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order!r}")
    if order == 1:
        return ElementHex1()
    if element not in ELEMENTS:
        raise ValueError(f"element must be one of {', '.join(ELEMENTS)}, got {element!r}")
    return ElementHexS2() if element == "hex20" else ElementHex2()


def _check_int(name: str, value: object, minimum: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def solid_arguments(mesh: MeshSettings | None) -> MeshSettings:
    """Validated, normalized 3D settings (:meth:`fem.mesh_settings.MeshSettings.solid`), the
    key of the cached 3D models (full and quarter plate).

    Raises
    ------
    ValueError
        Naming the first bad argument and its allowed values.
    """
    mesh = (MeshSettings() if mesh is None else mesh).solid()
    _element(mesh.order, mesh.element)
    return replace(mesh, order=int(mesh.order), refine=_check_int("refine", mesh.refine),
                   layers=_check_int("layers", mesh.layers),
                   edge_grading=_check_int("edge_grading", mesh.edge_grading, 0))


@dataclass(frozen=True, eq=False)
class SolidMatrices:
    """The assembled matrices of a 3D piezoelastic model and the potential dofs they tie
    (treat as read-only): the fields :class:`SolidPlateModel` and the quarter plate's
    :class:`fem.solid3d.symmetric.QuarterPlateModel` share, each with its own dofs.

    Attributes
    ----------
    Kuu : scipy.sparse.csr_matrix
        Elastic stiffness at constant field (N/m) on the model's displacements.
    M : scipy.sparse.csr_matrix
        Mass (kg) on the model's displacements.
    Kuphi : scipy.sparse.csr_matrix
        Piezoelectric coupling (N/V = C/m), the model's displacements x all N potentials.
    Kphiphi : scipy.sparse.csr_matrix
        Dielectric stiffness (F), shape (N, N).
    electrode_dofs : tuple of numpy.ndarray or numpy.ndarray
        Scalar dofs tied to the electrodes (top face).
    ground_dofs : numpy.ndarray
        Scalar dofs whose potential is 0.
    assembly_time_s : float
        Mesh and assembly wall time (s).
    """

    Kuu: sp.csr_matrix
    M: sp.csr_matrix
    Kuphi: sp.csr_matrix
    Kphiphi: sp.csr_matrix
    electrode_dofs: object
    ground_dofs: np.ndarray
    assembly_time_s: float


@dataclass(frozen=True, eq=False)
class SolidPlateModel(SolidMatrices):
    """Assembled 3D piezoelastic matrices of the plate (treat as read-only).

    Attributes
    ----------
    stator : PlateStator
        The plate modelled, poled along z.
    material : PiezoMaterial
        Its full 3D constants.
    order : int
        1 (trilinear) or 2 (quadratic).
    element : str
        ``'hex20'``, ``'hex27'`` (order 2) or ``'hex8'`` (order 1).
    refine, layers : int
        In-plane refinement (elements per width) and element layers through the thickness.
    basis : skfem.CellBasis
        Scalar basis; displacement dofs are blocked: ``u[c * N + i]`` is component ``c`` of
        scalar dof ``i`` (``N = basis.N``), the potential uses the scalar dofs directly.
    Kuu : scipy.sparse.csr_matrix
        Elastic stiffness at constant field (N/m), shape (3N, 3N).
    M : scipy.sparse.csr_matrix
        Mass (kg), shape (3N, 3N).
    Kuphi : scipy.sparse.csr_matrix
        Piezoelectric coupling (N/V = C/m), shape (3N, N).
    Kphiphi : scipy.sparse.csr_matrix
        Dielectric stiffness (F), shape (N, N).
    electrode_dofs : tuple of numpy.ndarray
        Scalar dofs tied to electrodes 1..4 (top face).
    ground_dofs : numpy.ndarray
        Scalar dofs of the grounded bottom face.
    assembly_time_s : float
        Mesh and assembly wall time (s).
    """

    stator: PlateStator
    material: PiezoMaterial
    order: int
    element: str
    refine: int
    layers: int
    basis: object

    @property
    def n_nodes(self) -> int:
        """Number of scalar dofs (nodes) ``N``."""
        return int(self.basis.N)

    @property
    def n_dofs(self) -> int:
        """Displacement plus potential dofs before constraints, ``4 N``."""
        return 4 * self.n_nodes

    @property
    def n_displacement_dofs(self) -> int:
        """Displacement dofs ``3 N``."""
        return 3 * self.n_nodes

    def saddle_point_order(self, open_circuit: bool) -> np.ndarray:
        """Nested-dissection order of the saddle-point unknowns (displacements, then the
        free potentials of :meth:`potential_map`; the floating electrodes' potentials last),
        by :func:`fem.solid3d.grid_ordering.element_dissection_rank`: on the extruded
        planform of the designer's stator with a tip (layers graded once) it factorizes
        several times faster than SuperLU's own ``MMD_AT_PLUS_A`` (docs/fem3d.md 1.1)."""
        from fem.solid3d.grid_ordering import element_dissection_rank

        n = self.n_nodes
        rank = element_dissection_rank(self.basis.doflocs, self.basis.element_dofs)
        t = self.potential_map(open_circuit).tocsc()
        first = t.indices[t.indptr[:-1]]  # a node of each potential column
        key = np.concatenate((np.tile(rank, 3), rank[first]))
        n_free = np.count_nonzero(np.diff(t.indptr) == 1)
        if open_circuit:  # the electrode columns follow the free nodes' (potential_map)
            key[3 * n + n_free:] = n
        return np.argsort(key, kind="stable")

    def potential_map(self, open_circuit: bool) -> sp.csr_matrix:
        """Matrix ``T`` (N x n_free): full nodal potentials ``phi = T phi_free``.

        Bottom-face nodes are 0; electrode nodes are 0 (short) or share one column per
        electrode (open, the column's unknown is ``V_e``); all other nodes are free.
        """
        n = self.n_nodes
        fixed = np.zeros(n, dtype=bool)
        fixed[self.ground_dofs] = True
        for dofs in self.electrode_dofs:
            fixed[dofs] = True
        free = np.flatnonzero(~fixed)
        rows = [free]
        cols = [np.arange(free.size)]
        ncol = free.size
        if open_circuit:
            for dofs in self.electrode_dofs:
                rows.append(dofs)
                cols.append(np.full(dofs.size, ncol))
                ncol += 1
        r = np.concatenate(rows)
        c = np.concatenate(cols)
        return sp.csr_matrix((np.ones(r.size), (r, c)), shape=(n, ncol))

    def probe(self, points_m: np.ndarray) -> sp.csr_matrix:
        """Matrix ``P`` (3 n_points, 3N): ``P @ u`` stacks ``u_x``, ``u_y``, ``u_z``."""
        pts = np.atleast_2d(np.asarray(points_m, dtype=float))
        if pts.shape[0] != 3:
            pts = pts.T
        try:
            p = self.basis.probes(pts).tocsr()
        except Exception as exc:  # noqa: BLE001 - scikit-fem raises a bare Exception here
            # its Newton inverse of the hex map stalls beside a micrometre gap's layer of
            # bricks 2 000 times wider than thick (--gap-mm 0.0012 --model 3d); a box's map
            # is affine and inverted exactly instead (fem.model.affine_probes, as in 2D)
            p = affine_probes(self.basis, pts) if "Newton" in str(exc) else None
            if p is None:
                raise
        return sp.block_diag((p, p, p), format="csr")

    def voltage_coupling_N_V(self, electrodes: tuple[int, ...]) -> np.ndarray:
        """Force on the displacements per volt with ``electrodes`` at ``+1 V`` (N/V).

        The listed electrodes are held at 1 V, the other electrodes and the bottom at 0 V; the
        remaining nodal potentials are condensed statically with ``u = 0`` (clamped), and the
        force is ``-K_uphi phi``. In this model's convention (``E3 = -V/h``) it has the
        opposite sign of the 2D ``PiezoPlateModel.coupling``.
        """
        if any(e not in ELECTRODES for e in electrodes):
            raise ValueError(f"electrodes must be numbers in 1..4, got {electrodes!r}")
        t_free = self.potential_map(open_circuit=False)
        phi_imp = np.zeros(self.n_nodes)
        for e in electrodes:
            phi_imp[self.electrode_dofs[e - 1]] = 1.0
        kff = (t_free.T @ self.Kphiphi @ t_free).tocsc()
        rhs = -(t_free.T @ (self.Kphiphi @ phi_imp))
        phi = phi_imp + t_free @ sla.spsolve(kff, rhs)
        return -(self.Kuphi @ phi)


def check_solid_size(stator: PlateStator, refine: int, layers: int, edge_grading: int) -> None:
    """Refuse a 3D mesh above :data:`fem.meshing.mesh.MAX_LIBRARY_BRICKS_3D` bricks before it is
    built (``solid_modes(mesh=MeshSettings(refine=200))`` runs out of memory): the generated
    plate's bricks, counted from its lines, or a planform's elements times ``layers`` (at
    least)."""
    planform = planform_mesh(stator)
    if planform is None:
        check_generated_size(stator, refine, layers, count=lambda: math.prod(
            len(v) - 1 for v in hex_grid_lines(stator, refine, layers, edge_grading)),
            named=Words("{refine}, {layers} and {edge_grading}", refine=f"{refine}",
                        layers=f"{layers}", edge_grading=f"{edge_grading}"))
        return

    top = MAX_LIBRARY_BRICKS_3D * work_factor()
    n = planform.n_elements * layers
    if n > top:
        raise ParameterError(
            "layers", layers,
            message=Words("{layers}", layers=f"{layers}")
            + f" makes at least {n:.3g} bricks on this planform "
            f"({planform.n_elements} elements), above the limit {top:.0f} of a library call "
            "(set LUSM_MAX_WORK=N to allow N times more)")


def _voigt_B(grads: np.ndarray) -> np.ndarray:
    """Strain-displacement array B (6, 3*nloc, nel, nqp) from scalar gradients (nloc, 3, ...).

    Column ``c * nloc + a`` is component ``c`` of local function ``a``; Voigt order
    11, 22, 33, 23, 13, 12 with engineering shear strains.
    """
    nloc = grads.shape[0]
    B = np.zeros((6, 3 * nloc) + grads.shape[2:])
    gx, gy, gz = grads[:, 0], grads[:, 1], grads[:, 2]
    ux, uy, uz = slice(0, nloc), slice(nloc, 2 * nloc), slice(2 * nloc, 3 * nloc)
    B[0, ux] = gx
    B[1, uy] = gy
    B[2, uz] = gz
    B[3, uy] = gz
    B[3, uz] = gy
    B[4, ux] = gz
    B[4, uz] = gx
    B[5, ux] = gy
    B[5, uy] = gx
    return B


def _coo(local: np.ndarray, rows: np.ndarray, cols: np.ndarray, shape) -> sp.csr_matrix:
    """Global sparse matrix from element matrices ``local`` (a, b, nel)."""
    r = np.broadcast_to(rows[:, None, :], local.shape)
    c = np.broadcast_to(cols[None, :, :], local.shape)
    return sp.coo_matrix((local.ravel(), (r.ravel(), c.ravel())), shape=shape).tocsr()


def _graded_lines(lines: np.ndarray, edges: list[float], gap_m: float, levels: int) -> np.ndarray:
    """``lines`` plus geometric lines on both sides of every electrode edge in ``edges``.

    The potential is singular (``r^(1/2)``) at the electrode edges and its fringe spreads
    over every scale from the gap to the coarse element size, so the lines sit at distances
    ``g 2^-k`` (k = 1 .. levels, inside the gap and outside it) and ``g 2^j`` (j = 0, 1, ...
    outside, up to half the coarse spacing): elements grow geometrically away from the edge,
    which restores the convergence that uniform meshes lose there.
    """
    lo, hi = float(lines.min()), float(lines.max())
    coarse = float(np.max(np.diff(lines)))
    fine = [gap_m * 0.5**k for k in range(1, levels + 1)]
    far = []
    d = gap_m
    while d < 0.5 * coarse:
        far.append(d)
        d *= 2.0
    extra = []
    for e in edges:
        for d in fine:
            extra += [e - d, e + d]
        for d in far:
            extra += [e - d, e + d]
    pts = np.unique(np.concatenate((lines, np.clip(extra, lo, hi))))
    keep = np.concatenate(([True], np.diff(pts) > 1e-9 * (hi - lo)))
    return pts[keep]


def hex_grid_lines(stator: PlateStator, refine: int, layers: int, edge_grading: int = 0):
    """The tensor lines ``(x, y, z)`` (m) of the structured brick mesh of a plate.

    ``refine`` and ``layers`` give the uniform lines (the 2D mesh's in-plane lines,
    ``layers`` equal layers); ``edge_grading > 0`` adds the geometric lines of
    :func:`_graded_lines` towards the electrode edges in x and y and towards the top face
    in z. The element count is ``(len(x) - 1) (len(y) - 1) (len(z) - 1)``, which lets a
    caller bound the work before building anything.
    """
    x, y = grid_lines_m(stator, refine)
    g = stator.electrode_gap_m
    if edge_grading > 0 and g > 0.0:
        half = stator.length_m / 2
        x = _graded_lines(x, [-g / 2, g / 2], g, edge_grading)
        y = _graded_lines(y, [half - g / 2, half + g / 2], g, edge_grading)
    return x, y, _layer_levels(stator.thickness_m, layers, g, edge_grading)


def _layer_levels(h: float, layers: int, gap_m: float, edge_grading: int) -> np.ndarray:
    """``layers`` equal layers through ``-h/2 <= z <= h/2`` (m), plus, with
    ``edge_grading > 0`` and a gap, :func:`_graded_lines`' levels below the top face: the
    singular electrode edges lie on it, and the layers are graded towards it the way the
    in-plane lines are towards the edges."""
    z = np.linspace(-h / 2, h / 2, layers + 1)
    if edge_grading > 0 and gap_m > 0.0:
        depth = _graded_lines(np.array([0.0, h]), [0.0], gap_m, edge_grading)
        z = np.unique(np.concatenate((z, h / 2 - depth[depth < h])))
        z = z[np.concatenate(([True], np.diff(z) > 1e-9 * h))]
    return z


def gap_element_ratio(stator: PlateStator, refine: int, layers: int,
                      edge_grading: int = 0) -> float:
    """How much larger the brick mesh's elements beside the electrode gap are than the gap
    (-): the largest of the in-plane neighbours of the gap strips and the top layer's
    thickness, over the gap width. The singular potential at the electrode edges lives on
    the gap's scale; at 30 x 7.5 x 3 mm with the 0.5 mm gap the default mesh has a ratio of
    4.9 and B2's k_eff 5 % low (docs/fem3d.md, mesh study), and narrow gaps with ratios of
    tens give 6-29 % and open-circuit B2 modes mixed with out-of-plane ones. A stator with a
    planform mesh is measured on that mesh (its elements touching a gap strip's edges, the
    narrower strip) and its layers (:func:`planform_layer_lines`): the parametric tip's plate
    at a 0.05 mm gap has 20 from its 1 mm layers, and B2's k_eff 0.067 against 0.101 in 2D.
    ``inf`` for a plate without a gap."""
    planform = planform_mesh(stator)
    if planform is not None:
        return max(planform_gap_ratios(planform, stator.thickness_m, layers, edge_grading))
    g = stator.electrode_gap_m
    if g <= 0.0:
        return math.inf
    x, y, z = hex_grid_lines(stator, refine, layers, edge_grading)
    widths = []
    for lines, centre in ((x, 0.0), (y, stator.length_m / 2)):
        dx = np.diff(lines)
        mid = 0.5 * (lines[:-1] + lines[1:])
        gap_cells = np.flatnonzero(np.abs(mid - centre) < g / 2)
        for i in gap_cells:
            widths += [dx[j] for j in (i - 1, i + 1) if 0 <= j < dx.size
                       and abs(mid[j] - centre) >= g / 2]
    widths.append(float(z[-1] - z[-2]))
    return float(max(widths) / g)


def planform_gap_m(planform: PlateMesh) -> float:
    """The narrower positive gap strip of a quadrant mesh (m); 0 if the electrodes touch."""
    from fem.model import gap_layout

    return _narrower_gap_m(gap_layout(planform))


def _narrower_gap_m(layout) -> float:
    gaps = [g for g in (layout.gap_x_m, layout.gap_y_m) if g > 0.0]
    return min(gaps) if gaps else 0.0


def planform_gap_ratios(planform: PlateMesh, thickness_m: float, layers: int,
                        edge_grading: int = 0) -> tuple[float, float]:
    """``(in_plane, layer)``: the planform's widest electroded element touching a gap
    strip's edge and the top layer's thickness (:func:`planform_layer_lines`), each over the
    narrower gap strip (-); ``(inf, inf)`` when the electrodes touch. The first is the mesh
    file's (or gmsh's) to refine, the second ``edge_grading``'s."""
    from fem.model import gap_layout

    lay = gap_layout(planform)
    g = _narrower_gap_m(lay)
    if g <= 0.0:
        return math.inf, math.inf
    p = planform.points_m
    tol = 1e-9 * float(np.ptp(p[0]) + np.ptp(p[1]))
    quads = planform.quads
    electroded = planform.electrode > 0
    widths = [0.0]
    for axis, mid, gap in ((0, lay.x_mid_m, lay.gap_x_m), (1, lay.y_mid_m, lay.gap_y_m)):
        if gap <= 0.0:
            continue
        coord = p[axis, quads]  # (4, n_el)
        touches = np.zeros(quads.shape[1], dtype=bool)
        for e in (mid - gap / 2, mid + gap / 2):
            touches |= np.any(np.abs(coord - e) < tol, axis=0)
        sel = touches & electroded
        if np.any(sel):
            widths.append(float(np.max(np.ptp(coord[:, sel], axis=0))))
    z = _layer_levels(float(thickness_m), _check_int("layers", layers), g,
                      _check_int("edge_grading", edge_grading, 0))
    return max(widths) / g, float(z[-1] - z[-2]) / g


def planform_layer_lines(planform: PlateMesh, thickness_m: float, layers: int,
                         edge_grading: int = 0) -> np.ndarray:
    """The levels ``z`` (m) of a planform mesh's extrusion: ``layers`` equal layers, plus,
    with ``edge_grading > 0``, the generated plate's geometric levels below the top face
    (:func:`_graded_lines`) on the scale of the mesh's narrower gap strip. The in-plane mesh
    is the file's (or gmsh's) to grade; the layers are this module's, and at a narrow gap it
    is their thickness that misses the electrode edges' singular field (the parametric tip's
    plate at 0.05 mm: B2's k_eff 0.067 on 1 mm layers, 0.0678 with the planform's elements
    halved, 0.093 with one level of graded layers; 2D 0.101)."""
    layers = _check_int("layers", layers)
    edge_grading = _check_int("edge_grading", edge_grading, 0)
    g = planform_gap_m(planform) if edge_grading > 0 else 0.0
    return _layer_levels(float(thickness_m), layers, g, edge_grading)


def _hex_mesh(stator: PlateStator, refine: int, layers: int, edge_grading: int = 0):
    from skfem import MeshHex

    return MeshHex.init_tensor(*hex_grid_lines(stator, refine, layers, edge_grading))


def extruded_hex_mesh(planform: PlateMesh, thickness_m: float, layers: int,
                      z_m: np.ndarray | None = None):
    """Extrude a 2D quad mesh through ``-h/2 <= z <= h/2`` into ``layers`` layers of bricks.

    Parameters
    ----------
    planform : PlateMesh
        Counter-clockwise quads in the x-y plane (m).
    thickness_m : float
        Plate thickness ``h`` (m).
    layers : int
        Equal element layers through the thickness.
    z_m : numpy.ndarray, optional
        The levels (m), increasing from ``-h/2`` to ``h/2`` (:func:`planform_layer_lines`);
        they replace the ``layers`` equal layers.

    Returns
    -------
    skfem.MeshHex
        Node ``j * n + i`` is 2D node ``i`` at level ``z_j``; brick ``j * n_el + e`` is 2D
        element ``e`` in layer ``j`` (bottom layer first), so the top layer is the last
        ``n_el`` bricks.
    """
    from skfem import MeshHex

    layers = _check_int("layers", layers)
    p2 = planform.points_m
    n = p2.shape[1]
    z = (np.linspace(-thickness_m / 2, thickness_m / 2, layers + 1) if z_m is None
         else np.asarray(z_m, dtype=float))
    layers = z.size - 1
    points = np.vstack((np.tile(p2, layers + 1), np.repeat(z, n)))
    quads = planform.quads.copy()
    x, y = p2[0, quads], p2[1, quads]
    area2 = np.sum(x * np.roll(y, -1, axis=0) - np.roll(x, -1, axis=0) * y, axis=0)
    quads[:, area2 < 0] = quads[::-1][:, area2 < 0]  # counter-clockwise (PlateMesh's rule)
    a, b, c, d = quads
    # skfem's MeshHex1 local order (reference nodes 000, 001, 010, 100, 011, 101, 110, 111),
    # as MeshHex.init_tensor fills it (reference axes -> z, x, y): a counter-clockwise quad
    # a-b-c-d gives the brick [a, d, b, a', c, d', b', c'] (primes one level up), with the
    # same positive Jacobian as the structured box mesh
    t = np.hstack([
        np.vstack((a + lo, d + lo, b + lo, a + lo + n, c + lo, d + lo + n, b + lo + n,
                   c + lo + n))
        for lo in range(0, layers * n, n)
    ])
    return MeshHex(np.ascontiguousarray(points), np.ascontiguousarray(t, dtype=np.int32))


def _planform_electrodes(
    planform: PlateMesh, basis, thickness_m: float, layers: int, tol: float
) -> tuple[np.ndarray, ...]:
    """Top-face dofs of the bricks whose 2D element is tagged 1..4 (closed regions)."""
    n_el = planform.n_elements
    top_cells = np.arange((layers - 1) * n_el, layers * n_el)
    on_top = np.abs(basis.doflocs[2] - thickness_m / 2) < tol
    edofs = basis.element_dofs
    out = []
    for k in ELECTRODES:
        cells = top_cells[planform.electrode == k]
        dofs = np.unique(edofs[:, cells])
        out.append(dofs[on_top[dofs]])
    owner = np.zeros(basis.N, dtype=int)
    for k, dofs in zip(ELECTRODES, out, strict=True):
        clash = owner[dofs] > 0
        if np.any(clash):
            raise ValueError(
                f"electrodes {int(owner[dofs][clash][0])} and {k} of the planform mesh touch "
                f"(share a node) and would form one conductor; separate them by gap elements"
            )
        owner[dofs] = k
    return tuple(out)


def build_solid_model(
    stator: PlateStator,
    material: PiezoMaterial | str = "pzt8",
    mesh: MeshSettings | None = None,
    grid_lines: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
) -> SolidPlateModel:
    """Assemble the 3D model of ``stator`` on a quadratic brick mesh.

    A stator carrying a planform mesh (:class:`fem.meshing.meshed_stator.MeshedStator`) is meshed by
    :func:`extruded_hex_mesh` (``refine`` is then ignored) with the electrodes of its element
    tags; a plain :class:`fem.geometry.PlateStator` by the structured box mesh.

    Parameters
    ----------
    stator : PlateStator
        Geometry; its electrode gap must be > 0 (touching quadrants would be one conductor);
        with a planform mesh, differently tagged electrodes must not share a node.
    material : PiezoMaterial or str
        Full 3D constants ``c^E``, ``e``, ``eps^S``; poling along z.
    mesh : MeshSettings, optional
        ``order`` 2 (quadratic, default) or 1 (trilinear); ``refine``, in-plane elements
        per plate width, the grid lines following the electrode edges
        (:func:`fem.meshing.mesh.grid_lines_m`); ``layers`` through the thickness;
        ``element`` ``'hex20'`` (default) or ``'hex27'``, ignored for order 1;
        ``edge_grading``, levels of geometric refinement towards the electrode edges (0:
        uniform mesh): lines at ``g/2, ..., g/2^levels`` from each edge on both sides, and
        at ``g, 2g, 4g, ...`` outside up to half the coarse spacing; layers at the same
        depths below the top face. For a planform mesh only the layers are graded, on the
        scale of its narrower gap strip (:func:`planform_layer_lines`); its in-plane mesh
        is the file's.
    grid_lines : tuple of numpy.ndarray, optional
        Explicit tensor lines ``(x, y, z)`` (m) of the structured mesh of a plain plate,
        replacing those of ``refine``, ``layers`` and ``edge_grading`` (which are then only
        recorded); they must span the plate and contain the electrode edges
        (:func:`fem.solid3d.symmetric.quarter_grid_lines` mirrored gives such lines).

    Raises
    ------
    ValueError
        On a bad order, element, refine, layers, a zero electrode gap (touching electrodes
        of a planform mesh) or an electrode without a node.
    """
    t0 = time.perf_counter()
    mat = get_material(material)
    mesh = (MeshSettings() if mesh is None else mesh).solid()
    order, element = mesh.order, mesh.element
    _element(order, element)
    refine = _check_int("refine", mesh.refine)
    layers = _check_int("layers", mesh.layers)
    planform = planform_mesh(stator)
    if planform is None and stator.electrode_gap_m <= 0.0:
        raise ValueError(
            "PlateStator.electrode_gap_m must be > 0 in the 3D model: with no gap the four "
            "quadrants touch and form one conductor"
        )
    bricks, levels = _solid_mesh(stator, planform, refine, layers, mesh.edge_grading,
                                 grid_lines)
    basis, Kuu, M, Kuphi, Kphiphi = assemble_solid(bricks, mat, order, element,
                                                   _tip_cells(bricks, stator))
    electrode_dofs, bottom = _electrode_dofs(stator, planform, basis, levels)
    return SolidPlateModel(
        stator=stator,
        material=mat,
        order=int(order),
        element=element if order == 2 else "hex8",
        refine=refine,
        layers=layers,
        basis=basis,
        Kuu=Kuu,
        M=M,
        Kuphi=Kuphi,
        Kphiphi=Kphiphi,
        electrode_dofs=electrode_dofs,
        ground_dofs=bottom,
        assembly_time_s=time.perf_counter() - t0,
    )


def _solid_mesh(stator: PlateStator, planform, refine: int, layers: int, edge_grading: int,
                grid_lines):
    """The brick mesh of :func:`build_solid_model` and the layer levels of an extruded
    planform (None for the box mesh): the tensor mesh of ``grid_lines``, else the
    structured box mesh of a plain plate, else the planform extruded."""
    if planform is None and grid_lines is not None:
        from skfem import MeshHex

        return MeshHex.init_tensor(*(np.asarray(v, dtype=float) for v in grid_lines)), None
    if planform is None:
        return _hex_mesh(stator, refine, layers,
                         _check_int("edge_grading", edge_grading, 0)), None
    levels = planform_layer_lines(planform, stator.thickness_m, layers,
                                  _check_int("edge_grading", edge_grading, 0))
    return extruded_hex_mesh(planform, stator.thickness_m, layers, levels), levels


def _electrode_dofs(stator: PlateStator, planform, basis,
                    levels) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
    """Potential dofs of each electrode (top face, in the closed quadrant regions or the
    planform's tagged elements) and of the grounded bottom face, read-only; refuses an
    electrode without a node."""
    h = stator.thickness_m
    xyz = basis.doflocs
    tol = 1e-9 * max(stator.length_m, stator.width_m, h)
    top = np.flatnonzero(np.abs(xyz[2] - h / 2) < tol)
    bottom = np.flatnonzero(np.abs(xyz[2] + h / 2) < tol)
    if planform is None:
        # nodes on an electrode's edge belong to it (shrinking a copy of the stator's gap by
        # 2 tol instead would refuse a 1 um gap, the smallest a gap may have)
        tags = stator.electrode_of(xyz[0, top], xyz[1, top], tol_m=tol)
        electrode_dofs = tuple(top[tags == k] for k in ELECTRODES)
    else:
        electrode_dofs = _planform_electrodes(planform, basis, h, levels.size - 1, tol)
    for k, d in zip(ELECTRODES, electrode_dofs, strict=True):
        if d.size == 0:
            raise ValueError(f"the mesh has no node under electrode {k}")
        d.setflags(write=False)
    bottom.setflags(write=False)
    return electrode_dofs, bottom


def _tip_cells(mesh, stator) -> tuple[object, np.ndarray] | None:
    """``(material, cells)`` of a tip of its own material (:func:`fem.meshing.parametric.
    tip_of`): the bricks whose centre lies beyond the plate body's end; None otherwise."""
    from fem.meshing.parametric import tip_of

    found = tip_of(stator)
    if found is None:
        return None
    material, length = found
    return material, np.flatnonzero(mesh.p[1, mesh.t].mean(axis=0) > length)


def _cell_constants(material: PiezoMaterial, n_cells: int, tip) -> tuple[np.ndarray, ...]:
    """Per-brick ``c^E`` (nel, 6, 6), ``e`` (nel, 3, 6), ``eps^S`` (nel, 3, 3) and ``rho``
    (nel,): the ceramic's, and in the ``tip`` cells (``(ElasticMaterial, cells)``) the tip
    material's, without piezoelectric coupling."""
    c = np.broadcast_to(material.cE_Pa, (n_cells, 6, 6)).copy()
    e = np.broadcast_to(material.e_C_m2, (n_cells, 3, 6)).copy()
    eps = np.broadcast_to(material.epsS_F_m, (n_cells, 3, 3)).copy()
    rho = np.full(n_cells, float(material.rho_kg_m3))
    if tip is not None:
        tip_mat, cells = tip
        c[cells] = tip_mat.stiffness_Pa()
        e[cells] = 0.0
        eps[cells] = EPS0_F_M * tip_mat.relative_permittivity * np.eye(3)
        rho[cells] = tip_mat.rho_kg_m3
    return c, e, eps, rho


def assemble_solid(mesh, material: PiezoMaterial | str = "pzt8", order: int = 2,
                   element: str = DEFAULT_ELEMENT, tip=None):
    """Piezoelastic matrices of a brick mesh, before any electrical or mechanical constraint.

    Parameters
    ----------
    mesh : skfem.MeshHex
        Bricks (m); affine boxes are integrated exactly.
    material : PiezoMaterial or str
    order : int
        2 (quadratic) or 1 (trilinear).
    element : str
        ``'hex20'`` or ``'hex27'`` (order 2).
    tip : tuple, optional
        ``(ElasticMaterial, cells)``: bricks of a tip of its own material
        (:func:`_tip_cells`), isotropic and without piezoelectric coupling.

    Returns
    -------
    basis, Kuu, M, Kuphi, Kphiphi
        The scalar ``skfem.CellBasis`` and the CSR matrices of :class:`SolidPlateModel`
        (blocked displacement dofs ``u[c * N + i]``).
    """
    from skfem import CellBasis

    mat = get_material(material)
    elem = _element(order, element)
    # exact for K and M on the affine boxes of the structured mesh (on extruded general
    # quads the integrands are rational; the same rule is accurate there)
    intorder = 2 * order + 1
    basis = CellBasis(mesh, elem, intorder=intorder)
    n = basis.N
    grads = np.stack([basis.basis[i][0].grad for i in range(len(basis.basis))])
    vals = np.stack([np.asarray(basis.basis[i][0]) for i in range(len(basis.basis))])
    dx = basis.dx  # (nel, nqp) quadrature weights times Jacobian
    B = _voigt_B(grads)  # (6, 3nloc, nel, nqp)
    if tip is None:  # one material: its constants broadcast over the bricks
        cB = np.einsum("IJ,Jaeq->Iaeq", mat.cE_Pa, B)
        eB = np.einsum("kJ,Jaeq->kaeq", mat.e_C_m2, B)  # (3, 3nloc, nel, nqp): e S(v)
        epsg = np.einsum("kl,bleq->kbeq", mat.epsS_F_m, grads)
        rho = mat.rho_kg_m3
    else:  # per-brick constants: the tip's bricks are of their own material
        c_e, e_e, eps_e, rho_e = _cell_constants(mat, dx.shape[0], tip)
        cB = np.einsum("eIJ,Jaeq->Iaeq", c_e, B)
        eB = np.einsum("ekJ,Jaeq->kaeq", e_e, B)
        epsg = np.einsum("ekl,bleq->kbeq", eps_e, grads)
        rho = rho_e[None, None, :]
    k_loc = np.einsum("Iaeq,Ibeq,eq->abe", B, cB, dx, optimize=True)
    kup_loc = np.einsum("kaeq,kbeq,eq->abe", eB, grads.transpose(1, 0, 2, 3), dx, optimize=True)
    kpp_loc = np.einsum("akeq,kbeq,eq->abe", grads, epsg, dx, optimize=True)
    m_loc = rho * np.einsum("aeq,beq,eq->abe", vals, vals, dx, optimize=True)
    edofs = basis.element_dofs  # (nloc, nel)
    udofs = np.concatenate([edofs + c * n for c in range(3)])  # (3nloc, nel)
    Kuu = _coo(k_loc, udofs, udofs, (3 * n, 3 * n))
    Kuphi = _coo(kup_loc, udofs, edofs, (3 * n, n))
    Kphiphi = _coo(kpp_loc, edofs, edofs, (n, n))
    Ms = _coo(m_loc, edofs, edofs, (n, n))
    M = sp.block_diag((Ms, Ms, Ms), format="csr")
    Kuu = (0.5 * (Kuu + Kuu.T)).tocsr()
    Kphiphi = (0.5 * (Kphiphi + Kphiphi.T)).tocsr()
    return basis, Kuu, M, Kuphi.tocsr(), Kphiphi


@lru_cache(maxsize=8)
def _cached_solid_model(stator: PlateStator, material: PiezoMaterial,
                        mesh: MeshSettings) -> SolidPlateModel:
    return build_solid_model(stator, material, mesh)


def solid_model(stator: PlateStator | None = None, material: PiezoMaterial | str = "pzt8",
                mesh: MeshSettings | None = None) -> SolidPlateModel:
    """Cached :func:`build_solid_model` (default: the paper's plate, PZT-8, default mesh)."""
    return _cached_solid_model(*_solid_key("solid_model", stator, material, mesh))


def _solid_key(caller: str, stator: PlateStator | None, material: PiezoMaterial | str,
               mesh: MeshSettings | None) -> tuple[PlateStator, PiezoMaterial, MeshSettings]:
    """The cache key ``(stator, material, mesh)`` of :func:`solid_model` and
    :func:`solid_modes`, checked (plate, mesh settings, mesh size) before anything is cached
    or meshed."""
    stator = require_plate(stator, caller)
    mesh = solid_arguments(mesh)
    check_solid_size(stator, mesh.refine, mesh.layers, mesh.edge_grading)
    return stator, get_material(material), mesh


_SPLU_OPTIONS = {
    "permc_spec": "MMD_AT_PLUS_A",
    "diag_pivot_thresh": 0.1,
    "options": {"SymmetricMode": True},
}
"""SuperLU options for the symmetric (indefinite) saddle-point matrices: a symmetric
minimum-degree ordering with preference for diagonal pivots is 3-5x faster than the default
COLAMD here (measured) with the same residual."""


def _condensed_operators(Kuu, M, kup, kpp, sigma: float, row_order=None):
    """(OPinv, K_cond) linear operators on the displacements for shift ``sigma``."""
    nu = Kuu.shape[0]
    # potentials scaled so that both blocks have diagonals of similar size (|K_uu| ~ 1e10,
    # |K_phiphi| ~ 1e-9): without it the LU residual is ~1e-3, with it ~1e-11
    # (no potential left to condense, one layer at order 1: no scaling, and no mean of an
    # empty diagonal, whose NumPy warnings reached the user)
    alpha = (math.sqrt(float(Kuu.diagonal().mean()) / float(kpp.diagonal().mean()))
             if kpp.shape[0] else 1.0)
    kup = kup * alpha
    kpp = kpp * alpha**2
    A = sp.bmat([[Kuu - sigma * M, kup], [kup.T, -kpp]], format="csc")
    options = dict(_SPLU_OPTIONS)
    if row_order is not None:
        p = np.asarray(row_order)
        A = A[p][:, p].tocsc()
        options["permc_spec"] = "NATURAL"
    try:
        lu_pp = sla.splu(kpp.tocsc(), **_SPLU_OPTIONS)
        lu = sla.splu(A, **options)
    except RuntimeError as exc:
        raise ModeSolverError(f"saddle-point matrix singular at sigma={sigma:.6g}: {exc}") from exc
    del A
    n_phi = kpp.shape[0]

    def opinv(x: np.ndarray) -> np.ndarray:
        rhs = np.concatenate((np.asarray(x, dtype=float).ravel(), np.zeros(n_phi)))
        if row_order is None:
            return lu.solve(rhs)[:nu]
        y = np.empty_like(rhs)
        y[p] = lu.solve(rhs[p])
        return y[:nu]

    def kcond(x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float).ravel()
        return Kuu @ x + kup @ lu_pp.solve(kup.T @ x)

    op = sla.LinearOperator((nu, nu), matvec=opinv, dtype=float)
    kop = sla.LinearOperator((nu, nu), matvec=kcond, dtype=float)
    return op, kop


def saddle_point_frequencies_Hz(
    Kuu: sp.csr_matrix,
    M: sp.csr_matrix,
    Kuphi: sp.csr_matrix,
    Kphiphi: sp.csr_matrix,
    n_modes: int = 10,
    f_center_Hz: float = 0.0,
    maxiter: int | None = None,
    row_order: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequencies (Hz) and shapes of ``M u'' + K_uu u + K_uphi phi = 0``,
    ``K_uphi^T u = K_phiphi phi`` (the free potentials condensed), nearest ``f_center_Hz``.

    The one shift-invert driver of the 3D models: the saddle-point matrix
    ``[[K_uu - sigma M, K_uphi], [K_uphi^T, -K_phiphi]]`` is factorized once (sparse LU,
    potentials scaled to the displacements' size) and ``eigsh`` runs on the displacements
    with a fixed start vector (bit-identical runs). ``Kuphi`` and ``Kphiphi`` act on the free
    potential unknowns only (fixed potentials eliminated, tied ones summed).
    ``f_center_Hz = 0`` uses a small negative shift (rigid-body modes at 0 Hz); negative
    eigenvalues from round-off come back as negative frequencies. ``row_order``, a
    fill-reducing permutation of the saddle-point unknowns (displacements, then potentials),
    replaces SuperLU's own column ordering (e.g. :mod:`fem.solid3d.grid_ordering`).

    Raises
    ------
    ModeSolverError
        If the matrix is singular at the shift or eigsh does not converge.
    """
    if f_center_Hz > 0.0:
        sigma = (2.0 * math.pi * f_center_Hz) ** 2
    else:
        sigma = -((2.0 * math.pi * 100.0) ** 2)
    op, kop = _condensed_operators(Kuu, M, Kuphi, Kphiphi, sigma, row_order)
    w, v = shift_invert_eigsh(kop, M, op, sigma, min(int(n_modes), Kuu.shape[0] - 2), maxiter,
                              label="3D, ")
    return np.sign(w) * np.sqrt(np.abs(w)) / (2.0 * math.pi), v


def solid_frequencies_Hz(model: SolidPlateModel, n_modes: int = 10, f_center_Hz: float = 0.0,
                         open_circuit: bool = False,
                         maxiter: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The ``n_modes`` natural frequencies (Hz) nearest ``f_center_Hz`` and their shapes.

    ``model`` is the full plate or one symmetry class of its quarter
    (:class:`fem.solid3d.symmetric.QuarterPlateModel`, shapes on its free displacements),
    solved in the row order the model gives (:meth:`SolidPlateModel.saddle_point_order`).
    Shapes are displacement vectors (3N). ``f_center_Hz = 0`` uses a small negative shift so
    that the six rigid-body modes (short circuit) come out at 0 Hz. Negative eigenvalues from
    round-off are returned as negative frequencies (:func:`saddle_point_frequencies_Hz`).
    """
    t = model.potential_map(open_circuit)
    kup = (model.Kuphi @ t).tocsr()
    kpp = (t.T @ model.Kphiphi @ t).tocsr()
    return saddle_point_frequencies_Hz(model.Kuu, model.M, kup, kpp, n_modes, f_center_Hz,
                                       maxiter, model.saddle_point_order(open_circuit))


def sampling_points_3d(model: SolidPlateModel):
    """Sampling grid (ny, nx), probe matrices at mid-plane/top/bottom, mask of points used.

    On a planform mesh, grid points outside it (and their mirror images about ``x = 0``) are
    dropped: their rows of the probe matrices are zero and the mask is False there.
    """
    st = model.stator
    X, Y = sampling_grid(st)
    zt = 0.5 * st.thickness_m * (1.0 - SAMPLE_INSET)
    planform = planform_mesh(st)
    inside = np.ones(X.shape, dtype=bool)
    if planform is not None:
        inside = planform.contains(np.vstack((X.ravel(), Y.ravel()))).reshape(X.shape)
        inside &= inside[:, ::-1]
    levels = (("mid", 0.0), ("top", zt), ("bottom", -zt))
    try:
        return X, Y, _probes3d(model, X, Y, inside, levels), inside
    except ValueError:
        # scikit-fem locates points on the mesh's own (polygonal) edges, which can miss a
        # grid point the nominal outline counts inside (beside a hole on the centre line:
        # "Point is outside of the mesh" after the whole 3D solve); such points are dropped
        # like those outside, as in 2D (fem.modes.sampling_points)
        flat = inside.ravel()
        for _, z in levels:
            pts = np.vstack((X.ravel(), Y.ravel(), np.full(X.size, z)))
            flat[flat] = locatable(model.basis, pts[:, flat])
        inside = flat.reshape(X.shape)
        inside &= inside[:, ::-1]
        return X, Y, _probes3d(model, X, Y, inside, levels), inside


def _probes3d(model: SolidPlateModel, X: np.ndarray, Y: np.ndarray, inside: np.ndarray,
              levels) -> dict[str, sp.csr_matrix]:
    """Probe matrices of the grid points where ``inside`` at each ``(key, z)`` of ``levels``,
    with zero rows elsewhere."""
    idx = np.flatnonzero(inside.ravel())
    probes = {}
    for key, z in levels:
        pts = np.vstack((X.ravel(), Y.ravel(), np.full(X.size, z)))
        if inside.all():
            probes[key] = model.probe(pts)
            continue
        sub = model.probe(pts[:, idx]).tocoo()  # rows: component * idx.size + point
        comp, point = np.divmod(sub.row, idx.size)
        rows = comp * X.size + idx[point]
        probes[key] = sp.csr_matrix((sub.data, (rows, sub.col)), shape=(3 * X.size, sub.shape[1]))
    return probes


def thickness_symmetric_fraction(top: np.ndarray, bottom: np.ndarray) -> float:
    """Energy fraction of (top, bottom) samples (3, ...) in the in-plane (z-symmetric) class."""
    even = 0.5 * (top[:2] + bottom[:2])
    odd = 0.5 * (top[2] - bottom[2])
    total = 0.5 * float(np.sum(top * top) + np.sum(bottom * bottom))
    sym = float(np.sum(even * even)) + float(np.sum(odd * odd))
    return sym / total if total > 0 else 0.0


def _identify3d(model: SolidPlateModel, freqs_Hz: np.ndarray, shapes: np.ndarray):
    X, Y, probes, inside = sampling_points_3d(model)
    sampled = {k: (p @ shapes).reshape(3, *X.shape, -1) for k, p in probes.items()}
    return identify_sampled(X, Y, sampled, inside, overall_length_m(model.stator), freqs_Hz)


def identify_sampled(
    X: np.ndarray,
    Y: np.ndarray,
    sampled: dict[str, np.ndarray],
    inside: np.ndarray,
    length_m: float,
    freqs_Hz: np.ndarray,
    names: tuple[str, ...] = ("L1", "B2"),
) -> dict[str, tuple[int, float, float]]:
    """The 3D identification of L1/B2 from modes sampled on the full-plate grid.

    Parameters
    ----------
    X, Y : numpy.ndarray
        Sampling grid (ny, nx) of :mod:`fem.modes` (m).
    sampled : dict
        ``'mid'``, ``'top'``, ``'bottom'``: displacements (3, ny, nx, n_modes) (m) at
        ``z = 0`` and just inside the top and bottom faces.
    inside : numpy.ndarray
        Mask (ny, nx) of the grid points used.
    length_m : float
        Plate length (m), for the Eq. 3 reference shapes.
    freqs_Hz : numpy.ndarray
        Frequencies (Hz) of the modes; those below 1e-3 of the largest are skipped.
    names : tuple of str
        The modes to identify.

    Returns
    -------
    dict
        ``{name: (index, mac, symmetry)}``: among modes with at least
        :data:`MIN_THICKNESS_SYMMETRY` in the in-plane class, the :func:`fem.modes` rules
        (x-symmetry class, three nodes for B2, ``MAC >= MIN_MAC``), largest
        ``MAC * thickness symmetry``.

    Raises
    ------
    ModeSolverError
        If a mode is missing.
    """
    refs = reference_shapes(X, Y, length_m)
    if not inside.all():
        refs = {k: v * inside for k, v in refs.items()}
    zsym = np.array([thickness_symmetric_fraction(sampled["top"][..., i],
                                                   sampled["bottom"][..., i])
                     for i in range(sampled["mid"].shape[-1])])
    return match_modes(sampled["mid"][:2], freqs_Hz, refs, names,
                       weights=np.where(zsym < MIN_THICKNESS_SYMMETRY, np.nan, zsym),
                       what="3D modes")


@dataclass(frozen=True, eq=False)
class SolidModes(PlateModes):
    """:class:`fem.modes.PlateModes` of the 3D model, plus its mesh description.

    ``dofs`` counts the displacement and free potential unknowns of the short-circuit
    problem; shapes are 3D displacement vectors (3N), mass-normalized. ``order`` is the
    element order and ``refine`` the in-plane refinement.

    Attributes
    ----------
    layers : int
        Element layers through the thickness.
    element : str
        ``'hex20'``, ``'hex27'`` or ``'hex8'``.
    """

    layers: int = DEFAULT_LAYERS
    element: str = DEFAULT_ELEMENT


def modes_of_solid_model(
    model: SolidPlateModel,
    f_center_Hz: float | None = None,
    n_modes: int = 10,
    maxiter: int | None = None,
) -> SolidModes:
    """Short- and open-circuit L1 and B2 of an assembled 3D model (identified by shape).

    Raises
    ------
    ModeSolverError
        If eigsh does not converge or L1/B2 cannot be identified.
    """
    t0 = time.perf_counter()
    fs, fo, modes, t_short = solve_short_open(model, solid_frequencies_Hz, _identify3d,
                                              f_center_Hz, n_modes, maxiter)
    n_phi_free = model.potential_map(False).shape[1]
    return SolidModes(
        L1=modes["L1"],
        B2=modes["B2"],
        frequencies_short_Hz=fs,
        frequencies_open_Hz=fo,
        dofs=model.n_displacement_dofs + n_phi_free,
        wall_time_s=time.perf_counter() - t0 + model.assembly_time_s,
        solve_time_s=t_short,
        order=model.order,
        refine=model.refine,
        layers=model.layers,
        element=model.element,
    )


@lru_cache(maxsize=16)
def _cached_solid_modes(stator: PlateStator, material: PiezoMaterial,
                        mesh: MeshSettings) -> SolidModes:
    return modes_of_solid_model(build_solid_model(stator, material, mesh))


def solid_modes(stator: PlateStator | None = None, material: PiezoMaterial | str = "pzt8",
                mesh: MeshSettings | None = None) -> SolidModes:
    """L1 and B2 (short/open circuit, k_eff) of the 3D plate (cached).

    Parameters
    ----------
    stator : PlateStator, optional
        Default: the paper's 30 x 7.5 x 3 mm plate.
    material : PiezoMaterial or str
        ``'pzt8'`` or ``'paper'`` or a material.
    mesh : MeshSettings, optional
        Order, refinement, layers, element and edge grading (:func:`build_solid_model`);
        default :class:`fem.mesh_settings.MeshSettings`.
    """
    return _cached_solid_modes(*_solid_key("solid_modes", stator, material, mesh))
