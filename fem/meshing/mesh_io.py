"""Import any planar 2D mesh that meshio reads as the stator planform (gmsh ``.msh`` first).

Conventions (SI inside; see ``docs/designer.md``):

* coordinates in metres (``unit='mm'`` scales a millimetre mesh), ``z = 0``; ``x`` across
  the width centred on ``x = 0``, ``y`` along the length from the preload end ``y = 0``;
* gmsh physical groups (MSH 4.1 ASCII/binary as written by gmsh >= 4 and ``meshio``'s
  ``'gmsh'`` format; MSH 2.2, ``'gmsh22'``, is read too):

  - surfaces ``electrode1`` .. ``electrode4`` (``electrode_1`` .. also accepted) and an
    optional ``gap`` for unelectroded material; every surface cell must be in one of them;
  - optional vertex groups ``tip`` and ``preload`` (one node each): the contact tip and the
    preload point;
  - curve groups and line cells are ignored (boundaries);

* other formats (vtu, xdmf, ...) carry an integer cell array ``electrode`` (0 = no
  electrode), as written by :func:`write_mesh`.

Writing: :func:`write_mesh` (a :class:`fem.meshing.mesh.PlateMesh`, any meshio format) and
:func:`write_stator_msh` (any cells plus the ``tip``/``preload`` vertices) both name the
groups ``electrode1`` .. ``electrode4`` and ``gap`` (:func:`fem.meshing.mesh.electrode_name`).

Cells: ``quad`` and ``triangle`` (and the straight-sided ``quad8``, ``quad9``,
``triangle6``, whose mid-side nodes are dropped). The FE stage assembles on bilinear quads
(``MeshQuad1`` with ``ElementQuad1``/``ElementQuad2``), so a mesh containing triangles is
converted into an all-quad mesh of the same planform: every triangle is split into three
quads through its centroid and edge midpoints and, in a mixed mesh, every quad into four, so
the result is conforming. The electrode tag of a cell passes to its children.
"""

from __future__ import annotations

import contextlib
import io
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fem.geometry import ELECTRODES
from fem.limits import work_factor
from fem.meshing.mesh import GAP_NAME, GAP_PHYSICAL_TAG, PlateMesh, electrode_name

UNITS = {"m": 1.0, "mm": 1e-3}
"""Mesh coordinate units accepted by :func:`read_stator_mesh` and their size in metres."""

MAX_COORDINATE_M = 1.0
"""Coordinates beyond this (m) are refused: a millimetre mesh read as metres, or a stator
beyond the 1 m the tool accepts."""

MIN_EXTENT_M = 1e-4
"""A planform smaller than this (m) is refused: a metre mesh declared ``unit = "mm"``, or a
stator below the 0.1 mm the tool accepts."""

MAX_CELLS = 200_000
"""Largest mesh (quads after splitting triangles) accepted; the environment variable
``LUSM_MAX_WORK=N`` allows N times more (as for the other work bounds of ``lusm``)."""

SURFACE_TYPES = ("quad", "triangle", "quad8", "quad9", "triangle6")
"""meshio cell types read as the planform."""

IGNORED_TYPES = ("line", "line3", "vertex")
"""meshio cell types that are not part of the planform (vertices may name points)."""

POINT_GROUPS = ("tip", "preload")
"""Names of the vertex physical groups."""

TIP_PHYSICAL_TAG = 21
"""Physical tag written for the ``tip`` vertex group."""
PRELOAD_PHYSICAL_TAG = 22
"""Physical tag written for the ``preload`` vertex group."""

_ELECTRODE_RE = re.compile(r"^electrode_?(\d+)$", re.IGNORECASE)
_ALLOWED = "electrode1..electrode4 (or electrode_1..electrode_4), gap, tip, preload"


_FORMATS = (".msh (gmsh MSH 4.1 or 2.2) or, with an integer cell array 'electrode', another "
            "format meshio reads (.vtu, .vtk, .xdmf, ...)")
"""The mesh files read, for messages."""


def _no_group_message(path: Path, what: str) -> str:
    """The refusal of gmsh elements outside every physical group, ``what`` saying which."""
    return (f"mesh file {path}: {what} no physical group (gmsh writes such elements with "
            f"Mesh.SaveAll = 1, or when the model has no physical groups); put the surfaces in "
            f"physical groups named electrode1..electrode4 (or electrode_1..electrode_4) and "
            f"gap, the optional tip and preload vertices in groups named tip and preload, and "
            f"save with Mesh.SaveAll = 0")


@dataclass(frozen=True, eq=False)
class ImportedMesh:
    """A planform mesh read from a file, with its named points.

    Attributes
    ----------
    mesh : PlateMesh
        All-quad mesh in metres with electrode tags (0 = unelectroded).
    points_m : dict of str to (float, float)
        Named points from vertex groups (``'tip'``, ``'preload'``), metres.
    path : Path
        The file read.
    cell_types : tuple of str
        The surface cell types found in the file.
    converted : bool
        True if triangles were split into quads.
    """

    mesh: PlateMesh
    points_m: dict[str, tuple[float, float]] = field(default_factory=dict)
    path: Path = Path()
    cell_types: tuple[str, ...] = ()
    converted: bool = False


def _group_of(name: str, path: Path) -> int | str:
    """Electrode number (1..4), 0 for ``gap``, or the point name; ValueError otherwise."""
    key = name.strip()
    match = _ELECTRODE_RE.match(key)
    if match:
        k = int(match.group(1))
        if k not in ELECTRODES:
            raise ValueError(
                f"mesh file {path}: physical group {name!r} names electrode {k}, but the "
                f"electrodes are numbered 1..4"
            )
        return k
    if key.lower() == "gap":
        return 0
    if key.lower() in POINT_GROUPS:
        return key.lower()
    raise ValueError(f"mesh file {path}: unknown physical group {name!r}; allowed: {_ALLOWED}")


