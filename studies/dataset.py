"""The labelled dataset of a study and its netCDF file.

:func:`assemble` turns the per-geometry parts into an :class:`xarray.Dataset` with one
dimension per axis, units in each variable's attrs and provenance (package version,
parameter-set source, solver settings, the study itself) in the dataset's attrs;
:func:`write_dataset` writes it (h5netcdf engine) beside the target and renames it in.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from lusm.interrupts import checkpoint
from lusm.output_set import backup_name, staging
from studies.parts import parts_folder
from studies.study import AXIS_KIND, DRIVE_AXES, OUTPUTS, SI_UNIT, Study
from studies.task import package_version

AXIS_NAMES = {"length": "plate length", "width": "plate width",
               "thickness": "plate thickness", "gap": "electrode gap",
               "tip_length": "contact tip length", "tip_width": "contact tip width",
               "chamfer": "corner chamfer leg",
               "frequency": "drive frequency", "voltage": "drive amplitude V0",
               "preload": "preload F_P", "load": "load (braking force) on the slider"}


def assemble(study: Study, parts: dict[int, dict[str, np.ndarray]]):
    """The labelled :class:`xarray.Dataset` of a study from its per-geometry parts.

    Dimensions: the geometry axes, then the drive axes (``frequency`` only when fixed);
    coordinates in SI units (``units`` attrs); variables as asked by ``study.outputs``;
    provenance in the attrs (:func:`provenance`).
    """
    import xarray as xr

    missing = [i for i in range(study.n_geometries) if i not in parts]
    if missing:
        raise ValueError(f"{len(missing)} geometries are missing (first: {missing[0]})")
    return xr.Dataset(_variables(study, parts), coords=_coordinates(study),
                      attrs=provenance(study))


def _coordinates(study: Study) -> dict[str, tuple]:
    """The dataset's coordinates: each axis a dimension of, in SI units; the drive axes only
    of a study that drives the motor, ``frequency`` only when fixed."""
    dims = list(study.geometry_axes) + list(study.drive_dims)
    coords = {}
    for a in study.geometry_axes + DRIVE_AXES:
        if a not in dims and a != "frequency":
            continue
        if a in DRIVE_AXES and not study.needs_motor:  # an FE-only study drives nothing
            continue
        if a == "frequency" and study.auto_frequency:
            continue
        if a == "material":
            coords[a] = (a, np.array(study.axes[a], dtype=object),
                         {"long_name": "stator material"})
        else:
            coords[a] = (a, np.array(study.axes[a], dtype=float),
                         {"units": SI_UNIT[AXIS_KIND[a]], "long_name": AXIS_NAMES[a]})
    return coords


def _variables(study: Study, parts: dict[int, dict[str, np.ndarray]]) -> dict[str, tuple]:
    """The dataset's variables ``name -> (dims, values, attrs)``: the outputs the study asks
    for, stacked over the geometries, the auto drive frequency, and each geometry's status."""
    gdims = list(study.geometry_axes)
    mdims = [a for a in study.drive_dims if a != "load"]
    n = study.n_geometries
    data_vars = {}

    def stack(name: str) -> np.ndarray:
        arrs = [parts[i][name] for i in range(n)]
        return np.stack(arrs).reshape(study.geometry_shape + arrs[0].shape)

    def add(name: str, dims: list[str], values: np.ndarray, units: str, long_name: str):
        attrs = {"long_name": long_name}
        if units:
            attrs["units"] = units
        data_vars[name] = (dims, values, attrs)

    for o in study.outputs:
        unit, meaning = OUTPUTS[o]
        if o == "k_eff":
            for m in ("L1", "B2"):  # one mode each
                add(f"k_eff_{m}", gdims, stack(f"k_eff_{m}"), unit,
                    f"effective electromechanical coupling factor of {m}")
        elif o in ("f_L1_short", "f_L1_open", "f_B2_short", "f_B2_open", "split"):
            add(o, gdims, stack(o), unit, meaning)
        elif o == "velocity":
            add(o, gdims + mdims + ["load"], stack(o), unit, meaning)
        elif o == "motion_class":
            add(o, gdims + mdims, stack(o).astype(object), unit, meaning)
        else:
            add(o, gdims + mdims, stack(o), unit, meaning)
    if study.needs_motor and study.auto_frequency:
        add("f_drive", gdims, stack("f_drive"), "Hz",
            "drive frequency (auto: largest product of the free tip amplitudes, "
            "contact.drive.auto_frequency)")
    if study.needs_motor and study.solver.settle:
        add("duration", gdims, stack("duration"), "s",
            "transient run length: the plate's settling time, at least solver.duration's "
            "default, at most the step bound (contact.drive.default_duration_s, as lusm "
            "simulate's default)")
    add("status", gdims, stack("status").astype(object), "",
        "'ok', or why the geometry or some of its drive points failed")
    if study.needs_motor:
        add("point_status", gdims + mdims, stack("point_status").astype(object), "",
            "'ok', or why the drive point failed or did not settle (its answers are NaN, "
            "or where a transient stopped)")
    add("warnings", gdims, stack("warnings").astype(object), "",
        "what the geometry's computation warned (one line each), '' for nothing: e.g. a "
        "drive that excites no B2, where the motor gives no thrust")
    return data_vars


