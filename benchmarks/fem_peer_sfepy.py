"""Peer check of the 2D and 3D plate models against SfePy (a benchmark, not a test).

SfePy (https://sfepy.org, optional extra ``pip install -e .[peer]``) is an independent
open-source FE code with a piezoelasticity formulation. This script computes the default
plate (30 x 7.5 x 3 mm, PZT-8 of :func:`fem.material.pzt8`) at electrode gaps 0, 0.5 and
2 mm with

* the 2D model (:func:`fem.model.build_model` on the structured mesh, order 2, refine 4:
  what :func:`fem.model.plate_model` caches);
* the project's 3D model (:mod:`fem.solid3d.model`, hex20, default mesh and edge-graded meshes);
* SfePy: its own assembly (terms ``dw_lin_elastic``, ``dw_dot``, ``dw_piezo_coupling``,
  ``dw_diffusion``) of the same 3D problem on tensor-product hexahedral meshes generated here,
  with SfePy's 27-node Lagrange brick (``approx_order=2``, ``poly_space_basis='lagrange'``).
  Its 20-node serendipity brick enters only the assembly check below: in SfePy 2026.3
  ``Field.evaluate_at`` returns inf/NaN inside serendipity cells (seen here), so their mode
  shapes cannot be sampled for identification.

Problem (as in ``fem.solid3d.model``): IEEE e-form, poling along z; the bottom face is grounded;
the top face carries the four quadrant electrodes (closed regions, mesh lines on their
edges); gap strips and side faces are free. Short circuit: all electrodes at 0 V. Open
circuit: each electrode is one floating potential with zero net charge. At gap 0 the four
quadrants touch and form **one** conductor (the project's 3D model rejects gap 0 for that
reason): the open circuit is then one floating top electrode.

What is SfePy's and what is ours. SfePy generates the fields, the element bases and the
quadrature and assembles K_uu, M, K_uphi and K_phiphi (no boundary conditions). The
electrode constraints (one unknown per floating electrode, the bottom at 0 V) and the
eigensolution are applied here on those matrices. SfePy offers no ready-made floating
electrode with zero net charge (its example ``piezo_elastodynamic.py`` imposes an electrode
potential weakly, with a Nitsche penalty; its ``multi_node_combination`` linear-combination
condition might tie the nodes, not tried), so the free potentials are condensed exactly
inside a shift-invert operator (LU of the saddle-point matrix ``[[K_uu - sigma M, K_uphi],
[K_uphi^T, -K_phiphi]]``, ARPACK ``eigsh`` on the displacements with a fixed start vector),
the same algebra as ``fem.solid3d.model`` but written separately below. L1 and B2 are identified by
shape with the rules of ``fem.modes`` / ``fem.solid3d.model`` (mid-plane symmetry about x = 0,
three nodes for B2, MAC with the Eq. 3 shapes, thickness symmetry >= 0.5), sampling SfePy's
own field interpolation. k_eff = sqrt(1 - (f_short / f_open)^2).

Reference: per gap, the finest project 3D graded mesh of the run (``--grading`` levels on
refine = layers = 3, default 2); at gap 0, where that model does not run, the finest SfePy
mesh (hex27, refine = layers = 6). Every other row is compared with it. "Equal accuracy"
takes, per code and per tier of :data:`TIERS` (largest relative error of the four
frequencies, of both k_eff), the row with the least CPU time that meets the tier and reports
the time ratios; wall and CPU times are measured in the same run (2 shared cores: CPU time,
``time.process_time``, is the less load-sensitive of the two). The reference is not exact:
at gap 2 mm the L1 short-circuit frequency still rises by ~2e-4 per grading level, and a
hex20 reference favours the hex20 rows that converge to it, so the time ratios move with the
reference (see ``docs/fem3d.md``, "Peer check with SfePy").

A first block checks the assembly: on the same mesh and element (default 3D mesh, hex20 and
hex27) SfePy and ``fem.solid3d.model`` must give the same spectrum to round-off.

Run: ``python benchmarks/fem_peer_sfepy.py [--grading G] [--sfepy-grading S] [--quick]``
(default: about 6 minutes on 2 shared cores, more under load; ``--grading 3 --sfepy-grading 2``,
the run quoted in ``docs/fem3d.md``, about 17 minutes).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fem.geometry import ELECTRODES, PlateStator  # noqa: E402
from fem.material import PiezoMaterial, get_material  # noqa: E402
from fem.mesh_settings import MeshSettings  # noqa: E402
from fem.meshing.mesh import grid_lines_m  # noqa: E402
from fem.modes import N_SAMPLE_X, N_SAMPLE_Y, ModeSolverError  # noqa: E402
from fem.solid3d.model import identify_sampled  # noqa: E402

GAPS_M = (0.0, 0.5e-3, 2e-3)
"""Electrode gaps of the study (m)."""
SFEPY_TO_VOIGT = [0, 1, 2, 5, 4, 3]
"""SfePy's symmetric-tensor order is 11, 22, 33, 12, 13, 23; IEEE Voigt is 11, 22, 33, 23,
13, 12 (both with engineering shear strains)."""


@dataclass(frozen=True)
class Row:
    """One model on one mesh: four frequencies (Hz), two k_eff, dofs, wall and CPU time (s).

    CPU time (``time.process_time``, all threads of this process) is less sensitive than wall
    time to other jobs on the shared machine.
    """

    gap_m: float
    model: str
    mesh: str
    values: tuple[float, ...]
    dofs: int
    wall_s: float
    cpu_s: float


# --------------------------------------------------------------------------------------
# meshes


def _segments(breaks: list[float], size: float) -> np.ndarray:
    """Lines through ``breaks`` with every interval split into equal pieces <= ``size``."""
    out = [breaks[0]]
    for a, b in zip(breaks[:-1], breaks[1:], strict=True):
        n = max(1, math.ceil((b - a) / size - 1e-9))
        out.extend(a + (b - a) * np.arange(1, n + 1) / n)
    return np.array(out)


def _grade(lines: np.ndarray, edges: list[float], gap: float, levels: int) -> np.ndarray:
    """Add lines at ``gap/2^k`` (k = 1..levels) and ``gap*2^j`` from each edge, both sides."""
    lo, hi = float(lines[0]), float(lines[-1])
    coarse = float(np.max(np.diff(lines)))
    dists = [gap / 2**k for k in range(1, levels + 1)]
    d = gap
    while d < coarse / 2:
        dists.append(d)
        d *= 2
    extra = [e + s * d for e in edges for d in dists for s in (-1, 1)]
    pts = np.unique(np.concatenate((lines, np.clip(extra, lo, hi))))
    return pts[np.concatenate(([True], np.diff(pts) > 1e-9 * (hi - lo)))]


def plate_lines(stator: PlateStator, per_width: int, layers: int, levels: int = 0):
    """x, y, z grid lines (m): electrode edges on lines, optional grading towards them."""
    w, length, h, g = stator.width_m, stator.length_m, stator.thickness_m, stator.electrode_gap_m
    size = min(w, length) / per_width
    xb = [-w / 2, -g / 2, g / 2, w / 2] if g > 0 else [-w / 2, 0.0, w / 2]
    yb = [0.0, length / 2 - g / 2, length / 2 + g / 2, length] if g > 0 else [
        0.0, length / 2, length]
    x, y = _segments(xb, size), _segments(yb, size)
    z = np.linspace(-h / 2, h / 2, layers + 1)
    if levels > 0 and g > 0:
        x = _grade(x, [-g / 2, g / 2], g, levels)
        y = _grade(y, [length / 2 - g / 2, length / 2 + g / 2], g, levels)
        depth = _grade(np.array([0.0, h]), [0.0], g, levels)
        z = np.unique(np.concatenate((z, h / 2 - depth[depth < h])))
        z = z[np.concatenate(([True], np.diff(z) > 1e-9 * h))]
    return x, y, z


# --------------------------------------------------------------------------------------
# SfePy model


@dataclass(frozen=True, eq=False)
class SfepyPlate:
    """SfePy-assembled matrices (interleaved displacement dofs ``3 * node + component``)."""

    stator: PlateStator
    Kuu: sp.csr_matrix
    M: sp.csr_matrix
    Kuphi: sp.csr_matrix
    Kphiphi: sp.csr_matrix
    coor: np.ndarray
    field: object
    ground: np.ndarray
    electrodes: tuple
    label: str


def sfepy_plate(stator: PlateStator, material: PiezoMaterial, x, y, z,
                basis: str = "lagrange", label: str = "") -> SfepyPlate:
    """Assemble the plate with SfePy on the tensor grid ``x, y, z`` (quadratic bricks)."""
    from sfepy.base.base import output

    output.set_output(quiet=True)
    from sfepy.discrete import Equation, Equations, FieldVariable, Integral, Material, Problem
    from sfepy.discrete.fem import FEDomain, Field, Mesh
    from sfepy.terms import Term

    X, Y, Z = np.meshgrid(x, y, z, indexing="ij")
    coors = np.column_stack((X.ravel(), Y.ravel(), Z.ravel()))
    idx = np.arange(coors.shape[0]).reshape(len(x), len(y), len(z))
    c = [idx[i:i + len(x) - 1, j:j + len(y) - 1, k:k + len(z) - 1].ravel()
         for (i, j, k) in ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
                           (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1))]
    conn = np.column_stack(c).astype(np.int32)  # SfePy 3_8: bottom quad CCW, then top
    mesh = Mesh.from_data("plate", coors, np.zeros(len(coors), dtype=np.int32), [conn],
                          [np.zeros(len(conn), dtype=np.int32)], ["3_8"])
    omega = FEDomain("domain", mesh).create_region("Omega", "all")
    fu = Field.from_args("fu", np.float64, "vector", omega, approx_order=2,
                         poly_space_basis=basis)
    fp = Field.from_args("fp", np.float64, "scalar", omega, approx_order=2,
                         poly_space_basis=basis)
    u = FieldVariable("u", "unknown", fu)
    v = FieldVariable("v", "test", fu, primary_var_name="u")
    p = FieldVariable("p", "unknown", fp)
    q = FieldVariable("q", "test", fp, primary_var_name="p")
    ii = SFEPY_TO_VOIGT
    m = Material("m", C=material.cE_Pa[np.ix_(ii, ii)], e=material.e_C_m2[:, ii],
                 kappa=material.epsS_F_m, rho=np.array([[material.rho_kg_m3]]))
    integral = Integral("i", order=5)  # exact for K and M of quadratic bricks on boxes
    terms = {
        "K": Term.new("dw_lin_elastic(m.C, v, u)", integral, omega, m=m, v=v, u=u),
        "M": Term.new("dw_dot(m.rho, v, u)", integral, omega, m=m, v=v, u=u),
        # int S(v)^T e^T grad(p): the K_uphi of fem.solid3d.model with p = phi (E = -grad phi)
        "G": Term.new("dw_piezo_coupling(m.e, v, p)", integral, omega, m=m, v=v, p=p),
        "P": Term.new("dw_diffusion(m.kappa, q, p)", integral, omega, m=m, q=q, p=p),
    }
    eqs = {k: Equation(k, t) for k, t in terms.items()}
    pb = Problem("piezo", equations=Equations(list(eqs.values())))
    pb.time_update()
    pb.update_materials()
    mats = {}
    for k, eq in eqs.items():
        mtx = pb.mtx_a.copy()
        mtx.data[:] = 0.0
        mats[k] = eq.evaluate(mode="weak", dw_mode="matrix", asm_obj=mtx)
    iu = pb.equations.variables.adi.indx["u"]
    ip = pb.equations.variables.adi.indx["p"]
    coor = fp.get_coor()
    ground, electrodes = electrode_nodes(stator, coor)
    return SfepyPlate(stator=stator, Kuu=mats["K"][iu, iu].tocsr(), M=mats["M"][iu, iu].tocsr(),
                      Kuphi=mats["G"][iu, ip].tocsr(), Kphiphi=mats["P"][ip, ip].tocsr(),
                      coor=coor, field=fp, ground=ground, electrodes=electrodes, label=label)


def electrode_nodes(stator: PlateStator, coor: np.ndarray):
    """Grounded bottom nodes and the top-face node set of each conductor.

    Gap > 0: four quadrants (closed regions). Gap 0: one conductor, the whole top face.
    """
    h = stator.thickness_m
    tol = 1e-9 * max(stator.length_m, stator.width_m, h)
    top = np.flatnonzero(np.abs(coor[:, 2] - h / 2) < tol)
    bottom = np.flatnonzero(np.abs(coor[:, 2] + h / 2) < tol)
    if stator.electrode_gap_m <= 0.0:
        return bottom, (top,)
    closed = replace(stator, electrode_gap_m=max(stator.electrode_gap_m - 2 * tol, 0.0))
    tags = closed.electrode_of(coor[top, 0], coor[top, 1])
    return bottom, tuple(top[tags == k] for k in ELECTRODES)


def potential_map(n: int, ground: np.ndarray, electrodes, open_circuit: bool) -> sp.csr_matrix:
    """``phi = T phi_free``: ground and (short) electrodes at 0, one column per floating one."""
    fixed = np.zeros(n, dtype=bool)
    fixed[ground] = True
    for d in electrodes:
        fixed[d] = True
    free = np.flatnonzero(~fixed)
    rows, cols, ncol = [free], [np.arange(free.size)], free.size
    if open_circuit:
        for d in electrodes:
            rows.append(d)
            cols.append(np.full(d.size, ncol))
            ncol += 1
    r, c = np.concatenate(rows), np.concatenate(cols)
    return sp.csr_matrix((np.ones(r.size), (r, c)), shape=(n, ncol))


def condensed_eigs(pl: SfepyPlate, f_center_Hz: float, n_modes: int, open_circuit: bool):
    """Frequencies (Hz) and displacement shapes nearest ``f_center_Hz``, potentials condensed."""
    t = potential_map(pl.Kphiphi.shape[0], pl.ground, pl.electrodes, open_circuit)
    kup = (pl.Kuphi @ t).tocsr()
    kpp = (t.T @ pl.Kphiphi @ t).tocsr()
    alpha = math.sqrt(float(pl.Kuu.diagonal().mean()) / float(kpp.diagonal().mean()))
    kup, kpp = kup * alpha, kpp * alpha**2  # balance the blocks (1e10 against 1e-9)
    sigma = (2.0 * math.pi * f_center_Hz) ** 2
    a = sp.bmat([[pl.Kuu - sigma * pl.M, kup], [kup.T, -kpp]], format="csc")
    opts = {"permc_spec": "MMD_AT_PLUS_A", "diag_pivot_thresh": 0.1,
            "options": {"SymmetricMode": True}}
    lu = sla.splu(a, **opts)
    lu_pp = sla.splu(kpp.tocsc(), **opts)
    nu, nphi = pl.Kuu.shape[0], kpp.shape[0]

    def opinv(x):
        return lu.solve(np.concatenate((np.ravel(x), np.zeros(nphi))))[:nu]

    def kcond(x):
        x = np.ravel(x)
        return pl.Kuu @ x + kup @ lu_pp.solve(kup.T @ x)

    op = sla.LinearOperator((nu, nu), matvec=opinv, dtype=float)
    kop = sla.LinearOperator((nu, nu), matvec=kcond, dtype=float)
    v0 = np.random.default_rng(0).standard_normal(nu)
    w, vec = sla.eigsh(kop, k=n_modes, M=pl.M, sigma=sigma, OPinv=op, which="LM", v0=v0)
    order = np.argsort(w)
    w, vec = w[order], vec[:, order]
    return np.sign(w) * np.sqrt(np.abs(w)) / (2.0 * math.pi), vec


def identify(pl: SfepyPlate, freqs: np.ndarray, shapes: np.ndarray) -> dict[str, int]:
    """Index of L1 and B2 among ``shapes``: the rules of :func:`fem.solid3d.model.
    identify_sampled` on the modes sampled by SfePy's own interpolation."""
    st = pl.stator
    inset = 1e-9
    xs = np.linspace(-0.5, 0.5, N_SAMPLE_X) * st.width_m * (1.0 - inset)
    ys = (np.linspace(0.0, 1.0, N_SAMPLE_Y) * (1.0 - 2 * inset) + inset) * st.length_m
    X, Y = np.meshgrid(xs, ys)
    n_nod, k = pl.coor.shape[0], shapes.shape[1]
    vals = shapes.reshape(n_nod, 3 * k)  # interleaved dofs: columns (component, mode) per node
    sampled = {}
    for key, z in (("mid", 0.0), ("top", 0.5), ("bottom", -0.5)):
        zz = z * st.thickness_m * (1.0 - inset)
        pts = np.column_stack((X.ravel(), Y.ravel(), np.full(X.size, zz)))
        s = pl.field.evaluate_at(pts, vals)[:, :, 0]  # (points, 3k)
        sampled[key] = s.reshape(X.shape + (3, k)).transpose(2, 0, 1, 3)  # (3, ny, nx, k)
    try:
        found = identify_sampled(X, Y, sampled, np.ones(X.shape, dtype=bool), st.length_m,
                                 freqs)
    except ModeSolverError as exc:
        raise RuntimeError(f"SfePy: {exc}") from None
    return {name: int(v[0]) for name, v in found.items()}


