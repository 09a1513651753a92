"""The resume store of a study: one file per finished geometry in ``<out>.parts/``.

The client writes each finished geometry, as it arrives, to one small ``.npz`` file (written
aside and renamed in, so a part is there complete or not at all); ``study.json`` names the
study and lusm version the parts belong to, and a :mod:`filelock` lock keeps a second run
off the folder while one runs. ``--resume`` continues from the parts; the final dataset is
the same as an uninterrupted run's.
"""

from __future__ import annotations

import json
import os
import uuid
import zipfile
from pathlib import Path

import numpy as np

from studies.study import Study
from studies.task import TASK_EXTRAS, empty_outputs, has_results, package_version

PARTS_SUFFIX = ".parts"
"""Folder ``<out>.parts`` next to the output holds one file per finished geometry."""


STUDY_FILE = "study.json"
"""The study a parts folder belongs to (resume refuses another)."""


LOCK_FILE = ".lock"
"""The file of a parts folder a running ``explore`` holds locked (:mod:`filelock`)."""


def parts_folder(out: Path) -> Path:
    """The folder of per-geometry files of an output ``out``."""
    return out.with_name(out.name + PARTS_SUFFIX)


def part_path(folder: Path, index: int) -> Path:
    return folder / f"g{index:07d}.npz"


def write_part(folder: Path, index: int, data: dict[str, np.ndarray]) -> None:
    final = part_path(folder, index)
    tmp = folder / f".{final.name}-{uuid.uuid4().hex[:8]}"
    with open(tmp, "wb") as fh:
        np.savez(fh, **{k: v for k, v in data.items() if k not in TASK_EXTRAS})
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, final)  # a part is there complete or not at all


def read_part(folder: Path, index: int,
               template: dict[str, np.ndarray] | None = None) -> dict[str, np.ndarray] | None:
    """A part as written, or None (computed again) when it is missing, torn, or its arrays
    are not those of ``template`` (:func:`empty_outputs`: the same names, shapes and
    kinds: a part without ``velocity`` cannot go into the dataset)."""
    try:
        with np.load(part_path(folder, index), allow_pickle=False) as z:
            part = {k: z[k] for k in z.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile):  # missing or torn (a
        return None  # truncated .npz): computed again
    if template is not None and (
            set(part) != set(template)
            or any(part[k].shape != v.shape or part[k].dtype.kind != v.dtype.kind
                   for k, v in template.items())):
        return None
    return part


def open_parts(study: Study, out: Path, resume: bool):
    """The parts folder of ``out`` (made, or checked as this study's), its finished parts by
    geometry, whether this call made it, and the run's lock on it (:func:`_lock_parts`),
    taken before any part is read."""
    folder = parts_folder(out)
    template = empty_outputs(study)
    if not folder.exists():
        stamp = {"fingerprint": study.fingerprint, "study": json.loads(study.text),
                 "lusm_version": package_version()}
        try:
            folder.mkdir(parents=True)
            (folder / STUDY_FILE).write_text(json.dumps(stamp, indent=1))
        except OSError as exc:  # /sys/x.nc: named by its option, not only by its path
            raise ValueError(f"--out {out}: cannot write its parts folder {folder} "
                             f"({exc.strerror or exc})") from None
        return folder, {}, True, _lock_parts(folder, out)
    if not (folder / STUDY_FILE).is_file():  # not ours: nothing is written into it
        option = "--resume" if resume else f"--out {out}"
        raise ValueError(f"{option}: {folder} has no {STUDY_FILE}, so it is not the parts "
                         "folder of a lusm explore run (a finished run leaves only files "
                         "that are not its own there); move it away or choose another --out")
    lock = _lock_parts(folder, out)  # a live run's folder is refused before anything is said
    old = _stamp_of(folder)
    why = _not_this_runs(study, folder, old, "--resume" if resume else f"--out {out}")
    if why is None and not resume:
        why = _not_resumed(study, out, folder, template)
    if why is not None:
        lock.release()
        raise ValueError(why)
    return folder, _finished_parts(study, folder, template), False, lock


