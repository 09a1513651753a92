"""Structured quadrilateral meshes of the stator plate with tagged electrode subdomains.

The mesh is a tensor-product grid of rectangles whose lines follow the electrode edges, so
each element lies entirely under one electrode (tag 1..4) or in an unelectroded gap strip
(tag 0). The geometry is always bilinear (rectangles are represented exactly); the element
order (1: ``ElementQuad1``, 2: ``ElementQuad2``) is chosen when the model is assembled.

Files: :mod:`fem.meshing.mesh_io` reads and writes meshes (meshio; electrode groups ``electrode1``
.. ``electrode4`` and ``gap``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bounds import ParameterError, Words
from fem.geometry import ELECTRODES, PlateStator
from fem.limits import work_factor
from fem.mesh_settings import DEFAULT_REFINE

GAP_PHYSICAL_TAG = 10
"""gmsh physical tag of the unelectroded gap strips."""


GAP_NAME = "gap"
"""Name of the unelectroded region (scikit-fem subdomain, gmsh physical group)."""


def electrode_name(k: int) -> str:
    """Name of electrode ``k`` (1..4) as a scikit-fem subdomain and a gmsh physical group.

    The one convention written everywhere is ``electrode1`` .. ``electrode4``; readers also
    accept ``electrode_1`` .. ``electrode_4`` (files written by lusm before 2026-11).
    """
    return f"electrode{k}"


@dataclass(frozen=True, eq=False)
class PlateMesh:
    """A quadrilateral mesh of the plate and the electrode tag of every element.

    Attributes
    ----------
    points_m : numpy.ndarray
        Node coordinates, shape (2, n_nodes) (m): row 0 is x (width), row 1 is y (length).
    quads : numpy.ndarray
        Element connectivity, shape (4, n_elements), counter-clockwise.
    electrode : numpy.ndarray
        Electrode number (1..4) of each element, 0 for the unelectroded gap.
    """

    points_m: np.ndarray
    quads: np.ndarray
    electrode: np.ndarray

    def __post_init__(self) -> None:
        p = np.array(self.points_m, dtype=float)
        t = np.array(self.quads, dtype=np.int64)
        tags = np.array(self.electrode, dtype=np.int64)
        if p.ndim != 2 or p.shape[0] != 2:
            raise ValueError(f"PlateMesh.points_m must have shape (2, n), got {p.shape}")
        if t.ndim != 2 or t.shape[0] != 4:
            raise ValueError(f"PlateMesh.quads must have shape (4, n), got {t.shape}")
        if tags.shape != (t.shape[1],):
            raise ValueError("PlateMesh.electrode must hold one tag per element")
        if np.any((tags < 0) | (tags > 4)):
            raise ValueError("PlateMesh.electrode tags must lie in 0..4 (0 = gap)")
        if not np.any(tags > 0):
            raise ValueError("PlateMesh has no electroded element (all tags are 0)")
        for a in (p, t, tags):
            a.setflags(write=False)
        object.__setattr__(self, "points_m", p)
        object.__setattr__(self, "quads", t)
        object.__setattr__(self, "electrode", tags)

    @property
    def n_elements(self) -> int:
        """Number of quadrilaterals."""
        return int(self.quads.shape[1])

    def elements_of(self, electrode: int) -> np.ndarray:
        """Indices of the elements under ``electrode`` (1..4; 0 for the gap)."""
        return np.flatnonzero(self.electrode == electrode)

    def quadrant_problem(self) -> str | None:
        """Why the electrode tags are not the quadrants of :mod:`fem.geometry` (None if they are).

        All four electrodes need cells: the 2D model gives each its own capacitance
        (area / thickness) and coupling column, which an empty electrode leaves singular. The
        2D model reads its gap strips and which quadrants touch from the tags' places
        (:func:`fem.model.gap_layout`), and the beam and the drive diagonals assume Fig. 1's
        numbering: 1, 2 at ``x > 0`` and 3, 4 at ``x < 0``; 2, 4 toward the tip (larger y)
        and 1, 3 toward the preload end. Quadrants may touch (no gap) but not overlap.
        """
        p = self.points_m
        x0, x1, y0, y1 = self.bounding_box_m()
        tol = 1e-9 * max(x1 - x0, y1 - y0)
        # a mesh with electrodes 1 and 4 only has one on each side of both centre lines, and
        # failed later in the model as "mesh has no elements under electrode(s) [2, 3]"
        missing = [k for k in ELECTRODES if not np.any(self.electrode == k)]
        if missing:
            return (f"no cells under electrode{'s' if len(missing) > 1 else ''} "
                    f"{', '.join(map(str, missing))}: a stator needs all four quadrant "
                    f"electrodes 1..4 (1, 2 at x > 0, 3, 4 at x < 0; 2, 4 on the tip's half, "
                    f"1, 3 on the preload end's half), each with cells (tags "
                    f"{', '.join(electrode_name(k) for k in ELECTRODES)})")

        def nodes(tags):
            el = np.flatnonzero(np.isin(self.electrode, tags))
            return p[:, np.unique(self.quads[:, el])]

        for axis, name, (hi, lo), (where_hi, where_lo) in (
            (0, "x", ((1, 2), (3, 4)), ("x > 0", "x < 0")),
            (1, "y", ((2, 4), (1, 3)), ("the tip's half", "the preload end's half")),
        ):
            a, b = nodes(hi), nodes(lo)
            if b[axis].max() > a[axis].min() + tol:
                return (f"electrodes {hi[0]}, {hi[1]} must lie on {where_hi} and {lo[0]}, "
                        f"{lo[1]} on {where_lo} ({'width' if axis == 0 else 'length'} "
                        f"direction {name}), but {lo[0]}, {lo[1]} reach {name} = "
                        f"{b[axis].max() * 1e3:.4g} mm and {hi[0]}, {hi[1]} start at {name} = "
                        f"{a[axis].min() * 1e3:.4g} mm; number the quadrants as in the "
                        f"paper's Fig. 1 (docs/designer.md, mesh conventions)")
        return None

    def electroded_box_m(self) -> tuple[float, float, float, float]:
        """``(x_min, x_max, y_min, y_max)`` (m) of the electroded elements: the plate body
        without an unelectroded protrusion (a contact tip)."""
        p = self.points_m[:, np.unique(self.quads[:, self.electrode > 0])]
        return (float(p[0].min()), float(p[0].max()), float(p[1].min()), float(p[1].max()))

    def bounding_box_m(self) -> tuple[float, float, float, float]:
        """``(x_min, x_max, y_min, y_max)`` (m)."""
        p = self.points_m
        return (float(p[0].min()), float(p[0].max()), float(p[1].min()), float(p[1].max()))

    def contains(self, points_m: np.ndarray, rel_tol: float = 1e-9) -> np.ndarray:
        """Whether each point ``(x, y)`` (m), shape (2, n), lies in a (convex) element.

        Points on an element edge count as inside within ``rel_tol`` times the mesh size.
        """
        from scipy.spatial import cKDTree

        pts = np.atleast_2d(np.asarray(points_m, dtype=float))
        x0, x1, y0, y1 = self.bounding_box_m()
        tol = rel_tol * max(x1 - x0, y1 - y0)
        corners = self.points_m[:, self.quads]  # (2, 4, n_elements)
        nxt = np.roll(corners, -1, axis=1)

        def inside(p: np.ndarray, cells: np.ndarray) -> np.ndarray:
            a, b = corners[:, :, cells], nxt[:, :, cells]  # (2, 4, m, k)
            edge = b - a
            length = np.hypot(edge[0], edge[1])
            rel = p[:, None, :, None] - a
            cross = edge[0] * rel[1] - edge[1] * rel[0]
            return np.all(cross >= -tol * length, axis=0)  # (m, k)

        out = np.zeros(pts.shape[1], dtype=bool)
        if pts.shape[1] == 0:
            return out
        k = min(8, self.n_elements)
        tree = cKDTree(corners.mean(axis=1).T)
        near = tree.query(pts.T, k)[1].reshape(pts.shape[1], k)
        out = inside(pts, near).any(axis=1)
        for i in np.flatnonzero(~out):  # rare: big neighbours; check every element
            out[i] = bool(inside(pts[:, i : i + 1], np.arange(self.n_elements)[None]).any())
        return out

    def outline_distance_m(self, point_m) -> float:
        """Distance (m) from a point ``(x, y)`` (m) to the planform's outline: the edges that
        belong to one element only (holes' edges included, :func:`boundary_edges`)."""
        edges, _ = boundary_edges(self.quads)
        a, b = (self.points_m[:, edges[:, i]] for i in (0, 1))  # (2, m)
        p = np.asarray(point_m, dtype=float)[:, None]
        d = b - a
        t = np.clip(np.sum((p - a) * d, axis=0) / np.maximum(np.sum(d * d, axis=0), 1e-300),
                    0.0, 1.0)
        return float(np.min(np.hypot(*(a + t * d - p))))

    def to_skfem(self):  # -> skfem.MeshQuad1
        """The scikit-fem mesh (imported lazily), subdomains ``electrode1..4`` and ``gap``."""
        from skfem import MeshQuad1

        subdomains = {electrode_name(k): self.elements_of(k) for k in ELECTRODES}
        subdomains[GAP_NAME] = self.elements_of(0)
        subdomains = {k: v.astype(np.int32) for k, v in subdomains.items() if v.size}
        return MeshQuad1(
            np.ascontiguousarray(self.points_m),
            np.ascontiguousarray(self.quads),
            _subdomains=subdomains,
        )


def boundary_edges(quads: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The boundary edges of a set of quads (4, m): node pairs (k, 2) of the edges that belong
    to one quad only, in that quad's orientation, and the quad (column) owning each."""
    edges = np.stack((quads, np.roll(quads, -1, axis=0)), axis=-1).reshape(-1, 2)  # (4m, 2)
    owner = np.tile(np.arange(quads.shape[1]), 4)
    key = np.sort(edges, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    single = counts[inverse.ravel()] == 1
    return edges[single], owner[single]


def grid_segments(breaks: list[float], h_target: float) -> np.ndarray:
    """Grid lines through the sorted ``breaks``: each interval split into equal pieces no
    longer than ``h_target`` (same unit), empty intervals skipped."""
    nodes = [breaks[0]]
    for a, b in zip(breaks[:-1], breaks[1:], strict=True):
        if b - a <= 0.0:
            continue
        n = max(1, math.ceil((b - a) / h_target - 1e-9))
        nodes.extend(np.linspace(a, b, n + 1)[1:].tolist())
    return np.array(nodes)


MAX_LIBRARY_CELLS_2D = 200_000
"""Elements of a generated 2D mesh a library call builds (ten times the CLI's bound,
``lusm.limits.MAX_FE_CELLS_2D``; ``LUSM_MAX_WORK`` multiplies it):
``plate_modes(mesh=MeshSettings(refine=10000))`` would run out of memory."""
MAX_LIBRARY_BRICKS_3D = 20_000
"""Bricks of a generated 3D mesh a library call builds (ten times the CLI's bound)."""


def require_plate(stator: object, where: str) -> PlateStator:
    """``stator`` if it is a :class:`PlateStator` (None: the paper's plate), else a TypeError
    saying how to get one (a loaded stator file passed whole is a common slip, which would
    fail as "'StatorDesign' object has no attribute 'width_m'")."""
    if stator is None:
        return PlateStator()
    if isinstance(stator, PlateStator):
        return stator
    hint = ("; a loaded stator file carries it and its material: design = load_stator(path), "
            "then design.stator and design.material" if hasattr(stator, "stator") else
            "; a file is read by fem.stator_file.load_stator(path)")
    raise TypeError(f"{where}: stator must be a fem.geometry.PlateStator (or None for the "
                    f"paper's plate), got {type(stator).__name__}{hint}")


def check_generated_size(stator: PlateStator, refine: int, layers: int | None = None,
                         count=None, named: Words | None = None) -> None:
    """Refuse a generated mesh above :data:`MAX_LIBRARY_CELLS_2D` elements (or, with
    ``layers``, :data:`MAX_LIBRARY_BRICKS_3D` bricks) before it is built, naming ``refine``.
    A lower bound, ``refine^2 l W / min(l, W)^2`` elements (times ``layers``), is checked
    before any line is made, then ``count()`` (the exact count) when given; ``named``: the
    settings the message names (default ``refine``, and ``layers`` in 3D)."""
    top = (MAX_LIBRARY_CELLS_2D if layers is None else MAX_LIBRARY_BRICKS_3D) * work_factor()
    side = min(stator.length_m, stator.width_m)
    least = float(refine) ** 2 * stator.length_m * stator.width_m / side**2 * (layers or 1)
    n = least if least > top or count is None else count()
    if n > top:
        what = "elements" if layers is None else "bricks"
        named = named or (Words("{refine}", refine=f"{refine}") if layers is None else
                          Words("{refine} with {layers}", refine=f"{refine}", layers=f"{layers}"))
        raise ParameterError("refine", refine, message=named + (
            f" make{'s' if layers is None else ''} {'at least ' if n is least else ''}{n:.3g} "
            f"{what} on this plate, above the limit {top:.0f} of a library call (set "
            "LUSM_MAX_WORK=N to allow N times more)"))


def grid_lines_m(stator: PlateStator, refine: int) -> tuple[np.ndarray, np.ndarray]:
    """x and y grid lines (m) of the structured mesh.

    The target element size is ``min(W, l) / refine``; every segment between electrode edges
    (including a gap strip) gets ``ceil(length / size)`` equal elements, at least one.
    """
    if isinstance(refine, bool) or not isinstance(refine, (int, np.integer)) or refine < 1:
        raise ParameterError("refine", refine, 1, None,
                             message=f"refine must be an integer >= 1, got {refine!r}")
    w, length, g = stator.width_m, stator.length_m, stator.electrode_gap_m
    h = min(w, length) / int(refine)
    xb = [-w / 2, -g / 2, g / 2, w / 2] if g > 0 else [-w / 2, 0.0, w / 2]
    yb = [0.0, length / 2 - g / 2, length / 2 + g / 2, length] if g > 0 else [
        0.0, length / 2, length
    ]
    return grid_segments(xb, h), grid_segments(yb, h)


def max_element_size_m(stator: PlateStator, refine: int) -> float:
    """Largest element edge (m) of the structured mesh: the h of convergence studies."""
    x, y = grid_lines_m(stator, refine)
    return max(float(np.max(np.diff(x))), float(np.max(np.diff(y))))


def structured_mesh(stator: PlateStator, refine: int = DEFAULT_REFINE) -> PlateMesh:
    """Structured rectangle mesh of ``stator`` with electrode-tagged elements.

    Parameters
    ----------
    stator : PlateStator
        Plate geometry and electrode gap.
    refine : int
        Elements per smaller plate dimension: the target element size is ``min(W, l)/refine``.

    Returns
    -------
    PlateMesh
    """
    x, y = grid_lines_m(stator, refine)
    nx, ny = len(x), len(y)
    ix = np.arange(nx * ny).reshape(ny, nx)  # node (j, i) at (x[i], y[j])
    a = ix[:-1, :-1].ravel()
    b = ix[:-1, 1:].ravel()
    c = ix[1:, 1:].ravel()
    d = ix[1:, :-1].ravel()
    quads = np.vstack((a, b, c, d))
    X, Y = np.meshgrid(x, y)
    points = np.vstack((X.ravel(), Y.ravel()))
    xc = 0.25 * points[0, quads].sum(axis=0)
    yc = 0.25 * points[1, quads].sum(axis=0)
    return PlateMesh(points_m=points, quads=quads, electrode=stator.electrode_of(xc, yc))
