"""Offscreen pictures of the 3D model's mode shapes with pyvista (PNG) and one period (GIF).

Each picture shows the solid's deformed surface seen obliquely from above the ``+x`` side
(length horizontal, thickness up), the undeformed edges in grey, and a title with the mode's
name and short-circuit frequency. The surface is coloured either by the displacement
magnitude (``|u| / max|u|``, viridis, 0..1) or by the electric potential the mode carries
(``phi / max|phi|``, a diverging colormap centred at zero: the free potentials of the
short-circuit mode, ``phi = K_phiphi^-1 K_uphi^T u`` with the electrodes and the bottom face
at 0 V, :func:`mode_potential`). The deformation is scaled so that the largest displacement is
``scale_fraction`` of the overall length; the camera frames the whole period, so an animation
does not move.

Any mode of the 3D band table (:func:`fem.band.band_shapes`) can be drawn, not only L1 and
B2: out-of-plane bending and torsion are what a designer checks in 3D. Rendering is offscreen
(:func:`fem.render.headless_window`), the GIF is assembled by :func:`fem.render.scene_gif`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from fem.render import headless_window, scene_gif

WINDOW_SIZE = (1200, 700)
"""Default image size (pixels, width x height)."""
SCALE_FRACTION = 0.06
"""Default largest displayed displacement as a fraction of the overall length."""
COLORS = ("displacement", "potential")
"""What the surface may be coloured by."""
VIEW_DIRECTION = (1.0, -0.45, 0.75)
"""From the look-at point towards the camera (m, any length): above the ``+x`` side, a
little towards the preload end ``y = 0``, so that the length runs across the picture."""
_LABELS = {"displacement": "displacement magnitude / max",
           "potential": "electric potential / its largest magnitude"}
"""Colour bar titles (no ``|``: VTK hands text with it to matplotlib's mathtext, which takes
seconds per picture)."""


def mode_potential(model, shape: np.ndarray) -> np.ndarray:
    """Nodal electric potential (V per unit of ``shape``) that the short-circuit mode
    ``shape`` carries in the 3D model: the free potentials ``K_phiphi^-1 K_uphi^T u`` (the
    potential rows of the saddle-point system), 0 on the electrodes and the bottom face."""
    import scipy.sparse.linalg as sla

    t = model.potential_map(open_circuit=False)
    kup = (model.Kuphi @ t).tocsr()
    kpp = (t.T @ model.Kphiphi @ t).tocsc()
    return t @ sla.spsolve(kpp, kup.T @ np.asarray(shape, dtype=float))


def _surface(model, nrefs: int):
    """The solid's outer surface (pyvista PolyData) on the mesh refined ``nrefs`` times, and
    its points (3, n) in model coordinates (m)."""
    import pyvista as pv
    from skfem.io.meshio import to_meshio

    mesh = model.basis.mesh
    for _ in range(nrefs):
        mesh = mesh.refined()
    grid = pv.from_meshio(to_meshio(mesh))
    try:  # VTK's dataset surface filter, named (pyvista >= 0.47 warns of a coming default)
        surf = grid.extract_surface(pass_pointid=True, algorithm="dataset_surface")
    except TypeError:  # an older pyvista: that filter is its only one
        surf = grid.extract_surface(pass_pointid=True)
    pts = np.asarray(mesh.p)[:, np.asarray(surf.point_data["vtkOriginalPointIds"])]
    return surf, pts


class Scene3D:
    """One 3D mode on one offscreen plotter; :meth:`frame` re-poses it at a phase.

    Parameters
    ----------
    model : fem.solid3d.model.SolidPlateModel
    mode : object
        With ``name``, ``f_short_Hz`` and ``shape`` (3D displacement dofs):
        a :class:`fem.band.BandShape` or an L1/B2 of :func:`fem.solid3d.model.solid_modes`.
    color : str
        ``'displacement'`` or ``'potential'``.
    window_size : (int, int)
        Width and height (pixels).
    scale_fraction : float
        Largest drawn displacement over the overall length.
    decorations : bool
        Title and colour bar.
    nrefs : int
        Refinements of each brick for drawing the quadratic field.
    """

    def __init__(self, model, mode, color: str = "displacement",
                 window_size: tuple[int, int] = WINDOW_SIZE,
                 scale_fraction: float = SCALE_FRACTION, decorations: bool = True,
                 nrefs: int = 1) -> None:
        if color not in COLORS:
            raise ValueError(f"color must be one of {', '.join(COLORS)}, got {color!r}")
        headless_window()
        import pyvista as pv

        from fem.meshing.meshed_stator import overall_length_m

        self.surf, self.pts = _surface(model, nrefs)
        disp = (model.probe(self.pts) @ np.asarray(mode.shape)).reshape(3, -1)
        umag = np.linalg.norm(disp, axis=0)
        if not float(umag.max()) > 0.0:
            raise ValueError("mode shape is zero everywhere; nothing to render")
        length = overall_length_m(model.stator)
        self.disp = disp * (scale_fraction * length / float(umag.max()))
        self.color = color
        if color == "potential":
            phi = model.basis.probes(self.pts) @ mode_potential(model, mode.shape)
            top = float(np.max(np.abs(phi)))
            self.field = phi / top if top > 0.0 else phi
            cmap, clim = "coolwarm", (-1.0, 1.0)
        else:
            self.field = umag / float(umag.max())
            cmap, clim = "viridis", (0.0, 1.0)
        label = _LABELS[color]
        self.surf.point_data[label] = self.field
        self.plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
        self.plotter.set_background("white")
        bar = dict(title=label, color="black", vertical=False) if decorations else None
        self.plotter.add_mesh(self.surf, scalars=label, cmap=cmap, clim=clim,
                              show_scalar_bar=decorations, scalar_bar_args=bar,
                              smooth_shading=True)
        undeformed = self.surf.copy()
        undeformed.points = self.pts.T.copy()
        self.plotter.add_mesh(undeformed.extract_feature_edges(45.0), color="grey",
                              line_width=1.5)
        if decorations:
            self.plotter.add_title(_title(mode, color, scale_fraction, length), font_size=11,
                                   color="black")
        self._frame_camera()

    def _frame_camera(self) -> None:
        """A fixed camera that holds the surface at every phase."""
        lo = (self.pts - np.abs(self.disp)).min(axis=1)
        hi = (self.pts + np.abs(self.disp)).max(axis=1)
        centre = 0.5 * (lo + hi)
        cam = self.plotter.camera
        cam.focal_point = tuple(centre)
        direction = np.asarray(VIEW_DIRECTION) / np.linalg.norm(VIEW_DIRECTION)
        cam.position = tuple(centre + 10.0 * float(np.max(hi - lo)) * direction)
        cam.up = (0.0, 0.0, 1.0)
        self.plotter.reset_camera(bounds=(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]))
        cam.zoom(1.15)

    def frame(self, phase_rad: float) -> None:
        """Pose the deformed surface at ``cos(phase)`` of its amplitude."""
        c = float(np.cos(phase_rad))
        self.surf.points = (self.pts + c * self.disp).T
        label = _LABELS[self.color]
        if self.color == "potential":
            self.surf.point_data[label] = c * self.field
        else:
            self.surf.point_data[label] = abs(c) * self.field

    def bounds_m(self) -> tuple[float, ...]:
        """The surface's bounding box as posed, ``(x0, x1, y0, y1, z0, z1)`` (m, the
        deformation at its drawn scale); phase pi/2 poses the undeformed solid."""
        return tuple(float(b) for b in self.surf.bounds)

    def image(self) -> np.ndarray:
        """Current RGB image, shape (height, width, 3)."""
        self.plotter.render()
        return np.asarray(self.plotter.screenshot(None, return_img=True))

    def close(self) -> None:
        self.plotter.close()


def _title(mode, color: str, scale_fraction: float, length_m: float) -> str:
    shown = "displacement magnitude" if color == "displacement" else "electric potential"
    return (f"{mode.name}  f = {mode.f_short_Hz:,.1f} Hz (short circuit, 3D model), coloured "
            f"by the {shown}\nlargest displacement drawn at {scale_fraction:.0%} of the "
            f"{length_m * 1e3:.4g} mm length")


def render_mode3d_png(path: str | Path, model, mode, **kwargs) -> Path:
    """Write the picture of ``mode`` at phase 0 (:class:`Scene3D` options) as a PNG."""
    from PIL import Image

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    scene = Scene3D(model, mode, **kwargs)
    try:
        scene.frame(0.0)
        Image.fromarray(scene.image()).save(path)
    finally:
        scene.close()
    return path


def render_mode3d_gif(path: str | Path, model, mode, *, n_frames: int = 24,
                      frame_ms: int = 60, **kwargs) -> Path:
    """Write one period of ``mode`` (``n_frames`` phases, looping) as an animated GIF."""
    if n_frames < 2:
        raise ValueError(f"n_frames must be >= 2, got {n_frames!r}")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return scene_gif(path, Scene3D(model, mode, **kwargs), n_frames, frame_ms)


def render_modes3d(model, modes, out_dir: str | Path, animate: bool = False,
                   prefix: str = "3d_", **kwargs) -> list[Path]:
    """PNG (and with ``animate`` a GIF) of each of ``modes``; returns the files written.

    Files are ``<out_dir>/<prefix><name>.png`` (``.gif``); a mode named ``'other'`` is
    written as ``<prefix>mode<index>`` (its row of the band table).
    """
    out = Path(out_dir)
    written = []
    for mode in modes:
        stem = mode.name if mode.name != "other" else f"mode{getattr(mode, 'index', 0)}"
        written.append(render_mode3d_png(out / f"{prefix}{stem}.png", model, mode, **kwargs))
        if animate:
            written.append(render_mode3d_gif(out / f"{prefix}{stem}.gif", model, mode,
                                             **kwargs))
    return written