def provenance(study: Study) -> dict[str, str]:
    """The dataset's attributes: the study, the lusm version, how the parameter sets and the
    answers are computed, and the stator file a study starts from."""
    s = study.solver
    attrs = {
        "title": f"lusm explore: {study.name}",
        "lusm_version": package_version(),
        "study_source": study.source,
        "study": study.text,
        "study_fingerprint": study.fingerprint,
        "parameter_set_source": _parameter_set_source(study),
        "fe_solver": f"fem.modes.plate_modes, order {s.fe_order}, {_mesh_text(study)}, "
                     "shift-invert eigsh with a fixed start vector",
    }
    if study.needs_motor:
        attrs.update(_motor_provenance(study))
    else:  # FE outputs only: no contact model ran
        attrs["parameter_set_source"] = "none: FE outputs only"
    if study.stator is not None:
        d = study.stator
        stamp = json.loads(study.text)["stator"]
        attrs["stator_file"] = stamp["file"]
        attrs["stator_name"] = d.name
        attrs["stator_sha256"] = stamp["sha256"]
        if d.mesh_path is not None:
            attrs["stator_mesh_file"] = os.path.abspath(d.mesh_path)
    # the study's path (and the name it gives by default) may hold bytes that are not UTF-8
    return {k: storable_text(v) for k, v in attrs.items()}


def _motor_provenance(study: Study) -> dict[str, str]:
    """The attributes of a study that drives the motor: its contact solver, drive frequency
    rule, coupling, friction and damping."""
    s = study.solver
    return {
        "motor_solver": (
            f"contact.steady.steady_state and contact.characteristic.characteristic, "
            f"accuracy={s.accuracy}" + (f", rest={s.rest}" if s.accuracy == "exact" else "")
            + " (solver.duration and solver.dt unused)"
            if s.method == "steady" else
            f"contact.simulate.simulate method={s.method}, "
            + (f"duration_s=each plate's settling time, at least {s.duration_s:g} (duration), "
               if s.settle else f"duration_s={s.duration_s:g}, ")
            + (f"dt_s={s.dt_s:g}" if s.dt_s is not None else
               "dt_s=the largest step up to 1e-07 s dividing the drive period "
               "(lusm.options.time_step_s, as lusm simulate)")
            + ", from rest (a point that did not settle is named in status); "
            "stall_force, peak_efficiency, peak_power and loaded velocity need method = "
            "\"steady\" (NaN)"),
        "frequency_rule": "auto" if study.auto_frequency else "fixed (coordinate frequency)",
        "coupling": "consistent (auto: the work-consistent tangential coupling of every set "
                    "that is not Table 2's, contact.model.default_coupling; docs/contact.md "
                    "2.3.1)",
        "friction": ("Eq. 11 ultrasonic friction reduction (mu_d,eff)"
                     if s.ultrasonic_friction else "constant mu_d (solver.ultrasonic_friction "
                     "= false)"),
        "damping": damping_text(study),
    }