def _stamp_of(folder: Path) -> dict:
    """The ``study.json`` of a parts folder ({} when unreadable)."""
    try:
        old = json.loads((folder / STUDY_FILE).read_text())
    except (OSError, ValueError):
        return {}
    return old if isinstance(old, dict) else {}


def _finished_parts(study: Study, folder: Path, template) -> dict[int, dict]:
    """The readable, well-formed parts in ``folder`` by geometry."""
    done = {}
    for i in range(study.n_geometries):
        if part_path(folder, i).exists():
            part = read_part(folder, i, template)
            if part is not None:
                done[i] = part
    return done


def _not_this_runs(study: Study, folder: Path, old: dict, option: str) -> str | None:
    """Why the parts in ``folder`` (whose ``study.json`` is ``old``) cannot go into this run's
    dataset, naming ``option``: another lusm version's (said first: it may read the same file
    as another study) or another study's; None when they can."""
    if old.get("lusm_version") != package_version():
        return (f"{option}: {folder} was computed by lusm {old.get('lusm_version', 'unknown')} "
                f"(this is lusm {package_version()}); resuming would mix both in one dataset; "
                "remove that folder to start over")
    if old.get("fingerprint") != study.fingerprint:
        return (f"{option}: {folder} holds the parts of another study (the study file or its "
                "study.stator file changed); remove that folder, or restore the study")
    return None


def _not_resumed(study: Study, out: Path, folder: Path, template) -> str:
    """Why a run without ``--resume`` does not start over this study's parts folder, and what
    to do: every geometry computed (the dataset not written: an interrupt or a failed write
    at the end), a finished run in which none computed fully, or an unfinished run."""
    if not all(part_path(folder, i).exists() for i in range(study.n_geometries)):
        return (f"--out {out}: {folder} holds an unfinished run; pass --resume to continue "
                "it, or remove that folder to start over")
    parts = _finished_parts(study, folder, template)
    if len(parts) == study.n_geometries and not any(has_results(p) for p in parts.values()):
        return (f"--out {out}: {folder} holds a finished run in which no geometry computed "
                "fully (each part's reason in its 'status'; --resume says the first again); "
                "remove that folder to run a corrected study")
    return (f"--out {out}: {folder} holds every geometry of this study, computed (the dataset "
            "was not written); pass --resume to write it, or remove that folder to start over")


class PartsBusyError(ValueError):
    """Another ``explore`` holds the lock of the parts folder: this run is refused before any
    work, and the parts there are that run's, not this one's."""


def _lock_parts(folder: Path, out: Path):
    """Hold ``folder``'s lock for this run (a :class:`filelock.FileLock`, released by the
    caller; the system releases it when the process ends, however it ends), or refuse: two
    runs on one parts folder would both compute every geometry left."""
    from filelock import FileLock, Timeout

    lock = FileLock(folder / LOCK_FILE)
    try:
        lock.acquire(timeout=0)
    except Timeout:
        raise PartsBusyError(f"--out {out}: another lusm explore is running on {folder}; "
                             "wait for it to finish, or choose another --out") from None
    except OSError as exc:  # a read-only folder, or one a finishing run just removed
        raise ValueError(f"--out {out}: cannot lock its parts folder {folder} "
                         f"({exc.strerror or exc})") from None
    return lock


def remove_parts(folder: Path, n: int, made: list[Path] = ()) -> None:
    """Remove the files this module wrote, then the folder if nothing else is in it, then
    the folders ``made`` above it (deepest first) that are still empty."""
    for i in range(n):
        part_path(folder, i).unlink(missing_ok=True)
    (folder / STUDY_FILE).unlink(missing_ok=True)
    (folder / LOCK_FILE).unlink(missing_ok=True)
    for stray in folder.glob(".g*.npz-*"):  # torn temporaries of ours
        stray.unlink(missing_ok=True)
    for f in (folder, *made):
        try:
            f.rmdir()
        except OSError:
            break  # something of the user's is in it (or it is gone): left alone