def _straight_corners(cell_type: str, data: np.ndarray, pts: np.ndarray, path: Path):
    """Corner connectivity of a second-order cell whose mid-side nodes sit mid-edge."""
    n = 4 if cell_type.startswith("quad") else 3
    corners = data[:, :n]
    for j in range(n):
        a, b = corners[:, j], corners[:, (j + 1) % n]
        mid = 0.5 * (pts[a] + pts[b])
        dev = np.linalg.norm(pts[data[:, n + j]] - mid, axis=1)
        size = np.linalg.norm(pts[b] - pts[a], axis=1)
        if np.any(dev > 1e-6 * size):
            raise ValueError(
                f"mesh file {path}: curved {cell_type} cells are not supported (mid-side "
                f"nodes off the straight edges); export a first-order mesh"
            )
    return corners


def _signed_area(pts: np.ndarray, conn: np.ndarray) -> np.ndarray:
    """Shoelace area of polygons ``conn`` (n_cells, n_corners) over ``pts`` (n, 2)."""
    x, y = pts[conn, 0], pts[conn, 1]
    return 0.5 * np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)


def quadrangulate(
    points_m: np.ndarray, triangles: np.ndarray, quads: np.ndarray,
    tri_tags: np.ndarray, quad_tags: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Conforming all-quad mesh from triangles (3 quads each) and quads (4 each if mixed).

    Parameters
    ----------
    points_m : numpy.ndarray
        Node coordinates, shape (n, 2) (m).
    triangles, quads : numpy.ndarray
        Counter-clockwise connectivity, shapes (n_tri, 3) and (n_quad, 4).
    tri_tags, quad_tags : numpy.ndarray
        Electrode tag per cell.

    Returns
    -------
    points_m : numpy.ndarray
        (n', 2) nodes: the originals, then edge midpoints, then cell centroids.
    quads : numpy.ndarray
        (n_quads', 4) counter-clockwise.
    tags : numpy.ndarray
        Tag per new quad.
    """
    if triangles.shape[0] == 0:
        return points_m, quads, quad_tags
    cells = [triangles, quads] if quads.shape[0] else [triangles]
    tags = [tri_tags, quad_tags] if quads.shape[0] else [tri_tags]
    edges = np.concatenate(
        [np.stack((c, np.roll(c, -1, axis=1)), axis=-1).reshape(-1, 2) for c in cells]
    )
    uniq, inverse = np.unique(np.sort(edges, axis=1), axis=0, return_inverse=True)
    inverse = inverse.ravel()
    n0 = points_m.shape[0]
    mids = 0.5 * (points_m[uniq[:, 0]] + points_m[uniq[:, 1]])
    new_pts = [points_m, mids]
    out, out_tags = [], []
    offset_edge = 0
    next_node = n0 + uniq.shape[0]
    for c, t in zip(cells, tags, strict=True):
        k = c.shape[1]
        emid = n0 + inverse[offset_edge : offset_edge + c.size].reshape(-1, k)
        offset_edge += c.size
        centre = np.arange(next_node, next_node + c.shape[0])
        next_node += c.shape[0]
        new_pts.append(points_m[c].mean(axis=1))
        for j in range(k):  # child at corner j: corner, mid(j, j+1), centre, mid(j-1, j)
            out.append(np.column_stack((c[:, j], emid[:, j], centre, emid[:, (j - 1) % k])))
            out_tags.append(t)
    return np.concatenate(new_pts), np.concatenate(out), np.concatenate(out_tags)


def _cells_text(ids: np.ndarray, limit: int = 6) -> str:
    ids = np.unique(np.asarray(ids, dtype=np.int64))
    text = ", ".join(str(int(i)) for i in ids[:limit])
    return text + (f" and {ids.size - limit} more" if ids.size > limit else "")


_CELL_NUMBERS = "(surface cells numbered from 0 in file order)"


COINCIDENT_TOLERANCE = 1e-8
"""Distinct nodes of surface cells closer than this times the planform's extent count as one
place (an unmerged seam); gmsh's own ``Geometry.Tolerance`` (1e-8), which its Coherence uses to
merge duplicates, is of that size relative to the model."""


def _check_coincident_nodes(pts: np.ndarray, used: np.ndarray, path: Path) -> None:
    """Refuse distinct nodes at the same place that surface cells use (an unmerged seam).

    Cells on both sides of a line that use different nodes at the same coordinates are not
    connected there: the mesh has a crack, which moved L1 by 11 % on a 2.6 mm seam without a
    word, and a longer one made the modes unidentifiable. Every edge still meets its
    neighbour's end to end, so the crossing check does not see it. Nodes that no cell uses are
    dropped anyway and stay accepted.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    up = pts[used]
    extent = float(np.max(np.ptp(up, axis=0)))
    pairs = cKDTree(up).query_pairs(COINCIDENT_TOLERANCE * extent, output_type="ndarray")
    if pairs.shape[0] == 0:
        return
    # group the coincident nodes (three or more at one place form one location)
    graph = coo_matrix((np.ones(pairs.shape[0]), (pairs[:, 0], pairs[:, 1])),
                       shape=(up.shape[0], up.shape[0]))
    _, label = connected_components(graph, directed=False)
    involved = np.unique(pairs)
    n_places = np.unique(label[involved]).size
    x, y = up[involved[0]] / 1e-3
    raise ValueError(
        f"mesh file {path} has {involved.size} nodes used by its cells that coincide with "
        f"another node ({n_places} places, one at x = {x:.6g} mm, y = {y:.6g} mm): an "
        f"unmerged seam, the cells on either side of it not connected (a crack); merge the "
        f"duplicate nodes "
        f"(gmsh: Geometry.AutoCoherence = 1 before meshing, or 'Coherence Mesh;' / "
        f"gmsh.model.mesh.removeDuplicateNodes() after)"
    )


def _check_cells(pts: np.ndarray, tri: np.ndarray, quad: np.ndarray, id_tri: np.ndarray,
                 id_quad: np.ndarray, path: Path, box_area: float) -> None:
    """Refuse a planform that is not one valid, conforming, non-overlapping mesh.

    Orients every cell counter-clockwise in place. Refused, naming the cells: zero-area cells;
    distinct nodes at one place (:func:`_check_coincident_nodes`, naming the place);
    non-convex or self-intersecting quads; duplicated cells; overlapping cells (an
    edge used twice in one direction - a cell folded over its neighbour - or by more than two
    cells); boundary edges that cross
    or run into each other (overlaps, hanging nodes); parts that do not touch.
    """
    conns = [(c, i) for c, i in ((tri, id_tri), (quad, id_quad)) if c.shape[0]]
    areas = [_signed_area(pts, c) for c, _ in conns]
    tol = 1e-12 * box_area
    bad = np.concatenate([i[np.abs(a) <= tol] for (c, i), a in zip(conns, areas, strict=True)])
    if bad.size:
        raise ValueError(f"mesh file {path} has degenerate (zero-area) cells {_cells_text(bad)} "
                         f"{_CELL_NUMBERS}")
    # before the other checks: a seam can also split the mesh into "separate parts"
    _check_coincident_nodes(pts, np.unique(np.concatenate([c.ravel() for c, _ in conns])), path)
    # Corner order alone is repaired (each cell made counter-clockwise); a cell that is really
    # inverted or folded over its neighbour then traverses a shared edge in the same direction
    # as that neighbour, which the edge check below refuses.
    for (c, _), a in zip(conns, areas, strict=True):
        c[a < 0] = c[a < 0, ::-1]
    if quad.shape[0]:  # every corner of a quad must turn left (convex, not a bow tie)
        p = pts[quad]
        e1 = np.roll(p, -1, axis=1) - p
        e0 = p - np.roll(p, 1, axis=1)
        cross = e0[..., 0] * e1[..., 1] - e0[..., 1] * e1[..., 0]
        concave = np.any(cross <= 1e-12 * box_area, axis=1)
        if np.any(concave):
            raise ValueError(f"mesh file {path} has non-convex or self-intersecting quads "
                             f"{_cells_text(id_quad[concave])} {_CELL_NUMBERS}")
    for c, i in conns:
        key = np.sort(c, axis=1)
        _, first, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
        if np.any(counts > 1):
            _, inverse = np.unique(key, axis=0, return_inverse=True)
            dup = i[np.isin(inverse.ravel(), np.flatnonzero(counts > 1))]
            raise ValueError(f"mesh file {path} has duplicated cells {_cells_text(dup)} "
                             f"{_CELL_NUMBERS}: the same corners appear more than once")
    # directed edges: in a conforming, non-overlapping, consistently oriented mesh each
    # appears once, and each undirected edge is used by at most two cells
    edges = np.concatenate([np.stack((c, np.roll(c, -1, axis=1)), axis=-1).reshape(-1, 2)
                            for c, _ in conns])
    owner = np.concatenate([np.repeat(i, c.shape[1]) for c, i in conns])
    _, inv_d, cnt_d = np.unique(edges, axis=0, return_inverse=True, return_counts=True)
    inv_d = inv_d.ravel()
    und = np.sort(edges, axis=1)
    _, inv_u, cnt_u = np.unique(und, axis=0, return_inverse=True, return_counts=True)
    inv_u = inv_u.ravel()
    over = (cnt_d[inv_d] > 1) | (cnt_u[inv_u] > 2)
    if np.any(over):
        raise ValueError(f"mesh file {path} has overlapping (folded or inverted) cells "
                         f"{_cells_text(owner[over])} {_CELL_NUMBERS}: an edge is shared the "
                         "wrong way or by more than two cells")
    first = np.unique(inv_u, return_index=True)[1]  # one occurrence of every edge
    _check_crossings(pts, und[first], owner[first], path)
    # connectivity through shared nodes
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    n_cells = sum(c.shape[0] for c, _ in conns)
    rows = np.concatenate([np.repeat(np.arange(c.shape[0]), c.shape[1]) + off for (c, _), off in
                           zip(conns, np.cumsum([0] + [c.shape[0] for c, _ in conns])[:-1],
                               strict=True)])
    cols = np.concatenate([c.ravel() for c, _ in conns])
    inc = coo_matrix((np.ones(rows.size), (rows, cols)),
                     shape=(n_cells, pts.shape[0])).tocsr()
    n_parts, label = connected_components(inc @ inc.T, directed=False)
    if n_parts > 1:
        ids = np.concatenate([i for _, i in conns])
        sizes = np.bincount(label)
        small = int(np.argmin(sizes))
        raise ValueError(f"mesh file {path} has {n_parts} separate parts; cells "
                         f"{_cells_text(ids[label == small])} {_CELL_NUMBERS} do not touch the "
                         "rest of the stator")


def _candidate_pairs(lo: np.ndarray, hi: np.ndarray, max_pairs: int) -> np.ndarray | None:
    """Pairs ``(i, j)``, ``i < j``, of boxes that share a bin of a uniform grid (broad phase).

    ``lo``/``hi`` are integer bin ranges (n, 2). None if the grid would make too many pairs.
    """
    span = hi - lo + 1
    counts = span[:, 0] * span[:, 1]
    if counts.sum() > 50 * len(lo):
        return None
    idx = np.repeat(np.arange(len(lo)), counts)
    k = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    bx = lo[idx, 0] + k % span[idx, 0]
    by = lo[idx, 1] + k // span[idx, 0]
    key = (bx - bx.min()) * (int(by.max() - by.min()) + 1) + (by - by.min())
    order = np.argsort(key, kind="stable")
    key, idx = key[order], idx[order]
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    sizes = np.diff(np.r_[starts, key.size])
    pairs = []
    for size in np.unique(sizes[sizes > 1]):
        group = starts[sizes == size]
        iu, ju = np.triu_indices(int(size), 1)
        pairs.append(np.stack((idx[group[:, None] + iu], idx[group[:, None] + ju]), -1)
                     .reshape(-1, 2))
        if sum(len(q) for q in pairs) > max_pairs:
            return None
    if not pairs:
        return np.zeros((0, 2), dtype=np.int64)
    pairs = np.sort(np.concatenate(pairs), axis=1)
    return np.unique(pairs[pairs[:, 0] != pairs[:, 1]], axis=0)


def _check_crossings(pts: np.ndarray, edges: np.ndarray, owner: np.ndarray, path: Path) -> None:
    """No two edges of the mesh may cross, and no node may sit inside an edge.

    In a conforming mesh edges meet only at shared end nodes; a crossing means overlapping
    cells, a node inside an edge a hanging node (non-conforming neighbours). A uniform grid of
    about one edge length finds the candidate pairs (linear in the mesh size).
    """
    if edges.shape[0] < 2:
        return
    a, b = pts[edges[:, 0]], pts[edges[:, 1]]
    length = np.hypot(*(b - a).T)
    h = float(np.median(length))
    scale = float(np.max(np.ptp(pts[np.unique(edges)], axis=0)))
    if not h > 0:
        return
    base = np.minimum(a, b).min(axis=0)
    lo = np.floor((np.minimum(a, b) - base) / h).astype(np.int64)
    hi = np.floor((np.maximum(a, b) - base) / h).astype(np.int64)
    pairs = _candidate_pairs(lo, hi, max_pairs=20 * edges.shape[0])
    if pairs is None or pairs.size == 0:
        return
    i, j = pairs[:, 0], pairs[:, 1]
    shared = (edges[i][:, :, None] == edges[j][:, None, :]).any(axis=(1, 2))
    i, j = i[~shared], j[~shared]
    ai, bi, aj, bj = a[i], b[i], a[j], b[j]

    def orient(p, q, r):
        return (q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1]) - (q[:, 1] - p[:, 1]) * (
            r[:, 0] - p[:, 0])

    t = 1e-9 * length[i] * length[j]  # a relative tolerance on the cross products
    d1, d2 = orient(ai, bi, aj), orient(ai, bi, bj)
    d3, d4 = orient(aj, bj, ai), orient(aj, bj, bi)
    cross = (((d1 > t) & (d2 < -t)) | ((d1 < -t) & (d2 > t))) & (
        ((d3 > t) & (d4 < -t)) | ((d3 < -t) & (d4 > t)))
    len2 = length[i] ** 2
    margin = 1e-9 * scale * length[i]
    dot_a = np.sum((aj - ai) * (bi - ai), axis=1)
    dot_b = np.sum((bj - ai) * (bi - ai), axis=1)
    inside = ((np.abs(d1) <= t) & (dot_a > margin) & (dot_a < len2 - margin)) | (
        (np.abs(d2) <= t) & (dot_b > margin) & (dot_b < len2 - margin))
    # the same with the roles of the two edges swapped
    len2j = length[j] ** 2
    marginj = 1e-9 * scale * length[j]
    dot_ai = np.sum((ai - aj) * (bj - aj), axis=1)
    dot_bi = np.sum((bi - aj) * (bj - aj), axis=1)
    inside |= ((np.abs(d3) <= t) & (dot_ai > marginj) & (dot_ai < len2j - marginj)) | (
        (np.abs(d4) <= t) & (dot_bi > marginj) & (dot_bi < len2j - marginj))
    hit = cross | inside
    if np.any(hit):
        cells = np.concatenate((owner[i[hit]], owner[j[hit]]))
        raise ValueError(f"mesh file {path} has overlapping or non-conforming cells "
                         f"{_cells_text(cells)} {_CELL_NUMBERS}: their edges cross or meet "
                         "inside an edge (every neighbour must share whole edges)")


def _check_msh41_groups(path: Path) -> None:
    """Refuse an ASCII MSH 4.1 surface entity in more than one physical group.

    MSH 4.1 ties physical tags to entities, and meshio keeps one tag per entity: a surface in
    both ``electrode1`` and ``gap`` would be read as one of them without a word (MSH 2.2 writes such
    elements twice, which the duplicated-cell check refuses). Binary files and other formats
    are left to the reader.
    """
    if path.suffix.lower() != ".msh":
        return
    try:
        with open(path, encoding="ascii") as fh:
            head = [fh.readline() for _ in range(3)]
            if head[0].strip() != "$MeshFormat" or not head[1].startswith("4.1 0"):
                return  # MSH 2.2, or binary 4.1
            names: dict[str, str] = {}  # surface physical tag -> its name
            for line in fh:
                if line.strip() == "$Entities":
                    break
                words = line.split(maxsplit=2)
                if len(words) == 3 and words[0] == "2" and words[2].startswith('"'):
                    names[words[1]] = words[2].strip().strip('"')
            else:
                return
            counts = [int(c) for c in fh.readline().split()[:4]]
            for dim, n in enumerate(counts):
                for _ in range(n):
                    words = fh.readline().split()
                    at = 4 if dim == 0 else 7  # tag, then a point or a bounding box
                    n_phys = int(words[at])
                    if dim == 2 and n_phys > 1:
                        tags = ", ".join(names.get(t, f"tag {t}")
                                         for t in words[at + 1: at + 1 + n_phys])
                        raise ValueError(
                            f"mesh file {path}: surface entity {words[0]} belongs to "
                            f"{n_phys} physical groups ({tags}); a surface must be in one "
                            f"of electrode1..electrode4 and gap only (MSH 4.1 keeps one tag "
                            f"per entity, so the others would be lost)")
    except (UnicodeDecodeError, ValueError, IndexError) as exc:
        if isinstance(exc, ValueError) and str(exc).startswith("mesh file"):
            raise
        return  # not plain ASCII 4.1 entities: the reader reports what it finds


def read_meshio(path: Path):
    """``meshio.read`` with one error type (ValueError, FileNotFoundError) and no stdout."""
    import meshio

    if path.is_dir():
        raise ValueError(f"mesh file {path} is a folder, not a file")
    if not path.is_file():
        raise FileNotFoundError(f"mesh file not found: {path}")
    if path.stat().st_size == 0:
        raise ValueError(f"could not read mesh file {path}: it is empty")
    said = io.StringIO()
    try:
        # meshio's gmsh reader prints stray blank lines to stdout, and a file no reader takes
        # is reported on stderr before a SystemExit(1): keep both, the reason goes in the error
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(said):
            return meshio.read(path)
    except (Exception, SystemExit) as exc:  # meshio raises many types, even SystemExit
        if str(exc).startswith("Could not deduce file format"):  # meshio goes by the name
            what = ("has no extension" if not path.suffix else
                    f"has the extension {path.suffix!r}, which names no format meshio reads")
            raise ValueError(
                f"mesh file {path} {what}: the extension gives the mesh's format; name it "
                f"{_FORMATS}") from None
        if str(exc).startswith("Incompatible cell data 'gmsh:physical'"):
            # MSH 4.1 ties physical tags to entities; meshio cannot read a file in which only
            # some entities have one (gmsh's Mesh.SaveAll = 1 writes the others too)
            raise ValueError(_no_group_message(path, "some of its elements belong to")) \
                from None
        printed = " ".join(said.getvalue().split()).removeprefix("Error: ")
        reason = printed if isinstance(exc, SystemExit) and printed else str(exc)
        if not isinstance(exc, SystemExit):  # a reader's own failure: numpy's words
            reason = f"malformed or truncated ({reason})"
        raise ValueError(f"could not read mesh file {path}: {reason}") from exc


def _file_points(m, path: Path, unit: str) -> tuple[np.ndarray, np.ndarray]:
    """The file's nodes as read (``(n, 2 or 3)``) and their planform coordinates in metres."""
    pts3 = np.asarray(m.points, dtype=float)
    if pts3.ndim != 2 or pts3.shape[0] == 0:
        raise ValueError(f"mesh file {path} holds no points")
    bad = np.flatnonzero(~np.all(np.isfinite(pts3), axis=1))
    if bad.size:  # said as such, not as a tip "off the mesh (x in [nan, nan] mm)"
        raise ValueError(f"mesh file {path}: node {int(bad[0])} has a non-finite coordinate "
                         f"({', '.join(f'{v:g}' for v in pts3[bad[0]])}); "
                         f"{bad.size} node(s) in all")
    return pts3, pts3[:, :2] * UNITS[unit]


def _physical_names(m) -> dict[tuple[int, int], str]:
    """``(physical tag, dimension) -> name`` of the file's physical groups."""
    names: dict[tuple[int, int], str] = {}
    for name, value in (m.field_data or {}).items():
        v = np.atleast_1d(np.asarray(value)).astype(int)
        names[(int(v[0]), int(v[1]) if v.size > 1 else 2)] = str(name)
    return names


def _check_untagged(m, path: Path, physical) -> None:
    """Refuse elements with physical tag 0, outside every physical group, once for the file.

    MSH 2.2 writes tag 0 for such an element (with Mesh.SaveAll = 1 gmsh writes all elements
    so, even those of named groups); the message says so rather than "physical tag 0
    (dimension 0) has no name".
    """
    counts = {kind: sum(int(np.count_nonzero(np.asarray(physical[i]) == 0))
                        for i, blk in enumerate(m.cells) if blk.type in types)
              for kind, types in (("surface cells", SURFACE_TYPES), ("vertices", ("vertex",)))}
    total = sum(len(blk.data) for blk in m.cells if blk.type in SURFACE_TYPES)
    if counts["surface cells"]:
        n = counts["surface cells"]
        raise ValueError(_no_group_message(
            path, f"all {n} of its surface cells belong to" if n == total else
            f"{n} of its {total} surface cells belong to"))
    if counts["vertices"]:
        raise ValueError(_no_group_message(
            path, f"{counts['vertices']} of its vertex elements belong to"))


def _physical_groups(m, i: int, dim: int, names: dict, path: Path) -> list:
    """``(mask, group)`` of the cells of block ``i`` per physical tag (gmsh files); a tag with
    no name in the file is looked up in meshio's cell sets, else refused."""
    tags = np.asarray(m.cell_data["gmsh:physical"][i], dtype=int)
    sets = getattr(m, "cell_sets", None) or {}
    groups = []
    for tag in np.unique(tags):
        name = names.get((int(tag), dim))
        if name is None and not names:  # MSH without names: try cell_sets
            name = next(
                (n for n, s in sets.items()
                 if not n.startswith("gmsh:") and i < len(s) and s[i] is not None
                 and len(s[i]) and np.all(tags[np.asarray(s[i])] == tag)),
                None,
            )
        if name is None:
            raise ValueError(
                f"mesh file {path}: physical tag {int(tag)} (dimension {dim}) has no "
                f"name; name the physical groups {_ALLOWED}"
            )
        groups.append((tags == tag, _group_of(name, path)))
    return groups


def _electrode_array_groups(raw, path: Path) -> list:
    """``(mask, electrode)`` of a block from the integer cell array ``electrode`` (0..4)."""
    raw = np.asarray(raw)
    if raw.ndim != 1 or not np.issubdtype(raw.dtype, np.number) \
            or not np.all(np.isfinite(raw)) or np.any(raw != np.round(raw)):
        bad = raw.ravel()[:3].tolist() if raw.size else []
        raise ValueError(
            f"mesh file {path}: cell array 'electrode' must hold one integer 0..4 per "
            f"cell, found {raw.dtype} values such as {bad}")
    values = raw.astype(int)
    if np.any((values < 0) | (values > 4)):
        raise ValueError(
            f"mesh file {path}: cell array 'electrode' must hold 0..4, found "
            f"{sorted(set(values.tolist()) - set(range(5)))}"
        )
    return [(values == v, int(v)) for v in np.unique(values)]


def _block_groups(m, i: int, names: dict, path: Path) -> list | None:
    """``(mask, group)`` of block ``i``'s cells (group: electrode number, 0 for the gap, or a
    point name); None for a block the reader skips (lines; vertices of a file without
    physical groups)."""
    ctype = m.cells[i].type
    if ctype not in SURFACE_TYPES and ctype not in IGNORED_TYPES:
        raise ValueError(
            f"mesh file {path}: unsupported cell type {ctype!r}; supported: "
            f"{', '.join(SURFACE_TYPES)} (plus ignored {', '.join(IGNORED_TYPES)})"
        )
    if ctype in ("line", "line3"):
        return None
    if m.cell_data.get("gmsh:physical") is not None:
        return _physical_groups(m, i, 0 if ctype == "vertex" else 2, names, path)
    if ctype == "vertex":
        return None
    plain = m.cell_data.get("electrode")
    if plain is not None:
        return _electrode_array_groups(plain[i], path)
    if path.suffix.lower() == ".msh" or any(k.startswith("gmsh:") for k in m.cell_data):
        # MSH 4.1 without any physical group: meshio gives no tags at all
        raise ValueError(_no_group_message(path, "its elements belong to"))
    raise ValueError(
        f"mesh file {path} has no electrode tags: expected gmsh physical groups "
        f"{_ALLOWED} or an integer cell-data array 'electrode'"
    )


def _add_named_points(data: np.ndarray, groups: list, pts: np.ndarray, path: Path,
                      named_points: dict[str, tuple[float, float]]) -> None:
    """Record the one node (m) of each vertex group (``tip``, ``preload``) of a block."""
    for mask, group in groups:
        if not isinstance(group, str):
            raise ValueError(
                f"mesh file {path}: vertex group {group!r} is not a point; vertex "
                f"groups must be named {' or '.join(POINT_GROUPS)}"
            )
        nodes = np.unique(data[mask].ravel())
        if nodes.size != 1 or group in named_points:
            raise ValueError(
                f"mesh file {path}: point group {group!r} must hold exactly one node"
            )
        x, y = pts[nodes[0]]
        named_points[group] = (float(x), float(y))


class _SurfaceCells:
    """Triangles and quads gathered block by block, with their electrode tags and their
    surface cell numbers (file order, for messages)."""

    def __init__(self) -> None:
        self.polys: dict[int, list[np.ndarray]] = {3: [], 4: []}
        self.tags: dict[int, list[np.ndarray]] = {3: [], 4: []}
        self.ids: dict[int, list[np.ndarray]] = {3: [], 4: []}
        self.count = 0
        self.types: list[str] = []

    def add(self, ctype: str, data: np.ndarray, groups: list, path: Path) -> None:
        self.types.append(ctype)
        k = data.shape[1]
        tag_arr = np.zeros(data.shape[0], dtype=np.int64)
        for mask, group in groups:
            if isinstance(group, str):
                raise ValueError(
                    f"mesh file {path}: surface cells in group {group!r}; {group!r} must be "
                    f"a vertex group"
                )
            tag_arr[mask] = group
        self.polys[k].append(data)
        self.tags[k].append(tag_arr)
        self.ids[k].append(np.arange(self.count, self.count + data.shape[0]))
        self.count += data.shape[0]

    def arrays(self, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Connectivity ``(n, k)``, tags and cell numbers of the ``k``-node cells."""
        if not self.polys[k]:
            return (np.zeros((0, k), dtype=np.int64), np.zeros(0, dtype=np.int64),
                    np.zeros(0, dtype=np.int64))
        return (np.concatenate(self.polys[k]), np.concatenate(self.tags[k]),
                np.concatenate(self.ids[k]))


def _check_planform(pts3: np.ndarray, pts: np.ndarray, used: np.ndarray, n_tri: int,
                    n_quad: int, path: Path, unit: str) -> float:
    """Refuse a mesh that is not planar, not in metres or millimetres as said, too large for a
    library call or not in the stator frame (x centred, preload end at y = 0); checked on the
    nodes ``used`` by surface cells. Returns the area of the planform's bounding box (m^2)."""
    up = pts[used]
    size = float(np.max(np.abs(up)))
    if pts3.shape[1] > 2 and np.max(np.abs(pts3[used, 2])) * UNITS[unit] > 1e-9 * size:
        raise ValueError(f"mesh file {path} is not planar: z != 0 (a 2D mesh in z = 0 is needed)")
    if size > MAX_COORDINATE_M:
        hint = ('this looks like millimetres; set unit = "mm" in the [mesh] table or scale the '
                'mesh to metres') if unit == "m" else "a stator is at most 1 m"
        raise ValueError(
            f"mesh file {path}: coordinates up to {size:g} m (unit {unit!r}), above the "
            f"{MAX_COORDINATE_M:g} m limit; {hint}"
        )
    extent = float(np.max(np.ptp(up, axis=0)))
    if extent < MIN_EXTENT_M:
        hint = ('this looks like metres; set unit = "m" in the [mesh] table'
                if unit == "mm" else "a stator is at least 0.1 mm")
        raise ValueError(
            f"mesh file {path}: the planform spans only {extent:g} m (unit {unit!r}), below "
            f"the {MIN_EXTENT_M:g} m limit; {hint}"
        )
    factor = work_factor()
    n_quads = 3 * n_tri + (4 if n_tri else 1) * n_quad
    if n_quads > MAX_CELLS * factor:
        raise ValueError(
            f"mesh file {path}: {n_quads} quads (after splitting triangles), above the limit "
            f"{int(MAX_CELLS * factor)}; coarsen the mesh or set LUSM_MAX_WORK=N to allow N "
            f"times more"
        )
    x0, x1 = float(up[:, 0].min()), float(up[:, 0].max())
    y0, y1 = float(up[:, 1].min()), float(up[:, 1].max())
    tol = 1e-6 * max(x1 - x0, y1 - y0)
    if abs(x0 + x1) > tol or abs(y0) > tol:
        raise ValueError(
            f"mesh file {path}: the mesh spans x = [{x0 / UNITS[unit]:g}, {x1 / UNITS[unit]:g}] "
            f"{unit}, y = [{y0 / UNITS[unit]:g}, {y1 / UNITS[unit]:g}] {unit}; "
            f"the stator frame needs x centred on 0 (width) and the preload end at y = 0"
        )
    return (x1 - x0) * (y1 - y0)


def _gathered_cells(m, path: Path, pts3: np.ndarray, pts: np.ndarray,
                    named_points: dict[str, tuple[float, float]]) -> _SurfaceCells:
    """The surface cells of every block with their tags; vertex groups go to
    ``named_points``."""
    names = _physical_names(m)
    if m.cell_data.get("gmsh:physical") is not None and (0, 2) not in names \
            and (0, 0) not in names:
        _check_untagged(m, path, m.cell_data["gmsh:physical"])
    cells = _SurfaceCells()
    for i, blk in enumerate(m.cells):
        groups = _block_groups(m, i, names, path)
        if groups is None:
            continue
        ctype, data = blk.type, np.asarray(blk.data, dtype=np.int64)
        if ctype == "vertex":
            _add_named_points(data, groups, pts, path, named_points)
            continue
        if ctype in ("quad8", "quad9", "triangle6"):
            data = _straight_corners(ctype, data, pts3[:, :2], path)
        cells.add(ctype, data, groups, path)
    return cells


def read_stator_mesh(path: str | Path, unit: str = "m") -> ImportedMesh:
    """Read a planform mesh with electrode groups (and tip/preload vertices) through meshio.

    Parameters
    ----------
    path : str or Path
        Mesh file; gmsh ``.msh`` (MSH 4.1 or 2.2) or any meshio format with an integer cell
        array ``electrode``.
    unit : {'m', 'mm'}
        Unit of the file's coordinates.

    Returns
    -------
    ImportedMesh

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    ValueError
        Unreadable file, unsupported cell type, unknown or unnamed physical group, no
        electrode, a mesh that is not planar, looks like millimetres, or is not in the stator
        frame (x centred, preload end at y = 0); cells that are not one valid conforming mesh,
        distinct nodes at one place among them (an unmerged seam) included.
    """
    path = Path(path)
    if unit not in UNITS:
        raise ValueError(f"mesh unit must be one of {', '.join(UNITS)}, got {unit!r}")
    m = read_meshio(path)
    _check_msh41_groups(path)
    pts3, pts = _file_points(m, path, unit)
    named_points: dict[str, tuple[float, float]] = {}
    cells = _gathered_cells(m, path, pts3, pts, named_points)
    tri, t_tri, id_tri = cells.arrays(3)
    quad, t_quad, id_quad = cells.arrays(4)
    if tri.shape[0] + quad.shape[0] == 0:
        found = sorted({blk.type for blk in m.cells})
        raise ValueError(
            f"mesh file {path} holds no surface cells ({', '.join(SURFACE_TYPES)}); found "
            f"{found}"
        )
    if not (np.any(t_tri > 0) or np.any(t_quad > 0)):
        raise ValueError(
            f"mesh file {path} has no electrode: every surface cell is in the gap; put cells "
            f"in the physical groups electrode1..electrode4"
        )
    used = np.unique(np.concatenate((tri.ravel(), quad.ravel())))
    area = _check_planform(pts3, pts, used, tri.shape[0], quad.shape[0], path, unit)
    _check_cells(pts, tri, quad, id_tri, id_quad, path, area)
    return ImportedMesh(
        mesh=_plate_mesh(pts, tri, quad, t_tri, t_quad, path),
        points_m=named_points,
        path=path,
        cell_types=tuple(dict.fromkeys(cells.types)),
        converted=bool(tri.shape[0]),
    )


def _plate_mesh(pts: np.ndarray, tri: np.ndarray, quad: np.ndarray, t_tri: np.ndarray,
                t_quad: np.ndarray, path: Path) -> PlateMesh:
    """The all-quad plate mesh of the cells (triangles split), on the nodes it uses."""
    p2, q2, tags = quadrangulate(pts, tri, quad, t_tri, t_quad)
    used = np.unique(q2)
    remap = -np.ones(p2.shape[0], dtype=np.int64)
    remap[used] = np.arange(used.size)
    mesh = PlateMesh(points_m=p2[used].T, quads=remap[q2].T, electrode=tags)
    problem = mesh.quadrant_problem()
    if problem is not None:
        raise ValueError(f"mesh file {path}: {problem}")
    return mesh


def _classify_a_node_on_each(blocks: list, node_entity: np.ndarray) -> None:
    """Classify at least one node on every surface entity (cell block ``i`` is entity
    ``i + 1``; ``node_entity`` holds ``(dimension, entity)`` per node): an entity with none
    takes one of its nodes from an entity that keeps another. MSH 4.1 ties physical tags to
    entities, and meshio lists an entity only if some node is classified on it."""
    n_surface = len(blocks)
    for i in range(n_surface):
        entity = i + 1
        nodes = np.unique(blocks[i].data)
        surface = node_entity[:, 0] == 2
        if np.any(node_entity[nodes, 1][surface[nodes]] == entity):
            continue
        counts = np.bincount(node_entity[surface, 1], minlength=n_surface + 1)
        owner = np.where(surface[nodes], node_entity[nodes, 1], 0)
        free = nodes[surface[nodes] & (counts[owner] > 1)]
        if free.size == 0:
            raise ValueError(f"cannot classify a node on cell block {i} ({blocks[i].type})")
        node_entity[free[0]] = (2, entity)


def keep_used_nodes(points: np.ndarray, cells: np.ndarray,
                    point_nodes: dict[str, int]) -> tuple[np.ndarray, np.ndarray, dict[str, int]]:
    """Drop the nodes no cell uses (a structured grid cut to a planform): the nodes kept, in
    their order, the cells and the named nodes (``'tip'``, ``'preload'``) on the new numbering,
    as :func:`write_stator_msh` takes them."""
    used = np.unique(cells)
    remap = -np.ones(len(points), dtype=int)
    remap[used] = np.arange(used.size)
    return points[used], remap[cells], {k: int(remap[v]) for k, v in point_nodes.items()}


def keep_used_nodes_at(points: np.ndarray, cells: np.ndarray,
                       point_xy: dict[str, tuple[float, float]]
                       ) -> tuple[np.ndarray, np.ndarray, dict[str, int]]:
    """:func:`keep_used_nodes` with the named nodes given by their coordinates.

    ``point_xy`` maps ``'tip'`` / ``'preload'`` to the coordinates of a grid node, in the
    unit of ``points``; each must be a node to the last bit (a structured grid's line
    crossing), which is found before the unused nodes are dropped.
    """
    nodes = {name: int(np.flatnonzero((points[:, 0] == x) & (points[:, 1] == y))[0])
             for name, (x, y) in point_xy.items()}
    return keep_used_nodes(points, cells, nodes)


def write_stator_msh(
    path: str | Path,
    points: np.ndarray,
    cells: dict[str, np.ndarray],
    electrode: dict[str, np.ndarray],
    point_nodes: dict[str, int] | None = None,
    file_format: str = "gmsh",
) -> Path:
    """Write a planform mesh as gmsh MSH with the physical groups :func:`read_stator_mesh` reads.

    Parameters
    ----------
    path : str or Path
        Output ``.msh`` file.
    points : numpy.ndarray
        Node coordinates, shape (n, 2), in metres or in the unit the stator file declares.
    cells : dict of str to numpy.ndarray
        meshio cell type (``'quad'``, ``'triangle'``) to connectivity (n_cells, k).
    electrode : dict of str to numpy.ndarray
        The same keys: electrode tag (0 = gap, 1..4) of every cell.
    point_nodes : dict of str to int, optional
        ``'tip'`` / ``'preload'`` to the index of their node.
    file_format : {'gmsh', 'gmsh22'}
        MSH 4.1 ASCII (default) or MSH 2.2 ASCII.

    Returns
    -------
    Path
    """
    import meshio

    path = Path(path)
    pts = np.column_stack((np.asarray(points, dtype=float), np.zeros(len(points))))
    blocks, phys, geom = [], [], []
    field_data: dict[str, np.ndarray] = {}
    node_entity = np.zeros((pts.shape[0], 2), dtype=np.int64)
    # one gmsh entity (its own geometrical tag) per cell block; MSH 4.1 ties physical tags to
    # entities and meshio lists an entity only if some node is classified on it
    for ctype, conn in cells.items():
        tags = np.asarray(electrode[ctype], dtype=int)
        for k in np.unique(tags):
            tag = int(k) if k > 0 else GAP_PHYSICAL_TAG
            name = electrode_name(int(k)) if k > 0 else GAP_NAME
            sel = np.asarray(conn)[tags == k]
            entity = len(blocks) + 1
            blocks.append(meshio.CellBlock(ctype, sel.astype(np.int64)))
            phys.append(np.full(sel.shape[0], tag, dtype=np.int32))
            geom.append(np.full(sel.shape[0], entity, dtype=np.int32))
            field_data[name] = np.array([tag, 2])
            node_entity[sel.ravel()] = (2, entity)
    point_tags = {"tip": TIP_PHYSICAL_TAG, "preload": PRELOAD_PHYSICAL_TAG}
    for name, node in (point_nodes or {}).items():
        node_entity[int(node)] = (0, point_tags[name])
    _classify_a_node_on_each(blocks, node_entity)
    for name, node in (point_nodes or {}).items():
        tag = point_tags[name]
        blocks.append(meshio.CellBlock("vertex", np.array([[int(node)]], dtype=np.int64)))
        phys.append(np.array([tag], dtype=np.int32))
        geom.append(np.array([tag], dtype=np.int32))
        field_data[name] = np.array([tag, 0])
    mesh = meshio.Mesh(
        pts,
        blocks,
        point_data={"gmsh:dim_tags": node_entity},
        cell_data={"gmsh:physical": phys, "gmsh:geometrical": geom},
        field_data=field_data,
    )
    meshio.write(path, mesh, file_format=file_format, binary=False)
    return path


def write_mesh(mesh: PlateMesh, path: str | Path, file_format: str | None = None) -> Path:
    """Write a plate mesh with meshio; gmsh files get the electrode physical groups.

    Parameters
    ----------
    mesh : PlateMesh
    path : str or Path
        Output file; the format follows the suffix unless ``file_format`` is given.
    file_format : str, optional
        A meshio format name (``'gmsh'`` for MSH 4.1 ASCII, ``'gmsh22'``, ``'vtu'``, ...).
        gmsh files carry the groups of :func:`write_stator_msh`; other formats an integer
        cell-data array ``electrode`` (0 = gap). :func:`read_stator_mesh` reads both.

    Returns
    -------
    Path
        The path written.
    """
    import meshio

    path = Path(path)
    is_gmsh = (file_format or "").startswith("gmsh") or (
        file_format is None and path.suffix == ".msh"
    )
    if is_gmsh:
        return write_stator_msh(path, mesh.points_m.T, {"quad": mesh.quads.T},
                                {"quad": mesh.electrode}, file_format=file_format or "gmsh")
    pts = np.vstack((mesh.points_m, np.zeros(mesh.points_m.shape[1]))).T
    cells = [("quad", mesh.quads.T.astype(np.int64))]
    m = meshio.Mesh(pts, cells, cell_data={"electrode": [mesh.electrode.astype(np.int32)]})
    meshio.write(path, m, file_format=file_format)
    return path