def sfepy_row(stator: PlateStator, material: PiezoMaterial, per_width: int, layers: int,
              levels: int = 0, basis: str = "lagrange", f_center_Hz: float = 55e3,
              n_modes: int = 12) -> Row:
    """Assemble with SfePy, solve short and open circuit, identify L1 and B2 (one uncached run)."""
    t0, c0 = time.perf_counter(), time.process_time()
    x, y, z = plate_lines(stator, per_width, layers, levels)
    elem = "hex27" if basis == "lagrange" else "hex20"
    label = f"{elem} {per_width}x{layers}" + (f" graded {levels}" if levels else "")
    pl = sfepy_plate(stator, material, x, y, z, basis, label)
    res = {}
    for oc in (False, True):
        f, v = condensed_eigs(pl, f_center_Hz, n_modes, oc)
        ids = identify(pl, f, v)
        res[oc] = {name: float(f[i]) for name, i in ids.items()}
    fs, fo = res[False], res[True]
    k = [math.sqrt(max(1.0 - (fs[n] / fo[n]) ** 2, 0.0)) for n in ("L1", "B2")]
    dofs = pl.Kuu.shape[0] + potential_map(pl.Kphiphi.shape[0], pl.ground, pl.electrodes,
                                           False).shape[1]
    return Row(stator.electrode_gap_m, "SfePy", label,
               (fs["L1"], fo["L1"], fs["B2"], fo["B2"], *k), dofs, time.perf_counter() - t0,
               time.process_time() - c0)