def _mesh_text(study: Study) -> str:
    """The FE mesh of the study's plates, in words: ``refine N``, or a stator file's own."""
    d = study.stator
    if d is not None and d.mesh_path is not None:
        return f"the stator file's mesh {d.mesh_path}"
    from fem.meshing.meshed_stator import has_planform

    if d is not None and has_planform(d.stator):
        return "gmsh at the stator file's [mesh] size_mm (solver.fe_refine unused)"
    return f"refine {study.solver.fe_refine}"


def damping_text(study: Study) -> str:
    """The modal damping of the study's parameter sets, in words (every answer with a
    velocity depends on it): each material's ``Q_m`` with the mount's for the plain plates
    (:func:`validation.summaries.plate_damping`; Table 2's ratios, borrowed, for a material
    without ``Q_m``), or the stator file's ``[damping]``."""
    from rom import table2

    t2 = table2()
    borrowed = (f"Table 2's ratios zeta_L1 = {t2.zeta_L1:.4g}, zeta_B2 = {t2.zeta_B2:.4g} "
                "(borrowed: the FE reduction has no damping of its own)")
    d = study.stator
    if d is None:
        from fem.material import get_material
        from validation.summaries import plate_damping

        said = []
        for name in study.axes["material"]:
            ratios, origin = plate_damping(get_material(name), "fem")
            said.append(borrowed if ratios is None else
                        f"zeta_L1 = zeta_B2 = {ratios[0]:.4g} ({origin})")
        return "; ".join(dict.fromkeys(said))
    # the values first: a figure's title shortens the end, where the path is
    from rom.from_fem import design_damping

    ratios = design_damping(d)  # the file's ratios, Q_m's, or Table 2's by name
    if ratios is not None:
        z1, z2 = ratios
        return (f"zeta_L1 = {z1:.4g}, zeta_B2 = {z2:.4g} ({d.damping_origin}), from stator "
                f"file {d.path}")
    if d.damping_origin:  # fitted per plate, or Table 2's by name
        return f"{d.damping_origin}, from stator file {d.path}"
    return f"{borrowed}; stator file {d.path} has no [damping]"


def _parameter_set_source(study: Study) -> str:
    """How each geometry's parameter set is built, for the dataset's attributes."""
    s = study.solver
    fe = (f"FE modal reduction per geometry (rom.from_fem.fem_params: scikit-fem plane stress, "
          f"order {s.fe_order}, {_mesh_text(study)}")
    d = study.stator
    if d is None:
        return (f"{fe}); damping {damping_text(study)}; contact, slider and friction "
                "constants from rom.table2 (Li, Yao & Wu 2016, Table 2)")
    motor = ("; " + ", ".join(f"{where} from the file" for where in d.motor_keys().values())
             if d.motor else "")
    return (f"{fe}) of stator file {d.path} ({d.name}), its plate dimensions from the "
            f"geometry axes; damping {damping_text(study)}{motor}; the other contact, slider "
            "and friction constants from rom.table2 (Li, Yao & Wu 2016, Table 2)")


def storable_text(text: str) -> str:
    """``text`` as a netCDF attribute can hold it (UTF-8): a file name's bytes that are not
    UTF-8, which Python keeps as lone surrogates (``'st\\udcfe.toml'``), written as
    ``\\xNN`` (``'st\\xfe.toml'``), so the path stays readable and exact, and the write,
    after every geometry is computed, does not fail on them ("'utf-8' codec can't encode
    character '\\udcfe'")."""
    try:
        raw = os.fsencode(text)  # a path's undecodable bytes back as they were
    except UnicodeEncodeError:  # a lone surrogate no file name decodes to
        raw = text.encode("utf-8", "backslashreplace")
    return raw.decode("utf-8", "backslashreplace")


