"""Parametric stators: the quadrant-electrode plate with a contact tip, chamfers and holes.

:class:`ParametricStator` is a :class:`fem.geometry.PlateStator` with common features
described by numbers (a stator file's ``[tip]``, ``[chamfers]`` and ``[[holes]]`` tables,
:mod:`fem.stator_file`); :func:`parametric_mesh` meshes its planform through gmsh's Python
API (a core dependency, imported only when a mesh is needed).

Geometry (m; the frame of :mod:`fem.geometry`: ``x`` across the width, centred, ``y`` along
the length from the preload end)::

               chamfer c                          tip: t_w wide, t_l long
      y=0    /-----------+-----------\\  y=l
            |     1     |     2     |--+
            +-----------+-----------+  |  <- unelectroded protrusion, centred on x = 0
            |   3  (o)  |     4     |--+       (o) a through hole
             \\-----------+-----------/
     preload                              tip point (0, l + t_l)

* the plate body keeps its own ``length_m`` (l) and ``width_m`` (W): the tip adds
  ``tip_length_m`` beyond ``y = l`` (headers print "plate 30 x 7.5 x 3 mm + tip 1 mm");
* the four quadrant electrodes and the gap strips (width ``electrode_gap_m``) are those of
  :class:`PlateStator`, on the plate body only; the tip is unelectroded material (tag 0
  outside the gap strips, so :func:`fem.model.gap_layout` reads the strips as before);
* chamfers cut the four corners at 45 degrees with legs ``chamfer_m``;
* holes go through the thickness (no electrode, no material) anywhere inside the body.

Meshing (gmsh, OpenCASCADE kernel): the outline, the tip and the two gap strips are
fragmented so that every electrode edge is a mesh line; holes are cut out; the surfaces are
meshed with triangles (Frontal-Delaunay for quads) at twice the target size, recombined into
quads (Blossom) and split once (``Mesh.SubdivisionAlgorithm = 1``), which gives an all-quad
mesh with edges of about ``mesh_size_m``. Blossom can leave an inverted element next to a
finely divided hole rim; the mesh is then checked (every element's signed area against its
surface's orientation) and, if one is inverted, remeshed with triangles (Frontal-Delaunay),
each split into three quads (:func:`fem.meshing.mesh_io.quadrangulate`, as for triangle mesh files).
Hole rims get at least :data:`HOLE_SEGMENTS` edges. Every element lies under one electrode
or in unelectroded material; its tag is read at its centroid. The mesh is cached per stator
(the dataclass is hashable), so repeated commands and tuning steps do not remesh the same
geometry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from fem.errors import FeatureError
from fem.geometry import PlateStator
from fem.limits import work_factor
from fem.meshing.mesh import PlateMesh
from fem.meshing.mesh_io import quadrangulate

GMSH_SYSTEM_LIBRARIES = "libglu1-mesa libxrender1 libxcursor1 libxft2 libxinerama1"
"""The Debian/Ubuntu packages of the OpenGL/X11 libraries that gmsh's wheel links."""

DEFAULT_SIZE_DIVISIONS = 8
"""Default target element size: ``min(l, W) / 8`` (0.9375 mm on the paper's 7.5 mm width)."""

SIZE_DIVISIONS_RANGE = (1, 100)
"""Allowed element size: between ``min(l, W) / 100`` and ``min(l, W)``."""

HOLE_SEGMENTS = 24
"""Least number of mesh edges around a hole."""