# --------------------------------------------------------------------------------------
# project models


def row_2d(stator: PlateStator, material: PiezoMaterial, refine: int = 4) -> Row:
    """The 2D model (order 2), one uncached run (the gap-validity warning is silenced)."""
    import warnings

    from fem.meshing.mesh import structured_mesh
    from fem.model import build_model
    from fem.modes import modes_of_model

    t0, c0 = time.perf_counter(), time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = build_model(structured_mesh(stator, refine), stator, material, 2)
    r = modes_of_model(model, refine=refine)
    return Row(stator.electrode_gap_m, "2D", f"order 2, refine {refine}",
               (r.L1.f_short_Hz, r.L1.f_open_Hz, r.B2.f_short_Hz, r.B2.f_open_Hz,
                r.L1.k_eff, r.B2.k_eff), r.dofs, time.perf_counter() - t0,
               time.process_time() - c0)


def row_3d(stator: PlateStator, material: PiezoMaterial, refine: int = 3, layers: int = 3,
           grading: int = 0, element: str = "hex20") -> Row:
    """The project's 3D model, one uncached run."""
    from fem.solid3d.model import build_solid_model, modes_of_solid_model

    t0, c0 = time.perf_counter(), time.process_time()
    model = build_solid_model(stator, material, MeshSettings(2, refine, layers, element, grading))
    r = modes_of_solid_model(model)
    label = f"{element} {refine}x{layers}" + (f" graded {grading}" if grading else "")
    return Row(stator.electrode_gap_m, "3D", label,
               (r.L1.f_short_Hz, r.L1.f_open_Hz, r.B2.f_short_Hz, r.B2.f_open_Hz,
                r.L1.k_eff, r.B2.k_eff), r.dofs, time.perf_counter() - t0,
               time.process_time() - c0)