def write_dataset(ds, out: Path, force: bool = False) -> None:
    """Write ``ds`` to netCDF aside and rename it onto ``out``.

    A file already at ``out`` is refused unless ``force``; with ``force`` it is kept as
    ``out.bak-N``, never deleted. HDF5 builds the file in memory and this process writes its
    bytes (as many as the file has), so a disk that refuses them (full, or a file size limit)
    is an ``OSError`` of an ordinary write, not a failure inside h5py's close (which crashes
    the process at exit).

    Raises
    ------
    ValueError
        If ``out`` is refused (:func:`check_out`) or the dataset cannot be written there:
        one line naming ``--out`` and the system's reason; no staging file is left.
    """
    import dask

    out = Path(out)
    check_out(out, force)
    # memory only: nothing of HDF5 touches the disk. xarray locks the target on the active
    # dask scheduler; with a distributed Client alive in this process that is a
    # distributed.Lock named by the in-memory buffer, which the scheduler refused ("Semaphore
    # or Lock <_io.BytesIO ...> not known"). The dataset is NumPy, not dask: no scheduler runs
    with dask.config.set(scheduler="synchronous"):
        data = ds.to_netcdf(engine="h5netcdf")
    out.parent.mkdir(parents=True, exist_ok=True)
    with staging(out.parent, out.name, "--out", out) as stage:
        tmp = stage / out.name
        try:
            with open(tmp, "xb") as fh:  # closed (and its error raised) before the removal
                fh.write(data)
                fh.flush()
                os.fsync(fh.fileno())
        except OSError as exc:
            raise ValueError(f"--out {out}: cannot write the dataset "
                             f"({exc.strerror or exc}; {len(data)} bytes)") from None
        checkpoint()  # a Ctrl-C / SIGTERM that Python swallowed: nothing is moved in
        if os.path.lexists(out):  # a link (dangling or not) itself, not its file
            os.replace(out, backup_name(out))
        os.replace(tmp, out)


def is_complete(study: Study, out: str | Path) -> bool:
    """Whether ``out`` holds the finished dataset of ``study``: a dataset carrying its
    fingerprint and no parts folder beside it (what a run that finished leaves)."""
    out = Path(out)
    if not out.is_file() or parts_folder(out).exists():
        return False
    try:
        ds = open_result(out)
    except (OSError, ValueError):  # not a dataset: check_out refuses it as the user's file
        return False
    return ds.attrs.get("study_fingerprint") == study.fingerprint


def check_out(out: Path, force: bool) -> None:
    """Refuse, before any work, an output the dataset could not be written to."""
    if not str(out).strip():
        raise ValueError(f"--out must name a netCDF file (.nc, .nc4 or .h5), got {str(out)!r}")
    out = Path(out)
    if out.suffix.lower() not in (".nc", ".nc4", ".h5"):
        zarr = "; zarr stores are not supported yet" if out.suffix.lower() == ".zarr" else ""
        raise ValueError(f"--out {out}: name a netCDF file (.nc, .nc4 or .h5){zarr}")
    if out.is_dir():
        raise ValueError(f"--out {out} is a folder; name a .nc file")
    if out.exists() and not force:
        raise ValueError(f"--out {out} exists; choose a new name or pass --force (the old "
                         "file is kept as a .bak file)")
    if out.is_symlink() and not out.exists() and not force:
        # a link to nowhere is the user's too: not renamed over without --force
        raise ValueError(f"--out {out} exists, a symbolic link to {os.readlink(out)}, which "
                         "does not exist; choose a new name or pass --force (the link is kept "
                         "as a .bak file)")
    existing = next((p for p in [out.parent, *out.parent.parents] if p.exists()), Path.cwd())
    if not existing.is_dir() or not os.access(existing, os.W_OK | os.X_OK):
        raise ValueError(f"--out {out}: {existing} is not a writable folder")


def open_result(path: str | Path):
    """Read a dataset written by :func:`explore` (loaded into memory, file closed)."""
    import xarray as xr

    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()
