"""Offscreen pictures of mode shapes with pyvista (PNG) and one-period animations (GIF).

Each picture shows the deformed planform coloured by the displacement magnitude
(``|u| / max|u|``), the undeformed outline (grey), the electrode outlines on the deformed
shape (driven electrodes red, grounded ones black) and a title with the mode name and its
short-circuit frequency. The plate is drawn with its length horizontal, preload end left and
``x > 0`` up, as in the sketch of :mod:`fem.geometry` ("1 2" above "3 4"); screen
coordinates are ``(y, x)``, so the long axis ``x = 0`` is the horizontal centre line of the
image. The deformation is scaled so that the largest displacement is
``scale_fraction * length``.

Rendering is always offscreen (``off_screen=True``); VTK >= 9.4 picks OSMesa or EGL at run
time, so no X server is needed; on a machine with no display and libEGL installed,
:func:`headless_window` selects EGL before VTK tries X (which would print a warning).
GIFs are assembled from screenshots with Pillow (a
matplotlib dependency), so imageio is not required.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from fem.meshing.mesh import boundary_edges

WINDOW_SIZE = (1200, 520)
"""Default image size (pixels, width x height)."""
DECORATED_BAND = 0.67
"""Share of the view's half-height, on each side of the long axis, left to the plate and its
ruler between the title (top) and the colour bar (bottom) of a decorated picture."""
SCALE_FRACTION = 0.06
"""Default largest displayed displacement as a fraction of the plate length."""
_MAG = "displacement magnitude / max"


def _refined_field(model, shape: np.ndarray, nrefs: int):
    """Refined quad mesh points (2, n), cells (4, m) and displacement (2, n) of ``shape``."""
    (ux, bx), (uy, by) = model.basis.split(np.asarray(shape, dtype=float))
    mesh_r, vx = bx.refinterp(ux, nrefs=nrefs)
    _, vy = by.refinterp(uy, nrefs=nrefs)
    return np.asarray(mesh_r.p), np.asarray(mesh_r.t), np.vstack((vx, vy))


def outline_points(model, quads_idx: np.ndarray, n_per_edge: int = 6) -> np.ndarray:
    """Points along the boundary of the elements ``quads_idx``, shape (2, n_edges, n) (m).

    Each point is pulled 1e-7 of the way towards its element's centroid so that probing it
    never falls off the mesh.
    """
    mesh = model.mesh
    quads = mesh.quads[:, quads_idx]
    edges, owner = boundary_edges(quads)
    p = mesh.points_m
    s = np.linspace(0.0, 1.0, n_per_edge)
    a, b = p[:, edges[:, 0]], p[:, edges[:, 1]]
    pts = a[:, :, None] + (b - a)[:, :, None] * s  # (2, k, n)
    centre = p[:, quads[:, owner]].mean(axis=1)  # (2, k)
    return pts + 1e-7 * (centre[:, :, None] - pts)


def headless_window() -> str | None:
    """Pick VTK's EGL render window on a machine with no display, before VTK creates one.

    Without ``DISPLAY`` VTK >= 9.4 first tries its X window, prints ``bad X server
    connection`` on stderr and only then falls back to EGL or OSMesa. When EGL is installed
    and the user has not chosen a window (``VTK_DEFAULT_OPENGL_WINDOW``, the documented VTK
    runtime setting), choose it directly, so rendering prints nothing. Returns the choice,
    or None when VTK's own order is kept (a display, a user choice, or no libEGL).
    """
    import ctypes.util
    import os

    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY") or os.environ.get(
            "VTK_DEFAULT_OPENGL_WINDOW"):
        return None
    if ctypes.util.find_library("EGL") is None:
        return None
    os.environ["VTK_DEFAULT_OPENGL_WINDOW"] = "vtkEGLRenderWindow"
    return "vtkEGLRenderWindow"


def _lines(points_2d: np.ndarray):
    """pyvista PolyData of polylines from (2, k, n) points given in model (x, y) coordinates."""
    import pyvista as pv

    k, n = points_2d.shape[1:]
    xyz = np.column_stack(
        (points_2d[1].ravel(), points_2d[0].ravel(), np.full(k * n, 1e-6))
    )  # screen (y, x)
    cells = np.hstack([np.r_[n, np.arange(i * n, (i + 1) * n)] for i in range(k)])
    return pv.PolyData(xyz, lines=cells)


class _Scene:
    """One mode on one offscreen plotter; :meth:`frame` re-poses it at a phase."""

    def __init__(self, model, shape, title, window_size, scale_fraction, decorations, nrefs):
        headless_window()
        import pyvista as pv

        self.model = model
        st = model.stator
        length = st.length_m
        pts, cells, disp = _refined_field(model, shape, nrefs)
        umax = float(np.max(np.hypot(disp[0], disp[1])))
        if umax <= 0.0:
            raise ValueError("mode shape is zero everywhere; nothing to render")
        self.scale = scale_fraction * length / umax
        self.pts, self.disp = pts, disp * self.scale
        n = pts.shape[1]
        self.grid = pv.UnstructuredGrid(
            np.hstack((np.full((cells.shape[1], 1), 4), cells.T)).ravel(),
            np.full(cells.shape[1], pv.CellType.QUAD, dtype=np.uint8),
            np.column_stack((pts[1], pts[0], np.zeros(n))),
        )
        self.grid.point_data[_MAG] = np.zeros(n)
        self.plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
        self.plotter.set_background("white")
        bar = dict(title=_MAG, color="black", vertical=False) if decorations else None
        self.plotter.add_mesh(
            self.grid, scalars=_MAG, cmap="viridis", clim=(0.0, 1.0),
            show_scalar_bar=decorations, scalar_bar_args=bar,
        )
        mesh = model.mesh
        outline = outline_points(model, np.arange(mesh.n_elements), 2)
        self.plotter.add_mesh(_lines(outline), color="grey", line_width=2)
        # electrode outlines, deformed: probe the field along each electrode boundary
        self.electrode_lines = []
        driven = set(st.drive_electrodes)
        for k in sorted({int(e) for e in np.unique(mesh.electrode) if e > 0}):
            opts = outline_points(model, mesh.elements_of(k))
            P = model.probe(opts.reshape(2, -1))
            u = (P @ np.asarray(shape)).reshape(opts.shape) * self.scale
            poly = _lines(opts)
            self.plotter.add_mesh(poly, color="red" if k in driven else "black", line_width=2)
            self.electrode_lines.append((poly, opts, u))
        if decorations and title:
            self.plotter.add_title(title, font_size=12, color="black")
        # camera: parallel projection centred on the long axis x = 0 (screen y = 0)
        x0, x1, y0, y1 = mesh.bounding_box_m()
        reach = scale_fraction * length
        if decorations:  # a millimetre ruler along the length and the deformation scale
            above = x1 + 1.4 * reach  # labels on the right of a->b: above, read from y0
            self.plotter.add_ruler([y1, above, 0.0], [y0, above, 0.0], flip_range=True,
                                   title="mm", scale=1e3, label_format="%.0f",
                                   label_color="black", tick_color="black",
                                   font_size_factor=0.5)
            self.plotter.add_text(
                f"largest displacement drawn at {scale_fraction:.0%} of the "
                f"{length * 1e3:.4g} mm length", position="lower_left", font_size=7,
                color="black")
        half_w = 0.5 * (y1 - y0) + reach
        half_h = max(x1, -x0) + reach
        aspect = window_size[0] / window_size[1]
        cam = self.plotter.camera
        cam.parallel_projection = True
        centre = (0.5 * (y0 + y1), 0.0, 0.0)
        cam.focal_point = centre
        cam.position = (centre[0], 0.0, 10.0 * length)
        cam.up = (0.0, 1.0, 0.0)
        scale = 1.08 * max(half_h, half_w / aspect) * (1.25 if decorations else 1)
        if decorations:
            # the title takes about the top quarter of the half-height and the colour bar the
            # bottom third: the ruler (and its labels) and the deformed plate stay between
            # them: a plate wider than about 0.4 of its length would have the ruler drawn
            # through the title and the plate over the bar's label; narrower plates are
            # bound by their length and keep their view.
            scale = max(scale, above / DECORATED_BAND, half_h / DECORATED_BAND)
        cam.parallel_scale = scale
        cam.clipping_range = (length, 20.0 * length)

    def frame(self, phase_rad: float) -> None:
        """Pose the deformed shape at ``cos(phase)`` of its amplitude."""
        c = float(np.cos(phase_rad))
        d = self.disp * c
        self.grid.points[:, 0] = self.pts[1] + d[1]
        self.grid.points[:, 1] = self.pts[0] + d[0]
        self.grid.point_data[_MAG] = np.hypot(d[0], d[1]) / np.max(np.hypot(*self.disp))
        for poly, opts, u in self.electrode_lines:
            moved = opts + c * u
            poly.points[:, 0] = moved[1].ravel()
            poly.points[:, 1] = moved[0].ravel()

    def image(self) -> np.ndarray:
        """Current RGB image, shape (height, width, 3)."""
        self.plotter.render()
        return np.asarray(self.plotter.screenshot(None, return_img=True))

    def close(self) -> None:
        self.plotter.close()


def _title(mode, stator) -> str:
    drive = ", ".join(str(e) for e in stator.drive_electrodes)
    return (
        f"{mode.name}  f = {mode.f_short_Hz:,.1f} Hz (short circuit)   "
        f"driven electrodes {drive} (red)"
    )


def mode_image(
    model, mode, *, phase_rad: float = 0.0, window_size: tuple[int, int] = WINDOW_SIZE,
    scale_fraction: float = SCALE_FRACTION, decorations: bool = True, nrefs: int = 2,
) -> np.ndarray:
    """RGB image (height, width, 3) of one mode at one phase.

    Parameters
    ----------
    model : fem.model.PiezoPlateModel
    mode : fem.modes.IdentifiedMode
        L1 or B2 of ``model`` (or any object with ``name``, ``f_short_Hz``, ``shape``).
    phase_rad : float
        The shape is drawn at ``cos(phase)`` of its amplitude.
    window_size : (int, int)
        Width and height (pixels).
    scale_fraction : float
        Largest drawn displacement over the plate length.
    decorations : bool
        Title and colour bar (off: only the plate, e.g. for symmetry checks).
    nrefs : int
        Refinements of each element for drawing the (biquadratic) field.
    """
    scene = _Scene(model, mode.shape, _title(mode, model.stator), window_size,
                   scale_fraction, decorations, nrefs)
    try:
        scene.frame(phase_rad)
        return scene.image()
    finally:
        scene.close()


def render_mode_png(path: str | Path, model, mode, **kwargs) -> Path:
    """Write :func:`mode_image` of ``mode`` to a PNG file; returns the path."""
    from PIL import Image

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(mode_image(model, mode, **kwargs)).save(path)
    return path


def render_mode_gif(
    path: str | Path, model, mode, *, n_frames: int = 24, frame_ms: int = 60,
    window_size: tuple[int, int] = WINDOW_SIZE, scale_fraction: float = SCALE_FRACTION,
    decorations: bool = True, nrefs: int = 2,
) -> Path:
    """Write one period of ``mode`` (``n_frames`` phases, looping) as an animated GIF."""
    if n_frames < 2:
        raise ValueError(f"n_frames must be >= 2, got {n_frames!r}")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    scene = _Scene(model, mode.shape, _title(mode, model.stator), window_size,
                   scale_fraction, decorations, nrefs)
    return scene_gif(path, scene, n_frames, frame_ms)


def scene_gif(path: Path, scene, n_frames: int, frame_ms: int) -> Path:
    """Write one period of ``scene`` (``frame(phase)``, ``image()``, ``close()``; closed
    here) as a looping GIF of ``n_frames`` phases, ``frame_ms`` each; returns the path."""
    from PIL import Image

    try:
        frames = []
        for phase in np.linspace(0.0, 2.0 * np.pi, n_frames, endpoint=False):
            scene.frame(float(phase))
            frames.append(Image.fromarray(scene.image()))
    finally:
        scene.close()
    frames[0].save(path, save_all=True, append_images=frames[1:], duration=frame_ms, loop=0)
    return path


def render_modes(
    model, modes, out_dir: str | Path, which: tuple[str, ...] = ("L1", "B2"),
    animate: bool = False, prefix: str = "", **kwargs,
) -> list[Path]:
    """PNG (and with ``animate`` a GIF) of each mode in ``which``; returns the files written.

    Files are ``<out_dir>/<prefix><name>.png`` and ``.gif``.
    """
    out = Path(out_dir)
    written = []
    for name in which:
        if name not in ("L1", "B2"):
            raise ValueError(f"mode must be L1 or B2, got {name!r}")
        mode = getattr(modes, name)
        written.append(render_mode_png(out / f"{prefix}{name}.png", model, mode, **kwargs))
        if animate:
            written.append(render_mode_gif(out / f"{prefix}{name}.gif", model, mode, **kwargs))
    return written


def mirror_difference(img: np.ndarray) -> float:
    """Mean absolute pixel difference between an image and its mirror about the horizontal
    centre line (the plate's long axis x = 0 in :func:`mode_image`'s orientation)."""
    img = np.asarray(img, dtype=float)
    return float(np.mean(np.abs(img - img[::-1])))


def centre_line_offset_px(img: np.ndarray) -> float:
    """90th percentile over the image columns of the distance (px) between the plate's
    deformed centre line and the image's horizontal centre line.

    The plate is every pixel that is not background or grey outline; per column (away from
    the plate's ends), its centre line is halfway between its two edges. L1 keeps it on the
    axis, B2 (bending) moves it off.
    """
    img = np.asarray(img, dtype=float)
    grey = (np.ptp(img, axis=-1) < 30) & (img.mean(axis=-1) > 60)  # background, outline
    coloured = ~grey  # the plate: viridis, red and black electrode outlines
    count = coloured.sum(axis=0)
    cols = np.flatnonzero(count > 0.5 * count.max())  # away from the ends
    rows = [np.flatnonzero(coloured[:, c]) for c in cols]
    mid = np.array([0.5 * (r[0] + r[-1]) for r in rows])  # between the two edges
    return float(np.percentile(np.abs(mid - (img.shape[0] - 1) / 2), 90))