def same_mesh_check(material: PiezoMaterial) -> list[str]:
    """Spectra of SfePy and fem.solid3d.model on the same mesh and element (gap 0.5 mm)."""
    from fem.solid3d.model import build_solid_model, solid_frequencies_Hz

    stator = PlateStator()
    x, y = grid_lines_m(stator, 3)
    z = np.linspace(-stator.thickness_m / 2, stator.thickness_m / 2, 4)
    lines = []
    for basis, element in (("serendipity", "hex20"), ("lagrange", "hex27")):
        pl = sfepy_plate(stator, material, x, y, z, basis)
        model = build_solid_model(stator, material, MeshSettings(2, 3, 3, element))
        worst = 0.0
        for oc in (False, True):
            fa, _ = condensed_eigs(pl, 55e3, 10, oc)
            fb, _ = solid_frequencies_Hz(model, 10, 55e3, oc)
            elastic = np.abs(fb) > 1.0
            worst = max(worst, float(np.max(np.abs(fa[elastic] / fb[elastic] - 1))))
        lines.append(f"{element}, default 3D mesh ({pl.Kuu.shape[0]} displacement dofs): the 10 "
                     f"short- and open-circuit frequencies nearest 55 kHz agree to "
                     f"{worst:.1e} (relative)")
    return lines