def _finite(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(
        value)


@dataclass(frozen=True)
class ParametricStator(PlateStator):
    """A quadrant-electrode plate with a contact tip, corner chamfers and through holes.

    Attributes
    ----------
    tip_length_m : float
        Length of the protrusion beyond the end ``y = length_m`` (m); 0: no tip.
    tip_width_m : float
        Its width across x, centred on ``x = 0`` (m); > 0 when ``tip_length_m > 0``.
    chamfer_m : float
        Leg of the 45-degree chamfer at each of the four corners (m); 0: square corners.
    holes_m : tuple of (float, float, float)
        Through holes ``(x, y, diameter)`` (m), each inside the plate body.
    mesh_size_m : float or None
        Target element edge (m); None: ``min(length_m, width_m) / 8``.
    tip_material : str
        The tip's own material, a name of :data:`fem.material.TIP_MATERIALS` (isotropic,
        not piezoelectric: ``"alumina"``, ``"steel"``); ``""``: the plate's ceramic,
        unelectroded.
    """

    tip_length_m: float = 0.0
    tip_width_m: float = 0.0
    chamfer_m: float = 0.0
    holes_m: tuple[tuple[float, float, float], ...] = ()
    mesh_size_m: float | None = None
    tip_material: str = ""

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.tip_material:
            from fem.material import tip_material

            object.__setattr__(self, "tip_material", tip_material(self.tip_material).name)
            if not self.tip_length_m > 0.0:
                raise FeatureError("ParametricStator.tip_material needs a tip (tip_length_m > 0)")
        length, width, gap = self.length_m, self.width_m, self.electrode_gap_m
        for name in ("tip_length_m", "tip_width_m", "chamfer_m"):
            v = getattr(self, name)
            if not _finite(v) or v < 0.0:
                raise FeatureError(f"ParametricStator.{name} must be a finite number >= 0, "
                                   f"got {v!r}")
        c = self.chamfer_m
        c_max = 0.5 * (min(width, length) - gap)
        if c >= c_max:
            raise FeatureError(f"ParametricStator.chamfer_m must lie in [0, {c_max!r}) m "
                               f"((min(width, length) - gap) / 2), got {c!r})",
                               f"[chamfers] size_mm {c * 1e3:g} mm must be below "
                               f"{c_max * 1e3:.4g} mm, half the plate's smaller side less the "
                               f"gap, on a "
                               f"{length * 1e3:.4g} x {width * 1e3:.4g} mm plate")
        if self.tip_length_m > 0.0:
            flat = width - 2.0 * c
            # a plate without chamfers has no "end face between the chamfers"
            face = "end face between the chamfers" if c > 0.0 else "plate's end face (its width)"
            if not 0.0 < self.tip_width_m <= flat * (1 + 1e-12):
                raise FeatureError(f"ParametricStator.tip_width_m must lie in (0, {flat!r}] m "
                                   f"(the {face}), got "
                                   f"{self.tip_width_m!r})",
                                   f"[tip] width_mm "
                                   f"{self.tip_width_m * 1e3:g} mm must be at most the "
                                   f"{flat * 1e3:.4g} mm {face}, on a "
                                   f"{length * 1e3:.4g} x {width * 1e3:.4g} mm plate")
            if self.tip_length_m > length:
                raise FeatureError(f"ParametricStator.tip_length_m must lie in [0, {length!r}] "
                                   f"m (the plate length), got {self.tip_length_m!r})",
                                   f"[tip] length_mm {self.tip_length_m * 1e3:g} mm must be "
                                   f"at most the plate's length, on a {length * 1e3:.6g} x "
                                   f"{width * 1e3:.4g} mm plate")
        elif self.tip_width_m != 0.0:
            raise FeatureError("ParametricStator.tip_width_m needs tip_length_m > 0")
        holes = tuple(tuple(float(v) for v in hole) for hole in self.holes_m)
        for i, hole in enumerate(holes):
            if len(hole) != 3 or not all(math.isfinite(v) for v in hole) or hole[2] <= 0.0:
                raise FeatureError(f"ParametricStator.holes_m[{i}] must be (x, y, diameter) "
                                   f"with a diameter > 0 (m), got {self.holes_m[i]!r}")
            clear = hole_clearance_m(hole, width, length, c)
            if clear <= 0.0:  # said in mm too: a sweep or a tuning meets it on its own plates
                raise FeatureError(
                    f"ParametricStator.holes_m[{i}] = {hole!r} m reaches the plate's outline "
                    f"(it must lie inside the plate body)",
                    f"hole {i + 1}, {hole[2] * 1e3:g} mm "
                    f"across at [{hole[0] * 1e3:g}, {hole[1] * 1e3:g}] mm, reaches the "
                    f"outline of a {length * 1e3:.4g} x {width * 1e3:.4g} mm plate")
            for j, other in enumerate(holes[:i]):
                if math.hypot(hole[0] - other[0], hole[1] - other[1]) <= 0.5 * (
                        hole[2] + other[2]):
                    raise FeatureError(f"ParametricStator.holes_m[{i}] overlaps holes_m[{j}]")
        object.__setattr__(self, "holes_m", holes)
        if self.mesh_size_m is not None:
            lo, hi = (min(width, length) / d for d in SIZE_DIVISIONS_RANGE[::-1])
            if not _finite(self.mesh_size_m) or not lo <= self.mesh_size_m <= hi:
                raise FeatureError(f"ParametricStator.mesh_size_m must lie in [{lo:g}, {hi:g}] "
                                   f"m (min(length, width) / 100 .. / 1), got "
                                   f"{self.mesh_size_m!r})",
                                   f"[mesh] size_mm "
                                   f"{self.mesh_size_m * 1e3:g} mm must lie in "
                                   f"[{lo * 1e3:.4g}, {hi * 1e3:.4g}] mm, 1/100 to 1 of the "
                                   f"plate's smaller side, on a {length * 1e3:.6g} x "
                                   f"{width * 1e3:.4g} mm plate")

    @property
    def element_size_m(self) -> float:
        """Target element edge of the planform mesh (m)."""
        if self.mesh_size_m is not None:
            return float(self.mesh_size_m)
        return min(self.width_m, self.length_m) / DEFAULT_SIZE_DIVISIONS

    @property
    def overall_length_m(self) -> float:
        """Plate length plus tip length (m): the planform's extent along y."""
        return self.length_m + self.tip_length_m

    @property
    def tip_point_m(self) -> tuple[float, float]:
        """Contact tip ``(x, y)``: the centre of the tip's end (m)."""
        return (0.0, float(self.overall_length_m))

    @property
    def area_m2(self) -> float:
        """Exact planform area (m^2): plate minus chamfers and holes, plus the tip."""
        holes = sum(math.pi * d * d / 4.0 for _, _, d in self.holes_m)
        return (self.length_m * self.width_m - 2.0 * self.chamfer_m ** 2
                + self.tip_length_m * self.tip_width_m - holes)

    def electrode_of(self, x_m: np.ndarray, y_m: np.ndarray) -> np.ndarray:
        """Electrode number (1..4) above points ``(x, y)``; 0 in gaps, tip, holes, outside."""
        x = np.asarray(x_m, dtype=float)
        y = np.asarray(y_m, dtype=float)
        out = super().electrode_of(x, y)
        c, w2, length = self.chamfer_m, 0.5 * self.width_m, self.length_m
        inside = (np.abs(x) <= w2) & (y >= 0.0) & (y <= length)
        if c > 0.0:
            inside &= (np.abs(x) - (w2 - c)) + (c - np.minimum(y, length - y)) <= c
        for hx, hy, d in self.holes_m:
            inside &= np.hypot(x - hx, y - hy) >= 0.5 * d
        return np.where(inside, out, 0)

    def features_mm(self) -> dict[str, object]:
        """The features in millimetres (JSON keys ``tip_length_mm``, ``tip_width_mm``,
        ``chamfer_mm``, ``holes_mm`` = ``[[x, y, diameter], ...]``, ``mesh_size_mm``)."""
        mm = 1e3
        return {"tip_length_mm": self.tip_length_m * mm, "tip_width_mm": self.tip_width_m * mm,
                "chamfer_mm": self.chamfer_m * mm,
                "holes_mm": [[v * mm for v in hole] for hole in self.holes_m],
                "mesh_size_mm": self.element_size_m * mm,
                **({"tip_material": self.tip_material} if self.tip_material else {})}

    def features_text(self) -> str:
        """The features in millimetres for headers, e.g. ``' + tip 1 mm (2 mm wide)'``."""
        mm = 1e3
        parts = []
        if self.tip_length_m > 0.0:
            parts.append(f" + tip {self.tip_length_m * mm:g} mm "
                         f"({self.tip_width_m * mm:g} mm wide"
                         + (f", {self.tip_material}" if self.tip_material else "") + ")")
        if self.chamfer_m > 0.0:
            parts.append(f", chamfers {self.chamfer_m * mm:g} mm")
        if self.holes_m:
            n = len(self.holes_m)
            parts.append(f", {n} hole{'s' if n > 1 else ''}")
        return "".join(parts)


def hole_clearance_m(hole: tuple[float, float, float], width_m: float, length_m: float,
                     chamfer_m: float) -> float:
    """Distance (m) from a hole's rim to the nearest edge of the plate body (< 0: it cuts
    the outline)."""
    x, y, d = hole
    w2 = 0.5 * width_m
    dist = min(w2 - abs(x), y, length_m - y)
    if chamfer_m > 0.0:  # the chamfer line |x| + (c - dist_end) = w2 of the nearest corner
        dist = min(dist, (w2 - chamfer_m + min(y, length_m - y) - abs(x)) / math.sqrt(2.0))
    return dist - 0.5 * d


def _import_gmsh():
    try:
        import gmsh
    except ImportError:  # a broken install: gmsh is a core dependency
        raise ImportError("meshing a stator with [tip], [chamfers] or [[holes]] needs gmsh's "
                          "Python API, which lusm depends on: reinstall lusm (pip install "
                          "-e .) or pip install gmsh") from None
    except OSError as exc:  # the wheel's libgmsh links OpenGL/X11 libraries
        raise ImportError(f"gmsh is installed but its library does not load ({exc}); install "
                          "the OpenGL/X11 libraries it links (Debian/Ubuntu: apt-get install "
                          f"{GMSH_SYSTEM_LIBRARIES})") from None
    return gmsh


def gmsh_problem() -> str | None:
    """Why gmsh's Python API does not import here (not installed, or its library does not
    load), or None: a dask worker is asked before a study of a parametric stator."""
    try:
        _import_gmsh()
    except ImportError as exc:
        return str(exc)
    return None


def parametric_mesh(stator: ParametricStator, cached: bool = True) -> PlateMesh:
    """The all-quad planform mesh of ``stator`` (m) with electrode tags.

    ``cached=False`` meshes anew (for timing); the default returns the cached mesh.

    Raises
    ------
    ImportError
        If gmsh does not import (not installed, or its system libraries missing).
    ValueError
        If the mesh leaves an electrode without elements (e.g. holes covering it).
    """
    if not isinstance(stator, ParametricStator):
        raise TypeError("parametric_mesh needs a ParametricStator")
    # the cache key is the planform alone: thickness and drive do not change the mesh
    key = replace(stator, thickness_m=1.0, drive_electrodes=(1, 4))
    return _cached_mesh(key) if cached else _cached_mesh.__wrapped__(key)


@lru_cache(maxsize=32)
def _cached_mesh(stator: ParametricStator) -> PlateMesh:
    from fem.meshing.mesh_io import MAX_CELLS

    estimate, top = estimated_elements(stator), int(MAX_CELLS * work_factor())
    if estimate > top:  # refused from the 1D mesh, before the 2D mesh's minutes
        raise ValueError(_too_many_elements(stator, f"about {estimate:.3g}", top))
    gmsh = _import_gmsh()
    half = is_mirror_symmetric(stator)
    xy, tri, quad = _gmsh_mesh(gmsh, stator, recombine=True, half=half)
    if xy is None:  # Blossom left an inverted element: mesh with triangles instead
        xy, tri, quad = _gmsh_mesh(gmsh, stator, recombine=False, half=half)
    if xy is None:
        raise ValueError("gmsh produced inverted elements for this geometry; change "
                         "[mesh] size_mm slightly or use a mesh file")
    if half:
        xy, tri, quad = _mirror(xy, tri, quad, 1e-9 * max(stator.width_m, stator.length_m))
    made = 3 * tri.shape[0] + quad.shape[0]  # quads once its triangles are split
    if made > top:  # the estimate runs low on clusters of holes
        raise ValueError(_too_many_elements(stator, str(made), top))
    cells = [c for c in (tri, quad) if c.shape[0]]
    used = np.unique(np.concatenate([c.ravel() for c in cells]))
    remap = -np.ones(xy.shape[0], dtype=np.int64)
    remap[used] = np.arange(used.size)
    xy, tri, quad = xy[used], remap[tri], remap[quad]

    def tags_of(cells: np.ndarray) -> np.ndarray:
        # mesh lines follow every electrode edge, so the centroid decides; the tip is bare
        centre = xy[cells].mean(axis=1)
        tags = PlateStator.electrode_of(stator, centre[:, 0], centre[:, 1])
        tags[centre[:, 1] > stator.length_m] = 0
        return tags

    p2, q2, tags = quadrangulate(xy, tri, quad, tags_of(tri), tags_of(quad))
    missing = [k for k in (1, 2, 3, 4) if not np.any(tags == k)]
    if missing:
        raise ValueError(f"the parametric mesh has no element under electrode(s) {missing} "
                         f"(holes covering them?)")
    return PlateMesh(points_m=p2.T, quads=q2.T, electrode=tags)


ELEMENTS_PER_SIZE_AREA = 4.0
"""Final quads per ``s^2`` of planform area, where ``s`` is the size gmsh interpolates from
the boundary mesh (:func:`estimated_elements`): its triangles of edge ``s`` paired into quads,
each split into four. Measured, the mesh over the estimate (``tests/test_parametric.py``):
1.01-1.04 on fine meshes (element size 0.1 mm on the paper's plate, plain, with a tip, a
hole or a 1 mm chamfer; 0.05 mm on a 90 x 5 mm plate), 1.05-1.1 at 0.2-0.3 mm and with long
narrow tips, 1.47 at the default size, 2.3 with holes of 0.3 and 2 mm, and 6.1-6.5 for
blocks of 16 and 32 holes of 0.1 mm 0.48 mm apart, whose sizes gmsh grades more slowly than
linearly. The estimate is never high: it refuses only meshes above the bound, and the mesh
is counted again once made."""


ESTIMATE_LOW_FACTOR = 6.5
"""The most the planform mesh has been measured above :func:`estimated_elements` (blocks of
holes, :data:`ELEMENTS_PER_SIZE_AREA`): a count within this factor below a bound may still
cross it once meshed."""


def estimated_elements(stator: ParametricStator) -> int:
    """The planform mesh's elements, estimated before gmsh meshes it in 2D.

    gmsh's 2D mesh takes its element size from the boundary: each boundary node carries the length
    of its edges (a hole's rim has at least :data:`HOLE_SEGMENTS` of them, however small the hole),
    interpolated linearly over the Delaunay triangulation of the boundary nodes. The estimate
    integrates ``1 / s^2`` over that triangulation exactly (the Hermite-Genocchi formula: over a
    triangle of area ``A`` with linear ``s``, ``2 A`` times the second divided difference of
    ``-ln s`` at its vertices) and scales it by :data:`ELEMENTS_PER_SIZE_AREA`. The 1D mesh takes
    milliseconds, where 64 holes of 0.01 mm in a cluster take more than ten minutes and 1.1 GB to
    mesh in 2D. Never high: within 4 % on fine meshes, 1.5 times low at the default size, up to 6.5
    times low on a dense cluster of holes (:data:`ELEMENTS_PER_SIZE_AREA`); triangles of the
    triangulation off the planform (beside a tip, beyond a chamfer) and inside holes are left out.
    """
    from scipy.spatial import Delaunay

    gmsh = _import_gmsh()
    key = replace(stator, thickness_m=1.0, drive_electrodes=(1, 4))
    xy, edges = _gmsh_mesh(gmsh, key, recombine=True, boundary_only=True)
    if edges.shape[0] == 0:
        return 0
    length = np.linalg.norm(xy[edges[:, 0]] - xy[edges[:, 1]], axis=1)
    total, count = np.zeros(xy.shape[0]), np.zeros(xy.shape[0])
    for k in (0, 1):
        np.add.at(total, edges[:, k], length)
        np.add.at(count, edges[:, k], 1.0)
    used = count > 0
    pts, size = xy[used], total[used] / count[used]
    tri = Delaunay(pts).simplices
    p = pts[tri]
    area = 0.5 * np.abs((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                        - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    centre = p.mean(axis=1)
    inside = _in_planform(stator, centre[:, 0], centre[:, 1])
    for x, y, d in stator.holes_m:  # the holes are not meshed
        inside &= np.hypot(centre[:, 0] - x, centre[:, 1] - y) > 0.5 * d
    s = np.sort(size[tri], axis=1)
    # distinct values for the divided differences (equal ones: their limits, to 1e-6)
    s = s * (1.0 + 1e-6 * np.arange(3))
    a, b, c = s[:, 0], s[:, 1], s[:, 2]
    g = [-np.log(v) for v in (a, b, c)]
    gab, gbc = (g[0] - g[1]) / (a - b), (g[1] - g[2]) / (b - c)
    per_triangle = 2.0 * area * (gab - gbc) / (a - c)
    return int(ELEMENTS_PER_SIZE_AREA * float(np.sum(per_triangle[inside])))


def _too_many_elements(stator: ParametricStator, count: str, top: int) -> str:
    """The refusal of a planform mesh above the bound, with the remedy that helps: holes
    (each rim has at least :data:`HOLE_SEGMENTS` edges however small the hole, and gmsh
    grades the elements from there), else the element size."""
    size = f"element size {stator.element_size_m * 1e3:g} mm"
    if stator.holes_m:
        why = (f"{len(stator.holes_m)} hole(s), {size}: a hole's rim has at least "
               f"{HOLE_SEGMENTS} edges however small the hole, and the elements grade from "
               "there")
        fix = "use fewer or larger [[holes]], or a coarser [mesh] size_mm"
    else:
        why, fix = size, "use a coarser [mesh] size_mm"
    return (f"its planform needs {count} elements, above the limit {top} of any stator mesh "
            f"({why}); {fix} (set LUSM_MAX_WORK=N to allow N times more)")


def _in_planform(stator: ParametricStator, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Whether points (m) lie on the planform (holes aside): the plate body without its
    chamfered corners, or the tip. The boundary's Delaunay triangulation covers its convex
    hull, beside a long tip too."""
    w2, length, c = 0.5 * stator.width_m, stator.length_m, stator.chamfer_m
    body = (np.abs(x) <= w2) & (y >= 0.0) & (y <= length)
    body &= (w2 - np.abs(x)) + np.minimum(y, length - y) >= c
    tip = ((np.abs(x) <= 0.5 * stator.tip_width_m) & (y >= length)
           & (y <= length + stator.tip_length_m))
    return body | tip


def is_mirror_symmetric(stator: ParametricStator) -> bool:
    """True if the planform is its own mirror image about ``x = 0`` (the holes are)."""
    tol = 1e-9 * max(stator.width_m, stator.length_m)
    holes = sorted(stator.holes_m)
    mirrored = sorted((-x if abs(x) > tol else x, y, d) for x, y, d in stator.holes_m)
    return all(np.allclose(a, b, rtol=0.0, atol=tol) for a, b in zip(holes, mirrored,
                                                                     strict=True))


def _mirror(xy: np.ndarray, tri: np.ndarray, quad: np.ndarray, tol: float):
    """The half mesh ``x >= 0`` and its mirror image, sharing the nodes on ``x = 0``."""
    on_axis = np.abs(xy[:, 0]) <= tol
    xy = xy.copy()
    xy[on_axis, 0] = 0.0
    off = np.flatnonzero(~on_axis)
    image = np.arange(xy.shape[0])
    image[off] = xy.shape[0] + np.arange(off.size)
    xy2 = np.vstack((xy, xy[off] * np.array([-1.0, 1.0])))
    # a mirror image turns clockwise: reverse the node order
    return (xy2, np.vstack((tri, image[tri][:, ::-1])),
            np.vstack((quad, image[quad][:, ::-1])))


def _signed_area(xy: np.ndarray, cells: np.ndarray) -> np.ndarray:
    p = xy[cells]
    return 0.5 * np.sum(p[..., 0] * np.roll(p[..., 1], -1, axis=1)
                        - np.roll(p[..., 0], -1, axis=1) * p[..., 1], axis=1)


def _initialize_keeping_signals(gmsh) -> None:
    """``gmsh.initialize`` with the process's signal handlers as they were.

    gmsh resets SIGTERM (and SIGPIPE's ignore) to the default in C even with
    ``interruptible=False``, while Python's ``signal.getsignal`` still reports the old
    handler: a SIGTERM then killed ``lusm render`` or ``lusm report`` of a parametric stator
    outright, without a message and with its staging folder left behind. The handlers are
    installed again (in the main thread, the only one that may).
    """
    import signal
    import threading

    names = ("SIGINT", "SIGTERM", "SIGPIPE")
    main = threading.current_thread() is threading.main_thread()
    saved = {getattr(signal, n): signal.getsignal(getattr(signal, n)) for n in names
             if hasattr(signal, n)} if main else {}
    gmsh.initialize(interruptible=False)
    for sig, handler in saved.items():
        if handler is not None:
            signal.signal(sig, handler)


_GMSH_MM = 1e3
"""gmsh works in millimetres (its tolerances are absolute): metres times this."""


def _gmsh_mesh(gmsh, stator: ParametricStator, recombine: bool, half: bool = False,
               boundary_only: bool = False):
    """Nodes (n, 2) (m), counter-clockwise triangles (k, 3) and quads (m, 4) of the planform
    (with ``half``: of its part ``x >= 0``); ``(None, None, None)`` if an element came out
    inverted. With ``boundary_only``: the boundary's 1D mesh alone, ``(nodes (n, 2) (m),
    edges (k, 2))``, in milliseconds where the 2D mesh can take minutes."""
    ours = not gmsh.isInitialized()  # leave a caller's own gmsh session running
    if ours:
        _initialize_keeping_signals(gmsh)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("lusm_stator")
        _planform_geometry(gmsh, stator, half)
        _mesh_settings(gmsh, stator, recombine)
        if boundary_only:
            gmsh.model.mesh.generate(1)
            index, xy = _gmsh_nodes(gmsh)
            edges = [index[np.asarray(n, dtype=np.int64).reshape(-1, 2)]
                     for t, n in zip(*gmsh.model.mesh.getElements(1)[::2], strict=True)
                     if int(t) == 1]
            return xy, np.concatenate(edges) if edges else np.zeros((0, 2), dtype=np.int64)
        gmsh.model.mesh.generate(2)
        index, xy = _gmsh_nodes(gmsh)
        cells = _oriented_cells(gmsh, index, xy)
        if cells is None:
            return None, None, None
    finally:
        if ours:
            gmsh.finalize()
        else:
            gmsh.model.remove()
    tri = np.concatenate(cells[3]) if cells[3] else np.zeros((0, 3), dtype=np.int64)
    quad = np.concatenate(cells[4]) if cells[4] else np.zeros((0, 4), dtype=np.int64)
    return xy, tri, quad


def _planform_geometry(gmsh, stator: ParametricStator, half: bool) -> None:
    """The planform in gmsh's OpenCASCADE kernel: the plate (chamfered), its tip, cut by
    the electrode gaps (lines where the gap is zero) and the holes; with ``half`` its part
    ``x >= 0`` alone."""
    mm = _GMSH_MM
    length, width = stator.length_m * mm, stator.width_m * mm
    gap, c = stator.electrode_gap_m * mm, stator.chamfer_m * mm
    tl, tw = stator.tip_length_m * mm, stator.tip_width_m * mm
    w2 = 0.5 * width
    occ = gmsh.model.occ
    if c > 0.0:
        corners = [(-w2 + c, 0.0), (w2 - c, 0.0), (w2, c), (w2, length - c),
                   (w2 - c, length), (-w2 + c, length), (-w2, length - c), (-w2, c)]
    else:
        corners = [(-w2, 0.0), (w2, 0.0), (w2, length), (-w2, length)]
    pts = [occ.addPoint(x, y, 0.0) for x, y in corners]
    lines = [occ.addLine(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
    parts = [(2, occ.addPlaneSurface([occ.addCurveLoop(lines)]))]
    if tl > 0.0:
        parts.append((2, occ.addRectangle(-0.5 * tw, length, 0.0, tw, tl)))
    if gap > 0.0:
        tools = [(2, occ.addRectangle(-0.5 * gap, 0.0, 0.0, gap, length)),
                 (2, occ.addRectangle(-w2, 0.5 * (length - gap), 0.0, width, gap))]
    else:  # zero gap: the quadrant boundaries are still mesh lines
        tools = [(1, occ.addLine(occ.addPoint(0.0, 0.0, 0.0),
                                 occ.addPoint(0.0, length, 0.0))),
                 (1, occ.addLine(occ.addPoint(-w2, 0.5 * length, 0.0),
                                 occ.addPoint(w2, 0.5 * length, 0.0)))]
    pieces, _ = occ.fragment(parts, tools)
    pieces = [p for p in pieces if p[0] == 2]
    if stator.holes_m:
        disks = [(2, occ.addDisk(x * mm, y * mm, 0.0, 0.5 * d * mm, 0.5 * d * mm))
                 for x, y, d in stator.holes_m]
        pieces, _ = occ.cut(pieces, disks)
    if half:
        box = occ.addRectangle(0.0, -1.0, 0.0, w2 + 1.0, length + tl + 2.0)
        pieces, _ = occ.intersect(pieces, [(2, box)])
    occ.synchronize()


def _mesh_settings(gmsh, stator: ParametricStator, recombine: bool) -> None:
    """Element size and algorithm (quads by recombination and one subdivision where
    ``recombine``), and a fixed number of edges on each hole's rim."""
    mm = _GMSH_MM
    length, width = stator.length_m * mm, stator.width_m * mm
    h = stator.element_size_m * mm
    # hole rims: a fixed number of edges (the split below halves them once more)
    per_turn = HOLE_SEGMENTS // 2 if recombine else HOLE_SEGMENTS
    for x, y, d in stator.holes_m:
        r, e = 0.5 * d * mm, 1e-6 * max(length, width)
        for _, curve in gmsh.model.getEntitiesInBoundingBox(
                x * mm - r - e, y * mm - r - e, -e, x * mm + r + e, y * mm + r + e, e, 1):
            lo, hi = gmsh.model.getParametrizationBounds(1, curve)
            turn = abs(hi[0] - lo[0]) / (2.0 * math.pi)
            n = max(1, math.ceil(turn * per_turn - 1e-9),
                    math.ceil(turn * 2.0 * math.pi * r / (2.0 * h) - 1e-9))
            gmsh.model.mesh.setTransfiniteCurve(curve, n + 1)
    opt = gmsh.option.setNumber
    opt("Mesh.MeshSizeMax", 2.0 * h)  # split once below: edges of about h
    opt("Mesh.MeshSizeMin", 0.0)
    opt("Mesh.Algorithm", 8 if recombine else 6)  # Frontal-Delaunay (for quads)
    if recombine:
        opt("Mesh.RecombineAll", 1)
        opt("Mesh.RecombinationAlgorithm", 1)  # Blossom
        opt("Mesh.SubdivisionAlgorithm", 1)  # every element into quads


def _gmsh_nodes(gmsh) -> tuple[np.ndarray, np.ndarray]:
    """``(index, xy)``: row of each gmsh node tag, and the nodes' coordinates (n, 2) (m)."""
    node_tags, coords, _ = gmsh.model.mesh.getNodes()
    index = np.zeros(int(node_tags.max()) + 1, dtype=np.int64)
    index[np.asarray(node_tags, dtype=np.int64)] = np.arange(node_tags.size)
    return index, np.asarray(coords, dtype=float).reshape(-1, 3)[:, :2] / _GMSH_MM


def _oriented_cells(gmsh, index: np.ndarray, xy: np.ndarray) -> dict | None:
    """Triangles (3) and quads (4) of every surface, counter-clockwise; None if an element
    came out inverted. One orientation per surface (its normal): a -z surface is flipped as
    a whole; an element of the other sign is inverted."""
    cells: dict[int, list[np.ndarray]] = {3: [], 4: []}
    for _, surface in gmsh.model.getEntities(2):
        types, _, enodes = gmsh.model.mesh.getElements(2, surface)
        blocks = []
        for t, nodes in zip(types, enodes, strict=True):
            k = {2: 3, 3: 4}.get(int(t))
            if k is None:
                raise ValueError(f"gmsh returned element type {t}; expected triangles "
                                 "or quads")
            blocks.append((k, index[np.asarray(nodes, dtype=np.int64).reshape(-1, k)]))
        if not blocks:
            continue
        areas = [_signed_area(xy, b) for _, b in blocks]
        sign = np.sign(sum(float(a.sum()) for a in areas))
        for (k, b), a in zip(blocks, areas, strict=True):
            if np.any(a * sign <= 0.0):
                return None
            cells[k].append(b if sign > 0 else b[:, ::-1])
    return cells


def tip_of(stator) -> tuple[object, float] | None:
    """``(material, plate_length_m)`` of a stator whose tip is of its own material
    (:class:`fem.material.ElasticMaterial`; the tip's cells are those beyond ``y =
    plate_length_m``), None for any other stator (its tip, if any, is the ceramic)."""
    name = getattr(stator, "tip_material", "")
    if not name:
        return None
    from fem.material import tip_material

    return tip_material(name), float(stator.length_m)


def tip_elements(mesh: PlateMesh, stator) -> tuple[object, np.ndarray] | None:
    """``(material, elements)`` of a planform mesh's tip of its own material
    (:func:`tip_of`): the unelectroded elements whose centre lies beyond the plate body's
    end; None where the tip, if any, is the plate's ceramic."""
    found = tip_of(stator)
    if found is None:
        return None
    material, length = found
    centre_y = mesh.points_m[1, mesh.quads].mean(axis=0)
    return material, np.flatnonzero((centre_y > length) & (mesh.electrode == 0))
