"""Quarter-plate 3D model: L1 and B2 from the plate's two mirror symmetries.

The rectangular plate, its four quadrant electrodes (bottom face grounded) and the
transversely isotropic, z-poled material are symmetric about the two mid-planes normal to
the plate: ``x = 0`` (across the width) and ``y = l/2`` (along the length), in the
coordinates of :mod:`fem.solid3d.model`. Every mode of the full 3D model therefore lies in one of
four classes, and L1 and B2 lie in two of them. With ``R`` the mirror, a field is symmetric
when ``u(R p) = R u(p)``, ``phi(R p) = phi(p)`` and antisymmetric when
``u(R p) = -R u(p)``, ``phi(R p) = -phi(p)``:

* **L1** (``u_y ~ cos(pi y / l)``) is symmetric about both planes: ``u_x`` odd in ``x``,
  ``u_y`` odd about ``y = l/2``, the potential even about both. On the quarter
  ``x >= 0, y >= l/2``: ``u_x = 0`` on ``x = 0``, ``u_y = 0`` on ``y = l/2``, ``D . n = 0``
  (natural) on both planes, and all four electrodes at one potential.
* **B2** (``u_x ~ phi_B(y)``, three nodes, ``phi_B`` odd about ``y = l/2``) is
  antisymmetric about both planes: ``u_x`` even in ``x`` and odd about ``y = l/2``,
  ``u_y`` odd in ``x`` and even about ``y = l/2``, ``u_z`` odd about both, the potential odd
  about both (diagonal quadrants at equal potential). On the quarter: ``u_y = u_z = 0`` on
  ``x = 0``, ``u_x = u_z = 0`` on ``y = l/2``, ``phi = 0`` on both planes.

The quarter carries one quadrant electrode: grounded in short circuit, floating with zero net
charge in open circuit (by symmetry the four charges are equal in size, so zero on one is
zero on all). Each class is a 3D eigenproblem of about a quarter of the full size with only
the modes of its class competing; both use the shift-invert driver of
:func:`fem.solid3d.model.saddle_point_frequencies_Hz`, :func:`fem.modes.solve_short_open` and the
3D identification :func:`fem.solid3d.model.identify_sampled` on the full-plate sampling grid
(the quarter's field unfolded with the class parities), so the results are those of
:func:`fem.solid3d.model.solid_modes` on the mirrored mesh (a test checks it to round-off).

With no gap (``electrode_gap_m = 0``) the electrode reaches both planes: in the L1 class it
is the one conductor covering the top face, in the B2 class it touches ``phi = 0`` and is
grounded in both circuits, so ``k_eff(B2) = 0`` (touching quadrants are one conductor).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.sparse as sp

from fem.geometry import PlateStator
from fem.material import PiezoMaterial, get_material
from fem.mesh_settings import MeshSettings
from fem.meshing.meshed_stator import has_planform
from fem.modes import SAMPLE_INSET, sampling_grid, solve_short_open
from fem.solid3d.grid_ordering import nested_dissection_rank
from fem.solid3d.model import (
    DEFAULT_LAYERS,
    DEFAULT_REFINE_3D,
    SolidMatrices,
    SolidModes,
    assemble_solid,
    hex_grid_lines,
    identify_sampled,
    solid_arguments,
    solid_frequencies_Hz,
)

MODE_CLASSES = ("L1", "B2")
"""The symmetry classes solved: L1 (symmetric about both planes), B2 (antisymmetric)."""

_FIXED_U = {"L1": {"x": (0,), "y": (1,)}, "B2": {"x": (1, 2), "y": (0, 2)}}
"""Displacement components (0: u_x, 1: u_y, 2: u_z) fixed to 0 on the planes x = 0 and
y = l/2 in each class."""

_MIRROR_SIGN = {"L1": {"x": (-1.0, 1.0, 1.0), "y": (1.0, -1.0, 1.0)},
                "B2": {"x": (1.0, -1.0, -1.0), "y": (-1.0, 1.0, -1.0)}}
"""Factor of each displacement component at the mirror image of a point, per class."""


def quarter_grid_lines(stator: PlateStator, refine: int = DEFAULT_REFINE_3D,
                       layers: int = DEFAULT_LAYERS, edge_grading: int = 0):
    """Tensor lines ``(x, y, z)`` (m) of the quarter ``x >= 0``, ``y >= l/2``.

    The lines of :func:`fem.solid3d.model.hex_grid_lines` on the quarter, plus the planes ``x = 0``
    and ``y = l/2``. Mirrored (:func:`mirrored_grid_lines`) they give the full mesh the
    quarter model equals.
    """
    x, y, z = hex_grid_lines(stator, refine, layers, edge_grading)
    half = stator.length_m / 2
    tol = 1e-9 * max(stator.length_m, stator.width_m)
    x = np.concatenate(([0.0], x[x > tol]))
    y = np.concatenate(([half], y[y > half + tol]))
    return x, y, z


def mirrored_grid_lines(lines, length_m: float):
    """Full-plate lines ``(x, y, z)`` (m) from quarter lines, mirrored about both planes."""
    x, y, z = (np.asarray(v, dtype=float) for v in lines)
    return np.unique(np.concatenate((-x, x))), np.unique(np.concatenate((length_m - y, y))), z


@dataclass(frozen=True, eq=False)
class QuarterPlateModel(SolidMatrices):
    """Assembled quarter-plate matrices of one symmetry class (treat as read-only).

    Attributes
    ----------
    stator : PlateStator
        The whole plate (plain, rectangular); the model is its quarter.
    material : PiezoMaterial
        Its full 3D constants.
    mode : str
        ``'L1'`` or ``'B2'``: the symmetry class.
    basis : skfem.CellBasis
        Scalar basis on the quarter mesh.
    free_u : numpy.ndarray
        Indices into the blocked displacement vector (3N) of the unconstrained components.
    Kuu, M : scipy.sparse.csr_matrix
        Stiffness (N/m) and mass (kg) on the free displacements.
    Kuphi : scipy.sparse.csr_matrix
        Coupling (C/m), free displacements x all N potentials.
    Kphiphi : scipy.sparse.csr_matrix
        Dielectric stiffness (F), N x N.
    electrode_dofs : numpy.ndarray
        Scalar dofs of the quarter's electrode (top face, closed quadrant).
    ground_dofs : numpy.ndarray
        Potentials fixed to 0: bottom face (and both symmetry planes in the B2 class).
    assembly_time_s : float
        Mesh and assembly wall time (s).
    """

    stator: PlateStator
    material: PiezoMaterial
    mode: str
    basis: object
    free_u: np.ndarray

    @property
    def n_displacement_dofs(self) -> int:
        """Free displacement unknowns."""
        return int(self.free_u.size)

    @property
    def electrode_grounded(self) -> bool:
        """True when the electrode touches a grounded node (B2 class with no gap)."""
        return bool(np.intersect1d(self.electrode_dofs, self.ground_dofs).size)

    def potential_map(self, open_circuit: bool) -> sp.csr_matrix:
        """Matrix ``T`` (N x n_free): nodal potentials ``phi = T phi_free``.

        Ground nodes are 0, the electrode's nodes are 0 (short circuit, or grounded through a
        symmetry plane) or share one column (open circuit), all others are free.
        """
        n = int(self.basis.N)
        fixed = np.zeros(n, dtype=bool)
        fixed[self.ground_dofs] = True
        fixed[self.electrode_dofs] = True
        free = np.flatnonzero(~fixed)
        rows, cols, ncol = [free], [np.arange(free.size)], free.size
        if open_circuit and not self.electrode_grounded:
            rows.append(self.electrode_dofs)
            cols.append(np.full(self.electrode_dofs.size, ncol))
            ncol += 1
        r, c = np.concatenate(rows), np.concatenate(cols)
        return sp.csr_matrix((np.ones(r.size), (r, c)), shape=(n, ncol))

    def saddle_point_order(self, open_circuit: bool) -> np.ndarray:
        """Nested-dissection order of the saddle-point unknowns (free displacements, then the
        free potentials of :meth:`potential_map`; the electrode's potential last)."""
        n = int(self.basis.N)
        mesh = self.basis.mesh
        planes = tuple(np.unique(mesh.p[a]) for a in range(3))
        rank = nested_dissection_rank(self.basis.doflocs, planes)
        t = self.potential_map(open_circuit).tocsc()
        free_phi = t.indices[t.indptr[:-1]]  # first node of each column
        key = np.concatenate((rank[self.free_u % n], rank[free_phi]))
        if t.shape[1] > 0 and np.diff(t.indptr)[-1] > 1:  # the floating electrode
            key[-1] = n
        return np.argsort(key, kind="stable")

    def unfold_probe(self, X: np.ndarray, Y: np.ndarray, z_m: float) -> sp.csr_matrix:
        """Matrix (3 X.size, n_free_u): the full-plate displacements at ``(X, Y, z_m)``.

        Points outside the quarter are mapped to their mirror images and the components
        multiplied by the class parities, so the result stacks ``u_x, u_y, u_z`` as the full
        model's probe does.
        """
        st = self.stator
        xq = np.abs(X.ravel())
        low = Y.ravel() < st.length_m / 2
        yq = np.where(low, st.length_m - Y.ravel(), Y.ravel())
        p = self.basis.probes(np.vstack((xq, yq, np.full(xq.size, z_m)))).tocsr()
        n = int(self.basis.N)
        select = sp.csr_matrix((np.ones(self.free_u.size), (self.free_u,
                                                            np.arange(self.free_u.size))),
                               shape=(3 * n, self.free_u.size))
        signs = _MIRROR_SIGN[self.mode]
        neg_x = X.ravel() < 0.0
        blocks = []
        for c in range(3):
            s = np.where(neg_x, signs["x"][c], 1.0) * np.where(low, signs["y"][c], 1.0)
            blocks.append(sp.diags(s) @ p)
        return (sp.block_diag(blocks, format="csr") @ select).tocsr()


def build_quarter_model(
    stator: PlateStator,
    mode: str,
    material: PiezoMaterial | str = "pzt8",
    mesh: MeshSettings | None = None,
    grid_lines: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
) -> QuarterPlateModel:
    """Assemble the quarter ``x >= 0, y >= l/2`` of a plain plate for one symmetry class.

    Parameters
    ----------
    stator : PlateStator
        A plain rectangular plate (no planform mesh); any gap >= 0.
    mode : str
        ``'L1'`` or ``'B2'`` (module docstring: the constraints of each class).
    material, mesh
        As :func:`fem.solid3d.model.build_solid_model`; the mesh is :func:`quarter_grid_lines`.
    grid_lines : tuple of numpy.ndarray, optional
        Explicit quarter lines ``(x, y, z)`` (m), from ``x = 0`` and ``y = l/2``.

    Raises
    ------
    ValueError
        On a stator with a planform mesh, a bad mode or mesh parameters.
    """
    from skfem import MeshHex

    t0 = time.perf_counter()
    if mode not in MODE_CLASSES:
        raise ValueError(f"mode must be one of {', '.join(MODE_CLASSES)}, got {mode!r}")
    if has_planform(stator):
        raise ValueError("the quarter model needs a plain rectangular plate (its planform mesh "
                         "need not be symmetric); use fem.solid3d.model.build_solid_model")
    mat = get_material(material)
    mesh = (MeshSettings() if mesh is None else mesh).solid()
    lines = quarter_grid_lines(stator, mesh.refine, mesh.layers, mesh.edge_grading) \
        if grid_lines is None else grid_lines
    bricks = MeshHex.init_tensor(*(np.asarray(v, dtype=float) for v in lines))
    basis, Kuu, M, Kuphi, Kphiphi = assemble_solid(bricks, mat, mesh.order, mesh.element)
    n = int(basis.N)
    xyz = basis.doflocs
    length, h, g = stator.length_m, stator.thickness_m, stator.electrode_gap_m
    tol = 1e-9 * max(length, stator.width_m, h)
    on = {"x": np.abs(xyz[0]) < tol, "y": np.abs(xyz[1] - length / 2) < tol}
    fixed = np.zeros(3 * n, dtype=bool)
    for plane, comps in _FIXED_U[mode].items():
        for c in comps:
            fixed[c * n + np.flatnonzero(on[plane])] = True
    free_u = np.flatnonzero(~fixed)
    top = np.abs(xyz[2] - h / 2) < tol
    electrode = np.flatnonzero(top & (xyz[0] >= g / 2 - tol) & (xyz[1] >= length / 2 + g / 2 - tol))
    ground = np.abs(xyz[2] + h / 2) < tol
    if mode == "B2":
        ground |= on["x"] | on["y"]
    ground_dofs = np.flatnonzero(ground)
    for a in (free_u, electrode, ground_dofs):
        a.setflags(write=False)
    return QuarterPlateModel(
        stator=stator,
        material=mat,
        mode=mode,
        basis=basis,
        free_u=free_u,
        Kuu=Kuu[free_u][:, free_u].tocsr(),
        M=M[free_u][:, free_u].tocsr(),
        Kuphi=Kuphi[free_u].tocsr(),
        Kphiphi=Kphiphi,
        electrode_dofs=electrode,
        ground_dofs=ground_dofs,
        assembly_time_s=time.perf_counter() - t0,
    )


def _identify_quarter(model: QuarterPlateModel, freqs_Hz: np.ndarray, shapes: np.ndarray):
    st = model.stator
    X, Y = sampling_grid(st)  # a plain plate: its length is its whole extent
    zt = 0.5 * st.thickness_m * (1.0 - SAMPLE_INSET)
    sampled = {key: (model.unfold_probe(X, Y, z) @ shapes).reshape(3, *X.shape, -1)
               for key, z in (("mid", 0.0), ("top", zt), ("bottom", -zt))}
    return identify_sampled(X, Y, sampled, np.ones(X.shape, dtype=bool), st.length_m,
                            freqs_Hz, names=(model.mode,))


@dataclass(frozen=True, eq=False)
class SymmetricSolidModes(SolidModes):
    """:class:`fem.solid3d.model.SolidModes` from the two quarter models.

    ``L1.shape`` and ``B2.shape`` are vectors of their own class's free displacements
    (:attr:`QuarterPlateModel.free_u`); the spectra are both classes' frequencies, merged
    and sorted; ``dofs`` sums both classes' short-circuit unknowns.

    Attributes
    ----------
    edge_grading : int
        Levels of grading towards the electrode edges.
    """

    edge_grading: int = 0


def modes_of_quarter_models(l1: QuarterPlateModel, b2: QuarterPlateModel,
                            mesh: MeshSettings | None = None,
                            f_center_Hz: float | None = None,
                            n_modes: int = 8) -> SymmetricSolidModes:
    """Short- and open-circuit L1 and B2 from the assembled quarter models of both classes
    (``mesh``, the models' settings, is recorded in the result).

    Raises
    ------
    fem.modes.ModeSolverError
        If eigsh does not converge or a mode cannot be identified.
    """
    t0 = time.perf_counter()
    mesh = (MeshSettings() if mesh is None else mesh).solid()
    modes, f_short, f_open, dofs, t_short = {}, [], [], 0, 0.0
    for model in (l1, b2):
        fs, fo, found, ts = solve_short_open(model, solid_frequencies_Hz, _identify_quarter,
                                             f_center_Hz, n_modes, None,
                                             max_modes=model.n_displacement_dofs - 2,
                                             names=(model.mode,))
        modes.update(found)
        f_short.append(fs)
        f_open.append(fo)
        dofs += model.n_displacement_dofs + model.potential_map(False).shape[1]
        t_short += ts
    return SymmetricSolidModes(
        L1=modes["L1"],
        B2=modes["B2"],
        frequencies_short_Hz=np.sort(np.concatenate(f_short)),
        frequencies_open_Hz=np.sort(np.concatenate(f_open)),
        dofs=dofs,
        wall_time_s=time.perf_counter() - t0 + l1.assembly_time_s + b2.assembly_time_s,
        solve_time_s=t_short,
        order=mesh.order,
        refine=mesh.refine,
        layers=mesh.layers,
        element=mesh.element if mesh.order == 2 else "hex8",
        edge_grading=mesh.edge_grading,
    )


def quarter_model_applies(stator: PlateStator, edge_grading: int) -> bool:
    """Whether :func:`symmetric_solid_modes` gives :func:`fem.solid3d.model.solid_modes`' results:
    a plain plate (no planform mesh) on a graded mesh, whose first grading level puts lines
    on both symmetry planes ``x = 0`` and ``y = l/2`` (the uniform default mesh has none)."""
    return edge_grading > 0 and not has_planform(stator)


@lru_cache(maxsize=16)
def _cached_symmetric_modes(stator: PlateStator, material: PiezoMaterial,
                            mesh: MeshSettings) -> SymmetricSolidModes:
    l1, b2 = (build_quarter_model(stator, m, material, mesh) for m in MODE_CLASSES)
    return modes_of_quarter_models(l1, b2, mesh)


def symmetric_solid_modes(stator: PlateStator | None = None, material: PiezoMaterial | str = "pzt8",
                          mesh: MeshSettings | None = None) -> SymmetricSolidModes:
    """L1 and B2 (short/open circuit, k_eff) of a plain plate from its quarter (cached).

    The same fields as :func:`fem.solid3d.model.solid_modes` with the same arguments; the mesh is
    the quarter of that model's lines plus the two symmetry planes (equal to the full model
    on the mirrored lines, :func:`mirrored_grid_lines`). Unlike the full model it accepts a
    zero gap.

    Raises
    ------
    ValueError
        On a stator with a planform mesh or bad mesh parameters.
    fem.modes.ModeSolverError
        If a mode cannot be found.
    """
    stator = PlateStator() if stator is None else stator
    return _cached_symmetric_modes(stator, get_material(material), solid_arguments(mesh))