# --------------------------------------------------------------------------------------


def _err(row: Row, ref: Row) -> list[float]:
    return [abs(a / b - 1.0) if b else abs(a) for a, b in zip(row.values, ref.values,
                                                              strict=True)]


def _fmt_gap(g: float) -> str:
    return f"{g * 1e3:g}"


TIERS = ((1e-3, 0.05), (2e-4, 0.01))
"""Equal-accuracy tiers: (largest relative error of the four frequencies, of both k_eff)."""


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grading", type=int, default=2,
                    help="edge-grading levels of the project 3D meshes; the finest is the "
                         "reference at gaps 0.5 and 2 mm")
    ap.add_argument("--sfepy-grading", type=int, default=1,
                    help="edge-grading levels of the SfePy meshes")
    ap.add_argument("--quick", action="store_true", help="coarse meshes only (smoke run)")
    args = ap.parse_args(argv)
    try:
        import sfepy
    except ImportError:
        print("SfePy is not installed: pip install -e .[peer]  (or pip install sfepy)")
        raise SystemExit(1) from None
    mat = get_material("pzt8")
    print(f"SfePy {sfepy.__version__}; plate 30 x 7.5 x 3 mm, PZT-8\n")
    print("Same mesh, same element (assembly check):")
    for line in same_mesh_check(mat):
        print("  " + line)
    print()
    levels_3d = 0 if args.quick else args.grading
    levels_sf = 0 if args.quick else args.sfepy_grading
    rows: list[Row] = []
    refs: dict[float, Row] = {}

    def add(row: Row) -> Row:
        rows.append(row)
        print(f"  done gap {_fmt_gap(row.gap_m)} mm {row.model} {row.mesh}: {row.dofs} dofs, "
              f"{row.wall_s:.1f} s wall, {row.cpu_s:.1f} s CPU", file=sys.stderr, flush=True)
        return row

    for gap in GAPS_M:
        st = PlateStator(electrode_gap_m=gap)
        add(row_2d(st, mat))
        if gap > 0:
            refs[gap] = add(row_3d(st, mat))
            add(sfepy_row(st, mat, 3, 3))
            for lv in range(1, levels_sf + 1):
                add(sfepy_row(st, mat, 3, 3, lv))
            for lv in range(1, levels_3d + 1):
                refs[gap] = add(row_3d(st, mat, grading=lv))
        else:  # the project's 3D model rejects gap 0: SfePy on refined uniform meshes
            refs[gap] = add(sfepy_row(st, mat, 3, 3))
            if not args.quick:
                add(sfepy_row(st, mat, 4, 4))
                refs[gap] = add(sfepy_row(st, mat, 6, 6))

    _print_table(rows, refs)
    for gap in GAPS_M:
        _print_tiers(rows, refs[gap], gap)


def _print_table(rows: list[Row], refs: dict[float, Row]) -> None:
    """Every row of the study as a Markdown table, with its errors against its gap's
    reference and its CPU time over the 2D model's."""
    print("| gap (mm) | model | mesh | dofs | L1 f_short (Hz) | L1 f_open (Hz) | B2 f_short (Hz) "
          "| B2 f_open (Hz) | k L1 | k B2 | max freq err | max k err | CPU / 2D |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    cpu_2d = {r.gap_m: r.cpu_s for r in rows if r.model == "2D"}
    for r in rows:
        ref = refs[r.gap_m]
        e = _err(r, ref)
        tag = " (ref)" if r is ref else ""
        print(f"| {_fmt_gap(r.gap_m)} | {r.model} | {r.mesh}{tag} | {r.dofs} | "
              + " | ".join(f"{v:.1f}" for v in r.values[:4]) + " | "
              + " | ".join(f"{v:.4f}" for v in r.values[4:])
              + f" | {max(e[:4]):.1e} | {max(e[4:]):.1e} | {r.cpu_s / cpu_2d[r.gap_m]:.3g} |")
    print("\nmax freq err / max k err: largest relative difference from the reference (ref) of "
          "the four frequencies / of the two k_eff (k_B2 = 0 at gap 0: absolute there); "
          "CPU / 2D: CPU time as a multiple of the 2D model's at the same gap, same run\n")


def _print_tiers(rows: list[Row], ref: Row, gap: float) -> None:
    """At one gap, the fastest row of each model within each accuracy tier of the
    reference ``ref``, and SfePy's time over the project models'."""
    cpu_2d = {r.gap_m: r.cpu_s for r in rows if r.model == "2D"}
    for tol_f, tol_k in TIERS:
        print(f"gap {_fmt_gap(gap)} mm, reference {ref.model} {ref.mesh}: fastest row (CPU) "
              f"within {tol_f:.0e} on the four frequencies and {tol_k:.0%} on both k_eff")
        best = {}
        for r in rows:
            if r.gap_m != gap or r is ref:
                continue
            e = _err(r, ref)
            if max(e[:4]) <= tol_f and max(e[4:]) <= tol_k and (
                    r.model not in best or r.cpu_s < best[r.model].cpu_s):
                best[r.model] = r
        for model in ("2D", "3D", "SfePy"):
            if model in best:
                r = best[model]
                print(f"  {model}: {r.mesh}, {r.dofs} dofs, CPU "
                      f"{r.cpu_s / cpu_2d[gap]:.3g} x the 2D model's")
            else:
                print(f"  {model}: none (besides the reference)")
        if "SfePy" in best:
            for model in ("2D", "3D"):
                if model in best:
                    a, b = best["SfePy"], best[model]
                    print(f"  SfePy / {model}: wall {a.wall_s / b.wall_s:.1f}x, "
                          f"CPU {a.cpu_s / b.cpu_s:.1f}x")
        print()


if __name__ == "__main__":
    main()
